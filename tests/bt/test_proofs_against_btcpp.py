"""Proofs checked in the real runtime: every pair of trees that schemalog PROVES equal (verdict
equal and complete, default options: each Action a StatefulActionNode or re-ticked, the executor
halting the tree between root ticks and ticking it anew) must run alike in BT.CPP 4
(behaviortreepy) under the same environment. A wrong "proved" is the worst bug the prover can
have, so this drives it with pairs a reviewer would write by hand: a random tree and an edit of
it that is often, but not always, harmless (a single-child composite wrapped or unwrapped,
siblings nested or flattened, two children swapped, a node dropped, a retry count changed, an
Inverter or Force pair, a RunOnce, attributes reordered, a type changed for a near relative).

Each proved pair is run in BT.CPP for several environments (tests/bt/test_against_btcpp.py's
Draws: the k-th leaf tick takes draw k), three registrations (every action a StatefulActionNode;
every action a SimpleActionNode, SUCCESS/FAILURE only; a mixture decided per type, as one
robot registers each type once) and an executor that runs three goals on the same Tree object:
tick_exactly_once (one executeTick, the prover's root tick) until the root completes or a
seeded number of ticks, a haltTree at a seeded tick or after a goal, then the next goal. The
flat record (leaf ticks with outcomes, onHalted callbacks, root statuses, haltTree calls, the
counters that `_onHalted`/`_onSuccess`/... scripts increment on the blackboard, errors) must be
equal for the two trees.

Found by this campaign and fixed (the regression tests at the end):
- a differing root of the main tree was proved by parts in a parent's contexts, but
  Tree::haltTree halts the root twice (haltNode, then the visitor), whatever its status: an
  `_onHalted` there counts twice in BT.CPP, and `<Sequence><C0 _onHalted=../></Sequence>` was
  proved equal to `<C0 _onHalted=../>` (and compress made that rewrite); about 2% of the proved
  pairs whose root carries an `_onHalted` ran apart. The main tree's root part is now proved as
  the executor runs the whole tree.
- the prover's root tick is one executeTick, but an executor that ticks with Tree::tickOnce
  (Nav2's BehaviorTreeEngine::run) sees the executeTicks that a wake-up signal chains as one call,
  and halts only between calls: Repeat num_cycles=-1 and KeepRunningUntilFailure were proved
  equal and run apart. A root tick's end now carries the wake-up signal, and two trees must agree
  on it. The campaign ticks with tick_exactly_once; a tick_once campaign can hang inside BT.CPP
  (Repeat -1 over a leaf that keeps succeeding wakes itself up for ever in one tickOnce call).

SCHEMALOG_FUZZ=N runs N seeds (the default profile runs DEFAULT_SEEDS in about 10 s; 60,000 seeds
gave 13,529 proved pairs, each run 18 ways, without another difference).
"""

from __future__ import annotations

import os
import random
from dataclasses import dataclass, field

import pytest

from schemalog.api.behaviour_trees import prove_trees
from schemalog.bt.model import Document, Node, NodeModel
from schemalog.errors import SchemalogError
from schemalog.formats.btxml import write_bt

bt = pytest.importorskip("behaviortreepy")

from test_against_btcpp import Draws

ACTIONS = tuple(f"A{i}" for i in range(5))
CONDITIONS = tuple(f"C{i}" for i in range(3))
COUNTERS = ("h0", "h1", "h2", "h3")
MODELS = tuple(NodeModel(t, "Action") for t in ACTIONS) + tuple(NodeModel(t, "Condition") for t in CONDITIONS)
MAX_STATES = 20_000
DEFAULT_SEEDS = 3000
RUNS_PER_PAIR = 6

CONTROLS = ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory",
            "Parallel", "IfThenElse", "WhileDoElse")
DECORATORS = ("Inverter", "ForceSuccess", "ForceFailure", "RetryUntilSuccessful", "Repeat",
              "KeepRunningUntilFailure", "RunOnce")
SINGLE = ("Sequence", "Fallback", "SequenceWithMemory", "ReactiveSequence", "ReactiveFallback")


def n(t: str, *kids: Node, **attrs: str) -> Node:
    return Node(t, tuple(attrs.items()), tuple(kids))


def document(root: Node) -> Document:
    return Document((("Main", root),), "Main", MODELS)


# -- trees ------------------------------------------------------------------------------------

def _scripts(rng: random.Random, leaf: bool) -> list[tuple[str, str]]:
    """Optional `_`-attributes: counters the executor reads on the blackboard, constant or
    counter-reading pre-conditions."""
    attrs: list[tuple[str, str]] = []
    if rng.random() < 0.15:
        attrs.append(("_onHalted", f"{(c := rng.choice(COUNTERS))} := {c} + 1"))
    if rng.random() < 0.05:
        attrs.append((rng.choice(("_onSuccess", "_onFailure", "_post")), f"{(c := rng.choice(COUNTERS))} := {c} + 1"))
    if rng.random() < 0.08:
        key = rng.choice(("_skipIf", "_successIf", "_failureIf", "_while"))
        value = rng.choice(("true", "false", "false", f"{rng.choice(COUNTERS)} > 0"))
        attrs.append((key, value))
    return attrs


def gen_tree(rng: random.Random, depth: int = 0, budget: list[int] | None = None, scripts: bool = True) -> Node:
    budget = [rng.randint(3, 10)] if budget is None else budget
    budget[0] -= 1
    extra = _scripts(rng, True) if scripts else []
    leafy = depth >= 3 or budget[0] < 2 or rng.random() < (0.0, 0.4, 0.6)[min(depth, 2)]
    if leafy:
        t = rng.choice(ACTIONS + ACTIONS + CONDITIONS + ("AlwaysSuccess", "AlwaysFailure"))
        return Node(t, tuple(extra))
    if rng.random() < 0.35:
        t = rng.choice(DECORATORS)
        kid = gen_tree(rng, depth + 1, budget, scripts)
        if t == "RetryUntilSuccessful":
            extra.append(("num_attempts", rng.choice(("1", "2", "3", "-1"))))
        elif t == "Repeat":
            extra.append(("num_cycles", rng.choice(("1", "2", "3", "-1"))))
        return Node(t, tuple(extra), (kid,))
    t = rng.choice(CONTROLS)
    lo = 2 if t in ("IfThenElse", "WhileDoElse") else 1
    hi = 3 if t in ("IfThenElse", "WhileDoElse") else max(lo, min(3, budget[0]))
    kids = tuple(gen_tree(rng, depth + 1, budget, scripts) for _ in range(rng.randint(lo, hi)))
    if t == "Parallel":
        extra += [("success_count", str(rng.randint(-1, len(kids)))), ("failure_count", str(rng.randint(-1, len(kids))))]
    return Node(t, tuple(extra), kids)


# -- edits ------------------------------------------------------------------------------------

def _paths(node: Node, path: tuple = ()) -> list[tuple]:
    out = [path]
    for i, c in enumerate(node.children):
        out += _paths(c, path + (i,))
    return out


def _get(node: Node, path: tuple) -> Node:
    for i in path:
        node = node.children[i]
    return node


def _put(node: Node, path: tuple, new: Node) -> Node:
    if not path:
        return new
    kids = list(node.children)
    kids[path[0]] = _put(kids[path[0]], path[1:], new)
    return node.with_children(tuple(kids))


def _retype(node: Node, t: str, attrs=None) -> Node:
    return Node(t, node.attrs if attrs is None else tuple(attrs), node.children)


NEAR = {"Sequence": ("SequenceWithMemory", "ReactiveSequence"),
        "SequenceWithMemory": ("Sequence", "ReactiveSequence"),
        "ReactiveSequence": ("Sequence", "SequenceWithMemory"),
        "Fallback": ("ReactiveFallback",), "ReactiveFallback": ("Fallback",),
        "IfThenElse": ("WhileDoElse",), "WhileDoElse": ("IfThenElse",),
        "ForceSuccess": ("ForceFailure", "Inverter"), "ForceFailure": ("ForceSuccess", "Inverter"),
        "Inverter": ("ForceSuccess", "ForceFailure"),
        "KeepRunningUntilFailure": ("Repeat",), "Repeat": ("KeepRunningUntilFailure", "RetryUntilSuccessful"),
        "RetryUntilSuccessful": ("Repeat",), "RunOnce": ("Inverter",)}


def edit(rng: random.Random, root: Node) -> tuple[str, Node]:
    """One edit at a random node: (its name, the edited tree)."""
    path = rng.choice(_paths(root))
    x = _get(root, path)
    kind = rng.choice(["wrap", "wrap", "unwrap", "pair", "nest", "flatten", "swap", "drop", "count",
                       "runonce", "attrs", "retype", "retype", "script"])
    new = None
    if kind == "wrap":
        new = n(rng.choice(SINGLE + ("ForceSuccess", "Inverter", "KeepRunningUntilFailure")), x) if rng.random() < 0.2 \
            else n(rng.choice(SINGLE), x)
        if rng.random() < 0.2:
            new = Node(new.type, (("_onHalted", f"{(c := rng.choice(COUNTERS))} := {c} + 1"),), new.children)
    elif kind == "unwrap" and len(x.children) == 1:
        new = x.children[0]
    elif kind == "pair":
        new = rng.choice([lambda: n("Inverter", n("Inverter", x)),
                          lambda: n("ForceSuccess", n("ForceSuccess", x)),
                          lambda: n("ForceFailure", n("ForceSuccess", x)),
                          lambda: n("ForceSuccess", n("ForceFailure", x)),
                          lambda: n("Inverter", n("ForceSuccess", x)),
                          lambda: n("RetryUntilSuccessful", x, num_attempts="1"),
                          lambda: n("Repeat", x, num_cycles="1")])()
    elif kind == "nest" and len(x.children) >= 2 and x.type in SINGLE + ("Parallel",):
        i = rng.randrange(len(x.children) - 1)
        j = rng.randint(i + 1, len(x.children))
        inner_type = x.type if rng.random() < 0.8 else rng.choice(SINGLE)
        kids = x.children[:i] + (n(inner_type, *x.children[i:j]),) + x.children[j:]
        new = x.with_children(kids)
    elif kind == "flatten" and x.children:
        kids: list[Node] = []
        for c in x.children:
            if c.type == x.type and c.children and rng.random() < 0.7 and not c.attrs:
                kids += c.children
            else:
                kids.append(c)
        new = x.with_children(tuple(kids))
    elif kind == "swap" and len(x.children) >= 2:
        i, j = rng.sample(range(len(x.children)), 2)
        kids = list(x.children)
        kids[i], kids[j] = kids[j], kids[i]
        new = x.with_children(tuple(kids))
    elif kind == "drop" and len(x.children) >= 2 and x.type not in ("IfThenElse", "WhileDoElse"):
        i = rng.randrange(len(x.children))
        new = x.with_children(x.children[:i] + x.children[i + 1:])
    elif kind == "count" and x.type in ("RetryUntilSuccessful", "Repeat", "Parallel"):
        attrs = dict(x.attrs)
        key = {"RetryUntilSuccessful": "num_attempts", "Repeat": "num_cycles"}.get(x.type) or \
            rng.choice(("success_count", "failure_count"))
        attrs[key] = rng.choice(("-1", "0", "1", "2", "3"))
        new = _retype(x, x.type, attrs.items())
    elif kind == "runonce":
        new = n("RunOnce", x) if rng.random() < 0.8 else n("RunOnce", x, then_skip="false")
    elif kind == "attrs" and len(x.attrs) >= 2:
        attrs = list(x.attrs)
        rng.shuffle(attrs)
        new = _retype(x, x.type, attrs)
    elif kind == "retype" and x.type in NEAR:
        t = rng.choice(NEAR[x.type])
        attrs = [(k, v) for k, v in x.attrs if k.startswith("_")]
        if t == "RetryUntilSuccessful":
            attrs.append(("num_attempts", rng.choice(("1", "-1"))))
        elif t == "Repeat":
            attrs.append(("num_cycles", rng.choice(("1", "-1"))))
        new = _retype(x, t, attrs)
        if (t in DECORATORS) != (x.type in DECORATORS) or (t in DECORATORS and len(x.children) != 1):
            new = None
    elif kind == "script":
        attrs = [(k, v) for k, v in x.attrs if not k.startswith("_")] if rng.random() < 0.5 \
            else list(x.attrs) + [("_skipIf", "false")] if "_skipIf" not in dict(x.attrs) else list(x.attrs)
        new = _retype(x, x.type, attrs)
    if new is None:
        return "none", root
    return kind, _put(root, path, new)


# -- BT.CPP, run as an executor does ----------------------------------------------------------

@dataclass
class Plan:
    """What the executor does, decided by a seed: for each goal, the root tick after which it
    halts the tree (or None: it ticks until the root completes or `limit`), and whether it
    halts the tree after a completed goal."""

    goals: list = field(default_factory=list)     # (limit, halt_at or None, halt_after)

    @classmethod
    def seeded(cls, seed: int, goals: int = 3) -> Plan:
        rng = random.Random(seed ^ 0x5EED)
        return cls([(rng.randint(1, 10), rng.choice([None, None, rng.randint(1, 6)]), rng.random() < 0.4)
                    for _ in range(goals)])


def run_btcpp(xml: str, draws: Draws, plan: Plan, registration: dict, tick: str = "tick_exactly_once") -> list:
    """The record of running `xml` in BT.CPP under the plan: each action type registered as
    `registration[type]` ('stateful' or 'sync')."""
    S = bt.NodeStatus
    record: list = []
    k = [0]

    def outcome(options):
        d = draws[k[0]]
        k[0] += 1
        return options[d % len(options)]

    def action(t, sync):
        def ticked(_node):
            o = outcome((S.SUCCESS, S.FAILURE) if sync else (S.SUCCESS, S.FAILURE, S.RUNNING))
            record.append(("tick", t, o.name))
            return o

        def halted(_node):
            record.append(("halted", t))
        return ticked, halted

    def condition(t):
        def ticked(_node):
            o = outcome((S.SUCCESS, S.FAILURE))
            record.append(("tick", t, o.name))
            return o
        return ticked

    factory = bt.BehaviorTreeFactory()
    for t in ACTIONS:
        ticked, halted = action(t, registration[t] == "sync")
        if registration[t] == "sync":
            factory.register_simple_action(t, ticked)
        else:
            factory.register_simple_stateful_action(t, ticked, ticked, halted)
    for t in CONDITIONS:
        factory.register_simple_condition(t, condition(t))
    try:
        tree = factory.create_tree_from_text(xml)
    except Exception as err:                              # noqa: BLE001 - BT.CPP's load error
        return [("load error", str(err).split("\n")[0][:60])]
    board = tree.root_blackboard()
    for c in COUNTERS:
        board.set_int(c, 0)
    seen = {c: 0 for c in COUNTERS}

    def counters():
        now = {c: board.get_int(c) for c in COUNTERS}
        if now != seen:
            record.append(("counters", tuple(sorted(now.items()))))
            seen.update(now)

    try:
        for goal, (limit, halt_at, halt_after) in enumerate(plan.goals):
            record.append(("goal", goal))
            for i in range(1, limit + 1):
                status = getattr(tree, tick)()
                record.append(("root", status.name))
                counters()
                if status in (S.SUCCESS, S.FAILURE):
                    if halt_after:
                        tree.halt_tree()
                        record.append(("haltTree",))
                        counters()
                    break
                if halt_at == i:
                    tree.halt_tree()
                    record.append(("haltTree",))
                    counters()
                    break
            else:
                tree.halt_tree()                          # a goal cut short: cancelled
                record.append(("haltTree",))
                counters()
    except Exception:                              # noqa: BLE001 - BT.CPP's tick error
        record.append(("error",))
    return record


REGISTRATIONS = ("stateful", "sync", "mixed")


def registration(kind: str, seed: int) -> dict:
    if kind != "mixed":
        return {t: kind for t in ACTIONS}
    rng = random.Random(seed ^ 0xAC7)
    return {t: rng.choice(("stateful", "sync")) for t in ACTIONS}


def differences(xml_a: str, xml_b: str, seed: int, runs: int = RUNS_PER_PAIR,
                tick: str = "tick_exactly_once") -> list[str]:
    """Each (registration, seed) under which the two files run apart in BT.CPP."""
    found = []
    for r in range(runs):
        s = seed * 1000 + r
        rng = random.Random(s)
        draws = Draws([rng.randrange(6) for _ in range(rng.randint(0, 12))], s)
        plan = Plan.seeded(s)
        for kind in REGISTRATIONS:
            reg = registration(kind, s)
            a, b = run_btcpp(xml_a, draws, plan, reg, tick), run_btcpp(xml_b, draws, plan, reg, tick)
            if a != b:
                found.append(f"{kind} {reg} {draws} {plan}\n  a: {a}\n  b: {b}")
    return found


# -- the campaign -----------------------------------------------------------------------------

@dataclass
class Stats:
    generated: int = 0
    proved: int = 0
    refuted: int = 0
    unknown: int = 0
    refused: int = 0
    runs: int = 0
    edits: dict = field(default_factory=dict)


def _no_root_on_halted(root: Node) -> Node:
    """The root as drawn; SCHEMALOG_FUZZ_NO_ROOT_ON_HALTED=1 strips its `_onHalted` (what the
    campaign did to look past test_on_halted_at_the_root_is_not_proved_equal's bug, now fixed)."""
    if not os.environ.get("SCHEMALOG_FUZZ_NO_ROOT_ON_HALTED"):
        return root
    return Node(root.type, tuple((k, v) for k, v in root.attrs if k != "_onHalted"), root.children)


def pair(seed: int) -> tuple[str, Node, Node]:
    rng = random.Random(seed)
    root = gen_tree(rng, scripts=rng.random() < 0.5)
    kind, edited = edit(rng, root)
    if rng.random() < 0.3:
        k2, edited = edit(rng, edited)
        kind = f"{kind}+{k2}"
    if rng.random() < 0.5:
        root, edited = edited, root
    return kind, _no_root_on_halted(root), _no_root_on_halted(edited)


def campaign(seeds, stats: Stats, tick: str = "tick_exactly_once") -> list[str]:
    failures = []
    for seed in seeds:
        kind, a, b = pair(seed)
        if a == b:
            continue
        stats.generated += 1
        try:
            v = prove_trees(document(a), document(b), max_states=MAX_STATES)
        except SchemalogError:                            # a file the reader refuses: no verdict
            stats.refused += 1
            continue
        if not v.complete:
            stats.unknown += 1
            continue
        if not v.equal:
            stats.refuted += 1
            continue
        stats.proved += 1
        stats.edits[kind] = stats.edits.get(kind, 0) + 1
        xa, xb = write_bt(document(a)), write_bt(document(b))
        stats.runs += RUNS_PER_PAIR * len(REGISTRATIONS)
        found = differences(xa, xb, seed, tick=tick)
        if found:
            failures.append(f"seed {seed} ({kind}): {v.reason[:120]}\n{xa}\n{xb}\n" + found[0])
    return failures


def _seeds() -> range:
    return range(int(os.environ.get("SCHEMALOG_FUZZ", DEFAULT_SEEDS)))


def test_every_proved_pair_runs_alike_in_btcpp():
    stats = Stats()
    failures = campaign(_seeds(), stats)
    print(f"\n{stats}")
    assert stats.proved > 0
    assert not failures, f"{len(failures)} proved pairs run apart in BT.CPP:\n" + "\n\n".join(failures[:3])


# -- what the campaign found --------------------------------------------------------------------

HALTS = (("_onHalted", "h0 := h0 + 1"),)
WRAPPED = n("Sequence", Node("C0", HALTS))          # <Sequence><C0 _onHalted=".."/></Sequence>
BARE = Node("C0", HALTS)                            # <C0 _onHalted=".."/>


def _halt_tree_counts(root: Node) -> int:
    """h0 after one goal (C0 SUCCESS) and one Tree::haltTree in BT.CPP."""
    factory = bt.BehaviorTreeFactory()
    factory.register_simple_condition("C0", lambda _node: bt.NodeStatus.SUCCESS)
    for t in ACTIONS:
        factory.register_simple_action(t, lambda _node: bt.NodeStatus.SUCCESS)
    tree = factory.create_tree_from_text(write_bt(document(root)))
    tree.root_blackboard().set_int("h0", 0)
    assert tree.tick_exactly_once() == bt.NodeStatus.SUCCESS
    tree.halt_tree()
    return tree.root_blackboard().get_int("h0")


def test_on_halted_at_the_root_runs_twice_under_halt_tree_in_btcpp():
    # Tree::haltTree (src/bt_factory.cpp) calls rootNode()->haltNode(), whatever the root's
    # status, then haltNode on every node (applyRecursiveVisitor): the root's _onHalted runs
    # twice; a child's once (its parent's halt halts a child only if RUNNING, ControlNode::haltChild)
    assert _halt_tree_counts(BARE) == 2
    assert _halt_tree_counts(WRAPPED) == 1
    assert differences(write_bt(document(WRAPPED)), write_bt(document(BARE)), 0, runs=2)


def test_the_whole_tree_prover_refutes_it():
    from schemalog.bt.prove import prove_equal

    v = prove_equal(document(WRAPPED), document(BARE), max_states=MAX_STATES, max_events_per_tick=10_000, halts=True)
    assert v.complete and not v.equal, v.reason


def test_on_halted_at_the_root_is_not_proved_equal():
    v = prove_trees(document(WRAPPED), document(BARE), max_states=MAX_STATES)
    assert not (v.equal and v.complete), v.reason


def test_compress_keeps_a_root_whose_removal_doubles_an_on_halted():
    from schemalog.api.behaviour_trees import compress_tree

    small = compress_tree(document(WRAPPED))
    assert not differences(write_bt(document(WRAPPED)), write_bt(small.compressed), 0, runs=2)


# Tree::tickOnce (ONCE_UNLESS_WOKEN_UP, src/bt_factory.cpp Tree::tickRoot) runs executeTick again,
# in the same call, while the root is RUNNING and a node emitted the wake-up signal; Nav2's
# BehaviorTreeEngine::run calls tickOnce in its loop and haltTree on a cancel between two calls.
# Repeat(-1) emits it after a child that succeeded from IDLE; KeepRunningUntilFailure does not.
KRUF = n("KeepRunningUntilFailure", Node("C0"))
REPEAT = n("Repeat", Node("C0"), num_cycles="-1")


def test_repeat_for_ever_and_keep_running_until_failure_are_told_apart_by_the_wake_up_signal():
    v = prove_trees(document(KRUF), document(REPEAT), max_states=MAX_STATES)
    assert not v.equal and "wake-up signal" in v.reason, v.reason
    draws = Draws([0, 0, 0, 1], 0)                   # C0: SUCCESS, SUCCESS, SUCCESS, FAILURE
    plan = Plan([(3, 1, False), (3, None, False)])   # goal 1 cancelled after its first call
    reg = registration("stateful", 0)
    # one executeTick at a time they run alike; tickOnce chains Repeat's ticks in one call, and
    # the cancel after it finds the two trees in different places
    assert run_btcpp(write_bt(document(KRUF)), draws, plan, reg) == run_btcpp(write_bt(document(REPEAT)), draws, plan, reg)
    a = run_btcpp(write_bt(document(KRUF)), draws, plan, reg, tick="tick_once")
    b = run_btcpp(write_bt(document(REPEAT)), draws, plan, reg, tick="tick_once")
    assert a != b
