"""Proofs in every context and by parts (bt/prove.py): a subtree equal in every context can
replace the other under any parent; where that is not shown, the whole trees decide."""

from __future__ import annotations

from hypothesis import given, settings, strategies as st

from schemalog.bt.compress import compress
from schemalog.bt.model import Document, Node
from schemalog.bt.prove import differing_parts, explain, prove_by_parts, prove_equal
from schemalog.bt.semantics import SYNC_ACTION

LIMITS = dict(max_states=20_000, max_events_per_tick=30)


def act(name: str, **ports: str) -> Node:
    return Node(name, tuple(ports.items()), (), "Action")


def n(node_type: str, *children: Node, **attrs: str) -> Node:
    return Node(node_type, tuple(attrs.items()), children)


def doc(root: Node, **trees: Node) -> Document:
    return Document((("Main", root), *trees.items()), "Main")


A, B, C, D = act("A"), act("B"), act("C"), act("D")


def test_run_once_is_told_apart_only_when_ticked_anew():
    # Ticked until done and never again, RunOnce(A) is A. A parent that ticks it anew after it
    # finished sees the difference: RunOnce does not tick A again.
    once, plain = doc(n("RunOnce", A)), doc(A)
    alone = prove_equal(once, plain, **LIMITS)
    assert alone.equal and alone.complete
    anywhere = prove_equal(once, plain, contextual=True, **LIMITS)
    assert not anywhere.equal and anywhere.complete
    text = explain(anywhere)
    assert "root -> SUCCESS" in text and "the trees part here" in text


def test_a_sequence_with_memory_inside_another_is_not_flattened():
    # SequenceWithMemory hands the tick back (RUNNING) after a child that started this tick
    # succeeds (src/controls/sequence_with_memory_node.cpp, requiresWakeUp): nested, the inner
    # one's last success does not, so the two shapes yield at different places.
    nested = doc(n("SequenceWithMemory", n("SequenceWithMemory", A, B), C))
    v = prove_equal(nested, doc(n("SequenceWithMemory", A, B, C)), **LIMITS)
    assert not v.equal and "tick C" in explain(v)
    assert compress(nested).rewrites == ()


REWRITES = [(n("Sequence", n("Sequence", A, B), C), n("Sequence", A, B, C)),
            (n("ReactiveFallback", n("ReactiveFallback", A, B), C), n("ReactiveFallback", A, B, C)),
            (n("SequenceWithMemory", A), A),
            (n("Fallback", A), A), (n("Inverter", n("Inverter", A)), A),
            (n("ForceSuccess", n("ForceFailure", A)), n("ForceSuccess", A))]


def test_the_rewrites_hold_in_every_context_for_synchronous_actions():
    sync = {t: SYNC_ACTION for t in "ABC"}
    for before, after in REWRITES:
        v = prove_equal(doc(before), doc(after), contextual=True, rules=sync, **LIMITS)
        assert v.equal and v.complete, (before.type, explain(v))


def test_a_removed_node_that_reset_a_stateful_action_is_told_apart_where_no_parent_resets():
    # Issue 48: under a parent that ticks a finished child again unreset (PipelineSequence,
    # WhileDoElse), a finished StatefulActionNode returns its last status without running,
    # while SequenceWithMemory(A) had reset A and runs it again. By default a proof covers both
    # registrations, so only a resetting parent keeps the single-child rewrites.
    for before, after in REWRITES:
        under_reset = prove_equal(doc(before), doc(after), contextual=True, unreset=False, **LIMITS)
        assert under_reset.equal and under_reset.complete, (before.type, explain(under_reset))
    anywhere = prove_equal(doc(n("SequenceWithMemory", A)), doc(A), contextual=True, **LIMITS)
    assert not anywhere.equal and anywhere.counterexample.kinds == (("A", "stateful"),)
    sync = prove_equal(doc(n("SequenceWithMemory", A)), doc(A), contextual=True, rules={"A": SYNC_ACTION}, **LIMITS)
    assert sync.equal and sync.complete


def test_differing_parts_are_the_smallest_subtrees_that_differ():
    a = n("RecoveryNode", n("PipelineSequence", A, n("Sequence", n("Sequence", B, C), D)), B)
    b = n("RecoveryNode", n("PipelineSequence", A, n("Sequence", B, C, D)), B)
    assert differing_parts(a, a) == []
    assert differing_parts(a, b) == [(a.children[0].children[1], b.children[0].children[1])]


def test_a_proof_by_parts_explores_only_the_parts():
    big = n("RecoveryNode", n("PipelineSequence", *[n("Fallback", act(f"Is{i}"), act(f"Do{i}")) for i in range(6)],
                              n("Sequence", n("Sequence", B, C), D)), n("RoundRobin", A, B, C))
    small = compress(doc(big)).document
    by_parts = prove_by_parts(doc(big), small, **LIMITS)
    assert by_parts.equal and by_parts.complete and "by parts" in by_parts.reason
    whole = prove_equal(doc(big), small, **{**LIMITS, "max_states": by_parts.states * 10})
    assert whole.equal and not whole.complete        # the whole product is far larger


def test_a_wrong_part_is_refuted_on_the_whole_trees():
    a = doc(n("Sequence", n("RecoveryNode", A, B, number_of_retries="1"), C))
    b = doc(n("Sequence", n("RecoveryNode", B, A, number_of_retries="1"), C))
    v = prove_by_parts(a, b, **LIMITS)
    assert not v.equal and v.complete
    assert "by parts" not in v.reason and v.counterexample is not None


def test_subtrees_called_by_a_part_are_kept():
    sub = n("Sequence", n("Sequence", A, B))
    a = doc(n("Fallback", n("SubTree", ID="Sub"), C), Sub=sub)
    small = compress(a).document
    assert small.tree("Sub") == n("Sequence", A, B)
    v = prove_by_parts(a, small, **LIMITS)
    assert v.equal and v.complete


LEAVES = st.sampled_from([A, B, C])
KINDS = ["Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory", "Inverter",
         "ForceSuccess", "ForceFailure"]


@st.composite
def trees(draw, depth=3):
    if depth == 0 or draw(st.integers(0, 3)) == 0:
        return draw(LEAVES)
    kind = draw(st.sampled_from(KINDS))
    count = 1 if kind.startswith(("Inverter", "Force")) else draw(st.integers(1, 3))
    return n(kind, *(draw(trees(depth - 1)) for _ in range(count)))


@settings(max_examples=60, deadline=None)
@given(trees())
def test_compression_is_proved_by_parts_and_agrees_with_the_whole_proof(tree):
    original = doc(tree)
    small = compress(original).document
    by_parts = prove_by_parts(original, small, **LIMITS)
    assert by_parts.equal, explain(by_parts)
    whole = prove_equal(original, small, **LIMITS)
    assert whole.equal, explain(whole)


def test_a_rewrite_is_kept_only_where_its_parent_makes_it_sound():
    # A single-child Sequence resets its child when it finishes; Nav2's RateController ticks its
    # child at once only from IDLE. Under a Sequence (which resets a finished child itself) the
    # wrapper can go; under a PipelineSequence (which ticks finished children again, unreset) it
    # cannot, and compress_proved keeps it there while it removes the other.
    from schemalog.bt.prove import compress_proved

    def rated():
        return n("Sequence", n("RateController", n("Fallback", act("IsPathValid"), act("Plan")), hz="1.0"))

    tree = doc(n("Sequence", n("PipelineSequence", rated(), act("Follow")), rated()))
    small, verdict = compress_proved(tree, **LIMITS)
    assert verdict.equal and verdict.complete, explain(verdict)
    pipeline, second = small.document.root.children
    assert pipeline.children[0].type == "Sequence"           # kept under the PipelineSequence
    assert second.type == "RateController"                   # removed under the Sequence
    assert [r.rule for r in small.rewrites] == ["single"]
    unsound = compress(tree)                                 # the rules alone remove both
    assert len(unsound.rewrites) == 2
    assert not prove_by_parts(tree, unsound.document, **LIMITS).equal


def test_ports_are_compared_by_name_not_by_their_order_in_the_element():
    """Issue 48: `p="1" q="2"` and `q="2" p="1"` were refuted (ports a tuple in document order);
    BT.CPP gives a node its ports by name. Neither the whole trees nor the parts tell them apart,
    and a real difference still shows each side's ports as its element writes them."""
    pq = act("X", p="1", q="2")
    qp = Node("X", (("q", "2"), ("p", "1")), (), "Action")
    a, b = doc(n("Sequence", pq, A)), doc(n("Sequence", qp, A))
    whole = prove_equal(a, b, **LIMITS)
    assert whole.equal and whole.complete
    assert differing_parts(a.root, b.root) == []
    by_parts = prove_by_parts(a, b, **LIMITS)
    assert by_parts.equal and by_parts.complete and by_parts.states == 0, by_parts.reason
    other = Node("X", (("q", "3"), ("p", "1")), (), "Action")
    refuted = prove_by_parts(a, doc(n("Sequence", other, A)), **LIMITS)
    assert not refuted.equal
    assert refuted.reason == 'the next event differs: a tick X p="1" q="2", b tick X q="3" p="1"'
