"""The lint rules decided on a tree's runs (docs/lint.md, "Run rules"): every run of the main tree
under BT.CPP's semantics (bt/semantics.py; a document read under 3.8 runs under RULES_V3), in
every environment, as an executor runs it (bt/prove.py's moves with `halts`: the root ticked
again while RUNNING, Tree::haltTree between any two root ticks, the tree ticked anew).

    run_findings(document, rules, max_states) -> [RunFinding]   the findings of the rules below
    RunFinding = (pos, severity, code, message, hint)  run/lint.py's Finding's fields (bt/ may not
                                                       import run/: tests/test_layers.py)

    unreachable    a node no run ticks; the topmost of such a subtree only          (warning)
    endless        a root tick that never returns (BT.CPP's executeTick, or
                   Tree::tickOnce after wake-up signals): on every environment once
                   reached (error), or on a run where leaves complete at once (warning)
    endless-tree   no run of the tree ever finishes (SUCCESS, FAILURE)               (warning)
    halt-safety    a node left RUNNING while its parent is not, by a rule that
                   finished without halting it (never by BT.CPP's own nodes)         (error)
    not-decided    the exploration stopped at a limit: what it did not explore is
                   claimed by no finding                                             (warning)

The explorer is prove_equal's for one tree: breadth-first over the configurations between
events, merged on the interrupted tick as data (semantics._continuation) where it can be frozen.
Blackboard values are not interpreted: a leaf may return any status its kind allows at each
tick, a script condition either truth value, a timer fire or not, an opaque custom node tick any
children and return anything. A finding names a run of that model; an error is claimed only
where every environment goes the same way.
"""

from __future__ import annotations

import sys
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, replace
from types import MappingProxyType

from schemalog import defaults
from schemalog.bt.model import Document, Node
from schemalog.bt.prove import describe
from schemalog.bt.semantics import (COMPLETED, FAILURE, KINDS, OPAQUE, PRE_CONDITIONS, RESETTING_PARENTS, RETICKED_ACTION,
                                    RUNNING, SKIPPED, SUCCESS, Await,
                                    Config, PNode, Program, RootTicked, Rule, Status, frozen_locals,
                                    advance, halt_step, halt_tree_step, initial, program, step, visit_step)
from schemalog.errors import SourcePos

EVENTS_PER_TICK = 10_000          # api/behaviour_trees.EVENTS_PER_TICK: events in one root tick before
                                  # the exploration stops (not decided)
MAX_NODE_TICKS = 100_000          # semantics.step's: node ticks in one root tick without an event

ERROR, WARNING = "error", "warning"


@dataclass(frozen=True)
class RunFinding:
    """One diagnostic of a run rule, with run/lint.py's Finding's fields: where, how bad, which
    rule, what is wrong, what to do."""

    pos: SourcePos | None
    severity: str
    code: str
    message: str
    hint: str = ""


# ---------------------------------------------------------------------------------------------
# The exploration: one tree's states, as an executor runs it

_TICK, _TREE, _HALT, _VISIT = "tick", "haltTree", "halt", "visit"   # phases: ticking the root, Tree::haltTree,
                                                                  # its parent's haltChild, haltTree's visitor
_AGAIN, _WOKEN, _ANEW, _HALTED, _KEEP = "again", "woken", "anew", "haltTree", "keep"   # moves between root ticks
_STEPS = {_TICK: step, _TREE: halt_tree_step, _HALT: halt_step, _VISIT: visit_step}


@dataclass
class _Vertex:
    """A state of the run (its first node, for the run that leads to it) and where it goes."""

    node: tuple                        # (phase, Config): the first one met with this key
    step: Await | RootTicked | None    # None: a registration asked (two successors)
    succ: list                         # [(label, node)]: the nodes it leads to


@dataclass
class _Explored:
    vertices: list
    of_node: dict                      # node -> vertex index (nodes stepped)
    parent: dict                       # node -> (node, label) | None: the breadth-first tree
    limit: str                         # why the exploration stopped early, or ""
    merged: list                       # nodes whose key was seen: their tick's prefix is their own
    looped: dict                       # vertex index -> the loop proved inside its root tick
    cut: set                           # vertex indices left unexpanded at a limit
    unproved: str                      # a root tick past MAX_NODE_TICKS whose loop was not proved

    @property
    def decided(self) -> bool:
        return not (self.limit or self.unproved)


def _key(phase: str, s: Await | RootTicked, config: Config) -> tuple:
    if isinstance(s, Await) and s.key is not None:
        return (phase, s.key)
    return (phase, config)


def _explore(prog: Program, max_states: int, moves=None) -> _Explored:
    """Every state of the program's runs, up to `max_states` keys: as an executor runs the tree
    (`_executor`), or as `moves` says what follows a root tick (`_in_every_context`)."""
    moves = moves or _executor
    start = (_TICK, initial())
    parent: dict = {start: None}
    keys: dict = {}
    vertices: list[_Vertex] = []
    of_node: dict = {}
    merged: list = []
    looped: dict = {}
    cut: set = set()
    limit = unproved = ""
    queue = deque([start])
    while queue:
        node = queue.popleft()
        phase, config = node
        s = _STEPS[phase](prog, config)
        if isinstance(s, Await) and s.event.kind == "registration":
            # how an action type is registered: decided once per run, each way (as prove_equal)
            asked = s.event.node[1][1]
            v = len(vertices)
            vertices.append(_Vertex(node, None, [(kind, (phase, config.with_kind(asked, kind))) for kind in KINDS]))
            of_node[node] = v
        else:
            key = _key(phase, s, config)
            if key in keys:
                of_node[node] = keys[key]
                merged.append(node)
                continue
            if len(keys) >= max_states:
                limit = limit or f"{max_states} states explored (max_states)"
                break
            v = keys[key] = len(vertices)
            of_node[node] = v
            succ = ([(o, (phase, advance(config, o))) for o in s.options] if isinstance(s, Await)
                    else moves(phase, s))
            vertices.append(_Vertex(node, s, succ))
            if isinstance(s, Await) and len(s.config.pending) >= EVENTS_PER_TICK:
                vertices[v].succ = []
                cut.add(v)
                limit = limit or f"a root tick reached {EVENTS_PER_TICK} events"
            elif isinstance(s, RootTicked) and s.limited:
                loop = _loop_inside(prog, config)
                if loop is None:
                    cut.add(v)
                    unproved = unproved or s.error
                else:
                    looped[v] = loop
        for label, nxt in vertices[of_node[node]].succ:
            if nxt not in parent:
                parent[nxt] = (node, label)
                queue.append(nxt)
    return _Explored(vertices, of_node, parent, limit, merged, looped, cut, unproved)


def _executor(phase: str, s: RootTicked) -> list:
    """What an executor may do after a root tick (or a haltTree): tick again (at once after a
    wake-up signal, Tree::tickOnce), call Tree::haltTree, tick the tree anew for the next goal."""
    if s.status is None:                          # BT.CPP threw (or a limit): the run ends
        return []
    # Tree::tickOnce ticks again within the call only after a RUNNING root tick that emitted the
    # wake-up signal (tickRoot's inner loop: status == RUNNING && wake_up_->waitFor(0))
    again = (_WOKEN if s.woken else _AGAIN) if s.status is RUNNING else _ANEW
    moves = [(again, (_TICK, s.config))]
    return moves + [(_HALTED, (_TREE, s.config))]


def _in_every_context(unreset: bool):
    """What any parent may do to a subtree between its ticks (prove_equal's contextual moves with
    halts): tick it again; halt it while RUNNING (haltChild); tick it anew once finished or
    halted, its memory kept; tick it again unreset (`unreset`: WhileDoElse's condition); reach it
    with Tree::haltTree's visitor."""
    def moves(phase: str, s: RootTicked) -> list:
        if s.status is None:
            return []
        if phase == _TICK and s.status is RUNNING:
            return [(_WOKEN if s.woken else _AGAIN, (_TICK, s.config)), (_HALT, (_HALT, s.config))]
        out = [(_ANEW, (_TICK, s.config))]
        if unreset and s.kept is not None:
            out.append((_KEEP, (_TICK, s.kept)))
        return out + [(_VISIT, (_VISIT, s.config))]
    return moves


# ---------------------------------------------------------------------------------------------
# Replays: what a root tick ticked (the explorer's steps keep only events)

class _Recorder:
    """A program whose rules note each node whose rule ticks, and the innermost node that
    emitted the wake-up signal; replaying a state's tick with it shows what the tick ticked."""

    def __init__(self, prog: Program) -> None:
        self.ticked: set[tuple] = set()
        self.emitter: PNode | None = None
        self.program = replace(prog, rules=MappingProxyType({k: self._wrap(r) for k, r in prog.rules.items()}))

    def _wrap(self, rule: Rule) -> Rule:
        def tick(run, n: PNode) -> Status:
            self.ticked.add(n.path)
            before = run.woken
            status = rule.tick(run, n)
            if run.woken and not before and self.emitter is None:
                self.emitter = n
            return status
        return Rule(tick, rule.halt, rule.literal, rule.visit)

    def replay(self, config: Config) -> Await | RootTicked:
        self.emitter = None
        return step(self.program, config)


class _Looped(Exception):
    """A root tick came back to a state it was in, with no event between: it never returns."""

    def __init__(self, driver: PNode, path: tuple) -> None:
        self.driver, self.path = driver, path


def _loop_inside(prog: Program, config: Config) -> tuple | None:
    """The node that loops for ever inside the root tick from `config` (the tick went past
    MAX_NODE_TICKS without an event), as (driver path, ticked path): proved by the tick coming
    back to a state it was in (memory, every frame's instruction and locals, no event between),
    from which it runs the same way again. None when no state came back (a long finite loop, or
    a frame that cannot be frozen: a user's rule)."""
    seen: dict = {}
    stack: list[PNode] = []
    stuck = [False]
    step_code = step.__code__

    def wrap(rule: Rule) -> Rule:
        def tick(run, n: PNode) -> Status:
            stack.append(n)
            try:
                if not stuck[0]:
                    state = _tick_state(run, n, step_code, tick.__code__)
                    if state is None:
                        stuck[0] = True
                    elif state in seen:
                        entries = [s for s in history[seen[state]:]]
                        shallow = min(entries, key=len)
                        driver = shallow[-2] if len(shallow) > 1 else shallow[-1]
                        raise _Looped(driver, n.path)
                    else:
                        seen[state] = len(history)
                        history.append(tuple(stack))
                return rule.tick(run, n)
            finally:
                stack.pop()
        return Rule(tick, rule.halt, rule.literal, rule.visit)

    history: list[tuple] = []
    detector = replace(prog, rules=MappingProxyType({k: wrap(r) for k, r in prog.rules.items()}))
    try:
        step(detector, config, max_node_ticks=MAX_NODE_TICKS)
    except _Looped as loop:
        return (loop.driver.path, loop.path)
    return None


def _tick_state(run, n: PNode, step_code, wrapper_code) -> tuple | None:
    """The whole state of a replay as it enters `n`'s rule: memory, registrations, events so
    far, and every frame below step() (semantics' with its instruction and locals, the wrapper's
    by its node); None when a frame cannot be frozen."""
    frames = []
    f = sys._getframe(2)
    while f is not None and f.f_code is not step_code:
        if f.f_code is wrapper_code:
            frames.append(("node", f.f_locals["n"].path))
        elif f.f_globals.get("__name__") == "schemalog.bt.semantics":
            local = frozen_locals(f)
            if local is None:
                return None
            frames.append((f.f_code, f.f_lasti, local))
        else:
            return None
        f = f.f_back
    return (n.path, run.freeze(), tuple(sorted(run.kinds.items())), run.pos, len(run.events), run.woken,
            tuple(frames))


# ---------------------------------------------------------------------------------------------
# The findings

def run_findings(document: Document, rules: Mapping[str, Rule] | None = None, *,
                 max_states: int = defaults.MAX_STATES) -> list[RunFinding]:
    """The run rules' findings on the document's main tree, under `rules` (a user's semantics):
    from the whole tree's runs when at most WHOLE_STATES states hold them, else from its parts
    (_by_parts) for what parts decide, and from the whole runs explored for what was found."""
    prog = program(document, rules)
    places = _places(prog.root)
    whole = _explore(prog, min(max_states, WHOLE_STATES))
    findings = _endless(document, prog, whole, places)
    orphans = _halt_safety(prog, whole, places)
    findings += orphans
    finishes = _finishes(whole)
    if whole.decided:
        findings += _unreachable(prog, whole, places)
        if not finishes and not _throws(whole):
            findings.append(_endless_tree(document, f"all {_states(len(whole.vertices))} of its runs explored"))
        return findings
    parts = _by_parts(prog, places, max_states)
    undecided = []
    if parts is None:
        undecided = ["unreachable"] + ([] if finishes else ["endless-tree"])
    else:
        findings += _unreachable_by_parts(prog, parts, places)
        root = parts[prog.root.path]
        if not finishes and not root.statuses & {SUCCESS, FAILURE, SKIPPED} and not root.throws:
            findings.append(_endless_tree(document, f"decided node by node: {len(parts)} parts, each in every "
                                                    f"context its parent can make"))
    if parts is None or any(p.loops for p in parts.values()):
        undecided.append("endless")
    if not orphans and (parts is None or any(p.orphans for p in parts.values())):
        undecided.append("halt-safety")
    if undecided:
        where = (f"a part of it has more than {max_states} states (max_states)" if parts is None else
                 f"its parts do not decide {'them' if len(undecided) > 1 else 'it'}")
        findings.append(RunFinding(
            _pos(document.root), WARNING, "not-decided",
            f"not decided: {', '.join(undecided)}: the whole tree's runs were explored to "
            f"{_states(len(whole.vertices))} only ({whole.limit or whole.unproved}), and {where}; no finding claims "
            f"what was not explored", "raise --max-states, or lint the subtrees apart"))
    return findings


WHOLE_STATES = 5_000          # states of the whole tree's runs explored before the rules go by parts


def _states(count: int) -> str:
    return f"{count} state{'' if count == 1 else 's'}"


def _finishes(explored: _Explored) -> bool:
    """Whether some run's root tick returns SUCCESS or FAILURE (or SKIPPED, which ends
    tickWhileRunning too: no endless tree)."""
    return any(isinstance(v.step, RootTicked) and v.node[0] == _TICK and v.step.status in (*COMPLETED, SKIPPED)
               for v in explored.vertices)


# ---------------------------------------------------------------------------------------------
# By parts: each node with its children summarised, in every context its parent can make

@dataclass(frozen=True)
class _Part:
    """What the runs of one node, its children summarised, show in every context."""

    statuses: frozenset                # what the node returned
    reached: frozenset                 # the paths of the children it ticked
    orphans: bool                      # a child left RUNNING while the node is not
    loops: bool                        # a wake-up signal, or a loop inside a tick: endless not ruled out
    throws: bool                       # BT.CPP threw in some run


_SUMMARY = "\0summary"                # the rule key of a summary that returns any status


def _by_parts(prog: Program, places: dict, max_states: int) -> dict | None:
    """Each node with children (post-order) explored with its children summarised by what their
    own parts returned (a leaf as itself), in every context its parent can make (the root as an
    executor runs it). Every run of the tree is, node by node, a run of these parts (a parent
    sees a child only through its statuses and these moves; a summary returns at least what the
    child can), so what no part does, no run does: a child no part ticks is ticked by no run, a
    root whose part never finishes never finishes. None when a part goes past `max_states`."""
    rules = MappingProxyType({**prog.rules, _SUMMARY: RETICKED_ACTION})
    parts: dict = {}
    order: list[PNode] = []
    stack = [prog.root]
    while stack:
        n = stack.pop()
        if n.kids or n is prog.root:
            order.append(n)
            stack.extend(n.kids)
    for n in reversed(order):                          # children before parents
        kids = tuple(k if not k.kids else _summary(k, parts[k.path].statuses) for k in n.kids)
        piece = replace(prog, root=replace(n, kids=kids), rules=rules, passing=frozenset())
        up = places[n.path][1]
        moves = None if up is None else _in_every_context(places[up][0].rule not in RESETTING_PARENTS)
        explored = _explore(piece, max_states, moves)
        if not explored.decided:
            return None
        parts[n.path] = _part(piece, explored, {k.path for k in n.kids})
    return parts


def _summary(k: PNode, statuses: frozenset) -> PNode:
    """A child as a node of the table that returns the statuses `statuses` (at least): a leaf, or
    a decorator over one; with SKIPPED an opaque node (every status)."""
    def leaf(rule: str, node_type: str, path: tuple) -> PNode:
        return PNode(Node(node_type, (("name", k.node.name),), (), "", k.node.line, k.node.column, k.node.file),
                     rule, (), k.context, path)

    def over(rule: str, inner: PNode) -> PNode:
        return PNode(Node(rule, (("name", k.node.name),), (), "", k.node.line, k.node.column, k.node.file),
                     rule, (inner,), k.context, k.path, decorator=rule != "<opaque>")
    t, below = k.node.type, k.path + (0,)
    s = set(statuses)
    if SKIPPED in s:
        return over("<opaque>", leaf("AlwaysSuccess", "AlwaysSuccess", below))
    if s == {SUCCESS}:
        return leaf("AlwaysSuccess", t, k.path)
    if s == {FAILURE}:
        return leaf("AlwaysFailure", t, k.path)
    if s == {SUCCESS, FAILURE}:
        return leaf("<condition>", t, k.path)
    if s == {RUNNING}:
        return over("KeepRunningUntilFailure", leaf("AlwaysSuccess", "AlwaysSuccess", below))
    if s == {SUCCESS, RUNNING}:
        return over("ForceSuccess", leaf(_SUMMARY, t, below))
    if s == {FAILURE, RUNNING}:
        return over("ForceFailure", leaf(_SUMMARY, t, below))
    return leaf(_SUMMARY, t, k.path)                    # all three, or none (it never returns: any)


def _part(piece: Program, explored: _Explored, kids: set) -> _Part:
    """What a part's runs show."""
    statuses, orphans, woken, throws = set(), False, False, False
    for v in explored.vertices:
        s = v.step
        if not isinstance(s, RootTicked):
            continue
        if s.status is None:
            throws = True
            continue
        if v.node[0] == _TICK:
            statuses.add(s.status)
            woken |= s.woken
        memory = {p: st for p, st, _ in s.config.memory}
        # an opaque node may leave a child RUNNING in the model (it may do anything): not claimed
        orphans |= (piece.rules[piece.root.rule] is not OPAQUE and memory.get(piece.root.path) != RUNNING.value
                    and any(memory.get(k) == RUNNING.value for k in kids))
    within = [[explored.of_node.get(x) for _, x in v.succ]
              if isinstance(v.step, Await) and v.step.event.kind != "choose" else [] for v in explored.vertices]
    within = [[j for j in js if j is not None] for js in within]
    loops = woken or bool(explored.looped) or bool(_cycles(within))
    reached = _ticked(piece, explored) & kids
    return _Part(frozenset(statuses), frozenset(reached), orphans, loops, throws)


def _ticked(prog: Program, explored: _Explored) -> set:
    """The paths of the nodes some explored run ticks (replaying each root tick's end and each
    merged state's tick with a recorder: the explorer keeps events only); a node whose
    pre-condition (_skipIf, ...) was checked was ticked, though its rule may not have run."""
    recorder = _Recorder(prog)
    checked: set[str] = set()
    for v in explored.vertices:
        if v.node[0] != _TICK:
            continue
        if isinstance(v.step, RootTicked):
            recorder.replay(v.node[1])
        elif isinstance(v.step, Await) and v.step.event.kind == "check" and \
                isinstance(v.step.event.node[1][0], str) and v.step.event.node[1][0] in PRE_CONDITIONS:
            checked.add(v.step.event.where)
    for node in explored.merged:
        if node[0] == _TICK:
            recorder.replay(node[1])
    ticked = set(recorder.ticked)
    if checked:
        stack = [prog.root]
        while stack:
            n = stack.pop()
            if _where_of(n.node) in checked:
                ticked.add(n.path)
            stack.extend(n.kids)
    return ticked


def _pos(node: Node) -> SourcePos | None:
    return SourcePos(node.file, node.line, node.column) if node.line else None


def _places(root: PNode) -> dict:
    """Every node of the expanded program by path, with its parent's path."""
    out, stack = {}, [(root, None)]
    while stack:
        n, up = stack.pop()
        out[n.path] = (n, up)
        stack.extend((k, n.path) for k in n.kids)
    return out


def _throws(explored: _Explored) -> bool:
    return any(isinstance(v.step, RootTicked) and v.step.status is None and not v.step.limited
               for v in explored.vertices)


def _labels(explored: _Explored, node: tuple) -> list:
    """The labels on the breadth-first path to `node`: outcomes, registrations, moves."""
    out = []
    while explored.parent[node] is not None:
        node, label = explored.parent[node]
        out.append(label)
    return out[::-1]


def _run_text(prog: Program, explored: _Explored, node: tuple, most: int = 6) -> str:
    """The run to `node` for people: its root ticks and executor moves, the last `most` events."""
    end = object()
    labels = [x for x in _labels(explored, node) if x is not None]     # events without a choice go by themselves
    config, phase = initial(), _TICK
    words: list[str] = []
    ticks = 0
    for label in labels + [end]:
        while True:
            s = _STEPS[phase](prog, config)
            if isinstance(s, Await) and s.event.kind == "registration":
                break
            if isinstance(s, Await) and s.options == (None,):
                words.append(describe(s.event))
                config = advance(config, None)
                continue
            break
        if label is end:
            break
        if label in KINDS:
            config = config.with_kind(s.event.node[1][1], label)
        elif isinstance(s, Await):
            words.append(describe(replace(s.event, outcome=label)))
            config = advance(config, label)
        else:
            ticks += phase == _TICK
            status = s.status.value if s.status is not None else "error"
            words.append(f"root tick {ticks} -> {status}" if phase == _TICK else phase)
            phase = {_HALTED: _TREE, _HALT: _HALT, _VISIT: _VISIT}.get(label, _TICK)
            config = s.config
    shown = words[-most:]
    return ("..., " if len(words) > most else "") + (", ".join(shown) if shown else "from the first root tick")


def _gw_successors(v: _Vertex) -> list:
    """A state's successors within one executor call (Tree::tickOnce): the outcomes of its
    events, and the next root tick after a wake-up signal; [] where the call returns."""
    if v.step is None or isinstance(v.step, Await):
        return [nxt for _, nxt in v.succ]
    return [nxt for label, nxt in v.succ if label == _WOKEN]


def _endless(document: Document, prog: Program, explored: _Explored, places: dict) -> list[RunFinding]:
    """endless: a root tick (or a Tree::tickOnce call) that never returns."""
    vs, of = explored.vertices, explored.of_node
    n = len(vs)
    succ = [[of.get(x) for x in _gw_successors(v)] for v in vs]
    # the states from which some environment gets the call to return (or not explored: assumed so)
    returns = [False] * n
    preds: list[list[int]] = [[] for _ in range(n)]
    todo = []
    for i, v in enumerate(vs):
        ends = ((isinstance(v.step, RootTicked) and not succ[i] and i not in explored.looped) or None in succ[i]
                or i in explored.cut)
        if ends:
            returns[i] = True
            todo.append(i)
        for j in succ[i]:
            if j is not None:
                preds[j].append(i)
    while todo:
        j = todo.pop()
        for i in preds[j]:
            if not returns[i]:
                returns[i] = True
                todo.append(i)
    findings: list[RunFinding] = []
    reported: set = set()
    # inside one root tick, proved by a state that came back (a 3.8 Repeat -1 over AlwaysSuccess)
    for i, (driver, ticked) in explored.looped.items():
        d, t = places[driver][0], places[ticked][0]
        if driver in reported:
            continue
        reported.add(driver)
        findings.append(RunFinding(
            _pos(d.node) or _pos(document.root), ERROR, "endless",
            f"{_name(d)} ticks {_name(t)} again and again with no event between: the root tick never returns, on "
            f"every environment once the run gets here (run: {_run_text(prog, explored, vs[i].node)})",
            _loop_hint(d)))
    # across root ticks: a wake-up signal after each, so Tree::tickOnce ticks again at once, for ever
    trapped = [i for i in range(n) if not returns[i]]
    for i in trapped:
        v = vs[i]
        if not (isinstance(v.step, RootTicked) and v.step.woken):
            continue
        emitter = _emitter(prog, v)
        if emitter is None or emitter.path in reported:
            continue
        reported.add(emitter.path)
        findings.append(RunFinding(
            _pos(emitter.node) or _pos(document.root), ERROR, "endless",
            f"{_name(emitter)} asks to be ticked again at once after every root tick (a wake-up signal) and nothing "
            f"can end the loop: Tree::tickOnce, which Nav2's BehaviorTreeEngine calls, never returns, on every "
            f"environment once the run gets here (run: {_run_text(prog, explored, v.node)})",
            _loop_hint(emitter)))
    findings += _endless_sometimes(document, prog, explored, places, succ, returns, reported)
    return findings


def _endless_sometimes(document: Document, prog: Program, explored: _Explored, places: dict, succ: list,
                       returns: list, reported: set) -> list[RunFinding]:
    """endless (warning): a loop of states within one executor call that the environment may
    keep going for ever (a leaf completing at once every time) and may also leave. Loops through
    an opaque node's own choices are its implementation's, not the tree's: left out."""
    vs = explored.vertices
    allowed = [[j for j in succ[i] if j is not None and returns[i]
                and not (isinstance(vs[i].step, Await) and vs[i].step.event.kind == "choose")]
               for i in range(len(vs))]
    findings = []
    for comp in _cycles(allowed):
        woken = [i for i in comp if isinstance(vs[i].step, RootTicked)]
        first = min(comp, key=lambda i: _depth(explored, vs[i].node))
        if woken:
            who = _emitter(prog, vs[woken[0]])
            call = "Tree::tickOnce (Nav2's BehaviorTreeEngine calls it) never returns"
        else:
            who = _driver_of(vs, comp, places)
            call = "the root tick never returns"
        if who is None or who.path in reported:
            continue
        reported.add(who.path)
        leaves = _leaves_on(explored, comp)
        findings.append(RunFinding(
            _pos(who.node) or _pos(document.root), WARNING, "endless",
            f"{_name(who)} may loop for ever within one executor call: on the runs where {leaves}, {call} "
            f"(the model does not know whether the robot can answer so; run: "
            f"{_run_text(prog, explored, vs[first].node)})",
            _loop_hint(who)))
    return findings


def _depth(explored: _Explored, node: tuple) -> int:
    d = 0
    while explored.parent[node] is not None:
        node = explored.parent[node][0]
        d += 1
    return d


def _cycles(graph: list[list[int]]) -> list[list[int]]:
    """The strongly connected components of `graph` that hold a cycle (Tarjan's, iterative)."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on: set[int] = set()
    stack: list[int] = []
    out = []
    counter = 0
    for root in range(len(graph)):
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            v, i = work.pop()
            if i == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on.add(v)
            recurse = False
            for k in range(i, len(graph[v])):
                w = graph[v][k]
                if w not in index:
                    work.append((v, k + 1))
                    work.append((w, 0))
                    recurse = True
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            if recurse:
                continue
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1 or v in graph[v]:
                    out.append(comp)
            if work:
                u = work[-1][0]
                low[u] = min(low[u], low[v])
    return out


def _emitter(prog: Program, v: _Vertex) -> PNode | None:
    """The node that emitted the wake-up signal in the root tick `v` ended."""
    recorder = _Recorder(prog)
    recorder.replay(v.node[1])
    return recorder.emitter


def _driver_of(vs: list, comp: list, places: dict) -> PNode | None:
    """The loop node of a loop inside one root tick through events: the nearest Repeat or
    RetryUntilSuccessful above the first event's node."""
    for i in comp:
        s = vs[i].step
        if not isinstance(s, Await):
            continue
        for path, (n, _) in places.items():
            if _where_of(n.node) == s.event.where and n.context == s.event.node[0]:
                up = places[path][1]
                while up is not None:
                    p = places[up][0]
                    if p.node.type in ("Repeat", "RetryUntilSuccessful"):
                        return p
                    up = places[up][1]
                return n
    return None


def _where_of(node: Node) -> str:
    if not node.line:
        return ""
    return f"{node.file + ':' if node.file else ''}{node.line}:{node.column}"


def _leaves_on(explored: _Explored, comp: list) -> str:
    """The answers that keep a loop going: each choice on it with its outcome, "C -> FAILURE"."""
    inside = set(comp)
    names = []
    for i in comp:
        v = explored.vertices[i]
        if not isinstance(v.step, Await) or v.step.options == (None,):
            continue
        for o, nxt in v.succ:
            if explored.of_node.get(nxt) in inside:
                said = describe(replace(v.step.event, outcome=o, where="", ports=()))
                if said not in names:
                    names.append(said)
    shown = "; ".join(names[:3]) + ("; ..." if len(names) > 3 else "")
    return f"the environment answers so every time ({shown})" if names else "its children answer so every time"


def _name(n: PNode) -> str:
    shown = f"{n.node.type}" + (f" \"{n.node.name}\"" if n.node.name != n.node.type else "")
    ports = " ".join(f"{k}=\"{v}\"" for k, v in n.node.ports if k in ("num_cycles", "num_attempts"))
    return shown + (f" ({ports})" if ports else "")


def _loop_hint(n: PNode) -> str:
    return ("give the loop a way out that takes time: a finite num_cycles/num_attempts, a child that returns "
            "RUNNING while it works, or a condition that can end it; or tick the tree with Tree::tickExactlyOnce")


def _endless_tree(document: Document, how: str) -> RunFinding:
    """endless-tree: no run ever finishes."""
    return RunFinding(
        _pos(document.root), WARNING, "endless-tree",
        f"no run of tree {document.main!r} ever finishes: no root tick returns SUCCESS or FAILURE, whatever its "
        f"leaves return ({how}); many robots loop so by design",
        "if the tree should end (a goal reached, a task done), give it a way to SUCCESS or FAILURE; if it loops by "
        "design, silence the rule (endless-tree)")


def _halt_safety(prog: Program, explored: _Explored, places: dict) -> list[RunFinding]:
    """halt-safety: between root ticks, a RUNNING node whose parent is not RUNNING (its parent
    finished, or was reset, without halting it: ControlNode::haltChild was not called). BT.CPP's
    own nodes halt or reset every RUNNING child before they finish (resetChildren, haltChild); an
    opaque custom node may not, as the model lets it do anything: left out (docs/lint.md)."""
    findings = []
    seen: set = set()
    for v in explored.vertices:
        if not isinstance(v.step, RootTicked):
            continue
        status = {p: s for p, s, _ in v.step.config.memory}
        for path, s in status.items():
            if s != RUNNING.value or not path or path not in places:
                continue
            up = places[path][1]
            if status.get(up) == RUNNING.value or path in seen:
                continue
            parent = places[up][0]
            if prog.rules[parent.rule] is OPAQUE:
                continue
            seen.add(path)
            child = places[path][0]
            findings.append(RunFinding(
                _pos(child.node), ERROR, "halt-safety",
                f"{_name(child)} is left RUNNING while its parent {_name(parent)} is "
                f"{status.get(up, 'IDLE')}: the parent finished without halting it, so its halt() never runs "
                f"(run: {_run_text(prog, explored, v.node)})",
                f"make {parent.node.type} halt its RUNNING children before it returns (ControlNode::haltChild / "
                f"resetChildren)"))
    return findings


def _unreachable(prog: Program, explored: _Explored, places: dict) -> list[RunFinding]:
    """unreachable, from every run of the whole tree: the topmost nodes no run ticks."""
    ticked = _ticked(prog, explored)
    return _topmost(places, lambda path: path in ticked,
                    f"all {_states(len(explored.vertices))} of the tree's runs explored, every leaf outcome possible")


def _unreachable_by_parts(prog: Program, parts: dict, places: dict) -> list[RunFinding]:
    """unreachable, from the parts: a child its parent's part never ticks (in every context)."""
    reached = {prog.root.path}
    for path in sorted(parts):                         # parents before children (pre-order paths)
        if path in reached:
            reached |= parts[path].reached
    return _topmost(places, lambda path: path in reached,
                    "decided node by node, each in every context its parent can make, every leaf outcome possible")


def _topmost(places: dict, ticked, how: str) -> list[RunFinding]:
    """A finding for each node of the document no instance of which is ticked, whose parent is
    (the topmost of an unreached subtree; a tree called twice is reached if either call is). The
    unreached children that follow it under the same parent are named in its finding."""
    ticked_xml = {id(n.node) for path, (n, _) in places.items() if ticked(path)}
    findings = []
    done: set[int] = set()
    for path, (n, up) in sorted(places.items()):
        if up is None or id(n.node) in ticked_xml or id(n.node) in done:
            continue
        parent = places[up][0]
        if id(parent.node) not in ticked_xml:
            continue                                   # below a node no run ticks: the topmost is named
        i = parent.kids.index(n)
        rest = []
        for k in parent.kids[i:]:
            if id(k.node) in ticked_xml:
                break
            rest.append(k)
            done.add(id(k.node))
        after = f" (nor the {len(rest) - 1} after it)" if len(rest) > 1 else ""
        findings.append(RunFinding(
            _pos(n.node), WARNING, "unreachable",
            f"no run ticks {_name(n)}{after}: {_why_unreached(parent, n)} ({how})",
            "remove it, or change what comes before it so that it can run"))
    return findings


_PASSING_TYPES = ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "AsyncSequence", "AsyncFallback",
                  "SequenceWithMemory", "SequenceStar", "PipelineSequence")


def _why_unreached(parent: PNode, n: PNode) -> str:
    i = parent.kids.index(n)
    if parent.node.type in _PASSING_TYPES and i > 0:
        return f"its parent {_name(parent)} never gets past {_name(parent.kids[i - 1])}"
    if parent.node.type.startswith("Switch"):
        return f"its parent {_name(parent)} never selects its case"
    return f"its parent {_name(parent)} never ticks it"


__all__ = ["RunFinding", "run_findings", "EVENTS_PER_TICK"]
