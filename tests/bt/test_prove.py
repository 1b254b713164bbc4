"""The BT prover: proofs it must find (complete), refutations with a shortest counterexample, and
limits that are never passed off as proofs."""

from __future__ import annotations

from hypothesis import given, settings, strategies as st

from schemalog.bt.model import Document, Node
from schemalog.bt.prove import explain, prove_equal
from schemalog.bt.semantics import FAILURE, RUNNING, SUCCESS

LIMITS = dict(max_states=20_000, max_events_per_tick=30)


def act(name: str, **ports: str) -> Node:
    """An Action leaf."""
    return Node(name, tuple(ports.items()), (), "Action")


def n(node_type: str, *children: Node, **attrs: str) -> Node:
    """A node of a builtin type."""
    return Node(node_type, tuple(attrs.items()), children)


def doc(root: Node) -> Document:
    """A document of one tree."""
    return Document((("Main", root),), "Main")


def prove(a: Node, b: Node, **options):
    """prove_equal over two single-tree documents."""
    return prove_equal(doc(a), doc(b), **{**LIMITS, **options})


A, B, C = act("A"), act("B"), act("C")


def test_a_tree_is_equal_to_itself():
    tree = n("Sequence", n("Fallback", act("IsDoorOpen"), act("OpenDoor")),
             n("RecoveryNode", act("Nav", goal="{goal}"), act("Clear"), number_of_retries="2"))
    v = prove(tree, tree)
    assert v.equal and v.complete and v.states > 10
    assert explain(v).startswith("proved equal")


def test_nested_sequence_flattens():
    v = prove(n("Sequence", n("Sequence", A, B), C), n("Sequence", A, B, C))
    assert v.equal and v.complete


def test_single_child_sequence_is_its_child():
    v = prove(n("Sequence", A), A)
    assert v.equal and v.complete


def test_double_inverter_is_its_child():
    v = prove(n("Inverter", n("Inverter", A)), A)
    assert v.equal and v.complete


def test_swapped_recovery_children_are_refuted_at_the_first_tick():
    nav, clear = act("FollowPath", path="{path}"), act("ClearCostmap", service="local")
    good = n("RecoveryNode", nav, clear, number_of_retries="1", name="FollowPathWithRecovery")
    bad = n("RecoveryNode", clear, nav, number_of_retries="1", name="FollowPathWithRecovery")
    v = prove(good, bad)
    assert not v.equal and v.complete
    cex = v.counterexample
    assert cex.choices == ()                                  # shortest: no choice needed
    assert cex.ticks_a[0].events[0].node[1][0] == "FollowPath"
    assert cex.ticks_b[0].events[0].node[1][0] == "ClearCostmap"
    text = explain(v)
    assert "root tick 1:" in text
    assert 'a: tick FollowPath path="{path}"' in text and 'b: tick ClearCostmap service="local"' in text


def test_fallback_is_not_a_sequence():
    v = prove(n("Fallback", A, B), n("Sequence", A, B))
    assert not v.equal
    assert v.counterexample.choices in ((SUCCESS,), (FAILURE,))
    assert "SUCCESS" in explain(v) or "FAILURE" in explain(v)


def test_difference_in_a_later_root_tick_shows_every_tick_before_it():
    # a Sequence resumes at B; a ReactiveSequence re-ticks A first
    v = prove(n("Sequence", A, B), n("ReactiveSequence", A, B))
    assert not v.equal
    assert v.counterexample.choices == (SUCCESS, RUNNING)
    assert len(v.counterexample.ticks_a) == 2 and v.counterexample.ticks_a[0].status is RUNNING
    assert "root tick 2:" in explain(v) and "a: tick B   <- the trees part here" in explain(v)


def test_different_subtree_remappings_differ():
    def called(remap: str) -> Document:
        return Document((("Main", n("SubTree", ID="Go", goal=remap)), ("Go", act("Move", to="{goal}"))),
                        "Main")
    v = prove_equal(called("{a}"), called("{b}"), **LIMITS)
    assert not v.equal and "SubTree Go goal=" in explain(v)
    same = prove_equal(called("{a}"), called("{a}"), **LIMITS)
    assert same.equal and same.complete


def test_a_limit_reached_is_not_a_proof():
    tree = n("Sequence", A, B, C)
    v = prove(tree, tree, max_states=3)
    assert v.equal and not v.complete
    assert "not a proof" in v.reason and explain(v).startswith("NOT proved")
    v = prove(tree, tree, max_events_per_tick=1)
    assert v.equal and not v.complete and "max_events_per_tick" in v.reason


def test_counterexample_is_shortest():
    # they differ only after A succeeded twice in a row (Repeat 2 vs Repeat 3)
    v = prove(n("Repeat", A, num_cycles="2"), n("Repeat", A, num_cycles="3"))
    assert not v.equal and v.counterexample.choices == (SUCCESS, SUCCESS)


# -- hypothesis: random small trees -----------------------------------------------------------

LEAVES = st.sampled_from([act("A"), act("B"), act("C"), Node("IsOk", (), (), "Condition")])


def _trees(depth: int):
    if depth == 0:
        return LEAVES
    sub = _trees(depth - 1)
    composite = st.builds(lambda t, kids: Node(t, (), tuple(kids)),
                          st.sampled_from(["Sequence", "Fallback", "ReactiveSequence"]),
                          st.lists(sub, min_size=1, max_size=3))
    inverter = st.builds(lambda k: Node("Inverter", (), (k,)), sub)
    return st.one_of(LEAVES, composite, inverter)


TREES = _trees(3)
# a Sequence (ReactiveSequence) with a child of its own kind somewhere among its children
NESTED = st.builds(
    lambda t, before, inner, after: Node(t, (), tuple(before) + (Node(t, (), tuple(inner)),) + tuple(after)),
    st.sampled_from(["Sequence", "ReactiveSequence"]), st.lists(_trees(1), max_size=2),
    st.lists(_trees(1), min_size=1, max_size=3), st.lists(_trees(1), max_size=2))


def flatten(node: Node) -> Node:
    """Splice a Sequence into a parent Sequence, a ReactiveSequence into a ReactiveSequence."""
    kids: list[Node] = []
    for child in (flatten(c) for c in node.children):
        if child.type == node.type and node.type in ("Sequence", "ReactiveSequence") and not child.attrs:
            kids.extend(child.children)
        else:
            kids.append(child)
    return node.with_children(tuple(kids))


@settings(max_examples=40, deadline=None)
@given(TREES)
def test_random_trees_equal_themselves(tree):
    v = prove(tree, tree, max_states=50_000)
    assert v.equal and v.complete, explain(v)


@settings(max_examples=60, deadline=None)
@given(st.one_of(NESTED, TREES))
def test_flattening_same_kind_sequences_is_sound(tree):
    # Read from SequenceNode::tick and ReactiveSequence::tick: an inner one that returns
    # SUCCESS lets the outer go on exactly where the flat one goes on, RUNNING and FAILURE pass
    # through, and halts reach the same leaves in the same order.
    flat = flatten(tree)
    v = prove(tree, flat, max_states=50_000)
    assert v.equal and v.complete, explain(v)


MUTATIONS = st.sampled_from(["Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback",
                             "PipelineSequence", "Parallel"])


@settings(max_examples=40, deadline=None)
@given(TREES, MUTATIONS)
def test_merging_interrupted_ticks_changes_no_verdict(tree, kind):
    # the prover merges two interrupted root ticks with the same stack and memory; checked
    # against the prover that merges only whole configurations
    other = tree.with_children(tree.children) if not tree.children else Node(kind, (), tree.children)
    merged = prove(tree, other, max_states=50_000)
    plain = prove(tree, other, max_states=200_000, merge=False)
    assert (merged.equal, merged.complete) == (plain.equal, plain.complete)
    assert merged.states <= plain.states
    if not merged.equal:
        assert merged.counterexample.choices == plain.counterexample.choices


def nav2_navigate(swap: bool = False) -> Node:
    """Nav2's navigate_to_pose_w_replanning_and_recovery, by hand (names and ports as in Nav2)."""
    follow = [act("FollowPath", path="{path}", controller_id="FollowPath"),
              act("ClearEntireCostmap", service_name="local_costmap/clear_entirely_local_costmap")]
    if swap:
        follow.reverse()
    plan = n("RecoveryNode", act("ComputePathToPose", goal="{goal}", path="{path}"),
             act("ClearEntireCostmap", service_name="global_costmap/clear_entirely_global_costmap"),
             number_of_retries="1", name="ComputePathToPose")
    recoveries = n("RoundRobin",
                   n("Sequence", act("ClearEntireCostmap", service_name="local"),
                     act("ClearEntireCostmap", service_name="global")),
                   act("Spin", spin_dist="1.57"), act("Wait", wait_duration="5.0"),
                   act("BackUp", backup_dist="0.30", backup_speed="0.05"), name="RecoveryActions")
    return n("RecoveryNode",
             n("PipelineSequence", n("RateController", plan, hz="1.0"),
               n("RecoveryNode", *follow, number_of_retries="1", name="FollowPath"),
               name="NavigateWithReplanning"),
             n("ReactiveFallback", Node("GoalUpdated", (), (), "Condition"), recoveries,
               name="RecoveryFallback"),
             number_of_retries="6", name="NavigateRecovery")


def test_nav2_navigate_tree_is_proved_equal_to_itself_and_its_swapped_edit_refuted():
    v = prove(nav2_navigate(), nav2_navigate(), max_states=100_000, max_events_per_tick=40)
    assert v.equal and v.complete, v.reason
    bad = prove(nav2_navigate(), nav2_navigate(swap=True), max_states=100_000, max_events_per_tick=40)
    assert not bad.equal and bad.counterexample.choices == (SUCCESS,)
    assert "<- the trees part here" in explain(bad)


def test_flattening_a_reactive_sequence_into_a_sequence_is_not_sound():
    # the inner ReactiveSequence re-ticks A; a flat Sequence would resume at B
    v = prove(n("Sequence", n("ReactiveSequence", A, B), C), n("Sequence", A, B, C))
    assert not v.equal and v.counterexample.choices == (SUCCESS, RUNNING)


def test_a_proof_says_when_runs_end_in_an_error_both_trees_throw():
    # Repeat without num_cycles: BT.CPP's tick throws "Missing parameter"; equal, and said so
    bare = n("Repeat", act("A"))
    v = prove(n("Sequence", bare), bare)
    assert v.equal and v.complete
    assert "Missing parameter [num_cycles] in RepeatNode" in v.thrown and "end in an error" in v.reason
    assert prove(act("A"), n("Sequence", act("A"))).thrown == ""


def test_by_parts_carries_a_part_s_error_into_its_verdict():
    from schemalog.bt.prove import prove_by_parts
    a = doc(n("Sequence", n("Sequence", n("Sleep")), act("B")))
    b = doc(n("Sequence", n("Sleep"), act("B")))
    v = prove_by_parts(a, b, max_states=10_000, max_events_per_tick=64)
    assert v.equal and v.complete and "Missing parameter [msec] in SleepNode" in v.reason


def test_a_loop_for_ever_is_proved_whole_not_counted():
    # Issue 48: `num_attempts="-1"` / `num_cycles="-1"` never stop, so nothing reads their count;
    # counted, every retry was a new state and no number of states sufficed (auto-apms-px4's
    # tree: 1,000,000 states, no proof). Whole trees, no proof by parts.
    for loop, port in (("RetryUntilSuccessful", "num_attempts"), ("Repeat", "num_cycles")):
        nested = n(loop, n("Sequence", A, n("Sequence", B, C)), **{port: "-1"})
        flat = n(loop, n("Sequence", A, B, C), **{port: "-1"})
        v = prove(nested, flat)
        assert v.equal and v.complete and v.states < 100, explain(v)
        told = prove(nested, n(loop, n("Sequence", A, C, B), **{port: "-1"}))
        assert not told.equal


def test_a_counterexample_stops_at_the_event_where_the_trees_part_even_one_without_a_choice():
    """A Delay's `time` event offers no choice: the runs part there, and the counterexample must
    not run on to the next event that offers one (it marked a later ReactiveParallel's choice)."""
    from schemalog.bt.prove import prove_by_parts

    def tree(ms: str) -> Node:
        return n("Sequence", act("A"), n("Delay", act("B"), delay_msec=ms), act("C"))
    v = prove_by_parts(doc(tree("200")), doc(tree("300")), **LIMITS)
    assert not v.equal and v.counterexample is not None
    for ticks in (v.counterexample.ticks_a, v.counterexample.ticks_b):
        last = ticks[-1]
        assert last.status is None and last.events[-1].kind == "time"
    shown = explain(v).splitlines()
    assert [line for line in shown if line.endswith("<- the trees part here")] == [
        '  a: time at Delay delay_msec="200"   <- the trees part here',
        '  b: time at Delay delay_msec="300"   <- the trees part here']
