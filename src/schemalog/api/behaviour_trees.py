"""Behaviour trees as BT.CPP 4 runs them, compressed and proved: what `schemalog compress
F.xml` and `schemalog verify F.xml SMALL.xml` do with a tree that is not schemalog's own export
(docs/behaviour_trees.md).

    read_tree(paths, nodes=(), max_bytes, main, version=None) -> Document   one program: a file or
                                                              several, each a file or a folder of *.xml
                                                              files, their <include>s, --nodes' models;
                                                              under BT.CPP 3.8 or 4 (version)
    read_semantics(paths, profiles=())     -> rules           --semantics, --profile: custom node types as known ones
    compress_tree(document, max_states)    -> TreeCompression the rewrites (bt/compress.py), proved;
                                                              named nodes kept unless drop_names
    prove_trees(a, b, max_states)          -> Verdict         bt/prove.py's product exploration
    is_own_export(path)                    -> bool            schemalog's own exports (schemalog_run)
                                                              are task knowledge: the schema route

A compression is never trusted on its rewrites' word: the compressed tree is proved against the
original, and a verdict that a limit cut short says so (`complete` False).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .. import defaults
from ..errors import SchemalogError, SourcePos, shown_name

EVENTS_PER_TICK = 10_000     # events in one root tick before the prover stops (no proof): a loop


@dataclass(frozen=True)
class TreeCompression:
    """A tree compressed: the original and compressed documents, the rewrites made, the
    prover's verdict on the two, and the named nodes a rewrite would have removed, kept (each a
    bt/compress.py Rewrite naming the rule; empty with drop_names)."""

    original: object
    compressed: object
    rewrites: tuple
    verdict: object
    kept: tuple = ()

    @property
    def nodes_before(self) -> int:
        from ..bt.model import size
        return size(self.original)

    @property
    def nodes_after(self) -> int:
        from ..bt.model import size
        return size(self.compressed)


def _decoded(name: str, max_bytes: int) -> str:
    from ..inputs import read_utf8

    return read_utf8(name, max_bytes)


def read_models(paths, max_bytes: int = defaults.MAX_BYTES) -> tuple:
    """The TreeNodesModel entries of nodes files (Nav2's nav2_tree_nodes.xml), in order."""
    from ..formats.btxml import read_models as parse_models

    models: list = []
    seen: dict = {}                     # an ID's kind and element, across the files
    for path in paths:
        found = parse_models(_decoded(str(path), max_bytes), str(path), seen)
        if not found:
            raise SchemalogError("declares no node: a nodes file holds a <TreeNodesModel> with an <Action ID=..>, "
                                 "<Condition ID=..>, ... per custom node type", SourcePos(str(path), 1, 1))
        models.extend(found)
    return tuple(models)


def tree_files(paths) -> tuple[tuple[str, ...], tuple[str, ...], int | None]:
    """The files one program is read from, a path or several, each a BT.CPP file or a folder:
    (the files in reading order, those of them found in folders, the index of the main file).
    A folder gives its *.xml files, sorted by name, not its subfolders' (inputs.folder_files:
    Nav2's bt_search_directories and BehaviorTree.ROS2's behavior_trees folders are read so,
    with std::filesystem::directory_iterator); the main file is the first file named, None when
    only folders are (the main tree is then the one their files agree on: formats/btxml.read_bt)."""
    import os

    from ..inputs import folder_files

    given = [paths] if isinstance(paths, (str, os.PathLike)) else list(paths)
    if not given:
        raise SchemalogError("no BT.CPP tree file or folder given")
    files: list[str] = []
    members: list[str] = []
    main_from = None
    for path in map(os.fspath, given):
        if os.path.isdir(path):
            found = folder_files(path)
            if not found:
                raise SchemalogError(f"{shown_name(path)}: no *.xml file in this folder (schemalog reads the *.xml "
                                     f"files of a folder, not of its subfolders, as one BT.CPP program)")
            files.extend(found)
            members.extend(found)
        else:
            main_from = len(files) if main_from is None else main_from
            files.append(path)
    return tuple(files), tuple(members), main_from


def read_tree(paths, nodes=(), max_bytes: int = defaults.MAX_BYTES, main: str | None = None, *,
              version: int | None = None, notes: list | None = None):
    """One BT.CPP 4 program: the document in a file, or the documents of several files and
    folders read as one (tree_files; as BT.CPP's registerBehaviorTreeFromFile reads file after
    file into one factory), the files they include, the models of `nodes` files; `main` the
    tree to run (BT.CPP's createTree(main)), else the main file's main_tree_to_execute, else,
    for folders alone, the one their files agree on. The Document's `includes` lists every file
    read besides the ones named: a folder's, then those reached through <include>. `version` 3
    (BT.CPP 3.8) or 4 reads every file under that version whatever its BTCPP_format says (a
    contrary mark is a note appended to `notes`); by default the files tell (formats/btxml.read_bt)."""
    from dataclasses import replace

    from ..formats.btxml import read_bt

    files, members, main_from = tree_files(paths)
    documents = [(_decoded(name, max_bytes), name) for name in files]
    document = read_bt(documents, read=lambda p: _decoded(p, max_bytes), models=read_models(nodes, max_bytes),
                       main=main, main_from=main_from, version=version, notes=notes)
    return replace(document, includes=tuple(dict.fromkeys((*members, *document.includes))))


def version_words(version: int) -> str:
    """A BT.CPP version as verdicts name it: "BT.CPP 3.8" or "BT.CPP 4"."""
    return "BT.CPP 3.8" if version == 3 else "BT.CPP 4"


def readings_differ(document, rules=None) -> bool:
    """Whether BT.CPP 3.8 and 4 may run an unmarked `document` apart: a node whose rule differs
    between the two tables (bt/semantics.py's RULES and RULES_V3), an opaque node with children (SKIPPED under 4
    only) or a SubTree call that binds other entries (3.8 reads `goal="target"` as a key)."""
    from ..bt.model import walk
    from ..bt.semantics import ACTION, CONDITION, OPAQUE, _rule_key, call_identity, subtree_id, table_for

    d3, d4 = document.under(3), document.under(4)
    extra = {"<opaque>": OPAQUE, "<action>": ACTION, "<condition>": CONDITION}
    t3, t4 = {**table_for(d3, rules), **extra}, {**table_for(d4, rules), **extra}
    for _, root in document.trees:
        for n in walk(root):
            if subtree_id(n) is not None:
                if call_identity(n, d3) != call_identity(n, d4):
                    return True
                continue
            k3, k4 = _rule_key(n, d3, t3), _rule_key(n, d4, t4)
            if k3 != k4 or t3[k3] is not t4[k4] or (k4 == "<opaque>" and n.children):
                return True
    return False


def _readings(a, b, rules) -> list[tuple]:
    """The pairs of readings a verdict on `a` and `b` covers. One program reads both files, so an
    unmarked one (no BTCPP_format, no tell, no --btcpp) is read under the other's version when the
    other tells it; when both are unmarked, under BT.CPP 4 and under 3.8 alike, where the two may
    run them apart (readings_differ)."""
    marked = {d.version for d in (a, b) if not d.unmarked}
    if not a.unmarked and not b.unmarked:
        return [(a, b)]
    if marked:
        (v,) = marked
        return [(a.under(v) if a.unmarked else a, b.under(v) if b.unmarked else b)]
    if not any(readings_differ(d, rules) for d in (a, b)):
        return [(a, b)]
    return [(a.under(v), b.under(v)) for v in (4, 3)]


def _under(a, b) -> str:
    """The versions a verdict on `a` and `b` was proved under, in words ("" for BT.CPP 4 alone)."""
    if a.version == b.version:
        return "" if a.version == 4 else version_words(a.version)
    return f"{version_words(a.version)} (a) against {version_words(b.version)} (b)"


def _combined(verdicts: list, pairs: list) -> object:
    """One verdict of the proofs under each reading: proved when each is, else the first refutation
    or the first that is no proof, saying under which reading."""
    from dataclasses import replace

    named = [replace(v, under=_under(a, b) or version_words(4)) for v, (a, b) in zip(verdicts, pairs)]
    unmarked = "the file has no BTCPP_format and nothing only one version reads, so BT.CPP 3.8 loads it as 4 does"
    for v in named:
        if not v.equal:
            return replace(v, reason=f"{v.reason} (under {v.under}: {unmarked}; --btcpp 4 proves it under 4 alone)")
    for v in named:
        if not v.complete:
            return replace(v, reason=f"under {v.under}: {v.reason}")
    states = sum(v.states for v in named)
    reason = "; ".join(f"under {v.under}: {v.reason}" for v in named)
    return replace(named[0], states=states, reason=reason, under=" and ".join(v.under for v in named),
                   assumed=f"{named[0].assumed}; {unmarked}, so it was proved under both" if named[0].assumed
                   else f"{unmarked}, so it was proved under both")


def is_own_export(path: str | Path, max_bytes: int = defaults.MAX_BYTES) -> bool:
    """Whether `path` is a tree schemalog exported (its main tree is schemalog_run)."""
    from ..formats.btcpp import MAIN_TREE

    try:
        text = _decoded(str(path), max_bytes)
    except SchemalogError:
        return False          # the BT route reads it again and says what is wrong
    return f'main_tree_to_execute="{MAIN_TREE}"' in text


def _name_pairs(path: str | Path, max_bytes: int, what: str, entry: str):
    """The (key, value, fail) of each `key: value` line of a YAML mapping of names, `what` the
    file's kind and `entry` a line's shape for the messages; a key given twice is refused."""
    from ..inputs import compose_yaml

    name = str(path)
    root, fail = compose_yaml(_decoded(name, max_bytes), name)
    if root is None:
        raise SchemalogError(f"an empty {what} file: write `{entry}` per line", SourcePos(name, 1, 1))
    if root.tag != "tag:yaml.org,2002:map":
        raise fail(f"a {what} file is a mapping, `{entry}` per line", root)
    seen: set[str] = set()
    for key, value in root.value:
        if key.tag != "tag:yaml.org,2002:str" or value.tag != "tag:yaml.org,2002:str":
            raise fail(f"each entry is `{entry}`", key)
        if key.value in seen:
            raise fail(f"{key.value} is given twice", key)
        seen.add(key.value)
        yield key, value, fail


PROFILES = ("nav2",)
"""The node-semantics profiles schemalog ships (bt/profiles/NAME.yaml): `nav2`, Nav2's own node types
read from Nav2's source (the file names the commit)."""


def profile_path(name: str) -> Path:
    """The file of a shipped profile; an unknown name is refused with the known ones."""
    if name not in PROFILES:
        raise SchemalogError(f"unknown profile {name!r}; the profiles schemalog ships: {', '.join(PROFILES)}")
    return Path(__file__).resolve().parents[1] / "bt" / "profiles" / f"{name}.yaml"


def read_semantics(paths=(), max_bytes: int = defaults.MAX_BYTES, profiles=(), notes: list | None = None) -> dict:
    """A user's node semantics, from one file or several read as one: a YAML mapping from a custom
    node type to the type whose rule it follows, a node of the table (`RecoveryNode`, `Sequence`)
    or a leaf kind (`SyncAction`: never RUNNING; `ReTickedAction`: run at every tick, RUNNING
    too; `StatefulAction`; `Action`: a StatefulAction or a ReTickedAction, as an Action the XML
    does not register; `Condition`), e.g. `MyRecovery: RecoveryNode` or `IsBatteryOk: Condition`.
    A type given twice, or one of BT.CPP's own (no program can register a builtin's ID again, so a
    proof under another rule would be about no robot), is refused. `profiles` (names of PROFILES,
    `nav2`) are read first, as if given before the files; a type a file gives that a profile gives
    too takes the file's rule (a user extends and corrects a profile), with a note appended to
    `notes` when given."""
    from ..bt.ports import BUILTIN
    from ..bt.semantics import ACTION, CONDITION, RETICKED_ACTION, RULES, STATEFUL_ACTION, SYNC_ACTION

    leaves = {"Action": ACTION, "SyncAction": SYNC_ACTION, "ReTickedAction": RETICKED_ACTION,
              "StatefulAction": STATEFUL_ACTION, "Condition": CONDITION}
    rules: dict = {}
    given: dict[str, SourcePos] = {}
    from_profile: dict[str, str] = {}
    files = [paths] if isinstance(paths, (str, Path)) else list(paths)
    names = list(dict.fromkeys(profiles))
    for name, path in [*((n, profile_path(n)) for n in names), *((None, f) for f in files)]:
        for key, value, fail in _name_pairs(path, max_bytes, "node semantics", "MyType: KnownType"):
            if key.value in BUILTIN:
                raise fail(f"{key.value} is a node type of BT.CPP's own: its semantics is BT.CPP's, and no robot "
                           f"can register it under another", key)
            rule = leaves.get(value.value) or RULES.get(value.value)
            if rule is None:
                known = ", ".join(sorted({*leaves, *RULES}))
                raise fail(f"{value.value!r} is not a node type whose semantics schemalog knows; one of: {known}", value)
            where = SourcePos(str(path), key.start_mark.line + 1, key.start_mark.column + 1)
            if key.value in from_profile and name is None:
                if notes is not None:
                    notes.append(f"note: {where}: {key.value} follows {value.value} as this file says, not the "
                                 f"{from_profile[key.value]} profile's rule ({given[key.value]})")
                del from_profile[key.value]
            elif key.value in given:
                raise fail(f"{key.value} is given its semantics twice: first at {given[key.value]}", key)
            elif name is not None:
                from_profile[key.value] = name
            rules[key.value] = rule
            given[key.value] = where
    return rules


def read_node_types(path: str | Path, max_bytes: int = defaults.MAX_BYTES) -> dict:
    """The node types an export gives a task's actions: a YAML mapping from a functor to
    `NodeType(port, ...)`, one port per argument in order, e.g. `a1: PickUp(object)`."""
    import re

    from ..formats.btcpp import NodeType, check_node_types

    types: dict = {}
    for key, value, fail in _name_pairs(path, max_bytes, "node types", "functor: NodeType(port, ...)"):
        m = re.fullmatch(r"\s*([^\s(]+)\s*(?:\((.*)\))?\s*", value.value)
        if m is None:
            raise fail(f"{value.value!r}: write NodeType or NodeType(port, ...)", value)
        ports = tuple(q.strip() for q in m.group(2).split(",")) if m.group(2) and m.group(2).strip() else ()
        entry = NodeType(m.group(1), ports)
        try:
            check_node_types({key.value: entry})
        except ValueError as err:
            raise fail(str(err), value) from None
        types[key.value] = entry
    return types


def prove_trees(original, compressed, max_states: int = defaults.MAX_STATES, rules=None, *,
                run_once: bool = False):
    """Prove two documents equal under BT.CPP 4 semantics, or refute them (bt/prove.py): by the
    subtrees where they differ, each in every context, else by exploring both whole. `rules`:
    node semantics for custom types (read_semantics). `run_once`: for trees ticked until they
    finish, once, and never halted; by default, also halted (Tree::haltTree) between any two
    root ticks and ticked anew, as an executor may."""
    from dataclasses import replace

    from ..bt.prove import prove_by_parts

    pairs = _readings(original, compressed, rules)
    verdicts = [prove_by_parts(a, b, max_states=max_states, max_events_per_tick=EVENTS_PER_TICK,
                               rules=rules, halts=not run_once) for a, b in pairs]
    if len(pairs) == 1:
        v = replace(verdicts[0], under=_under(*pairs[0]), assumed=_alike(verdicts[0], *pairs[0]))
        if original.version != compressed.version:
            ported = ("each custom node is one node in both versions, ported: under 4 it returns SKIPPED no more "
                      "than under 3.8, where there is none")
            v = replace(v, assumed=f"{v.assumed}; {ported}" if v.assumed else ported)
        return v
    return _combined(verdicts, pairs)


def _alike(verdict, *documents) -> str:
    """The verdict's `assumed`, with a word on an unmarked file both versions run alike."""
    if not any(d.unmarked for d in documents):
        return verdict.assumed
    said = ("the file has no BTCPP_format and nothing only one version reads: BT.CPP 3.8 loads it too, and runs "
            "each of its nodes as 4 does, so this holds under both")
    return f"{verdict.assumed}; {said}" if verdict.assumed else said


def compress_tree(document, max_states: int = defaults.MAX_STATES, rules=None, *,
                  drop_names: bool = False, run_once: bool = False) -> TreeCompression:
    """Apply the BT rewrites to `document`, each kept only where the prover does not refute it
    in its parent's context, and prove the result against it (`rules`: node semantics for custom
    types, read_semantics). A node with a `name` attribute is never removed, for BT.CPP's
    substitution rules, Groot2 and loggers find nodes by name (the result's `kept` lists those
    a rewrite would have removed), unless `drop_names`. `run_once`: as prove_trees."""
    from dataclasses import replace

    from ..bt.prove import compress_proved, prove_by_parts

    result, verdict = compress_proved(document, max_states=max_states, max_events_per_tick=EVENTS_PER_TICK,
                                      rules=rules, keep_names=not drop_names, halts=not run_once)
    compressed = result.document                   # the version and the unmarked flag of `document`
    if verdict is not None and document.unmarked and readings_differ(document, rules):
        # the rewrites were kept where 4 proves them; an unmarked file runs under 3.8 too
        pairs = [(document.under(4), compressed.under(4)), (document.under(3), compressed.under(3))]
        second = prove_by_parts(*pairs[1], max_states=max_states, max_events_per_tick=EVENTS_PER_TICK,
                                rules=rules, halts=not run_once)
        verdict = _combined([verdict, second], pairs)
    elif verdict is not None:
        verdict = replace(verdict, under=_under(document, compressed), assumed=_alike(verdict, document))
    return TreeCompression(document, compressed, result.rewrites, verdict, result.kept)


def tree_xml(document, models=()) -> str:
    """The document as BT.CPP 4 XML with a TreeNodesModel (formats/btxml.py), read back with
    `models` (the nodes files it was read with) before it is given out."""
    from ..formats.btxml import read_bt, write_bt

    text = write_bt(document)
    try:
        read_bt(text, "<the tree to write>", None, models=tuple(models))
    except SchemalogError as err:
        # a file our own reader refuses is one BT.CPP refuses too: a bug of ours, never an output
        where = f" at line {err.pos.line}, column {err.pos.column}" if err.pos else ""
        raise SchemalogError(f"the tree to write would be refused when read back{where} ({err.message}): "
                             f"nothing written; please report it with the file") from None
    return text


def verdict_text(verdict, under: str = "") -> str:
    """The prover's verdict as a person reads it: a proof, a search a limit cut short, or the
    counterexample root tick by root tick; `under` follows its first words ("proved equal", "NOT
    proved", "refuted after N states"), e.g. " under BT.CPP 4 semantics with the nav2 profile"."""
    from ..bt.prove import explain

    return explain(verdict, under)
