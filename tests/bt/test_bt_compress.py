"""The BT rewrites (bt/compress.py): what each removes and what it must never touch."""

from __future__ import annotations

from schemalog.bt.compress import compress
from schemalog.bt.model import Document, Node


def leaf(t: str, **ports: str) -> Node:
    return Node(t, tuple(ports.items()))


def doc(root: Node) -> Document:
    return Document((("MainTree", root),), "MainTree")


A, B, C = leaf("A"), leaf("B", goal="{goal}"), leaf("C")


def test_nested_sequences_flatten_and_the_removed_node_is_named():
    inner = Node("Sequence", (("name", "inner"),), (A, B), line=4, column=7)
    result = compress(doc(Node("Sequence", (), (inner, C))))
    assert result.document.root == Node("Sequence", (), (A, B, C))
    assert [str(r) for r in result.rewrites] == ["4:7: flatten: removed Sequence 'inner'"]


def test_flattening_keeps_to_one_kind():
    # A Fallback inside a Sequence, a ReactiveSequence inside a Sequence: different rules.
    for inner_type in ("Fallback", "ReactiveSequence", "SequenceWithMemory"):
        tree = Node("Sequence", (), (Node(inner_type, (), (A, B)), C))
        assert compress(doc(tree)).document.root == tree


def test_single_child_composites_and_double_inverters_go():
    tree = Node("Fallback", (), (Node("Inverter", (), (Node("Inverter", (), (Node("Sequence", (), (B,)),)),)),))
    result = compress(doc(tree))
    assert result.document.root == B
    assert [r.rule for r in result.rewrites] == ["single", "inverters", "inverters", "single"]


def test_nested_forces_keep_the_outer_one():
    tree = Node("ForceFailure", (), (Node("ForceSuccess", (), (A,)),))
    assert compress(doc(tree)).document.root == Node("ForceFailure", (), (A,))


def test_a_node_with_a_pre_or_post_condition_is_kept():
    for attr in ("_skipIf", "_onSuccess", "_while", "_failureIf"):
        inner = Node("Sequence", ((attr, "x > 1"),), (A, B))
        tree = Node("Sequence", (), (inner, C))
        assert compress(doc(tree)).document.root == tree
        assert compress(doc(Node("Sequence", ((attr, "x"),), (A,)))).rewrites == ()


def test_custom_and_generic_nodes_are_never_rewritten():
    # <Control ID="Sequence"> is a registered custom control named like the builtin: opaque.
    generic = Node("Sequence", (), (A, B), form="Control")
    tree = Node("Sequence", (), (generic, Node("PipelineSequence", (), (Node("PipelineSequence", (), (A,)),))))
    assert compress(doc(tree)).document.root == tree


def test_every_tree_of_the_document_is_compressed_and_the_main_kept():
    d = Document((("MainTree", Node("SubTree", (("ID", "Sub"), ("goal", "{goal}")))),
                  ("Sub", Node("Sequence", (), (Node("Sequence", (), (A, B)),)))), "MainTree")
    result = compress(d)
    assert result.document.main == "MainTree"
    assert result.document.tree("MainTree") == d.tree("MainTree")
    assert result.document.tree("Sub") == Node("Sequence", (), (A, B))
