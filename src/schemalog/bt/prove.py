"""Prove two behaviour trees equal under BT.CPP 4 semantics, or refute them with a shortest
counterexample (docs/semantics.md, "Behaviour trees (BT.CPP 4 semantics)").

    pair        = (Config, Config)          both trees between two events, after the same choices
    Verdict     = Verdict(equal, complete, states, reason, counterexample)
    Counterexample = Counterexample(choices, ticks_a, ticks_b, difference)
    TickTrace   = TickTrace(events, status)  one root tick: its events, the root's status
                                             (None: the tick where the trees part, unfinished)

Both trees run under one environment: the i-th event of each gets the same outcome. The product
is explored breadth-first from the initial pair, memoised on pairs (of the interrupted ticks as
data, semantics._continuation, where it can be frozen; else of configurations); a pair whose next events
differ (kind, node identity, choices offered), or whose root ticks end differently, refutes.
The root is ticked again while it returns RUNNING; after SUCCESS, FAILURE or SKIPPED the run
ends, as Tree::tickWhileRunning does (src/bt_factory.cpp, Tree::tickRoot), unless `halts`: then
the executor may also call Tree::haltTree between any two root ticks and tick the tree anew. `equal` with
`complete` is a proof; `equal` without it only says no difference was found within the limits.
"""

from __future__ import annotations

import random
from collections import deque
from dataclasses import dataclass, replace
from collections.abc import Mapping

from schemalog.bt.congruence import abstract
from schemalog.bt.model import Document, Node, walk
from schemalog.memory import CeilingReached, near_ceiling
from schemalog.bt.semantics import (ACTION, KINDS, OPAQUE, RESETTING_PARENTS, RETICKED_ACTION, RUNNING,
                                    STATEFUL_ACTION, SYNC_ACTION, Await, Config, Event, Program, RootTicked, Rule, Status,
                                    _rule_key, advance, call_identity, halt_step, halt_tree_step, initial, program, step,
                                    subtree_id, table_for, visit_step)


@dataclass(frozen=True)
class TickTrace:
    """One root tick as a tree ran it: its events and the root's status (None: unfinished)."""

    events: tuple[Event, ...]
    status: Status | None
    error: str = ""
    move: str = ""                    # not a root tick: "halt" (by its parent), "haltTree", "visit"
    woken: bool = False               # it emitted the wake-up signal (tickOnce ticks again at once)


@dataclass(frozen=True)
class Counterexample:
    """The environment's choices that tell the trees apart, and what each tree did under them."""

    choices: tuple
    ticks_a: tuple[TickTrace, ...]
    ticks_b: tuple[TickTrace, ...]
    difference: str
    kinds: tuple = ()                  # ((type, "re-ticked" | "stateful"), ...): the registrations it needs


@dataclass(frozen=True)
class Verdict:
    """Whether the trees are equal, whether that was exhausted (a proof), and why."""

    equal: bool
    complete: bool
    states: int
    reason: str
    counterexample: Counterexample | None = None
    thrown: str = ""                  # an error both trees throw in some run (BT.CPP's tick would)
    registered: frozenset = frozenset()   # action types whose registration changed a run explored
    assumed: str = ""                 # what the verdict covers of what the XML leaves open, for people
    under: str = ""                   # the BT.CPP version(s) it was proved under, for people ("" : 4 alone)


def _difference(sa: Await | RootTicked, sb: Await | RootTicked) -> str:
    """Why two steps differ, or ''."""
    if isinstance(sa, Await) and isinstance(sb, Await):
        ea, eb = sa.event, sb.event
        if (ea.kind, ea.node) != (eb.kind, eb.node):
            return f"the next event differs: a {describe(ea)}, b {describe(eb)}"
        if sa.options != sb.options:
            return f"{describe(ea)} may have {_options(sa.options)} in a, {_options(sb.options)} in b"
        return ""
    if isinstance(sa, RootTicked) and isinstance(sb, RootTicked):
        if sa.status != sb.status or bool(sa.error) != bool(sb.error):
            return f"the root tick ends with {_end(sa)} in a, {_end(sb)} in b"
        if sa.woken != sb.woken:
            # Tree::tickOnce (Nav2's executor) ticks the root again within the same call after a
            # wake-up signal, so a haltTree between the two ticks is possible in one tree only
            woke = "a" if sa.woken else "b"
            return (f"the root tick ends with {_end(sa)} in both, but only {woke}'s asks to be ticked again at "
                    f"once (a wake-up signal: Tree::tickOnce ticks it again within the same call)")
        return ""
    if isinstance(sa, Await):
        return f"a goes on with {describe(sa.event)}, b's root tick ends with {_end(sb)}"
    return f"a's root tick ends with {_end(sa)}, b goes on with {describe(sb.event)}"


def _fewer(sa: Await | RootTicked, sb: Await | RootTicked) -> bool:
    """Whether `b` waits for the event `a` waits for, with outcomes `a` offers too (fewer or the same)."""
    return (isinstance(sa, Await) and isinstance(sb, Await) and (sa.event.kind, sa.event.node) ==
            (sb.event.kind, sb.event.node) and set(sb.options) <= set(sa.options))


def _end(s: RootTicked) -> str:
    return s.status.value if s.status is not None else f"an error ({s.error})"


def _options(options: tuple) -> str:
    return "/".join(_outcome(o) for o in options)


def _pairs(count: int) -> str:
    return f"{count} pair{'' if count == 1 else 's'} of states"


def _outcome(o: object) -> str:
    if isinstance(o, Status):
        return o.value
    if isinstance(o, bool):
        return "true" if o else "false"
    if isinstance(o, int):
        return f"case {o + 1}" if o >= 0 else str(o)
    return "" if o is None else str(o)


def prove_equal(a: Document, b: Document, *, max_states: int, max_events_per_tick: int,
                rules: Mapping[str, Rule] | None = None, contextual: bool = False,
                merge: bool = True, unreset: bool = True, programs: tuple[Program, Program] | None = None,
                halts: bool = False, subset: bool = False) -> Verdict:
    """Explore both trees under every environment; equal when no environment tells them apart.

    `contextual`: the roots stand for two subtrees under any parent, which between two root
    ticks may tick again, halt a RUNNING root (haltChild) or tick a finished or halted one
    anew, its memory kept (RunOnce, RoundRobin). Equal so, the subtrees can replace each other
    anywhere: a parent sees only their statuses, and their events are the same.
    `unreset=False`: the parent resets a finished subtree before it ticks it again (one of
    semantics.RESETTING_PARENTS), so that move is left out.
    `merge=False`: memoise on configurations only, never on interrupted ticks (for checking).
    `programs`: run these for `a` and `b` (bt/congruence.py's abstractions of them).
    `halts`: the executor may call Tree::haltTree at any point between root ticks, and tick the
    tree anew after it finished or was halted (what Nav2's navigators do: a cancelled goal, a
    haltTree after every goal, the next goal on the same tree): the roots are then halted so, or
    (contextual) visited by haltTree's visitor, besides the other moves. Without it, a run ends
    when the root finishes (Tree::tickWhileRunning, once).
    `subset`: prove only that every run of `b` is a run of `a` (trace inclusion): where both
    wait for the same event, `b` may offer fewer outcomes than `a` (a Condition where `a` has an
    Action), and only `b`'s are explored; everything else must be equal, as without it."""
    once = not contextual and not halts
    pa, pb = programs or _programs(a, b, rules, once)
    start = (_TICK, initial(), initial())
    parent: dict[tuple, tuple | None] = {start: None}
    seen: set = set()
    queue = deque([start])
    limit = ""
    thrown = ""                        # an error both trees' ticks throw (BT.CPP's would too)
    registered: set[str] = set()
    while queue:
        node = queue.popleft()
        phase, ca, cb = node
        move = _STEPS[phase]
        sa, sb = move(pa, ca), move(pb, cb)
        asked = _asked(sa) or _asked(sb)
        if asked is not None:
            # One registration runs both trees (the same robot loads either file): decide it for
            # both at once, each way, however far apart the two trees meet the question
            registered.add(asked)
            for kind in KINDS:
                nxt = (phase, ca.with_kind(asked, kind), cb.with_kind(asked, kind))
                if nxt not in parent:
                    parent[nxt] = (node, _Kind(asked, kind))
                    queue.append(nxt)
            continue
        key = (phase, _key(sa, ca), _key(sb, cb)) if merge else node
        if key in seen:                                   # the same interrupted ticks: merged
            continue
        if len(seen) >= max_states:
            limit = limit or f"{max_states} states explored (max_states)"
            break
        seen.add(key)
        if len(seen) & 1023 == 0 and near_ceiling():    # stop while there is room to say so
            raise CeilingReached("near the memory ceiling")
        diff = _difference(sa, sb)
        if diff and subset and _fewer(sa, sb):
            diff = ""
        if diff:
            kinds = ca.kinds
            # replayed label by label, events without a choice included, so that each run stops
            # at the event where the two part, even one that offers no choice (a `time` event)
            labels = _labels(parent, node)
            choices = tuple(x for x in labels if x not in _MOVES and x is not _NONE)
            cex = Counterexample(choices, _trace_moves(pa, labels, kinds), _trace_moves(pb, labels, kinds),
                                 diff, kinds)
            return Verdict(False, True, len(seen), diff, cex, registered=frozenset(registered))
        successors: list[tuple[tuple, object]] = []
        if isinstance(sa, Await):
            if len(sa.config.pending) >= max_events_per_tick:
                limit = limit or f"a root tick reached {max_events_per_tick} events (max_events_per_tick)"
                continue
            successors = [((phase, advance(ca, o), advance(cb, o)),
                           _NONE if sa.options == (None,) else o) for o in (sb.options if subset else sa.options)]
        elif sa.limited or sb.limited:
            limit = limit or sa.error or sb.error
        elif sa.status is None and sa.error:
            thrown = thrown or sa.error
        elif sa.status is RUNNING:
            successors = [((_TICK, sa.config, sb.config), _ROOT)]
            if contextual:
                successors.append(((_HALT, sa.config, sb.config), _HALT))
            elif halts:
                successors.append(((_TREE, sa.config, sb.config), _TREE))
        elif (contextual or halts) and sa.status is not None:
            successors = [((_TICK, sa.config, sb.config), _AGAIN)]
            if contextual and unreset and sa.kept is not None and sb.kept is not None:
                successors.append(((_TICK, sa.kept, sb.kept), _KEEP))
            if halts:
                successors.append(((_VISIT if contextual else _TREE, sa.config, sb.config),
                                   _VISIT if contextual else _TREE))
        for nxt, label in successors:
            if nxt not in parent:
                parent[nxt] = (node, label)
                queue.append(nxt)
    explored = len(seen)
    if limit:
        return Verdict(True, False, explored,
                       f"no difference found, but not a proof: {limit}", registered=frozenset(registered))
    if subset:
        return Verdict(True, True, explored, f"every run of b is a run of a, under every environment "
                                             f"({_pairs(explored)}, exhausted)", thrown=thrown,
                       registered=frozenset(registered))
    where = ("in every context and " if contextual else
             "as an executor runs them (ticked, halted by haltTree between any two ticks, ticked anew) and "
             if halts else "")
    # equal, errors included; but a run that ends in an error is no run a robot finishes
    errors = f"; in both, some runs end in an error, as BT.CPP's tick throws: {thrown}" if thrown else ""
    return Verdict(True, True, explored,
                   f"equal {where}under every environment ({_pairs(explored)}, exhausted){errors}",
                   thrown=thrown, registered=frozenset(registered))


def _programs(a: Document, b: Document, rules: Mapping[str, Rule] | None, once: bool) -> tuple[Program, Program]:
    """The two documents' programs; of two versions (3.8 against 4), with the custom nodes of the
    4 one returning no SKIPPED that the 3.8 one cannot: one robot's node, ported (the verdict says so)."""
    pa, pb = program(a, rules, once=once), program(b, rules, once=once)
    if a.version != b.version:
        pa, pb = replace(pa, skips=False), replace(pb, skips=False)
    return pa, pb


_TICK = "tick"                                        # the phases of a key: ticking the roots,
_HALT = "halt"                                        # or halting them (contextual),
_TREE = "haltTree"                                    # the executor's Tree::haltTree (halts),
_VISIT = "visit"                                      # its visitor reaching the roots (contextual, halts)
_AGAIN = "again"                                      # the label of "a finished root is ticked anew"
_KEEP = "keep"                                        # "a finished root is ticked again, its status
                                                      # not reset" (WhileDoElse's condition child)


def _key(s: Await | RootTicked, config: Config) -> object:
    """What identifies a side's state for memoisation: the interrupted tick, else the config."""
    if isinstance(s, Await) and s.key is not None:
        return s.key
    return config


_ROOT = object()                                      # the label of "the root is ticked again"
_NONE = object()                                      # the label of an event without a choice


_MOVES = (_ROOT, _HALT, _AGAIN, _KEEP, _TREE, _VISIT)
_STEPS = {_TICK: step, _HALT: halt_step, _TREE: halt_tree_step, _VISIT: visit_step}


@dataclass(frozen=True)
class _Kind:
    """The label of "the action type is registered so" (both trees at once)."""

    type: str
    kind: str


def _asked(s: Await | RootTicked) -> str | None:
    """The action type whose registration the step waits for, or None."""
    return s.event.node[1][1] if isinstance(s, Await) and s.event.kind == "registration" else None


def _labels(parent: dict, key: tuple) -> tuple:
    """Every label on the breadth-first path to `key`: outcomes, moves, events without a choice."""
    out = []
    while parent[key] is not None:
        key, label = parent[key]
        if not isinstance(label, _Kind):
            out.append(label)
    return tuple(reversed(out))


def _trace_moves(prog: Program, labels: tuple, kinds: tuple = ()) -> tuple[TickTrace, ...]:
    """Run `prog` along `labels` (outcomes, and at each root tick's end the parent's move: tick
    again, halt, tick anew) up to the last label's step; a halt shows as a tick with status IDLE."""
    ticks: list[TickTrace] = []
    config, phase, events = Config(kinds=kinds), _TICK, []
    todo = list(labels)
    while True:
        s = _STEPS[phase](prog, config)
        if isinstance(s, Await):
            if not todo:                      # the step the search stopped at: where the trees part
                ticks.append(TickTrace(tuple(events) + (s.event,), None))
                return tuple(ticks)
            label = todo.pop(0)
            if s.options == (None,):
                events.append(s.event)
                config = advance(config, None)
                continue
            events.append(replace(s.event, outcome=label))
            config = advance(config, label)
            continue
        ticks.append(TickTrace(s.events, s.status, s.error, "" if phase is _TICK else phase, s.woken))
        events = []
        if not todo:
            return tuple(ticks)
        move = todo.pop(0)
        phase = move if move in (_HALT, _TREE, _VISIT) else _TICK
        config = s.kept if move is _KEEP and s.kept is not None else s.config


def _trace(prog: Program, choices: tuple, max_ticks: int | None = None,
           kinds: tuple = ()) -> tuple[TickTrace, ...]:
    """Run `prog` under `choices` (and the registrations `kinds`), root tick by root tick, up to
    the first event left unanswered, the end of the run, `max_ticks` root ticks, or (no
    max_ticks) the end of the first root tick that leaves no choice unused."""
    ticks: list[TickTrace] = []
    config, i = Config(kinds=kinds), 0
    events: list[Event] = []
    while True:
        s = step(prog, config)
        if isinstance(s, Await):
            if s.options == (None,):                       # no choice: answered by itself
                events.append(s.event)
                config = advance(config, None)
                continue
            if i == len(choices):
                ticks.append(TickTrace(tuple(events) + (s.event,), None))
                return tuple(ticks)
            outcome = choices[i]
            events.append(replace(s.event, outcome=outcome))
            config, i = advance(config, outcome), i + 1
            continue
        ticks.append(TickTrace(s.events, s.status, s.error, woken=s.woken))
        events = []
        if s.status is not RUNNING or len(ticks) == max_ticks or (max_ticks is None and i == len(choices)):
            return tuple(ticks)
        config = s.config


def replay(document: Document, choices: tuple, *,
           rules: Mapping[str, Rule] | None = None) -> tuple[TickTrace, ...]:
    """Run the document under the given outcomes (events without a choice take none), root tick
    by root tick, until the run ends or the outcomes run out: at the end of a root tick, or in
    one, which then ends with the event waiting for an answer (status None)."""
    return _trace(program(document, rules), tuple(choices))


def describe(event: Event) -> str:
    """An event as a Nav2 user reads it: node type, name, ports, outcome."""
    context, identity = event.node
    where = "".join(f"SubTree {c[1]}{_ports(c[2])} > " for c in context)
    head, detail = identity
    if event.kind in ("script", "check") and isinstance(detail, str):
        what = f"{head} `{detail}`"                    # a script attribute and its code
    else:
        name = f" \"{event.label}\"" if event.label and event.label != head else ""
        what = f"{head}{name}{_ports(event.ports or detail)}"       # as the element writes them
    verb = {"tick": "tick", "halt": "halt", "check": "check", "script": "run script",
            "time": "time at", "choose": "choice of"}.get(event.kind, event.kind)
    outcome = _outcome(event.outcome)
    if isinstance(event.outcome, int) and not isinstance(event.outcome, bool):
        if event.kind == "choose":
            outcome = f"tick child {event.outcome + 1}"
        elif head.startswith("Switch") and head[6:].isdigit() and event.outcome == int(head[6:]):
            outcome = "default"
    place = f" at {event.where}" if event.where else ""
    return f"{verb} {where}{what}{place}" + (f" -> {outcome}" if outcome else "")


def _ports(ports) -> str:
    if not isinstance(ports, tuple) or not ports:
        return ""
    return " " + " ".join(f"{k}=\"{v}\"" for k, v in ports)


def explain(verdict: Verdict, under: str = "") -> str:
    """The verdict for people: a proof, a bounded search, or the counterexample tick by tick;
    `under` (what it was proved under) follows the verdict's first words."""
    if verdict.equal:
        covers = f"\nIt {verdict.assumed}." if verdict.assumed else ""
        return ("proved equal" if verdict.complete else "NOT proved") + under + ": " + verdict.reason + covers + "\n"
    cex = verdict.counterexample
    lines = [f"refuted after {verdict.states} states{under}: {verdict.reason}"
             + (f" ({verdict.assumed})" if verdict.assumed else "")]
    if cex is None:
        return lines[0] + "\n"
    lines.append("environment's choices: " + (", ".join(_outcome(c) or "-" for c in cex.choices) or "none"))
    count = max(len(cex.ticks_a), len(cex.ticks_b))
    k = 0
    while k < count:
        # a run of root ticks alike (a RUNNING action waited for) is shown once: "x 6"
        same = k + 1
        while same < count and _tick_again(cex, same, k):
            same += 1
        before = cex.ticks_a[k - 1] if 0 < k <= len(cex.ticks_a) else None
        anew = (" (the tree ticked anew, what its nodes keep kept)" if before is not None and before.status
                is not RUNNING and k < len(cex.ticks_a) and not cex.ticks_a[k].move else "")
        move = cex.ticks_a[k].move if k < len(cex.ticks_a) else ""
        if move:
            lines.append(f"then {_MOVE_HEADS[move]}:")
        else:
            lines.append(f"root tick {k + 1}{anew}:" if same == k + 1 else
                         f"root ticks {k + 1}-{same} (x {same - k}, each alike){anew}:")
        for side, ticks in (("a", cex.ticks_a), ("b", cex.ticks_b)):
            if k >= len(ticks):
                continue
            t = ticks[k]
            for j, e in enumerate(t.events):
                waiting = t.status is None and not t.error and j == len(t.events) - 1
                lines.append(f"  {side}: {describe(e)}" + ("   <- the trees part here" if waiting else ""))
            if t.move:
                lines.append(f"  {side}: {_MOVE_WORDS[t.move]}")
            elif t.status is not None or t.error:
                woke = " (a wake-up signal: Tree::tickOnce ticks it again at once)" if t.woken else ""
                lines.append(f"  {side}: root -> {t.status.value if t.status else 'error: ' + t.error}{woke}")
        k = same
    return "\n".join(lines) + "\n"


_MOVE_HEADS = {_HALT: "its parent halts the root", _TREE: "the executor halts the tree",
               _VISIT: "Tree::haltTree's visitor reaches the root"}
_MOVE_WORDS = {_HALT: "root halted by its parent (haltChild)", _TREE: "tree halted (Tree::haltTree)",
               _VISIT: "root reached by Tree::haltTree's visitor (haltNode on each node)"}


def _tick_again(cex: Counterexample, k: int, first: int) -> bool:
    """Whether root tick k is root tick `first` again, in both trees."""
    return all(k < len(t) and first < len(t) and t[k] == t[first] and t[k].status is not None
               for t in (cex.ticks_a, cex.ticks_b))


def simulate(document: Document, seed: int, root_ticks: int, *,
             rules: Mapping[str, Rule] | None = None,
             restart: bool = True) -> tuple[tuple[Event, ...], int, tuple[Status | None, ...]]:
    """Tick the tree `root_ticks` times under a seeded random environment; count node ticks."""
    prog = program(document, rules)
    rng = random.Random(seed)
    events: list[Event] = []
    statuses: list[Status | None] = []
    node_ticks = 0
    config = initial()
    while len(statuses) < root_ticks:
        s = step(prog, config)
        if isinstance(s, Await):
            config = advance(config, rng.choice(s.options))
            continue
        events.extend(s.events)
        node_ticks += s.node_ticks
        statuses.append(s.status)
        if s.status is RUNNING:
            config = s.config
        elif restart and s.status is not None:
            config = s.config                             # tickWhileRunning called again
        else:
            break
    return tuple(events), node_ticks, tuple(statuses)


# ---------------------------------------------------------------------------------------------
# Proofs by parts: where two documents differ only in some subtrees

def differing_parts(a: Node, b: Node, da: Document | None = None,
                    db: Document | None = None) -> list[tuple[Node, Node]]:
    """The pairs of subtrees where `a` (of document `da`) and `b` (of `db`) part, top-down: below
    two nodes alike (_alike) the children are compared pairwise; elsewhere the two nodes are a
    part. Equal trees of documents whose SubTree calls resolve alike have none."""
    empty = Document((), "")
    return [(na, nb) for na, nb, _ in _parts(a, b, None, da or empty, db or empty)]


def _alike(a: Node, b: Node, da: Document, db: Document) -> bool:
    """Whether two nodes, their children aside, are one node to BT.CPP: type, form, number of
    children, attributes by name and, for a SubTree call, its remapping as each document resolves it."""
    # BT.CPP reads attributes by name, so their order alone is no difference (and no part for the
    # prover to explore); a SubTree call's remapping takes its model's defaults, which two
    # documents may declare differently
    if (a.type, a.form, len(a.children)) != (b.type, b.form, len(b.children)) or sorted(a.attrs) != sorted(b.attrs):
        return False
    return subtree_id(a) is None or call_identity(a, da) == call_identity(b, db)


def _parts(a: Node, b: Node, parent: str | None, da: Document,
           db: Document) -> list[tuple[Node, Node, str | None]]:
    """differing_parts, each with the type of the parent it stands under (None: a tree's root)."""
    if not _alike(a, b, da, db):
        return [(a, b, parent)]
    under = a.type if not a.form else None            # a generic-form node is a custom one: opaque
    return [part for ca, cb in zip(a.children, b.children) for part in _parts(ca, cb, under or "\0custom", da, db)]


def _context(main_root: bool, parent: str | None, rules: Mapping[str, Rule] | None, halts: bool) -> dict:
    """How a differing part is explored: the main tree's root is the whole tree, which the executor
    runs (its haltTree calls haltNode on the root twice: once itself, once by the visitor); any
    other part stands under a parent, in every context that parent can make."""
    if main_root:
        return dict(halts=halts)
    return dict(contextual=True, unreset=_unreset(parent, rules), halts=halts)


def _unreset(parent: str | None, rules: Mapping[str, Rule] | None) -> bool:
    """Whether a parent of this type may tick a finished child again without resetting it (a
    type the user's rules define may)."""
    return parent is not None and (parent not in RESETTING_PARENTS or parent in (rules or {}))


def _part(document: Document, node: Node) -> Document:
    """`node` as the main tree of a document that still holds every tree it may call."""
    key = "\0part"                                   # an ID no XML document can hold
    return Document(document.trees + ((key, node),), key, document.models, document.includes, document.version,
                    document.unmarked)


def _kind_differences(a: Document, b: Document, rules: Mapping[str, Rule] | None) -> list[str]:
    """The node types that get another rule in each document, as "T (a: .., b: ..)": a type may
    be a Condition in one document's TreeNodesModel and unknown in the other's, and then two
    identical subtrees do not run alike (a part compared in one document is not in the other)."""
    words = {"<action>": "an Action", "<condition>": "a Condition", "<opaque>": "opaque"}

    def key(n: Node, d: Document) -> str:
        k = _rule_key(n, d, table_for(d, rules))
        return "<action>" if k == "<opaque>" and not n.children else k   # the same rule for a leaf

    differ: dict[str, str] = {}
    for d in (a, b):
        for _, root in d.trees:
            for n in walk(root):
                ka, kb = key(n, a), key(n, b)
                if ka != kb and n.type not in differ:
                    differ[n.type] = f"{n.type} (a: {words.get(ka, ka)}, b: {words.get(kb, kb)})"
    return list(differ.values())


def prove_by_parts(a: Document, b: Document, *, max_states: int, max_events_per_tick: int,
                   rules: Mapping[str, Rule] | None = None, halts: bool = True, known: dict | None = None) -> Verdict:
    """Prove two documents equal through the subtrees where they differ, each equal in every
    context its parent can make (a congruence: a parent sees a subtree only through its statuses, and the events
    are the same), and where that fails or a document's trees differ, by exploring both whole:
    a refutation is always one of the whole trees. The verdict says which registrations of the
    actions it covers (`assumed`). `halts` (the default): as an executor may run the trees, halted
    by Tree::haltTree between any two root ticks and ticked anew (prove_equal); without it, each
    ticked until it finishes, once, never halted (Tree::tickWhileRunning). `known`: the verdicts
    (with the subtrees taken whole) of parts proved already, by (id(a's), id(b's)) subtree, as
    bt/diff.py proves them in the same contexts; each one used is removed from it."""
    verdict = _prove_by_parts(a, b, max_states=max_states, max_events_per_tick=max_events_per_tick, rules=rules,
                              halts=halts, known=known if known is not None else {})
    return replace(verdict, assumed=assumed(a, b, rules, verdict, halts))


def open_registrations(documents: tuple[Document, ...], rules: Mapping[str, Rule] | None = None) -> list[str]:
    """The action types whose registration the XML leaves open (ACTION, or an unknown leaf),
    in document order: a SyncActionNode and a StatefulActionNode load alike and run apart."""
    found: dict[str, None] = {}
    for d in documents:
        table = {**table_for(d, rules), "<opaque>": OPAQUE, "<action>": ACTION}
        for _, root in d.trees:
            for n in walk(root):
                if not n.children and n.type != "SubTree" and n.form != "SubTree" \
                        and table.get(_rule_key(n, d, table)) in (ACTION, OPAQUE):
                    found.setdefault(n.type)
    return list(found)


def _and(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _names(types) -> str:
    types = sorted(types)
    return ", ".join(types[:4]) + (f" and {len(types) - 4} more" if len(types) > 4 else "")


def assumed(a: Document, b: Document, rules: Mapping[str, Rule] | None, verdict: Verdict,
            halts: bool = True) -> str:
    """What the verdict covers of what the XML leaves open (how the executor runs the tree, how
    each action is registered), in a reader's words."""
    run = ("covers an executor that halts the tree (Tree::haltTree) between any two ticks and ticks it "
           "anew for the next goal" if halts else
           "assumes the tree is ticked until it finishes, once, and never halted (--run-once)")
    if verdict.equal:
        rest = _registrations(a, b, rules, verdict)
        return run + ("; it " + rest if rest else "")
    return _registrations(a, b, rules, verdict) or ("" if halts else run)


def _registrations(a: Document, b: Document, rules: Mapping[str, Rule] | None, verdict: Verdict) -> str:
    """What the verdict covers of the registrations the XML leaves open, in a reader's words."""
    # the action types the trees use whose registration --semantics or a --profile gives
    used = {n.type for d in (a, b) for _, root in d.trees for n in walk(root)}
    fixed = sorted(t for t, r in (rules or {}).items()
                   if r in (SYNC_ACTION, STATEFUL_ACTION, RETICKED_ACTION) and t in used)
    given = (f"; it takes the registration{'s' if len(fixed) > 1 else ''} of {_names(fixed)} from --semantics or "
             f"--profile" if fixed else "")
    if not verdict.equal:              # a run under one registration tells the files apart
        cex = verdict.counterexample
        kinds = cex.kinds if cex is not None else ()
        stateful = [t for t, k in kinds if k == "stateful"]
        again = [t for t, k in kinds if k != "stateful"]
        parts = ([f"{_and(stateful)} registered as {'a StatefulActionNode' if len(stateful) == 1 else 'StatefulActionNodes'}"]
                 if stateful else []) + ([f"{_and(again)} run again when ticked finished (SyncActionNode, "
                                          f"ActionNodeBase)"] if again else [])
        return "a run with " + " and ".join(parts) if parts else ""
    open_ = open_registrations((a, b), rules)
    if not open_:
        return given[len("; it "):]
    n = len(open_)
    what = (f"every registration of the {n} action types the XML leaves open ({_names(open_)}), each a "
            f"StatefulActionNode or one run again when ticked finished (SyncActionNode, ActionNodeBase)" if n > 1
            else f"both registrations of {open_[0]}, which the XML leaves open: a StatefulActionNode or one run "
                 f"again when ticked finished (SyncActionNode, ActionNodeBase)")
    differ = (f"; the two run apart where a parent ticks a finished action again unreset, as runs here do "
              f"for {_names(verdict.registered)}: both were explored" if verdict.registered else
              "; the two run apart only where a parent ticks a finished action again unreset")
    return f"covers {what}{differ}{given}"


def _places(parts: list[tuple[Node, Node, str | None]]) -> str:
    """The differing subtrees by place, as "a: Type at file:line:col, b: ..." (three at most)."""
    from schemalog.bt.semantics import _where

    def one(node: Node) -> str:
        where = _where(node)
        return f"{node.type}{' at ' + where if where else ''}"
    shown = "; ".join(f"a: {one(na)}, b: {one(nb)}" for na, nb, _ in parts[:3])
    return shown + (f"; and {len(parts) - 3} more" if len(parts) > 3 else "")


def _prove_by_parts(a: Document, b: Document, *, max_states: int, max_events_per_tick: int,
                    rules: Mapping[str, Rule] | None = None, halts: bool = True, known: dict | None = None) -> Verdict:
    ids_a, ids_b = [i for i, _ in a.trees], [i for i, _ in b.trees]
    spent = 0                                 # max_states is one budget: the parts' and the whole's
    differ = _kind_differences(a, b, rules)
    # two versions give one node type two rules: the parts alike in both are no longer alike
    # (a Repeat of 3.8 is not one of 4), so trees of two versions are explored whole
    if ids_a == ids_b and a.main == b.main and not differ and a.version == b.version:
        parts = [p for (_, ra), (_, rb) in zip(a.trees, b.trees) for p in _parts(ra, rb, None, a, b)]
        proved = True
        thrown = ""
        registered: frozenset = frozenset()
        taken = 0
        for na, nb, parent in parts:
            v, k = (known or {}).pop((id(na), id(nb)), None) or _congruent(
                _part(a, na), _part(b, nb), max_states=max_states - spent, max_events_per_tick=max_events_per_tick,
                rules=rules, **_context(na is a.root, parent, rules, halts))
            spent += v.states
            taken += k
            thrown = thrown or v.thrown
            registered |= v.registered
            if not (v.equal and v.complete):
                proved = False
                break
        if proved:
            what = (f"{len(parts)} differing subtree{'s' if len(parts) != 1 else ''} ({_places(parts)}), each "
                    f"equal in every context its parent can make and under every environment" if parts
                    else "the documents' trees are the same to BT.CPP (attributes by name, each SubTree "
                         "call's remapping with its model's defaults)")
            errors = (f"; in both, a differing subtree's runs may end in an error, as BT.CPP's tick throws: "
                      f"{thrown}" if thrown else "")
            if taken:
                what += (f", {taken} subtree{'s' if taken != 1 else ''} identical in both taken whole "
                         f"(congruence)")
            return Verdict(True, True, spent, f"equal by parts: {what} ({_pairs(spent)}, exhausted){errors}",
                           thrown=thrown, registered=registered)
    whole, _ = _congruent(a, b, max_states=max_states - spent, max_events_per_tick=max_events_per_tick, rules=rules,
                          halts=halts)
    if differ and not whole.equal and a.version == b.version:
        # the usual cause: one file carries a TreeNodesModel (compress -o writes --nodes' models
        # into its output) and the other is read without it
        note = (f" (the two documents give node types different rules: {', '.join(differ[:3])}"
                f"{', ...' if len(differ) > 3 else ''}; read both with the same --nodes file)")
        whole = replace(whole, reason=whole.reason + note)
    if not spent:
        return whole
    reason = whole.reason
    if whole.equal and not whole.complete and "(max_states)" in reason:
        reason = (f"no difference found, but not a proof: {max_states} states explored (max_states; "
                  f"{spent} on the differing parts in every context, {whole.states} on the whole trees)")
    return replace(whole, states=spent + whole.states, reason=reason)


def _congruent(a: Document, b: Document, *, max_states: int, max_events_per_tick: int,
               rules: Mapping[str, Rule] | None = None, **explore) -> tuple[Verdict, int]:
    """prove_equal(a, b, ...) through the congruence first (bt/congruence.py, docs/semantics.md,
    "Congruence"): the maximal subtrees identical in both, taken whole as one opaque node each,
    explored within half the budget. A proof so is a proof of a and b. Otherwise (the abstract
    pair told apart, perhaps spuriously, or a limit) the concrete pair is explored with the rest,
    so a refutation is always of the trees as they are, and shortest. `states` counts both. The
    second value: how many subtrees a proof took whole (0 without one)."""
    once = not explore.get("contextual", False) and not explore.get("halts", False)
    pa, pb = _programs(a, b, rules, once)
    # a subtree identical in two documents read under two versions need not run alike (an opaque
    # node returns SKIPPED under 4 only): taken whole only within one version
    taken = abstract(pa, pb) if a.version == b.version else None
    opts = dict(max_events_per_tick=max_events_per_tick, rules=rules, **explore)
    if taken is None:
        return prove_equal(a, b, max_states=max_states, programs=(pa, pb), **opts), 0
    v = prove_equal(a, b, max_states=max_states // 2, programs=(taken.a, taken.b), **opts)
    if v.equal and v.complete:
        where = "in every context and " if explore.get("contextual") else ""
        # an error inside a subtree taken whole is not looked for: it is thrown alike in both
        # (docs/semantics.md, "Congruence"); one outside it may come from a status the subtree
        # never returns, so "may"
        errors = f"; in both, some runs may end in an error, as BT.CPP's tick throws: {v.thrown}" if v.thrown else ""
        n = taken.subtrees
        return replace(v, reason=f"equal {where}under every environment, {n} subtree{'s' if n != 1 else ''} identical "
                                 f"in both ({taken.nodes} nodes) taken whole, each as one node (congruence; "
                                 f"{_pairs(v.states)}, exhausted){errors}"), n
    rest = prove_equal(a, b, max_states=max_states - v.states, programs=(pa, pb), **opts)
    reason = rest.reason
    if rest.equal and not rest.complete and "(max_states)" in reason:
        reason = (f"no difference found, but not a proof: {max_states} states explored (max_states; {v.states} "
                  f"with the identical subtrees taken whole, {rest.states} on the trees as they are)")
    return replace(rest, states=v.states + rest.states, reason=reason, registered=v.registered | rest.registered), 0


def compress_proved(document: Document, *, max_states: int, max_events_per_tick: int,
                    rules: Mapping[str, Rule] | None = None, keep_names: bool = True, halts: bool = True):
    """Compress `document` (bt/compress.py) keeping only rewrites proved where they stand: each
    part the rewrites changed is proved in its parent's context, a refuted one is restored as it
    was (its nodes kept) and the rest compressed again. Return the Compressed document and
    prove_by_parts' verdict on it (None when nothing was rewritten). `keep_names`: remove no
    node that carries a `name` attribute (the Compressed document's `kept` lists them)."""
    from schemalog.bt.compress import compress

    keep: set[int] = set()
    while True:
        result = compress(document, frozenset(keep), keep_names)
        if not result.rewrites:
            return result, None
        refuted = []
        for (_, ra), (_, rb) in zip(document.trees, result.document.trees):
            for na, nb, parent in _parts(ra, rb, None, document, result.document):
                v = prove_equal(_part(document, na), _part(result.document, nb), max_states=max_states,
                                max_events_per_tick=max_events_per_tick, rules=rules,
                                **_context(na is document.root, parent, rules, halts))
                if v.complete and not v.equal:
                    refuted.append(na)
        grown = keep | {id(n) for na in refuted for n in walk(na)}
        if grown == keep:
            break
        keep = grown
    return result, prove_by_parts(document, result.document, max_states=max_states,
                                  max_events_per_tick=max_events_per_tick, rules=rules, halts=halts)
