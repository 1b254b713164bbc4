"""Lint of BT.CPP trees: the blackboard rules, decided on the tree's runs (docs/lint.md, "BT.CPP
trees"): every run of the main tree under BT.CPP's semantics (bt/semantics.py), in every
environment, as an executor runs it (bt/prove.py's moves: the root ticked again while RUNNING,
Tree::haltTree between any two root ticks, the tree ticked anew; with `once`, ticked until it
finishes, once).

    Entry    = (scope, name)      a blackboard entry as BT.CPP resolves a key: scope is the
                                  SubTree calls above the blackboard that holds it (semantics'
                                  context), () the root's
    Access   = Access(pnode, port, entry, mode, type)   mode "read" | "write" | "inout" | "unknown"
    Provided = Provided(provides, reads)   entries the program sets before the tree runs, and
                                  those it reads after (a profile, --provided)
    Check    = (document, rules, *, max_states) -> [LintFinding]     CHECKS, the pipeline

    read-before-write  an input port reads {x} on a run before any node that may write x ticked
    never-written      read, never written anywhere, not provided ("did you mean")
    type-clash         one entry reached by ports of two declared C++ types
    dead-write         written, never read by the tree nor by the program (info)

"May write" assumes a ticked writer may have written (an output port, an inout port, a
SetBlackboard, a Script's assignment, a remapped SubTree output): values are not interpreted, so
a node that returns FAILURE may still have written. A port whose direction no model declares (a
custom type without --nodes) is taken as a write, never as a read: lint claims no bug it cannot
show on a run. LintFinding has run/lint.py's Finding's fields (bt/ may not import run/).
"""

from __future__ import annotations

import difflib
import re
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from schemalog.bt.lint_runs import run_findings
from schemalog.bt.model import Document, Node
from schemalog.bt.ports import BUILTIN_PORTS, is_blackboard, is_port_name
from schemalog.bt.semantics import (KINDS, RETICKED_ACTION, RUNNING, Await, PNode, Program, Rule, halt_tree_step,
                                    initial, program, step, advance)
from schemalog.errors import SourcePos

ERROR, WARNING, INFO, NOTE = "error", "warning", "info", "note"
Entry = tuple          # (scope, name)


@dataclass(frozen=True)
class LintFinding:
    """One diagnostic: run/lint.py's Finding's fields (pos, severity, code, message, hint)."""

    pos: SourcePos | None
    severity: str
    code: str
    message: str
    hint: str = ""


@dataclass(frozen=True)
class Provided:
    """Entries the program provides: set before the tree runs (`provides`), read by the program
    after (`reads`); each name with where it is said (a profile cites its source)."""

    provides: Mapping[str, str] = field(default_factory=dict)
    reads: Mapping[str, str] = field(default_factory=dict)
    silence: Mapping[str, str] = field(default_factory=dict)    # rule -> where it is silenced

    def __or__(self, other: "Provided") -> "Provided":
        return Provided({**self.provides, **other.provides}, {**self.reads, **other.reads},
                        {**self.silence, **other.silence})


@dataclass(frozen=True)
class Access:
    """A node's port bound to a blackboard entry: how it uses it, its declared type."""

    pnode: PNode
    port: str
    entry: Entry
    mode: str                   # "read" | "write" | "inout" | "unknown"
    type: str = ""

    @property
    def reads(self) -> bool:
        return self.mode in ("read", "inout")

    @property
    def writes(self) -> bool:
        return self.mode in ("write", "inout", "unknown")


# BT.CPP 4.8.2's own ports that are no input (providedPorts(); every other port of ports.py's
# BUILTIN_PORTS is an InputPort): LoopNode<T>'s `queue` is a BidirectionalPort and `value` an
# OutputPort (decorators/loop_node.h); SetBlackboard's `output_key` names the entry it writes
# (actions/set_blackboard_node.h); the updated-entry nodes' `entry` names an entry whose update
# counter they compare, without reading its value (decorators/updated_decorator.h).
_BUILTIN_MODES = {
    **{t: {"queue": "inout", "value": "write"} for t in ("LoopInt", "LoopBool", "LoopDouble", "LoopString")},
    **{t: {"entry": "none"} for t in ("SkipUnlessUpdated", "WaitValueUpdate", "WasEntryUpdated")},
    "SetBlackboard": {"output_key": "key"}, "UnsetBlackboard": {"key": "none"},
}
_DIRECTIONS = {"input": "read", "output": "write", "inout": "inout"}
UNTYPED = frozenset({"", "BT::Any", "BT::AnyTypeAllowed", "AnyTypeAllowed"})
# the scripts BT.CPP runs (ScriptNode's code, the pre/post-condition attributes, Precondition's if)
SCRIPTS = ("_failureIf", "_successIf", "_skipIf", "_while", "_onSuccess", "_onFailure", "_onHalted", "_post")
_ASSIGN = re.compile(r"(@?[A-Za-z_][A-Za-z0-9_]*)\s*(?::=|\+=|-=|\*=|/=|=(?!=))")
_NAME = re.compile(r"@?[A-Za-z_][A-Za-z0-9_]*")
_STRING = re.compile(r"'[^']*'|\"[^\"]*\"")


def assigned(code: str) -> list[str]:
    """The entries a BT.CPP script assigns: `x := 1; y = x + 1` -> ['x', 'y']."""
    return _ASSIGN.findall(_STRING.sub("''", code))


def named(code: str) -> set[str]:
    """Every name a script mentions (entries it may read; enum names too, which BT.CPP registers)."""
    return set(_NAME.findall(_STRING.sub("''", code)))


def entry_of(context: tuple, key: str) -> Entry:
    """The entry `{key}` names in the blackboard of `context` (semantics' SubTree calls above a
    node), as BT.CPP's Blackboard::getEntry finds it: `@key` the root's; a remapped port the
    parent's entry it names (a literal remapping is the subtree's own entry, set when the tree is
    created); under _autoremap a key not starting with `_` the parent's of the same name."""
    while True:
        if key.startswith("@"):
            return ((), key[1:])
        if not context:
            return ((), key)
        _, _, remap, autoremap = context[-1]
        value = dict(remap).get(key)
        if value is not None:
            if not is_blackboard(value):
                return (context, key)
            key, context = value[1:-1].strip(), context[:-1]
        elif autoremap and not key.startswith("_"):
            context = context[:-1]
        else:
            return (context, key)


def _key(port: str, value: str) -> str | None:
    """The key a port's value names: `{x}` -> x, `{=}` -> the port's own name, else None."""
    v = value.strip()
    if v == "{=}":
        return port
    return v[1:-1].strip() if is_blackboard(v) else None


def accesses(pn: PNode, document: Document) -> list[Access]:
    """The node's ports bound to blackboard entries, each with its mode and declared type."""
    node = pn.node
    if pn.rule == "SubTree":
        return []                    # a call's ports are remappings (entry_of), no access
    model = document.model(node.type)
    declared = {p.name: p for p in model.ports} if model is not None else {}
    builtin = BUILTIN_PORTS.get(node.type)
    out = []
    for port, value in node.ports:
        if not is_port_name(port):
            continue
        mode = _BUILTIN_MODES.get(node.type, {}).get(port)
        if mode == "key":            # <SetBlackboard output_key="x"/> or "{x}": writes x
            key = _key(port, value) or value.strip()
            out.append(Access(pn, port, entry_of(pn.context, key), "write"))
            continue
        key = _key(port, value)
        if key is None or mode == "none":
            continue
        if mode is None:
            p = declared.get(port)
            mode = _DIRECTIONS.get(p.direction, "unknown") if p is not None else \
                "read" if builtin is not None else "unknown"
            typ = " ".join(p.type.split()) if p is not None else ""
        else:
            typ = ""
        out.append(Access(pn, port, entry_of(pn.context, key), mode, typ))
    return out


def _scripts(pn: PNode) -> list[tuple[str, str]]:
    """The node's scripts as (attribute, code): `code` of Script and ScriptCondition, `if` of
    Precondition, the pre/post-condition attributes."""
    node = pn.node
    out = [(k, node.attr(k)) for k in SCRIPTS if node.attr(k) is not None]
    if node.type in ("Script", "ScriptCondition") and node.attr("code") is not None:
        out.append(("code", node.attr("code")))
    if node.type == "Precondition" and node.attr("if") is not None:
        out.append(("if", node.attr("if")))
    return out


def _pnodes(root: PNode):
    stack = [root]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(n.kids))


def _pos(node: Node) -> SourcePos | None:
    return SourcePos(node.file or "<xml>", node.line, node.column) if node.line else None


def shown(entry: Entry) -> str:
    """`{x}`, or `{x}` of the subtree T for an entry of a subtree's own blackboard."""
    scope, name = entry
    return f"{{{name}}}" if not scope else f"{{{name}}} of SubTree {scope[-1][1]}"


# ---------------------------------------------------------------------------------------------
# The facts: every access, every script write, the entries set when the tree is created

@dataclass(frozen=True)
class Facts:
    """What the rules read off the expanded program."""

    accesses: tuple[Access, ...]
    script_writes: tuple[tuple[PNode, str, Entry], ...]      # (node, attribute, entry)
    script_names: frozenset                                  # entries a script may read
    literal: frozenset                                       # entries a SubTree call sets to a literal
    provided: frozenset                                      # entries the program provides
    unknown_types: tuple[str, ...]                           # types with ports of no known direction


def facts(prog: Program, document: Document, given: Provided) -> Facts:
    """The accesses of the program's nodes and what the program provides."""
    acc: list[Access] = []
    writes: list[tuple[PNode, str, Entry]] = []
    names: set = set()
    literal: set = set()
    for pn in _pnodes(prog.root):
        if pn.rule == "SubTree":
            call = pn.kids[0].context[-1]
            literal.update((pn.kids[0].context, k) for k, v in call[2] if not is_blackboard(v))
            continue
        acc.extend(accesses(pn, document))
        for attr, code in _scripts(pn):
            for key in assigned(code):
                writes.append((pn, attr, entry_of(pn.context, key)))
            names.update(entry_of(pn.context, k) for k in named(code))
    # a provided name is provided in every blackboard that holds an entry of that name (Nav2
    # sets `node`, `server_timeout`, ... in every subtree's: bt_action_server_impl.hpp)
    every = {a.entry for a in acc} | {e for _, _, e in writes} | names
    provided = frozenset(e for e in every if e[1] in given.provides)
    unknown = tuple(sorted({a.pnode.node.type for a in acc if a.mode == "unknown"}))
    return Facts(tuple(acc), tuple(writes), frozenset(names), frozenset(literal), provided, unknown)


# ---------------------------------------------------------------------------------------------
# The runs: the configurations between events, each with the reads its event makes and, on its
# way out, the entries its node may have written

@dataclass
class Runs:
    """The explored runs as a graph: state 0 the start; reads[s] the read keys of the event
    state s stops at; succ[s] its successors with the entries written on the way."""

    reads: list = field(default_factory=list)
    succ: list = field(default_factory=list)
    exhausted: bool = True
    events: set = field(default_factory=set)       # the (context, identity) of every event met


_TICK, _TREE = "tick", "haltTree"
_STEPS = {_TICK: step, _TREE: halt_tree_step}


def explore(prog: Program, effects: Mapping, *, max_states: int, once: bool = False) -> Runs:
    """Every run of `prog` as an executor runs it (bt/prove.py's moves with `halts`; `once`:
    ticked until it finishes, once), up to `max_states` states. `effects` maps an event's node
    (context, identity) to (read keys, written entries)."""
    runs = Runs()
    ids: dict = {}                   # a state's key (the interrupted tick as data) -> its id
    of: dict = {}                    # a (phase, config) met -> its state's id (-1: past the limit)
    edges: list = []                 # (state id, (phase, config) after, entries written on the way)
    todo = deque([(_TICK, initial())])
    none = (frozenset(), frozenset())
    while todo:
        node = todo.popleft()
        phase, config = node
        s = _STEPS[phase](prog, config)
        key = (phase, s.key if isinstance(s, Await) and s.key is not None else config)
        if key in ids:
            of[node] = ids[key]
            continue
        if len(ids) >= max_states:
            runs.exhausted = False
            of[node] = -1
            continue
        sid = of[node] = ids[key] = len(runs.reads)
        reads, nexts = frozenset(), []
        if isinstance(s, Await) and s.event.kind == "registration":
            # how the action type is registered: both ways, each a run (bt/prove.py's _Kind)
            nexts = [((phase, config.with_kind(s.event.node[1][1], k)), frozenset()) for k in KINDS]
        elif isinstance(s, Await):
            event_reads, writes = effects.get(s.event.node, none)
            runs.events.add(s.event.node)
            reads = event_reads if s.event.kind != "halt" else frozenset()
            gen = writes if s.event.kind in ("tick", "script", "choose") else frozenset()
            nexts = [((phase, advance(config, o)), gen) for o in s.options]
        elif s.status is not None and not s.limited and (not once or s.status is RUNNING):
            nexts = [((m, s.config), frozenset()) for m in ((_TICK,) if once else (_TICK, _TREE))]
        runs.reads.append(reads)
        for nxt, gen in nexts:
            edges.append((sid, nxt, gen))
            if nxt not in of:
                of[nxt] = None
                todo.append(nxt)
    succ: list = [[] for _ in runs.reads]
    for sid, nxt, gen in edges:
        target = of.get(nxt)
        if target is not None and target >= 0:
            succ[sid].append((target, gen))
    runs.succ = [tuple(x) for x in succ]
    return runs


def _reach_without(runs: Runs, entry: Entry) -> set:
    """The states some run reaches with no node that may write `entry` ticked."""
    seen, todo = {0}, [0]
    while todo:
        s = todo.pop()
        for t, gen in runs.succ[s]:
            if t not in seen and entry not in gen:
                seen.add(t)
                todo.append(t)
    return seen


def _written_first(runs: Runs, entry: Entry, at: set) -> bool:
    """Whether on some run a node that may write `entry` ticks before the first of the states `at`."""
    seen, todo = {(0, False)}, [(0, False)]
    while todo:
        s, written = todo.pop()
        if s in at:
            if written:
                return True
            continue
        for t, gen in runs.succ[s]:
            nxt = (t, written or entry in gen)
            if nxt not in seen:
                seen.add(nxt)
                todo.append(nxt)
    return False


# ---------------------------------------------------------------------------------------------
# The rules

def _read_key(a: Access) -> tuple:
    return (a.pnode.context, a.pnode.node.identity)


def blackboard_findings(document: Document, rules: Mapping[str, Rule] | None = None, *, max_states: int,
                        provided: Provided = Provided(), once: bool = False) -> list[LintFinding]:
    """read-before-write, never-written, type-clash and dead-write on `document`'s main tree,
    and a note of what was covered and assumed."""
    prog = program(document, rules)
    f = facts(prog, document, provided)
    readers = [a for a in f.accesses if a.reads]
    written = {a.entry for a in f.accesses if a.writes} | {e for _, _, e in f.script_writes}
    if not f.accesses and not f.script_writes:
        return [LintFinding(None, NOTE, "blackboard", "no blackboard entry read or written: nothing to check")]
    out: list[LintFinding] = []
    set_before = f.provided | f.literal
    out += _never_written(readers, written, set_before)
    out += _type_clashes(f.accesses)
    runs_note = ""
    ordered = [a for a in readers if a.entry in written and a.entry not in set_before]
    if ordered:
        effects = _effects(prog, f)
        # First on the program with every subtree that touches none of the entries ordered taken
        # as one leaf of any status (more runs than the tree has): a read found clean there is
        # clean; the reads it flags are decided on the program itself
        small = summarised(prog, f, {a.entry for a in ordered})
        runs = explore(small, effects, max_states=max_states, once=once)
        states, exhausted = len(runs.reads), runs.exhausted
        found, undecided = _read_before_write(ordered, runs)
        if found and small is not prog:
            flagged = {_pos(a.pnode.node) for a in ordered} & {x.pos for x in found}
            runs = explore(prog, effects, max_states=max_states, once=once)
            states, exhausted = max(states, len(runs.reads)), exhausted and runs.exhausted
            found, more = _read_before_write([a for a in ordered if _pos(a.pnode.node) in flagged], runs)
            undecided += more
        out += found
        states = f"{states:,} states"
        runs_note = (f"; the order of {len(ordered)} read{'s' if len(ordered) != 1 else ''} decided on every run "
                     f"({states}, exhausted)" if exhausted and not undecided else
                     f"; NOT decided for {_names(undecided)}: {states}, not every run "
                     f"(raise --max-states)" if not exhausted else
                     f"; {_names(undecided)}: read by no event the runs show (a control's port), order not checked")
    out += _dead_writes(f, provided)
    how = "ticked until it finishes, once" if once else "as an executor runs it (halted and ticked anew)"
    assumed = ("a ticked writer may have written (values are not interpreted); the names a script reads are "
               "not checked (a name there may be an enum the program registers)")
    if f.unknown_types:
        assumed += (f"; ports of {', '.join(f.unknown_types)} have no declared direction (give --nodes): "
                    f"taken as writes, never reads")
    out.append(LintFinding(None, NOTE, "blackboard",
                           f"blackboard: {len({a.entry for a in readers})} entries read at {len(readers)} ports, "
                           f"{len(written)} written, {len(f.provided)} provided by the program, the tree {how}"
                           f"{runs_note}; assumed: {assumed}"))
    return out


SUMMARY = "<summary>"


def summarised(prog: Program, f: Facts, entries: set) -> Program:
    """`prog` with each maximal subtree that neither reads nor writes one of `entries` (nor may
    return SKIPPED: no `_skipIf`, `_while`, no custom control) replaced by a leaf that returns
    any status at each tick and emits one event (semantics' RETICKED_ACTION): its runs include
    the program's, seen on the events of the nodes kept."""
    keep = {id(a.pnode) for a in f.accesses if a.entry in entries}
    keep |= {id(pn) for pn, _, e in f.script_writes if e in entries}

    def touches(pn: PNode) -> bool:
        return (id(pn) in keep or pn.rule == "<opaque>" and bool(pn.kids)
                or any(pn.node.attr(k) is not None for k in ("_skipIf", "_while")))

    def rebuild(pn: PNode) -> tuple[PNode, bool]:
        kids = [rebuild(k) for k in pn.kids]
        kept = touches(pn) or any(k for _, k in kids)
        if not kept and pn.path:
            leaf = Node(SUMMARY, (("at", ".".join(map(str, pn.path))),), (), "", pn.node.line, pn.node.column,
                        pn.node.file)
            return PNode(leaf, SUMMARY, (), pn.context, pn.path), False
        return PNode(pn.node, pn.rule, tuple(k for k, _ in kids), pn.context, pn.path, pn.decorator), kept

    root, kept = rebuild(prog.root)
    if not kept:
        return prog
    return Program(root, {**prog.rules, SUMMARY: RETICKED_ACTION}, prog.passing, prog.version, prog.skips)


def _names(accs) -> str:
    shown_ = sorted({f"{a.pnode.node.name}.{a.port}" for a in accs})
    return ", ".join(shown_[:5]) + (f" and {len(shown_) - 5} more" if len(shown_) > 5 else "")


def _effects(prog: Program, f: Facts) -> dict:
    """An event's node (context, identity) -> (the read keys of its reads, the entries it may write)."""
    reads: dict = {}
    writes: dict = {}
    for a in f.accesses:
        k = _read_key(a)
        if a.reads:
            reads.setdefault(k, set()).add((k, a.port, a.entry))
        if a.writes:
            writes.setdefault(k, set()).add(a.entry)
    for pn, attr, e in f.script_writes:
        k = (pn.context, pn.node.identity if attr == "code" else (attr, pn.node.attr(attr)))
        writes.setdefault(k, set()).add(e)
    return {k: (frozenset(reads.get(k, ())), frozenset(writes.get(k, ()))) for k in {*reads, *writes}}


def _read_before_write(readers: list[Access], runs: Runs) -> tuple[list[LintFinding], list[Access]]:
    """Each read of an entry some node writes, decided on the runs (first read of the node)."""
    out, undecided = [], []
    at: dict = {}
    for s, keys in enumerate(runs.reads):
        for k in keys:
            at.setdefault(k, set()).add(s)
    unwritten_cache: dict = {}
    for a in readers:
        states = at.get((_read_key(a), a.port, a.entry), set())
        if not states:
            # exhausted: no run ticks the node (unreachable), unless its reads show in no event
            # (a control's port: BT.CPP's controls tick without one)
            if not runs.exhausted or (a.pnode.kids and _read_key(a) not in runs.events):
                undecided.append(a)
            continue
        if a.entry not in unwritten_cache:
            unwritten_cache[a.entry] = _reach_without(runs, a.entry)
        if not states & unwritten_cache[a.entry]:
            if not runs.exhausted:
                undecided.append(a)
            continue
        first = _written_first(runs, a.entry, states)
        writers = "a node that may write it"
        if first:
            sev, why = WARNING, (f"{a.port} reads {shown(a.entry)} before {writers} has ticked on some runs "
                                 f"(on others after)")
        elif runs.exhausted:
            sev, why = ERROR, (f"{a.port} reads {shown(a.entry)} before {writers} has ticked, on every run "
                               f"(BT.CPP: getInput fails, the entry is missing)")
        else:
            sev, why = WARNING, (f"{a.port} reads {shown(a.entry)} before {writers} has ticked on the runs "
                                 f"explored (not every run: raise --max-states)")
        out.append(LintFinding(_pos(a.pnode.node), sev, "read-before-write", f"{a.pnode.node.name}: {why}",
                               f"tick a node that writes {shown(a.entry)} before {a.pnode.node.name}, or have "
                               f"the program set it (--provided)"))
    return out, undecided


def _never_written(readers: list[Access], written: set, set_before: frozenset) -> list[LintFinding]:
    out = []
    names = sorted({e[1] for e in written | set_before})
    for a in readers:
        if a.entry in written or a.entry in set_before:
            continue
        near = [n for n in sorted(names) if _one_edit(a.entry[1], n)] or \
            difflib.get_close_matches(a.entry[1], names, n=1, cutoff=0.8)
        hint = (f"did you mean {{{near[0]}}}?" if near else
                f"write {shown(a.entry)} before it is read, or declare it provided (--provided FILE)")
        out.append(LintFinding(_pos(a.pnode.node), ERROR, "never-written",
                               f"{a.pnode.node.name}: {a.port} reads {shown(a.entry)}, which no node writes and the "
                               f"program does not provide (BT.CPP: getInput fails)", hint))
    return out


def _type_clashes(accs: tuple[Access, ...]) -> list[LintFinding]:
    out = []
    first: dict = {}
    for a in accs:
        if a.type in UNTYPED:
            continue
        seen = first.setdefault(a.entry, a)
        if seen.type != a.type:
            out.append(LintFinding(_pos(a.pnode.node), ERROR, "type-clash",
                                   f"{a.pnode.node.name}: port {a.port} of type {a.type} reaches {shown(a.entry)}, "
                                   f"which {seen.pnode.node.name}.{seen.port} ({_pos(seen.pnode.node)}) declares "
                                   f"{seen.type} (BT.CPP: the port was initially created with one type, later "
                                   f"another was used)",
                                   f"use one type for {shown(a.entry)}, or remap one port to another entry"))
    return out


def _dead_writes(f: Facts, given: Provided) -> list[LintFinding]:
    read = {a.entry for a in f.accesses if a.mode in ("read", "inout", "unknown")} | f.script_names
    out, done = [], set()
    writers = [(a.pnode, a.entry) for a in f.accesses if a.mode in ("write", "inout")] + \
              [(pn, e) for pn, _, e in f.script_writes]
    for pn, e in writers:
        if e in read or e in done or e[1] in given.reads:
            continue
        done.add(e)
        out.append(LintFinding(_pos(pn.node), INFO, "dead-write",
                               f"{pn.node.name} writes {shown(e)}, which no node of the tree reads",
                               "remove the write, or list the entry under `reads:` of --provided when the "
                               "program reads it"))
    return out


def _one_edit(a: str, b: str) -> bool:
    """Whether `b` is `a` with one letter inserted, removed, changed, or two neighbours swapped
    ({remaning_path} for {remaining_path}, {paht} for {path})."""
    if a == b or abs(len(a) - len(b)) > 1:
        return False
    if len(a) == len(b):
        diff = [i for i in range(len(a)) if a[i] != b[i]]
        return len(diff) == 1 or (len(diff) == 2 and diff[1] == diff[0] + 1 and a[diff[0]] == b[diff[1]]
                                  and a[diff[1]] == b[diff[0]])
    short, long_ = (a, b) if len(a) < len(b) else (b, a)
    return any(long_[:i] + long_[i + 1:] == short for i in range(len(long_)))


Check = Callable[..., list]
CHECKS: tuple[Check, ...] = (blackboard_findings, run_findings)
"""The lint pipeline: each (document, rules, *, max_states[, provided][, once]) -> findings, given the
options it names (api/tree_lint.lint_document)."""
