"""A differential test of our BT.CPP 4 semantics (src/schemalog/bt/semantics.py) against the
real runtime (behaviortreepy, BT.CPP 4.x).

Hypothesis generates small trees over the builtin nodes that need no blackboard and no timer,
with stateful actions A0..A4 and conditions C0..C2 as leaves. An environment is a list of draws:
the k-th leaf tick, in either runtime, takes draw k (actions: (SUCCESS, FAILURE, RUNNING)[d % 3],
conditions: (SUCCESS, FAILURE)[d % 2]; the listed draws, then those of random.Random(seed)). Both runtimes
are ticked root tick by root tick until the root completes (or MAX_ROOT_TICKS), and the flat
sequence of ("tick", type, outcome) / ("halt", type) events and the root statuses tick by tick
must be equal; a run still RUNNING after MAX_ROOT_TICKS is halted (Tree::haltTree, halt_tree_step) and
its halt events compared too. An error (BT.CPP throws at load or tick; the model's RootTicked
with an error) must happen in both, after the same events.

The actions run as StatefulActionNodes (register_simple_stateful_action: RUNNING, onHalted)
against the rule STATEFUL_ACTION, and as SimpleActionNodes (register_simple_action: SUCCESS or
FAILURE) against SYNC_ACTION.

Root ticks: BT.CPP 4's Tree::tickOnce (ONCE_UNLESS_WOKEN_UP) calls the root's executeTick again
within the same call while the root is RUNNING and a node emitted the wake-up signal (Retry,
Repeat, SequenceWithMemory ... after a synchronous child); Tree::tickWhileRunning's inner loop
does the same (src/bt_factory.cpp, Tree::tickRoot). Our model's RootTicked is one executeTick,
so BT.CPP is driven with tick_exactly_once (EXACTLY_ONCE: one executeTick per call), which is
the grouping of executeTick calls that tickWhileRunning makes, observed one by one.
"""

from __future__ import annotations

import os
import random

import pytest
from hypothesis import HealthCheck, assume, event, given, note, settings
from hypothesis import strategies as st

from schemalog.bt.model import Document, Node, NodeModel
from schemalog.bt.semantics import (ACTION_OUTCOMES, CONDITION_OUTCOMES, RETICKED_ACTION, STATEFUL_ACTION, SYNC_ACTION, Await,
                                    Status, advance, halt_tree_step, initial, program, step)
from schemalog.formats.btxml import write_bt

try:
    import behaviortreepy as bt
except ImportError:                                     # pragma: no cover - CI installs it
    if os.environ.get("CI"):
        raise                                           # in CI a missing runtime is a failure
    pytest.skip("behaviortreepy (BT.CPP 4's Python binding) is not installed", allow_module_level=True)

ACTIONS = tuple(f"A{i}" for i in range(5))
CONDITIONS = tuple(f"C{i}" for i in range(3))
MAX_ROOT_TICKS = 12
MAX_NODES = 12

# -- trees ------------------------------------------------------------------------------------

CONTROLS = ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory",
            "Parallel", "IfThenElse", "WhileDoElse")
DECORATORS = ("Inverter", "ForceSuccess", "ForceFailure", "RetryUntilSuccessful", "Repeat",
              "KeepRunningUntilFailure", "RunOnce")


def act(t: str) -> Node:
    return Node(t)                  # <A0/>: BT.CPP 4.8 refuses <Action ID="A0"/> ("Unknown node type")


def cond(t: str) -> Node:
    return Node(t)


def n(t: str, *kids: Node, **attrs: str) -> Node:
    return Node(t, tuple(attrs.items()), tuple(kids))


def size(node: Node) -> int:
    return 1 + sum(size(c) for c in node.children)


def _tree(draw, depth: int, budget: list[int]) -> Node:
    """A node at `depth` (the root at 0, leaves by depth 3); budget[0] counts the nodes left."""
    budget[0] -= 1
    leaf_weight = (0, 2, 3)[depth] if depth < 3 else 1
    kinds = ["leaf"] * leaf_weight + (["control"] * 2 + ["decorator"] if depth < 3 and budget[0] >= 2 else [])
    kind = draw(st.sampled_from(kinds or ["leaf"]))
    if kind == "leaf":
        leaf = draw(st.sampled_from(ACTIONS + CONDITIONS + ("AlwaysSuccess", "AlwaysFailure")))
        return act(leaf) if leaf in ACTIONS else cond(leaf) if leaf in CONDITIONS else n(leaf)
    if kind == "decorator":
        t = draw(st.sampled_from(DECORATORS))
        kid = _tree(draw, depth + 1, budget)
        if t == "RetryUntilSuccessful":
            return n(t, kid, num_attempts=str(draw(st.integers(1, 3))))
        if t == "Repeat":
            return n(t, kid, num_cycles=str(draw(st.integers(1, 3))))
        return n(t, kid)
    t = draw(st.sampled_from(CONTROLS))
    lo = 2 if t in ("IfThenElse", "WhileDoElse") else 1
    hi = max(lo, min(3, budget[0]))
    count = draw(st.integers(lo, hi))
    kids = tuple(_tree(draw, depth + 1, budget) for _ in range(count))
    if t == "Parallel":
        # literal thresholds, in range or (rarely) out of it: BT.CPP then throws at the tick
        sc = draw(st.integers(-1, len(kids) + 1))
        fc = draw(st.integers(-1, len(kids) + 1))
        return n(t, *kids, success_count=str(sc), failure_count=str(fc))
    return n(t, *kids)


@st.composite
def trees(draw) -> Node:
    """A tree of depth <= 3 (the root at depth 0) and about MAX_NODES nodes at most."""
    return _tree(draw, 0, [MAX_NODES])


MODELS = tuple(NodeModel(t, "Action") for t in ACTIONS) + tuple(NodeModel(t, "Condition") for t in CONDITIONS)


def document(root: Node) -> Document:
    return Document((("Main", root),), "Main", MODELS)


# -- the two runtimes ------------------------------------------------------------------------

class Draws:
    """An environment: the listed draws, then the draws of random.Random(seed)."""

    def __init__(self, listed: list[int], seed: int) -> None:
        self.listed, self.seed = list(listed), seed
        rng = random.Random(seed)
        self.rest = [rng.randrange(6) for _ in range(400)]

    def __getitem__(self, k: int) -> int:
        return self.listed[k] if k < len(self.listed) else self.rest[(k - len(self.listed)) % 400]

    def __repr__(self) -> str:
        return f"Draws({self.listed}, seed={self.seed})"


def draw_at(draws: Draws, k: int) -> int:
    return draws[k]


def run_btcpp(xml: str, draws: Draws, sync: bool = False) -> tuple[list[tuple], list[str]]:
    """Tick `xml` in BT.CPP: the events and the root statuses ('ERROR' when it throws). The
    actions are StatefulActionNodes, or with `sync` SimpleActionNodes (SUCCESS/FAILURE only:
    a SyncActionNode must not return RUNNING, and has no halt callback)."""
    events: list[tuple] = []
    k = [0]
    statuses: list[str] = []
    S = bt.NodeStatus

    def outcome(options):
        d = draw_at(draws, k[0])
        k[0] += 1
        return options[d % len(options)]

    def action(t):
        def tick(_node):
            o = outcome((S.SUCCESS, S.FAILURE) if sync else (S.SUCCESS, S.FAILURE, S.RUNNING))
            events.append(("tick", t, o.name))
            return o

        def halted(_node):
            events.append(("halt", t, None))
        return tick, halted

    def condition(t):
        def tick(_node):
            o = outcome((S.SUCCESS, S.FAILURE))
            events.append(("tick", t, o.name))
            return o
        return tick

    factory = bt.BehaviorTreeFactory()
    for t in ACTIONS:
        tick, halted = action(t)
        if sync:
            factory.register_simple_action(t, tick)
        else:
            factory.register_simple_stateful_action(t, tick, tick, halted)
    for t in CONDITIONS:
        factory.register_simple_condition(t, condition(t))
    try:
        tree = factory.create_tree_from_text(xml)
    except Exception as err:                              # noqa: BLE001 - BT.CPP's load error
        return events, [f"LOAD ERROR {err}"]
    for _ in range(MAX_ROOT_TICKS):
        try:
            status = tree.tick_exactly_once()
        except Exception as err:                          # noqa: BLE001 - BT.CPP's tick error
            statuses.append(f"ERROR {err}")
            break
        statuses.append(status.name)
        if status in (S.SUCCESS, S.FAILURE):
            break
    if statuses and statuses[-1] == "RUNNING":
        tree.halt_tree()                                  # the run is cut short: halt it
        statuses.append("HALTED")
    done = list(events)
    events.append("the tree's destructor halts it again: not recorded")
    return done, statuses


def run_model(root: Node, draws: Draws, sync: bool = False,
              stateful_rule: bool = True) -> tuple[list[tuple], list[str]]:
    """Drive our semantics the same way: each leaf tick takes the next draw, a halt None."""
    # A0..A4 as StatefulActionNodes: STATEFUL_ACTION (a completed action its parent did not
    # reset returns its last status, no callback); as SimpleActionNodes: SYNC_ACTION
    # (re-ticked every time, SUCCESS/FAILURE only); else RETICKED_ACTION (RUNNING too)
    stateful = not sync and stateful_rule
    rule = STATEFUL_ACTION if stateful else SYNC_ACTION if sync else RETICKED_ACTION
    prog = program(document(root), rules={t: rule for t in ACTIONS})
    events: list[tuple] = []
    statuses: list[str] = []
    k = 0
    config = initial()
    while len(statuses) < MAX_ROOT_TICKS:
        s = step(prog, config)
        if isinstance(s, Await):
            if s.event.kind == "tick":
                t = s.event.node[1][0]
                assert set(s.options) == set(ACTION_OUTCOMES if t in ACTIONS and not sync else CONDITION_OUTCOMES), s
                options = CONDITION_OUTCOMES if t in CONDITIONS or sync else ACTION_OUTCOMES
                answer = options[draw_at(draws, k) % len(options)]
                k += 1
            else:
                assert s.event.kind == "halt", s.event
                answer = None
            config = advance(config, answer)
            continue
        for e in s.events:
            kind, t = e.kind, e.node[1][0]
            events.append((kind, t, e.outcome.name if e.outcome is not None else None))
        if s.status is None:
            statuses.append(f"ERROR {s.error}")
            break
        statuses.append(s.status.name)
        if s.status.name in ("SUCCESS", "FAILURE"):
            break
        config = s.config
    if statuses and statuses[-1] == "RUNNING":           # Tree::haltTree
        while True:
            h = halt_tree_step(prog, config)
            if isinstance(h, Await):
                assert h.event.kind == "halt", h.event
                events.append(("halt", h.event.node[1][0], None))
                config = advance(config, None)
                continue
            break
        statuses.append("HALTED")
    return events, statuses


def compare(root: Node, draws: Draws, sync: bool = False) -> None:
    xml = write_bt(document(root))
    note(xml)
    b_events, b_status = run_btcpp(xml, draws, sync)
    m_events, m_status = run_model(root, draws, sync)
    b_err = bool(b_status) and "ERROR" in b_status[-1]
    m_err = bool(m_status) and m_status[-1].startswith("ERROR")
    report = (f"\n{xml}\ndraws={draws} sync={sync}\n"
              f"BT.CPP events: {b_events}\nBT.CPP roots:  {b_status}\n"
              f"model events:  {m_events}\nmodel roots:   {m_status}")
    event(f"BT.CPP ends {b_status[-1].split(' ')[0] if b_status else '-'} after {len(b_status)} root ticks")
    event(f"{len(b_events)} leaf events" if len(b_events) < 5 else ">= 5 leaf events")
    if b_err:
        event(f"BT.CPP: {b_status[-1][:70]}")
    if b_err or m_err:
        # an error in either: both must end in one, after the same events and root statuses
        assert b_err and m_err, "one runtime threw, the other did not" + report
        assert b_events == m_events and b_status[:-1] == m_status[:-1], report
        return
    assert (b_events, b_status) == (m_events, m_status), report


# -- the property ------------------------------------------------------------------------------

@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(root=trees(), listed=st.lists(st.integers(0, 5), max_size=20), seed=st.integers(0, 2**32 - 1))
def test_semantics_agree_with_btcpp(root, listed, seed):
    """Stateful actions (RUNNING, halted) against STATEFUL_ACTION."""
    assume(size(root) <= MAX_NODES)
    compare(root, Draws(listed, seed))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(root=trees(), listed=st.lists(st.integers(0, 5), max_size=20), seed=st.integers(0, 2**32 - 1))
def test_semantics_agree_with_btcpp_sync_actions(root, listed, seed):
    """Synchronous actions (SUCCESS/FAILURE, re-ticked each time) against the default Action rule."""
    assume(size(root) <= MAX_NODES)
    compare(root, Draws(listed, seed), sync=True)


# -- regressions and the facts the driver relies on ------------------------------------------

def _tick_statuses(xml: str, outcomes: list, mode: str) -> list[str]:
    it = iter(outcomes)
    factory = bt.BehaviorTreeFactory()
    factory.register_simple_stateful_action("A0", lambda _n: next(it), lambda _n: next(it), None)
    tree = factory.create_tree_from_text(xml)
    statuses: list[str] = []
    while not statuses or statuses[-1] == "RUNNING":
        statuses.append(getattr(tree, mode)().name)
    return statuses


def test_tick_once_ticks_again_after_a_wake_up_and_tick_exactly_once_does_not():
    """Tree::tickRoot (src/bt_factory.cpp): ONCE_UNLESS_WOKEN_UP re-runs executeTick while the
    root is RUNNING and the wake-up signal is set (RetryNode emits it after a failure from IDLE);
    EXACTLY_ONCE does not. The model's root tick is one executeTick: tick_exactly_once."""
    xml = write_bt(document(n("RetryUntilSuccessful", act("A0"), num_attempts="2")))
    S = bt.NodeStatus
    assert _tick_statuses(xml, [S.FAILURE, S.SUCCESS], "tick_once") == ["SUCCESS"]
    assert _tick_statuses(xml, [S.FAILURE, S.SUCCESS], "tick_exactly_once") == ["RUNNING", "SUCCESS"]
    assert run_model(n("RetryUntilSuccessful", act("A0"), num_attempts="2"),
                     Draws([1, 0], 0))[1] == ["RUNNING", "SUCCESS"]


WHILE_DO = n("WhileDoElse", act("A0"), act("A0"))


def test_a_completed_stateful_action_returns_its_last_status_without_a_callback():
    """Found by this test: WhileDoElse does not reset its condition child, so on the next tick
    a StatefulActionNode there returns its last status (StatefulActionNode::tick, src/action_node.cpp,
    `return prev_status;`) with no callback. RETICKED_ACTION runs it again (as a SyncActionNode
    or an ActionNodeBase does); STATEFUL_ACTION models the stateful leaf; the default Action rule
    covers both (the environment's registration event)."""
    draws = Draws([0, 2, 0, 0], 0)                   # condition SUCCESS, do RUNNING; then SUCCESS
    xml = write_bt(document(WHILE_DO))
    expected = ([("tick", "A0", "SUCCESS"), ("tick", "A0", "RUNNING"), ("tick", "A0", "SUCCESS")],
                ["RUNNING", "SUCCESS"])
    assert run_btcpp(xml, draws) == expected
    assert run_model(WHILE_DO, draws) == expected                       # STATEFUL_ACTION
    default = run_model(WHILE_DO, draws, stateful_rule=False)           # RETICKED_ACTION
    assert default == (expected[0][:2] + [("tick", "A0", "SUCCESS"), ("tick", "A0", "SUCCESS")],
                       expected[1])


def test_a_completed_sync_action_is_ticked_again():
    draws = Draws([0, 0, 0, 0], 0)
    xml = write_bt(document(WHILE_DO))
    assert run_btcpp(xml, draws, sync=True) == run_model(WHILE_DO, draws, sync=True) == (
        [("tick", "A0", "SUCCESS")] * 2, ["SUCCESS"])


@pytest.mark.parametrize("root, listed", [
    # a run cut short at MAX_ROOT_TICKS is halted (Tree::haltTree / halt_tree_step)
    (n("RetryUntilSuccessful", n("KeepRunningUntilFailure", act("A0")), num_attempts="2"), [2] * 12),
    # the RUNNING child of a ReactiveSequence moves back to the first: the second is halted
    (n("ReactiveSequence", act("A0"), act("A1")), [0, 2, 2, 0, 0, 0]),
    (n("ReactiveFallback", n("Inverter", act("A0")), act("A1")), [0, 2, 2, 1, 0, 0]),
    # RunOnce's SKIPPED after it completed, under a Sequence and a Parallel
    (n("Repeat", n("Sequence", n("RunOnce", act("A0")), cond("C0")), num_cycles="3"), [0, 0, 0, 0]),
    (n("Parallel", n("RunOnce", act("A0")), act("A1"), success_count="-1", failure_count="1"), [2, 2, 0, 0]),
    # thresholds a Parallel cannot reach: BT.CPP throws at the tick, the model errs too
    (n("Parallel", act("A0"), success_count="3", failure_count="1"), [0]),
    (n("WhileDoElse", act("A0"), act("A0")), [0, 2, 0]),
])
def test_regressions(root, listed):
    draws = Draws(listed, 0)
    xml = write_bt(document(root))
    b, m = run_btcpp(xml, draws), run_model(root, draws)
    if b[1] and "ERROR" in b[1][-1]:
        assert m[1][-1].startswith("ERROR") and (b[0], b[1][:-1]) == (m[0], m[1][:-1]), (b, m)
    else:
        assert b == m, (b, m)


# -- compressed trees in the real runtime -----------------------------------------------------

@st.composite
def compressible(draw) -> Node:
    """A generated tree wrapped the way hand-merged trees look, so each rewrite has work: a
    Sequence grouped inside a Sequence, a single-child Fallback, a double Inverter, nested Forces."""
    root = draw(trees())
    other = draw(st.sampled_from(ACTIONS + CONDITIONS))
    shape = draw(st.sampled_from(["flatten", "single", "inverters", "forced", "all"]))
    if shape in ("flatten", "all"):
        kind = draw(st.sampled_from(["Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback"]))
        root = n(kind, n(kind, root, Node(other)), Node(draw(st.sampled_from(ACTIONS))))
    if shape in ("single", "all"):
        root = n(draw(st.sampled_from(["Sequence", "Fallback", "SequenceWithMemory"])), root)
    if shape in ("inverters", "all"):
        root = n("Inverter", n("Inverter", root))
    if shape in ("forced", "all"):
        root = n(draw(st.sampled_from(["ForceSuccess", "ForceFailure"])),
                 n(draw(st.sampled_from(["ForceSuccess", "ForceFailure"])), root))
    return root


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(root=compressible(), listed=st.lists(st.integers(0, 5), max_size=20), seed=st.integers(0, 2**32 - 1))
def test_a_compressed_tree_runs_as_its_original_in_btcpp(root, listed, seed):
    # Issue 33: the compressed document, written as BT.CPP XML with the original node types,
    # ticked in BT.CPP under the same leaf outcomes as the original, makes the same leaf ticks,
    # halts and root statuses. Issue 48: the actions here are StatefulActionNodes, which the
    # XML does not say; compress keeps only what is proved for every registration (the raw
    # rewrites removed a Sequence(A0) under WhileDoElse, which had reset a finished A0).
    from schemalog.api.behaviour_trees import compress_tree

    original = document(root)
    small = compress_tree(original)
    event(f"rewrites kept: {bool(small.rewrites)}")
    assert small.verdict is None or small.verdict.equal and small.verdict.complete
    draws = Draws(listed, seed)
    note(write_bt(small.compressed))
    assert run_btcpp(write_bt(small.compressed), draws) == run_btcpp(write_bt(original), draws)


@pytest.mark.parametrize("ticks, expected", [
    # RUNNING when halted: the cascade halts A1 (its _onHalted once), the root's _onHalted runs,
    # then the visitor runs every node's haltNode again: root, A0 (never RUNNING), A1
    (["SUCCESS", "RUNNING"], {"r": 2, "a": 1, "b": 2}),
    # finished when halted: haltTree still calls haltNode on every node (Nav2 halts the tree after
    # every goal)
    (["SUCCESS", "SUCCESS"], {"r": 2, "a": 1, "b": 1}),
])
def test_halt_tree_runs_every_nodes_on_halted_script_as_btcpp_does(ticks, expected):
    """Issue 48: Tree::haltTree calls haltNode on the root, then on every node in pre-order
    (src/bt_factory.cpp, applyRecursiveVisitor), and haltNode runs `_onHalted` whatever the
    node's status. The scripts count on the blackboard in BT.CPP; our halt_tree_step makes one
    `script` event per run of each."""
    root = n("Sequence", n("A0", _onHalted="a := a + 1"), n("A1", _onHalted="b := b + 1"),
             _onHalted="r := r + 1")
    outcomes = iter(getattr(bt.NodeStatus, t) for t in ticks)
    factory = bt.BehaviorTreeFactory()
    for t in ("A0", "A1"):
        factory.register_simple_stateful_action(t, lambda _node: next(outcomes), lambda _node: next(outcomes),
                                                lambda _node: None)
    tree = factory.create_tree_from_text(write_bt(document(root)))
    board = tree.root_blackboard()
    for key in "rab":
        board.set_int(key, 0)
    tree.tick_exactly_once()
    tree.halt_tree()
    assert {k: board.get_int(k) for k in "rab"} == expected

    prog = program(document(root), rules={t: STATEFUL_ACTION for t in ACTIONS})
    config = initial()
    answers = iter(getattr(Status, t) for t in ticks)
    while isinstance(s := step(prog, config), Await):
        config = advance(config, next(answers) if s.event.kind == "tick" else None)
    config, counts = s.config, {"r": 0, "a": 0, "b": 0}
    while isinstance(h := halt_tree_step(prog, config), Await):
        if h.event.kind == "script":
            counts[h.event.node[1][1][0]] += 1
        config = advance(config, None)
    assert counts == expected
