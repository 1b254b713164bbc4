"""The proof by parts against the whole-tree exploration, on real Nav2 and BT.CPP trees mutated at
random the way hand-edited and generated trees look: wrappers that compression removes, pre-
conditions on the nodes it would remove, composites of one kind nested. A proof by parts that the
whole trees refute would be a proof bought by a missing context; none may be."""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, assume, event, given, note, settings
from hypothesis import strategies as st

from schemalog.bt.model import Document, Node, size, walk
from schemalog.bt.prove import compress_proved, explain, prove_by_parts, prove_equal
from schemalog.formats.btxml import read_bt, read_models

CORPUS = Path(__file__).parent / "corpus"
NODES = read_models((CORPUS / "nav2" / "nav2_tree_nodes.xml").read_text(), "nav2_tree_nodes.xml")
SMALL = ["navigate_w_replanning_distance.xml", "navigate_w_replanning_only_if_goal_is_updated.xml",
         "navigate_w_replanning_speed.xml", "navigate_w_replanning_time.xml",
         "navigate_w_replanning_only_if_path_becomes_invalid.xml", "follow_point.xml"]
TREES = [read_bt((CORPUS / "nav2" / name).read_text(), name, models=NODES) for name in SMALL] + \
        [read_bt((CORPUS / "btcpp" / "tutorials" / "t09_scripting.xml").read_text(), "t09_scripting.xml")]
LIMITS = dict(max_states=3_000, max_events_per_tick=40)
WRAPPERS = ["Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory", "Inverter",
            "ForceSuccess", "ForceFailure"]
CONDITIONS = ["_skipIf", "_successIf", "_failureIf", "_while"]


def _mutate(node: Node, draw, budget: list[int]) -> Node:
    """`node` with its children mutated, then perhaps wrapped or given a pre-condition."""
    kids = tuple(_mutate(c, draw, budget) for c in node.children)
    node = node.with_children(kids)
    if budget[0] > 0 and draw(st.integers(0, 3)) == 0:
        budget[0] -= 1
        kind = draw(st.sampled_from(WRAPPERS))
        if kind == "Inverter" and draw(st.booleans()):
            node = Node("Inverter", (), (node,))                 # a double Inverter
        inner = Node(kind, (), (node,) if draw(st.booleans()) or kind in ("Inverter",) or kind.startswith("Force")
                     else (node, Node("Pad")))
        if kind in ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback") and draw(st.booleans()):
            inner = Node(kind, (), (inner, Node("After")))      # the same kind around it: flattened
        node = inner
    if budget[0] > 0 and draw(st.integers(0, 5)) == 0:
        budget[0] -= 1
        node = Node(node.type, node.attrs + ((draw(st.sampled_from(CONDITIONS)), "x"),), node.children, node.form)
    return node


@st.composite
def mutated(draw) -> Document:
    doc = draw(st.sampled_from(TREES))
    trees = tuple((tid, _mutate(root, draw, [3])) for tid, root in doc.trees)
    return doc.with_trees(trees)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated(), st.booleans())
def test_a_compression_proved_by_parts_is_never_refuted_whole(document, keep_names):
    # compress_proved keeps only the rewrites proved where they stand (a single-child Sequence
    # around Nav2's RateController under a PipelineSequence is not: the Sequence reset the
    # RateController when it finished, the PipelineSequence does not, and the RateController
    # ticks its child at once only from IDLE). Named nodes kept (the default) or not
    # (--drop-names): the Nav2 trees name many of the nodes a rewrite would remove.
    assume(size(document) <= 40)
    small, by_parts = compress_proved(document, **LIMITS, keep_names=keep_names)
    assume(small.rewrites)
    note("rewrites: " + ", ".join(map(str, small.rewrites)))
    whole = prove_equal(document, small.document, **LIMITS)
    note(explain(by_parts) + explain(whole))
    event(f"whole {'exhausted' if whole.complete else 'not exhausted'}, by parts "
          f"{'proved' if by_parts.complete and by_parts.equal else 'not proved'}")
    assert whole.equal or not whole.complete, "the whole trees differ"
    if by_parts.complete:
        assert by_parts.equal


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated(), st.data())
def test_a_part_changed_by_hand_is_refuted_when_the_whole_trees_differ(document, data):
    # Swap two children somewhere: where the whole trees can be told apart (and exhausted), the
    # proof by parts refutes too, with a counterexample of the whole trees.
    assume(size(document) <= 40)
    candidates = [n for _, root in document.trees for n in walk(root) if len(n.children) >= 2
                  and n.children[0] != n.children[1]]
    assume(candidates)
    target = data.draw(st.sampled_from(candidates))

    def swap(n: Node) -> Node:
        if n is target:
            kids = (n.children[1], n.children[0], *n.children[2:])
            return n.with_children(kids)
        return n.with_children(tuple(swap(c) for c in n.children))

    edited = document.with_trees(tuple((tid, swap(root)) for tid, root in document.trees))
    whole = prove_equal(document, edited, **LIMITS)
    assume(whole.complete)
    by_parts = prove_by_parts(document, edited, **LIMITS)
    event("the swap is " + ("seen" if not whole.equal else "not seen"))
    assert by_parts.equal == whole.equal
    if not whole.equal:
        assert by_parts.counterexample is not None
