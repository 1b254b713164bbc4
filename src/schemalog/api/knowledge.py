"""Knowledge files loaded as one program, and what a user asks of them: tasks, queries, lint.

    Knowledge = (KnowledgeBase, files read, warnings)     load(*paths) | loads(text)
    Value     = int | float | str | list[Value] | Term     one query variable's binding

Nothing here prints or exits: what the loader would say goes to `warnings`, what is wrong
is raised as a SchemalogError carrying file, line and column.
"""

from __future__ import annotations

import os
import time
from contextlib import AbstractContextManager, nullcontext
from typing import TYPE_CHECKING, Callable, Iterator, Union

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.exceptions import PrologError
from .limits import DEFAULT, LimitExceeded, within
from ..logic.kb import KnowledgeBase
from ..logic.opread import parse_term
from ..logic.terms import Atom, Float, Int, Str, Struct, Term, term_to_text
from .choosing import choose_task, choose_tasks, defines, root_candidates, task_term  # noqa: F401 (the API layer's)
from .arguments import Count, Name, Path, Seconds, Size, checked

if TYPE_CHECKING:
    from ..run.lint import Finding
    from .check import Checked
    from .task import Task

Value = Union[int, float, str, list, Term]


class Knowledge:
    """Knowledge files read into one knowledge base: schemas, tasks, initial states, rules."""

    def __init__(self, kb: KnowledgeBase, files: tuple[str, ...], sources: tuple[tuple[str, str | None], ...],
                 max_bytes: int, max_steps: int) -> None:
        self._kb = kb
        self._sources = sources       # (name, text) to read again for a query; text None: a file
        self._max_bytes = max_bytes
        self._max_steps = max_steps
        self._workspaces: dict = {}   # propagate -> the query workspace (api/workspace.py)
        self.files: tuple[str, ...] = files
        self.warnings: tuple[str, ...] = tuple(kb.warnings)

    def __repr__(self) -> str:
        return f"<Knowledge {', '.join(self.files) or '(no file)'}: {len(self.tasks())} tasks>"

    def tasks(self) -> list[str]:
        """The tasks task/1 declares, as text; else the schemas no other schema uses."""
        from ..task.tree import declared_tasks

        return [term_to_text(t) for t in declared_tasks(self._kb)] or root_candidates(self._kb)

    def declared(self) -> list[str]:
        """The distinct tasks task/1 declares, as text, in order (lint's tasks)."""
        from ..run.lint import task_declarations

        return [term_to_text(t) for t, _ in task_declarations(self._kb)]

    @checked
    def task(self, name: str | None = None, *, max_depth: Count = defaults.MAX_DEPTH,
             max_nodes: Count = defaults.MAX_NODES, timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Task:
        """The task's tree, instantiated from its schemas (name None: the first task/1)."""
        from .task import Task

        with within(timeout, max_memory):
            return Task.instantiated(self, choose_task(self._kb, name), max_depth, max_nodes)

    @checked
    def query(self, goal: str, *, first: bool = False, max_steps: Count | None = None, propagate: str = "full",
              output: Callable[[str], None] | None = None, timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Iterator[dict[str, Value]]:
        """Each answer of a Prolog query over the knowledge and its tasks' relations
        (docs/queries.md: merged/3, sequential/2, ...), as a dict of Python values; what the
        query writes (write/1, format/2) goes to `output` (default: standard output).

        Queries share one workspace per propagation mode, as goals share one Prolog session:
        what one asserts, the next sees (Knowledge.task() reads the files' knowledge alone).
        `timeout` bounds the time spent computing answers (not the time between them)."""
        from .answers import answers, read_query

        if propagate not in defaults.PROPAGATE_MODES:
            raise UsageError(f"propagate {propagate!r}: choose {', '.join(defaults.PROPAGATE_MODES)}")
        workspace = self._workspaces.get(propagate)
        if workspace is None:
            from .workspace import Options, Workspace

            options = Options(propagate=propagate, max_bytes=self._max_bytes, max_steps=self._max_steps)
            workspace = self._workspaces[propagate] = Workspace([n for n, _ in self._sources], options,
                                                                self._reread)
        query = read_query(goal, operators=workspace.kb.operators)
        solutions = answers(workspace, query, output, max_steps or self._max_steps)
        spent = 0.0
        while True:
            started = time.monotonic()
            left = None if timeout is None else max(timeout - spent, defaults.MIN_TIMEOUT)
            try:
                with within(left, max_memory):
                    try:
                        answer, _ = next(solutions)
                    except PrologError as err:      # said while the ceiling it names is in force
                        raise query_error(err, max_memory) from None
                    found = {name: python_value(value) for name, value in answer.values}
            except StopIteration:
                return
            except LimitExceeded as err:
                if err.limit == "time":
                    raise LimitExceeded(f"time limit of {timeout:g} s exceeded (raise it with timeout=)",
                                        "time") from None
                raise
            except RecursionError:
                raise SchemalogError("a term nests too deeply for schemalog to process (Python's "
                                     "recursion limit)") from None
            spent += time.monotonic() - started
            yield found
            if first:
                return

    @checked
    def lint(self, task: str | None = None, *, max_depth: Count = defaults.MAX_DEPTH,
             max_nodes: Count = defaults.MAX_NODES, timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> list[Finding]:
        """Every finding of `schemalog lint` about these files (task None: every task/1)."""
        from ..run.lint import lint_kb

        tasks = None if task is None else [(task_term(task), None)]
        with within(timeout, max_memory):
            return list(lint_kb(self._kb, max_depth, max_nodes, tasks))

    @checked
    def check(self, task: str | None = None, *, lint: bool = True, max_depth: Count = defaults.MAX_DEPTH,
              max_nodes: Count = defaults.MAX_NODES, timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Checked:
        """What `schemalog check` does: every schema read, the tasks instantiated (task None:
        every task/1), then linted; .schemas, .tasks, .findings, .errors."""
        from .check import check

        with within(timeout, max_memory):
            return check(self, task, lint, max_depth, max_nodes)

    def _reread(self) -> KnowledgeBase:
        """A fresh knowledge base of the same sources (a query's workspace adds facts to its own)."""
        return _read(self._sources, self._max_bytes, self._max_steps, nullcontext)[0]


class QueryError(SchemalogError):
    """A Prolog exception no goal of the query caught: `.term` is its ball, such as
    error(type_error(integer, a), _), the message what `schemalog query` prints."""

    def __init__(self, message: str, term: Term) -> None:
        super().__init__(message)
        self.term = term


def query_error(err: PrologError, max_memory) -> SchemalogError:
    """An uncaught Prolog exception as the API raises it: out of memory under a ceiling is
    LimitExceeded, anything else a QueryError."""
    from .failures import error_text
    from .limits import ceiling_in_force, out_of_memory_text

    ball = err.ball
    if (isinstance(ball, Struct) and ball.name == "error" and len(ball.args) == 2
            and ball.args[0] == Struct("resource_error", (Atom("memory"),))):
        text = out_of_memory_text(ceiling_in_force()).removeprefix("error: ")
        return LimitExceeded(text.replace("--max-memory", "max_memory="), "memory")
    return QueryError(error_text(err, "max_steps=").removeprefix("error: "), ball)


@checked
def load(*paths: Path, max_bytes: Count = defaults.MAX_BYTES, max_steps: Count = defaults.MAX_STEPS,
         timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Knowledge:
    """Read knowledge files as one program: schema text (.pl), SEED (.prolog), YAML, BT.CPP XML."""
    with within(timeout, max_memory):
        return _load(paths, max_bytes, max_steps)


@checked
def loads(text: str, name: Name = "<text>", *, max_steps: Count = defaults.MAX_STEPS,
          timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Knowledge:
    """Read knowledge from a string of schema text (or SEED knowledge)."""
    with within(timeout, max_memory):
        kb, files = _read(((name, text),), defaults.MAX_BYTES, max_steps, nullcontext)
    return Knowledge(kb, files, ((name, text),), defaults.MAX_BYTES, max_steps)


def _load(paths, max_bytes: int, max_steps: int,
          reading: Callable[[], AbstractContextManager] = nullcontext) -> Knowledge:
    """load(), with `reading` around each file's parse (the command line's: no collector)."""
    if not paths:
        raise UsageError("load needs at least one knowledge file")
    sources = tuple((os.fspath(p), None) for p in paths)
    kb, files = _read(sources, max_bytes, max_steps, reading)
    return Knowledge(kb, files, sources, max_bytes, max_steps)


def _read(sources, max_bytes: int, max_steps: int, reading) -> tuple[KnowledgeBase, tuple[str, ...]]:
    from ..formats.documents import document_from_text, read_document
    from ..inputs import is_xml
    from ..task.schema import knowledge_base

    kb = knowledge_base()
    kb.max_bytes = max_bytes
    kb.max_steps = max_steps       # each directive's budget
    for name, text in sources:
        with reading():
            if text is not None:
                doc = document_from_text(text, name)
            elif is_xml(name):          # a BT.CPP tree, told by its content (inputs.is_xml)
                doc = xml_document(name, max_bytes)[0]
            else:
                doc = read_document(name, max_bytes)
        doc.to_kb(kb)               # directives run here
    return kb, tuple(dict.fromkeys([*(n for n, t in sources if t is None), *kb.files]))


def node_clauses(imported, tree) -> list:
    """`bt_node(Label, 'NodeType', [port = 'value', ...])` for each action of `tree` (the
    imported tree, its labels made distinct) that the document wrote otherwise than an export
    would by default: what gives the robot its own nodes back when the knowledge is exported."""
    from ..formats.btcpp import default_node
    from ..logic.parse import Clause
    from ..logic.terms import TRUE, make_list
    from ..task.tree import walk

    out, seen = [], set()
    for before, after in zip(walk(imported.tree), walk(tree)):
        if before.children:
            continue
        pairs = [(o.label, o.label, o.post) for o in before.origins] if len(before.origins) > 1 else \
            [(after.label, before.origins[0].label if len(before.origins) == 1 else before.label, before.post)]
        for label, key, post in pairs:
            written = imported.nodes.get((key, post))
            if written is None or label in seen or written == default_node(label):
                continue
            seen.add(label)
            ident, ports = written
            out.append(Clause(Struct("bt_node", (label, Atom(ident), make_list(
                [Struct("=", (Atom(k), Atom(v))) for k, v in ports]))), TRUE, None))
    return out


def xml_document(path: str, max_bytes: int = defaults.MAX_BYTES):
    """A BehaviorTree.CPP v4 document (and the files it includes) as schema knowledge:
    (Document, Imported)."""
    from ..formats.btcpp import import_btcpp
    from ..formats.render import distinct_labels, tree_document
    from ..inputs import read_utf8
    from ..logic.parse import Clause
    from ..logic.terms import TRUE
    from ..task.schema import check_schemas

    def decoded(name: str) -> str:
        return read_utf8(name, max_bytes)

    imported = import_btcpp(decoded(path), path, decoded)
    initial = [Clause(Struct("initial", (atom,)), TRUE, None) for atom in imported.initial]
    tree = distinct_labels(imported.tree)
    doc = tree_document(tree, path, initial + node_clauses(imported, tree))
    check_schemas(doc.to_kb())     # what is written must load again
    return doc, imported


# ---------------------------------------------------------------------------
# Query answers as Python values

def python_value(term: Term) -> Value:
    """A binding as Python: integers and floats as numbers, atoms and strings as str, proper
    lists as lists, anything else (a compound, an unbound variable) as the term itself,
    whose str() is its Prolog text.

    >>> python_value(parse_term("[1, a, 2.5]"))
    [1, 'a', 2.5]
    """
    if isinstance(term, Int):
        return term.value
    if isinstance(term, Float):
        return term.value
    if isinstance(term, Atom):
        return [] if term.name == "[]" else term.name
    if isinstance(term, Str):
        return term.value
    items = []
    rest = term
    while isinstance(rest, Struct) and rest.name == "[|]" and len(rest.args) == 2:
        items.append(rest.args[0])
        rest = rest.args[1]
    if items and rest == Atom("[]"):
        return [python_value(t) for t in items]
    return term


def task_as_read(knowledge: Knowledge, name: str | None, max_depth: int = defaults.MAX_DEPTH,
                 max_nodes: int = defaults.MAX_NODES):
    """The task's tree exactly as its knowledge gives it, provenance not followed (show,
    decompress: a merged behaviour of a compressed file is shown, not refused)."""
    from .task import Task

    return Task.instantiated(knowledge, choose_task(knowledge._kb, name), max_depth, max_nodes, provenance=False)
