"""Knowledge files as documents: read .pl, SEED or YAML; write canonical .pl or YAML.

    Document = (items: tuple[Clause | Directive], notes: tuple[str], file: str)

The formats are equivalent: `pl -> yaml -> pl` gives back the same canonical text.
YAML (read with PyYAML's SafeLoader only, integers of any length) holds one record per clause, in order:

    schemalog: 1
    items:
      - task: use(spoon)                  # task/1, object/1, initial/1, behaviour/1 facts
      - schema: add(O)
        subtasks:
          - {behaviour: subtask(take,O), releaser: hand.free}
          - {behaviour: subtask(pour,O), releaser: O.taken, importance: 2}
        post: O.used
        if: string(O)                     # only for a rule schema
      - clause: "agent(gripper(_),gripper)."
      - directive: "dynamic foo/1"

Variables are shared by name within a record, as within a clause.
"""

from __future__ import annotations

import functools
import io
import os
import stat
import tempfile
from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass, replace
from pathlib import Path
from typing import BinaryIO

from ..inputs import check_yaml_nesting
from ..errors import READABLE, CannotWrite, SchemalogError, SourcePos
from ..logic.kb import KnowledgeBase
from ..logic.fastread import parse_text
from ..logic.parse import MAX_BYTES, Clause, Directive, read_source
from ..task import conditions as cond
from ..task.schema import DEFAULT_IMPORTANCE, Entry, knowledge_base, schema_term, static_schema, write_clause
from .seed import import_seed, is_seed
from ..logic.terms import TRUE, Struct, Term, int_of_digits, int_text, term_to_text, variable_names

YAML_SUFFIXES = (".yaml", ".yml")
_SIMPLE_FACTS = ("task", "object", "initial", "behaviour")


@dataclass(frozen=True)
class Document:
    """A knowledge file's clauses and directives, in order."""

    items: tuple[Clause | Directive, ...]
    file: str = "<string>"
    notes: tuple[str, ...] = ()
    seed: bool = False

    def to_kb(self, kb: KnowledgeBase | None = None) -> KnowledgeBase:
        """Load the document into a (new, schema-language) knowledge base."""
        kb = kb if kb is not None else knowledge_base()
        real = bool(self.file) and not self.file.startswith("<")
        base = Path(self.file).parent if real else None
        with kb.reading(self.file) if real else nullcontext():
            for item in self.items:
                if isinstance(item, Clause):
                    kb.add_clause(item.head, item.body, item.pos)
                else:
                    kb.run_directive(item, base)
        kb.warnings.extend(self.notes)
        if self.seed:
            kb.seed_files.add(self.file)
        return kb


# ---------------------------------------------------------------------------
# Reading

def read_document(path: str | Path, max_bytes: int = MAX_BYTES, operators=None) -> Document:
    """Read a knowledge file; SEED files are imported into the schema form. `operators` is
    the table the text starts with (the files read before it may have declared some)."""
    name = str(path)
    text = read_source(path, max_bytes)
    if name.endswith(YAML_SUFFIXES):
        return document_from_yaml(text, name)
    return document_from_text(text, name, operators)


def document_from_text(text: str, file: str = "<string>", operators=None) -> Document:
    """Parse Prolog text; SEED knowledge is imported."""
    items = parse_text(text, file, operators)
    if is_seed(items):
        imported = import_seed(items)
        notes = tuple(imported.warnings) + tuple(f"{file}: note: {n}" for n in imported.notes)
        return Document(tuple(imported.clauses), file, notes, seed=True)
    return Document(tuple(items), file)


def load_kb(paths: list[str] | tuple[str, ...], max_bytes: int = MAX_BYTES,
            max_steps: int | None = None) -> KnowledgeBase:
    """Read every file into one knowledge base, one program: what two files define alike is
    an error (docs/syntax.md, Several files); files they consult are held to `max_bytes`
    too, and every directive to `max_steps` resolution steps (default: the engine's)."""
    kb = knowledge_base()
    kb.max_bytes = max_bytes
    if max_steps is not None:
        kb.max_steps = max_steps
    for p in paths:
        read_document(p, max_bytes, kb.operators).to_kb(kb)
    return kb


def document_from_yaml(text: str, file: str = "<string>") -> Document:
    """Read the YAML form (safe_load only). Every key is one the format knows: any other (a
    misspelt `releasr`, a `post` indented into a sub-task) is an error at its own line and
    column, with the closest known key, never dropped (docs/formats.md, Schema text and YAML)."""
    import yaml  # loaded only when YAML is read or written

    check_yaml_nesting(text, file)
    lines = text.split("\n")
    loader = _safe_loader()(text)
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        pos = SourcePos(file, mark.line + 1, mark.column + 1) if mark else None
        line = text.splitlines()[mark.line] if mark and mark.line < len(text.splitlines()) else None
        problem = getattr(err, "problem", None) or str(err)
        raise SchemalogError(f"YAML syntax error: {problem}", pos, line) from None
    finally:
        loader.dispose()
    if not isinstance(data, dict) or not isinstance(data.get("items", []), list):
        raise SchemalogError("a schemalog YAML file is a mapping with an `items` list",
                             SourcePos(file, 1, 1))
    # Constructing flattened the merge keys (`<<: *name`) into the nodes, each key keeping
    # the place it was written: the nodes now hold exactly the keys `data` holds.
    keys = _Keys(file, lines)
    item_nodes = keys.top(root)
    items: list[Clause | Directive] = []
    for i, record in enumerate(data.get("items") or []):
        node = item_nodes[i] if i < len(item_nodes) else None
        line, column = (node.start_mark.line + 1, node.start_mark.column + 1) if node is not None else (1, 1)
        pos = SourcePos(file, line, column)
        if node is not None:
            keys.record(node, f"items[{i}]")
        try:
            # Each clause is where its record starts in the YAML file: messages that name it
            # (a sub-task defined in two files) point into the file the user wrote.
            items.extend(replace(item, pos=pos) for item in _record_items(record, f"items[{i}]", file, i))
        except SchemalogError as err:
            # The item's own place in the YAML file, and the clause it made, to see what broke.
            raise SchemalogError(err.message, pos, lines[line - 1] if line <= len(lines) else None) from None
    return Document(tuple(items), file)


@functools.cache
def _safe_loader():
    """PyYAML's SafeLoader, reading decimal integers of any length as the reader does
    (int_of_digits): its own int() stops at Python's 4,300 digits with a ValueError, where a
    weight too large is the schema reader's to refuse, at the record that holds it."""
    import yaml  # loaded only when YAML is read or written

    class Loader(yaml.SafeLoader):
        pass

    def integer(loader, node):
        text = loader.construct_scalar(node).replace("_", "")
        digits = text.lstrip("+-")
        if digits.isdigit() and digits[0] != "0":      # plain decimal; 0... is YAML 1.1's octal
            return -int_of_digits(digits) if text.startswith("-") else int_of_digits(digits)
        return yaml.SafeLoader.construct_yaml_int(loader, node)

    Loader.add_constructor("tag:yaml.org,2002:int", integer)
    return Loader


# The keys of the YAML format, for each kind of mapping (docs/formats.md lists them, with what
# a missing optional one means).
_TOP_KEYS = ("schemalog", "items")
_RECORD_KINDS = ("schema", "clause", "directive") + _SIMPLE_FACTS
_SCHEMA_KEYS = ("schema", "subtasks", "post", "if")
_SUBTASK_KEYS = ("behaviour", "releaser", "importance")
YAML_VERSION = 1


class _Keys:
    """Checks the keys of a YAML task's mappings on its composed nodes, where each key has its
    line and column: a key the format does not know, a key given twice (YAML keeps the last
    silently) and a required key missing are errors at their place."""

    def __init__(self, file: str, lines: list[str]) -> None:
        self.file, self.lines = file, lines

    def error(self, message: str, node) -> SchemalogError:
        line, column = node.start_mark.line + 1, node.start_mark.column + 1
        return SchemalogError(message, SourcePos(self.file, line, column),
                              self.lines[line - 1] if line <= len(self.lines) else None)

    def keys(self, node, where: str, known: tuple[str, ...], what: str,
             elsewhere: dict[str, str] | None = None) -> dict[str, object]:
        """The mapping's keys (name -> key node), each one of `known`."""
        import yaml  # loaded only when YAML is read or written

        seen: dict[str, object] = {}
        where = f"{where}: " if where else ""
        for key, _ in node.value:
            if not isinstance(key, yaml.ScalarNode):
                raise self.error(f"{where}a key must be a name ({what})", key)
            name = key.value
            # a key merged in (`<<: *name`) was written before this mapping; one of its own
            # overrides it, as YAML says
            own = key.start_mark.index >= node.start_mark.index
            if name in seen and own and seen[name].start_mark.index >= node.start_mark.index:
                first = seen[name].start_mark.line + 1
                raise self.error(f"{where}`{name}` is given twice (first at line {first}); "
                                 f"YAML would keep only this one", key)
            if name not in known:
                raise self.error(f"{where}unknown key `{name}`{self.advice(name, known, elsewhere)} "
                                 f"({what})", key)
            seen[name] = key
        return seen

    @staticmethod
    def advice(name: str, known: tuple[str, ...], elsewhere: dict[str, str] | None) -> str:
        import difflib

        if elsewhere and name in elsewhere:
            return f"; {elsewhere[name]}"
        near = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
        return f"; did you mean `{near[0]}`?" if near else ""

    def top(self, root) -> list:
        """Check the file's own keys; the nodes of its `items`."""
        import yaml  # loaded only when YAML is read or written

        self.keys(root, "", _TOP_KEYS, "a schemalog YAML file's keys: schemalog, items")
        values = dict((key.value, value) for key, value in root.value)
        version = values.get("schemalog")
        if version is not None and not (isinstance(version, yaml.ScalarNode)
                                        and version.value == str(YAML_VERSION)):
            raise self.error(f"`schemalog` is the format's version, {YAML_VERSION}; this one cannot "
                             f"be read", version)
        items = values.get("items")
        return list(items.value) if isinstance(items, yaml.SequenceNode) else []

    def record(self, node, where: str) -> None:
        """Check one record of `items`: its kind, its keys, its sub-tasks' keys."""
        import yaml  # loaded only when YAML is read or written

        if not isinstance(node, yaml.MappingNode):
            return                                      # _record_items names what it is instead
        names = [key.value for key, _ in node.value if isinstance(key, yaml.ScalarNode)]
        kinds = [name for name in names if name in _RECORD_KINDS]
        if not kinds:                                   # an unknown key, else _record_items:
            self.keys(node, where, _RECORD_KINDS + _SCHEMA_KEYS[1:],   # which kind it needs
                      f"a record's keys: {', '.join(_RECORD_KINDS)}; beside schema: subtasks, post, if")
            return
        kind = "schema" if "schema" in kinds else kinds[0]     # `behaviour` beside it is a sub-task's key
        if kind != "schema":
            for key, _ in node.value:
                if isinstance(key, yaml.ScalarNode) and key.value != kind and key.value in _RECORD_KINDS:
                    raise self.error(f"{where}: `{key.value}` beside `{kind}`: a record makes one "
                                     f"clause; give `{key.value}` a record of its own (`- {key.value}: ...`)",
                                     key)
            self.keys(node, where, (kind,), f"a {kind} record has the one key {kind}")
            return
        seen = self.keys(node, where, _SCHEMA_KEYS, f"a schema record's keys: {', '.join(_SCHEMA_KEYS)}", {
            **{k: f"a record makes one clause; give `{k}` a record of its own (`- {k}: ...`)"
               for k in _RECORD_KINDS if k != "schema"},
            **{k: f"`{k}` is a sub-task's key: write it in an entry of `subtasks`" for k in _SUBTASK_KEYS}})
        values = dict((key.value, value) for key, value in node.value)
        subtasks = values.get("subtasks")
        for j, entry in enumerate(subtasks.value if isinstance(subtasks, yaml.SequenceNode) else ()):
            w = f"{where}.subtasks[{j}]"
            if not isinstance(entry, yaml.MappingNode):
                continue                                # _record_items: expected a mapping
            mine = self.keys(entry, w, _SUBTASK_KEYS, f"a sub-task's keys: {', '.join(_SUBTASK_KEYS)}", {
                k: f"`{k}` is the schema's key: indent it as `subtasks:` is, not into a sub-task"
                for k in _SCHEMA_KEYS})
            if "behaviour" not in mine:
                raise self.error(f"{w}: missing `behaviour` (the sub-task)", entry)
        if "post" not in seen:                          # after the sub-tasks: one may hold it
            raise self.error(f"{where}: missing `post` (a schema's post-condition)", node)


def _record_items(record: object, where: str, file: str, index: int) -> list[Clause | Directive]:
    if not isinstance(record, dict):
        raise SchemalogError(f"{where}: expected a mapping, not {type(record).__name__}")
    text = _record_text(record, where)
    try:
        parsed = parse_text(text, f"{file}#items[{index}]")
    except SchemalogError as err:
        raise SchemalogError(f"{where}: {err.message.splitlines()[0]} (in the clause it makes: {text})") from None
    return list(parsed)


def _field(record: dict, key: str, where: str) -> str:
    value = record.get(key)
    if value is None:
        raise SchemalogError(f"{where}: missing `{key}`")
    if isinstance(value, bool):
        return "true" if value else "false"
    if not isinstance(value, (str, int, float)):
        raise SchemalogError(f"{where}: `{key}` must be text, not {type(value).__name__}")
    return str(value)


def _record_text(record: dict, where: str) -> str:
    if "schema" in record:
        unknown = set(record) - {"schema", "subtasks", "post", "if"}
        if unknown:
            raise SchemalogError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        subs = record.get("subtasks") or []
        if not isinstance(subs, list):
            raise SchemalogError(f"{where}: `subtasks` must be a list")
        entries = []
        for j, sub in enumerate(subs):
            w = f"{where}.subtasks[{j}]"
            if not isinstance(sub, dict):
                raise SchemalogError(f"{w}: expected a mapping with behaviour and releaser")
            behaviour = _field(sub, "behaviour", w)
            releaser = _field(sub, "releaser", w) if "releaser" in sub else "true"
            importance = sub.get("importance", DEFAULT_IMPORTANCE)
            if isinstance(importance, bool) or not isinstance(importance, (int, float)):
                raise SchemalogError(f"{w}: `importance` must be a number")
            written = int_text(importance) if isinstance(importance, int) else repr(importance)
            weight = "" if importance == DEFAULT_IMPORTANCE and isinstance(importance, int) else f", {written}"
            entries.append(f"({behaviour}, ({releaser}){weight})")
        head = f"schema(({_field(record, 'schema', where)}), [{', '.join(entries)}], ({_field(record, 'post', where)}))"
        return f"{head} :- {record['if']}." if record.get("if") is not None else f"{head}."
    for key in _SIMPLE_FACTS:
        if key in record:
            return f"{key}(({_field(record, key, where)}))."
    if "clause" in record:
        text = _field(record, "clause", where).strip()
        return text if text.endswith(".") else text + "."
    if "directive" in record:
        return f":- {_field(record, 'directive', where)}."
    raise SchemalogError(f"{where}: a record needs one of schema, clause, directive, "
                         f"{', '.join(_SIMPLE_FACTS)}")


# ---------------------------------------------------------------------------
# Writing

def _canonical_head(c: Clause) -> Term:
    s = static_schema(c.head, c.body, c.pos)
    return schema_term(s) if s is not None else c.head


def to_pl(doc: Document, header: str | None = None) -> str:
    """Canonical schema text: one clause per paragraph group, schemas laid out."""
    out: list[str] = []
    if header:
        out.extend(f"% {line}".rstrip() for line in header.splitlines())
        out.append("")
    previous = None
    for item in doc.items:
        if isinstance(item, Directive):
            out.append(f":- {term_to_text(item.goal, 1199, variable_names([item.goal]))}.")
            previous = None
            continue
        head = _canonical_head(item)
        key = (head.name, len(head.args)) if isinstance(head, Struct) else term_to_text(head)
        multi_line = isinstance(head, Struct) and head.name == "schema" and "\n" in write_clause(head, item.body)
        if previous is not None and (key != previous or multi_line):
            out.append("")
        out.append(write_clause(head, item.body))
        previous = key
    return "\n".join(out) + "\n"


def to_yaml(doc: Document) -> str:
    """The YAML form of a document."""
    import yaml  # loaded only when YAML is read or written

    records = []
    for item in doc.items:
        if isinstance(item, Directive):
            records.append({"directive": term_to_text(item.goal, 1199, variable_names([item.goal]))})
            continue
        s = static_schema(item.head, item.body, item.pos)
        head = schema_term(s) if s is not None else item.head
        names = variable_names([head, item.body])

        def text(t: Term, p: int = 999) -> str:
            return term_to_text(t, p, names, spaced=True)

        if s is not None:
            record: dict = {"schema": text(s.task),
                            "subtasks": [_entry_record(e, text) for e in s.entries],
                            "post": text(head.args[2])}
            if item.body is not TRUE:
                record["if"] = text(item.body, 1199)
            records.append(record)
        elif isinstance(head, Struct) and head.name in _SIMPLE_FACTS and len(head.args) == 1 \
                and item.body is TRUE:
            records.append({head.name: text(head.args[0])})
        else:
            flat = head if item.body is TRUE else Struct(":-", (head, item.body))
            records.append({"clause": term_to_text(flat, 1200, names) + "."})
    return yaml.safe_dump({"schemalog": 1, "items": records}, sort_keys=False, allow_unicode=True, width=100)


def _entry_record(e: Entry, text) -> dict:
    record = {"behaviour": text(e.behaviour), "releaser": text(cond.to_term(e.releaser))}
    if not (e.importance == DEFAULT_IMPORTANCE and isinstance(e.importance, int)):
        record["importance"] = e.importance
    return record


def file_mode(target: Path) -> int:
    """The mode a written file should get: the replaced file's, else what umask allows
    (mkstemp's temporary files are private, 0600, and a rename would keep that)."""
    try:
        return target.stat().st_mode & 0o7777
    except OSError:
        return new_file_mode()


def new_file_mode() -> int:
    """The mode a new file gets: what umask allows of 0666."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@dataclass(frozen=True)
class Target:
    """Where an output goes: `path` is written through a temporary file and a rename, or,
    when `in_place` (a FIFO, a device, /dev/stdout), opened and written into as `> path` does."""

    path: Path
    in_place: bool = False


def output_target(path: str | Path) -> Target:
    """Where writing `path` goes, or an error if it could not be written: a directory, a name
    ending in `/`, a missing or unwritable directory. A symbolic link is followed, never
    replaced: the file it points to is written (a new one if it dangles)."""
    name = str(path)
    if name.endswith(("/", os.sep)) or Path(name).name in ("", ".", ".."):
        raise SchemalogError(f"{name} names a directory; name a file")
    try:
        info = os.stat(name)                         # through links
    except FileNotFoundError:
        info = None
    except OSError as err:
        raise CannotWrite(name, err.strerror or str(err)) from None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise SchemalogError(f"{name} is a directory; name a file")
    if info is not None and not stat.S_ISREG(info.st_mode):
        if stat.S_ISSOCK(info.st_mode):
            raise SchemalogError(f"{name} is a socket; name a file")
        if not os.access(name, os.W_OK):
            raise CannotWrite(name, "it is not writable")
        return Target(Path(name), in_place=True)     # the name itself: /dev/stdout -> /proc/self/fd/1
    target = Path(os.path.realpath(name))            # a link is written through, not replaced
    directory = target.parent
    if not directory.is_dir():
        shown = directory if os.path.islink(name) else (Path(name).parent if str(Path(name).parent) else ".")
        raise SchemalogError(f"{name}: no such directory {shown}")
    if not os.access(directory, os.W_OK):
        raise CannotWrite(name, f"the directory {directory} is not writable")
    return Target(target)


def check_writable(path: str | Path) -> Path:
    """The directory `path` would be written in (see output_target); an error if it could not be."""
    target = output_target(path)
    return target.path.parent


def write_in_place(path: str | Path, data: bytes) -> None:
    """Write into an existing special file (FIFO, device) as `> path` does: it stays what it is."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_NOCTTY)   # no O_CREAT: never make a regular file
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
    except OSError as err:
        raise CannotWrite(path, err.strerror or str(err)) from None


def _write_text(handle, text: str) -> None:
    handle.write(text)


def write_atomically(path: str | Path, text: str | bytes) -> None:
    """Write `text` (or bytes: a picture) to `path` through a temporary file and a rename:
    never a partial file. A special file (FIFO, device) is written into instead (output_target)."""
    target = output_target(path)
    if target.in_place:
        write_in_place(target.path, text if isinstance(text, bytes) else text.encode("utf-8", READABLE))
        return

    def write(handle: BinaryIO) -> None:
        if isinstance(text, bytes):
            handle.write(text)
            return
        wrapped = io.TextIOWrapper(handle, encoding="utf-8", errors=READABLE)
        _write_text(wrapped, text)
        wrapped.flush()
        wrapped.detach()                # the handle is closed by _staged, not by the wrapper

    _staged(str(path), target.path, write, file_mode(target.path))


def write_in_folder(target: Path, content: str | bytes | Callable[[BinaryIO], None]) -> Path:
    """Write one file of an output folder (sweep's and bench's --out) through a temporary file
    in the folder and a rename onto `target`: never partial, and a link found there is replaced,
    never written through (the folder is the user's to name; what is in it is the run's, so a
    `sweep.md` linked to a file elsewhere cannot make the run write outside the folder).
    `content` is text, bytes, or a function that writes into the open binary file."""
    if callable(content):
        write = content                # pyarrow and matplotlib take the handle: a name need not be UTF-8
    else:
        data = content.encode("utf-8", READABLE) if isinstance(content, str) else content
        write = lambda handle: handle.write(data)       # noqa: E731
    try:
        info = os.lstat(target)
        mode = stat.S_IMODE(info.st_mode) if stat.S_ISREG(info.st_mode) else new_file_mode()
    except OSError:
        mode = new_file_mode()
    _staged(str(target), target, write, mode)
    return target


def _staged(shown: str, target: Path, write: Callable[[BinaryIO], None], mode: int) -> None:
    """Write through a temporary file beside `target`, then rename it onto `target` (a link there
    is replaced): never a partial file; what the system refuses is CannotWrite naming `shown`."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as err:
        raise CannotWrite(shown, err.strerror or str(err)) from None
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException as err:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(err, OSError):
            raise CannotWrite(shown, err.strerror or str(err)) from None
        raise


def write_together(files: list[tuple[str, bytes]]) -> None:
    """Write several files as one output: each made under a temporary name beside it, then all
    renamed, so a failure leaves none of them written or half written (a FIFO or a device
    among them is written into first, before any file is replaced)."""
    targets = [(name, data, output_target(name)) for name, data in files]
    staged: list[tuple[str, Path]] = []
    try:
        for name, data, target in targets:
            if target.in_place:
                write_in_place(target.path, data)
                continue
            try:
                fd, tmp = tempfile.mkstemp(prefix=f".{target.path.name}.", suffix=".tmp", dir=target.path.parent)
            except OSError as err:
                raise CannotWrite(name, err.strerror or str(err)) from None
            staged.append((tmp, target.path))
            try:
                with os.fdopen(fd, "wb") as handle:
                    handle.write(data)
                os.chmod(tmp, file_mode(target.path))
            except OSError as err:
                raise CannotWrite(name, err.strerror or str(err)) from None
        for tmp, path in staged:
            try:
                os.replace(tmp, path)
            except OSError as err:
                raise CannotWrite(str(path), err.strerror or str(err)) from None
    finally:
        for tmp, _ in staged:
            if os.path.exists(tmp):
                os.unlink(tmp)
