"""The congruence (bt/congruence.py, docs/semantics.md "Congruence"): subtrees identical in both
trees taken whole as one opaque node. It must bring a wrap of every Nav2 tree in reach, never
prove what the trees as they are refute, and its refutations are never printed (the concrete
explorers take over). The cases where a coarser abstraction would be wrong are refuted here,
and shown proved by that coarser abstraction, so the conditions are seen to matter."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from types import MappingProxyType

import pytest
from hypothesis import HealthCheck, assume, event, given, note, settings
from hypothesis import strategies as st

from schemalog.bt.congruence import CONGRUENT, RULE_KEY, TYPE, abstract
from schemalog.bt.model import Document, Node, size, walk
from schemalog.bt.prove import explain, program, prove_by_parts, prove_equal
from schemalog.bt.semantics import ACTION_OUTCOMES, PNode, Rule
from schemalog.formats.btxml import read_bt
from test_parts_against_whole import LIMITS, NODES, TREES, mutated

CORPUS = Path(__file__).parent / "corpus"
DEFAULT = dict(max_states=50_000, max_events_per_tick=10_000)        # verify's default limits


def _nav2(name: str) -> Document:
    return read_bt((CORPUS / "nav2" / name).read_text(), name, models=NODES)


def _wrapped(document: Document) -> Document:
    return document.with_trees(tuple((i, Node("Sequence", children=(r,)) if i == document.main else r)
                                     for i, r in document.trees))


NAV2 = sorted(p.name for p in (CORPUS / "nav2").glob("*.xml")
              if p.name not in ("nav2_tree_nodes.xml",
                                "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml"))   # BT.CPP 3


@pytest.mark.parametrize("name", NAV2)
def test_every_nav2_tree_wrapped_whole_is_proved_at_the_default_limits(name):
    # the largest, navigate_on_route_graph_w_recovery (49 nodes), was NOT proved in 50,000
    # states before: now each is two nodes against one
    document = _nav2(name)
    v = prove_by_parts(document, _wrapped(document), **DEFAULT)
    assert v.equal and v.complete, explain(v)
    assert "congruence" in v.reason
    assert v.states < 100


def test_a_wrap_with_a_step_added_is_refuted_with_a_concrete_counterexample():
    document = _nav2("navigate_on_route_graph_w_recovery.xml")
    other = document.with_trees(tuple((i, Node("Sequence", children=(r, Node("Extra"))) if i == document.main else r)
                                      for i, r in document.trees))
    v = prove_by_parts(document, other, **DEFAULT)
    assert not v.equal and v.complete
    assert TYPE not in explain(v)                     # no abstract node in what is printed
    assert any(e.node[1][0] == "Extra" for e in v.counterexample.ticks_b[-1].events)


# ---------------------------------------------------------------------------------------------
# The conditions, each where a coarser abstraction would prove a pair BT.CPP runs apart

def _doc(root: Node, **trees: Node) -> Document:
    return Document((("Main", root),) + tuple(trees.items()), "Main")


def A(name: str, **ports) -> Node:
    return Node(name, tuple(ports.items()), form="Action")


def C(name: str) -> Node:
    return Node(name, form="Condition")


def _coarse(document_a: Document, document_b: Document, *, status: bool = True, instances: bool = True):
    """The congruence made coarser on purpose: ticks without the status before them
    (`status=False`), or every instance of a subtree under one label (`instances=False`)."""
    pa, pb = program(document_a), program(document_b)
    taken = abstract(pa, pb)
    assert taken is not None

    def tick(run, n):
        outcome = run.event("tick", n, ACTION_OUTCOMES, (TYPE, n.node.ports))
        return outcome

    def halt(run, n):
        CONGRUENT.halt(run, n)

    def relabel(n: PNode) -> PNode:
        if n.rule == RULE_KEY and not instances:
            attrs = tuple((k, v.split(".")[0] if k == "subtree" else v) for k, v in n.node.attrs)
            return replace(n, node=Node(n.node.type, attrs))
        return replace(n, kids=tuple(relabel(k) for k in n.kids))

    rule = CONGRUENT if status else Rule(tick, halt)
    progs = [replace(p, root=relabel(p.root), rules=MappingProxyType({**p.rules, RULE_KEY: rule}))
             for p in (taken.a, taken.b)]
    return prove_equal(document_a, document_b, programs=tuple(progs), **LIMITS)


def _refuted_and_coarsely_proved(a: Document, b: Document, **coarse) -> None:
    reference = prove_equal(a, b, **LIMITS)
    assert not reference.equal and reference.complete
    ours = prove_by_parts(a, b, **LIMITS)
    assert not ours.equal and ours.complete, explain(ours)
    assert ours.counterexample is not None and TYPE not in explain(ours)
    assert len(ours.counterexample.choices) == len(reference.counterexample.choices)   # as short
    wrong = _coarse(a, b, **coarse)
    assert wrong.equal and wrong.complete, "the coarser abstraction should prove it (else the case shows nothing)"


def test_a_finished_subtree_reset_on_one_side_only_is_refuted():
    # PipelineSequence does not reset its finished first child; the Sequence around it in b
    # does. Ticked again from SUCCESS, the `_skipIf` is not checked; from IDLE it is.
    shared = Node("Sequence", (("_skipIf", "done"),), (A("Plan"), A("Check")))
    a = _doc(Node("PipelineSequence", (), (shared, A("Follow"))))
    b = _doc(Node("PipelineSequence", (), (Node("Sequence", (), (shared,)), A("Follow"))))
    _refuted_and_coarsely_proved(a, b, status=False)


@pytest.mark.parametrize("memory", [
    Node("RoundRobin", (), (A("Left"), A("Right"))),                       # its index outlives a success
    Node("SequenceWithMemory", (), (A("Left"), A("Right"))),               # its index outlives a failure
])
def test_two_instances_of_a_subtree_with_memory_are_not_confused(memory):
    # The same subtree twice: a ticks the first instance when Ready succeeds and the second
    # when it fails, b always the first; each instance remembers its own past. (Swapping the
    # two consistently would be invisible: that is the bijection.)
    def tree(condition: Node) -> Node:
        choice = Node("IfThenElse", (), (condition, memory, memory))
        return Node("Repeat", (("num_cycles", "3"),), (Node("ForceSuccess", (), (choice,)),))
    a = _doc(tree(C("Ready")))
    b = _doc(tree(Node("ForceSuccess", (), (C("Ready"),))))
    _refuted_and_coarsely_proved(a, b, instances=False)


def test_a_subtree_under_other_subtree_calls_is_not_taken_whole():
    # The same nodes called through SubTrees with another remapping: their events carry the
    # call, so they are other nodes.
    body = Node("Sequence", (), (A("Plan", goal="{goal}"), A("Follow")))
    a = _doc(Node("SubTree", (("ID", "Go"), ("goal", "{a}"))), Go=body)
    b = _doc(Node("Sequence", (), (Node("SubTree", (("ID", "Go"), ("goal", "{b}"))),)), Go=body)
    assert abstract(program(a), program(b)) is None
    v = prove_by_parts(a, b, **LIMITS)
    assert not v.equal and v.complete


def test_an_equal_subtree_call_to_trees_that_differ_is_not_taken_whole():
    # The SubTree node is the same in both documents; the trees it calls are not. The key of a
    # subtree is its expansion, not its XML node.
    call = Node("SubTree", (("ID", "Go"),))
    a = _doc(call, Go=Node("Sequence", (), (A("Plan"), A("Follow"))))
    b = _doc(Node("Sequence", (), (call,)), Go=Node("Sequence", (), (A("Plan"), A("Spin"))))
    taken = abstract(program(a), program(b))
    assert taken is None or all(n.node.type != "SubTree" for n in _pwalk(taken.a.root))
    v = prove_by_parts(a, b, **LIMITS)
    assert not v.equal and v.complete


def _pwalk(n: PNode):
    yield n
    for k in n.kids:
        yield from _pwalk(k)


def test_a_subtree_that_may_skip_offers_skipped_and_one_that_may_not_does_not():
    plain = Node("Sequence", (), (A("Plan"), A("Follow")))
    skipping = Node("Sequence", (), (Node("Plan", (("_skipIf", "x"),), form="Action"), A("Follow")))
    skipping_all = Node("Sequence", (), (Node("Plan", (("_skipIf", "x"),), form="Action"),
                                         Node("Follow", (("_while", "y"),), form="Action")))
    for body, skips in ((plain, None), (skipping, None), (skipping_all, "yes")):
        taken = abstract(program(_doc(body)), program(_doc(Node("Inverter", (), (body,)))))
        assert taken.a.root.node.attr("skips") == skips


# ---------------------------------------------------------------------------------------------
# Against the reference explorer on random trees and random edits

EDITS = ["wrap", "nest", "swap", "drop", "retype", "retries", "force pair", "inverter"]
RETYPE = {"Sequence": "Fallback", "Fallback": "Sequence", "ReactiveSequence": "Sequence",
          "PipelineSequence": "Sequence", "SequenceWithMemory": "Sequence", "ReactiveFallback": "Fallback",
          "RoundRobin": "Fallback", "ForceSuccess": "ForceFailure", "ForceFailure": "ForceSuccess"}


def _edit(node: Node, kind: str, draw) -> Node:
    kids = node.children
    if kind == "wrap":
        return Node(draw(st.sampled_from(["Sequence", "Fallback", "ReactiveSequence", "SequenceWithMemory"])), (),
                    (node,))
    if kind == "nest" and len(kids) >= 3:
        i = draw(st.integers(0, len(kids) - 2))
        return node.with_children(kids[:i] + (Node(node.type, (), kids[i:i + 2]),) + kids[i + 2:])
    if kind == "swap" and len(kids) >= 2:
        i = draw(st.integers(0, len(kids) - 2))
        return node.with_children(kids[:i] + (kids[i + 1], kids[i]) + kids[i + 2:])
    if kind == "drop" and len(kids) >= 3:
        i = draw(st.integers(0, len(kids) - 1))
        return node.with_children(kids[:i] + kids[i + 1:])
    if kind == "retype" and node.type in RETYPE and not node.form:
        return Node(RETYPE[node.type], node.attrs, kids)
    if kind == "retries":
        if node.type in ("RetryUntilSuccessful", "RecoveryNode"):
            port = "num_attempts" if node.type == "RetryUntilSuccessful" else "number_of_retries"
            attrs = tuple((k, v) for k, v in node.attrs if k != port) + ((port, str(draw(st.integers(1, 3)))),)
            return Node(node.type, attrs, kids)
        return Node("RetryUntilSuccessful", (("num_attempts", str(draw(st.integers(1, 3)))),), (node,))
    if kind == "force pair":
        return Node("ForceSuccess", (), (Node("ForceFailure", (), (node,)),))
    if kind == "inverter":
        return Node("Inverter", (), (Node("Inverter", (), (node,)) if draw(st.booleans()) else node,))
    return node


@st.composite
def edited_pairs(draw):
    document = draw(mutated())
    nodes = [n for n in walk(document.root)]
    target = draw(st.sampled_from(nodes))
    kind = draw(st.sampled_from(EDITS))

    def rebuild(n: Node) -> Node:
        if n is target:
            return _edit(n, kind, draw)
        return n.with_children(tuple(rebuild(c) for c in n.children))

    edited = document.with_trees(tuple((i, rebuild(r) if i == document.main else r) for i, r in document.trees))
    return document, edited, kind


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(edited_pairs(), st.booleans())
def test_the_congruence_agrees_with_the_reference_explorer(pair, contextual):
    # The abstract pair proved means the concrete pair is not refuted; and the verdict through
    # the congruence (with its fallback) is the reference's wherever the reference finishes.
    a, b, kind = pair
    assume(a != b and size(a) <= 40 and size(b) <= 40)
    opts = dict(LIMITS, contextual=contextual, unreset=True) if contextual else dict(LIMITS)
    reference = prove_equal(a, b, **opts)
    taken = abstract(program(a), program(b))
    if taken is not None:
        abstract_v = prove_equal(a, b, programs=(taken.a, taken.b), **opts)
        note(explain(abstract_v) + explain(reference))
        event(f"{kind}: abstract {'proved' if abstract_v.equal and abstract_v.complete else 'not proved'}, "
              f"reference {'proved' if reference.equal and reference.complete else 'refuted' if not reference.equal else 'cut'}")
        if abstract_v.equal and abstract_v.complete:
            assert reference.equal, "the congruence proved what the reference refutes"
    ours = prove_by_parts(a, b, **LIMITS) if not contextual else None
    if ours is not None and not contextual and reference.complete:
        if ours.complete:
            assert ours.equal == reference.equal, explain(ours) + explain(reference)
        if not reference.equal:
            assert ours.counterexample is not None and TYPE not in explain(ours)
