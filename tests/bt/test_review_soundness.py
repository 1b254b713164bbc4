"""Review of issue 33's prover and rewrites: proofs by parts that were bought by a missing
context, a model ignored, or a limit that did not hold."""

from __future__ import annotations

from schemalog.bt.compress import compress
from schemalog.bt.model import Document, Node, NodeModel
from schemalog.bt.prove import prove_by_parts, prove_equal

LIMITS = dict(max_states=20_000, max_events_per_tick=30)


def act(name: str, **attrs: str) -> Node:
    return Node(name, tuple(attrs.items()), (), "Action")


def n(node_type: str, *children: Node, **attrs: str) -> Node:
    return Node(node_type, tuple(attrs.items()), children)


def doc(root: Node, models: tuple = ()) -> Document:
    return Document((("Main", root),), "Main", models)


A, B, W, Z = act("A"), act("B"), act("W"), act("Z")
GUARDED = act("X", _skipIf="c")


def _refuted(a: Document, b: Document) -> None:
    whole = prove_equal(a, b, **LIMITS)
    assert not whole.equal and whole.complete
    parts = prove_by_parts(a, b, **LIMITS)
    assert not parts.equal, parts.reason


def test_a_condition_ticked_again_with_its_status_kept_is_a_context():
    # WhileDoElse does not reset its condition while a branch runs: BT.CPP ticks it again with
    # its status SUCCESS, and a _skipIf is checked only from IDLE (TreeNode::checkPreConditions).
    # Sequence(X _skipIf) resets X when it completes, bare X does not: they differ there.
    _refuted(doc(n("WhileDoElse", n("Sequence", GUARDED), A, B)), doc(n("WhileDoElse", GUARDED, A, B)))
    _refuted(doc(n("PipelineSequence", n("Inverter", n("Inverter", GUARDED)), Z)),
             doc(n("PipelineSequence", GUARDED, Z)))


def test_flattening_a_sequence_of_skippable_children_counts_skips_across_ticks():
    # skipped_count_ is reset only when the Sequence completes or starts IDLE: flattened under a
    # WhileDoElse that keeps its FAILURE status, it counts skips across ticks and returns SKIPPED.
    nested = n("Sequence", n("Sequence", act("X"), act("Y", _skipIf="c")), W)
    flat = n("Sequence", act("X"), act("Y", _skipIf="c"), W)
    _refuted(doc(n("WhileDoElse", nested, A, B)), doc(n("WhileDoElse", flat, A, B)))


def test_compress_keeps_a_parent_whose_removal_would_skip_a_precondition():
    for root in (n("WhileDoElse", n("Sequence", GUARDED), A, B),
                 n("PipelineSequence", n("Inverter", n("Inverter", GUARDED)), Z),
                 n("WhileDoElse", n("Sequence", n("Sequence", act("X"), act("Y", _skipIf="c")), W), A, B)):
        d = doc(root)
        result = compress(d)
        assert not result.rewrites, result.rewrites
    # without a pre-condition below, the rewrites still apply and are proved
    d = doc(n("WhileDoElse", n("Sequence", n("Sequence", act("X"), act("Y")), W), A, B))
    result = compress(d)
    assert [r.rule for r in result.rewrites] == ["flatten"]
    v = prove_by_parts(d, result.document, **LIMITS)
    assert v.equal and v.complete


def test_identical_trees_under_different_models_are_not_proved_by_parts():
    # X is a Condition in one document and an Action in the other: X may return RUNNING in one
    tree = n("Sequence", Node("X", (), ()), Node("Y", (), ()))
    a = doc(tree, (NodeModel("X", "Condition"),))
    b = doc(tree, (NodeModel("X", "Action"),))
    _refuted(a, b)
    # an unknown leaf and a leaf declared an Action run alike: by parts still applies
    c = doc(n("Sequence", n("Sequence", Node("X", (), ())), Node("Y", (), ())), (NodeModel("X", "Action"),))
    plain = doc(n("Sequence", Node("X", (), ()), Node("Y", (), ())))
    v = prove_by_parts(plain, c, **LIMITS)
    assert v.equal and v.complete and v.reason.startswith("equal by parts")


def test_max_states_is_one_budget_for_the_parts_and_the_whole():
    a = doc(n("Sequence", n("Sequence", A), n("Fallback", n("Fallback", B, W), Z)))
    b = doc(n("Sequence", A, n("Fallback", B, W, Z)))
    full = prove_by_parts(a, b, **LIMITS)
    assert full.equal and full.complete and full.reason.startswith("equal by parts")
    for limit in range(1, full.states):
        v = prove_by_parts(a, b, max_states=limit, max_events_per_tick=30)
        assert not v.complete and v.states <= limit, (limit, v)
    exact = prove_by_parts(a, b, max_states=full.states, max_events_per_tick=30)
    assert exact.complete and exact.states == full.states
