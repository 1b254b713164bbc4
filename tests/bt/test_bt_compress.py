"""The BT rewrites (bt/compress.py): what each removes and what it must never touch."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from schemalog.bt.compress import compress
from schemalog.bt.model import Document, Node, walk


def leaf(t: str, **ports: str) -> Node:
    return Node(t, tuple(ports.items()))


def doc(root: Node) -> Document:
    return Document((("MainTree", root),), "MainTree")


A, B, C = leaf("A"), leaf("B", goal="{goal}"), leaf("C")


def test_nested_sequences_flatten_and_the_removed_node_is_named():
    # a named node is removed only when names are dropped (--drop-names); the rewrite names it
    inner = Node("Sequence", (("name", "inner"),), (A, B), line=4, column=7)
    result = compress(doc(Node("Sequence", (), (inner, C))), keep_names=False)
    assert result.document.root == Node("Sequence", (), (A, B, C))
    assert [str(r) for r in result.rewrites] == ["4:7: flatten: removed Sequence 'inner'"]
    assert result.kept == ()
    unnamed = compress(doc(Node("Sequence", (), (Node("Sequence", (), (A, B)), C))))
    assert unnamed.document.root == Node("Sequence", (), (A, B, C)) and unnamed.kept == ()


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


# -- named nodes (issue 48, item 4): a name is part of the tree's interface -------------------

def named(node_type: str, name: str, *children: Node, line: int = 0, column: int = 0) -> Node:
    return Node(node_type, (("name", name),), children, line=line, column=column, file="t.xml" if line else "")


def test_t15s_counting_sequence_is_kept_and_said():
    # BT.CPP's examples/t15_nodes_mocking.cpp substitutes "counting" by name with a TestNode
    say = [leaf("SaySomething", message=m) for m in "123"]
    counting = named("Sequence", "counting", *say, line=13, column=7)
    tree = Node("Sequence", (), (leaf("SaySomething", name="talk", message="hello world"), counting))
    result = compress(doc(tree))
    assert result.document.root == tree and result.rewrites == ()
    assert [(k.rule, k.type, k.name, k.file, k.line, k.column) for k in result.kept] == \
        [("flatten", "Sequence", "counting", "t.xml", 13, 7)]
    assert result.kept[0].node == 't.xml:13:7 Sequence "counting"'
    dropped = compress(doc(tree), keep_names=False)
    assert dropped.document.root == Node("Sequence", (), (tree.children[0], *say))
    assert [r.rule for r in dropped.rewrites] == ["flatten"] and dropped.kept == ()


def test_each_rule_keeps_the_named_node_it_would_remove():
    cases = [
        # (tree, the rule, the kept node's name)
        (Node("Fallback", (), (named("Fallback", "inner", A, B), C)), "flatten", "inner"),
        (Node("ReactiveSequence", (), (named("ReactiveSequence", "inner", A, B), C)), "flatten", "inner"),
        (named("Sequence", "only", A), "single", "only"),
        (named("SequenceWithMemory", "only", A), "single", "only"),
        (named("Inverter", "outer", Node("Inverter", (), (A,))), "inverters", "outer"),
        (Node("Inverter", (), (named("Inverter", "inner", A),)), "inverters", "inner"),
        (Node("ForceSuccess", (), (named("ForceFailure", "inner", A),)), "forced", "inner"),
        (named("ForceSuccess", "outer", named("ForceSuccess", "inner", A)), "forced", "inner"),
    ]
    for tree, rule, name in cases:
        result = compress(doc(tree))
        assert result.document.root == tree and result.rewrites == (), tree
        assert [(k.rule, k.name) for k in result.kept] == [(rule, name)], tree
        assert compress(doc(tree), keep_names=False).rewrites, tree      # --drop-names: rewritten as before


def test_both_named_inverters_are_said_and_the_pair_stays_whole():
    tree = named("Inverter", "a", named("Inverter", "b", A))
    result = compress(doc(tree))
    assert result.document.root == tree and [k.name for k in result.kept] == ["a", "b"]


def test_any_explicit_name_is_kept_the_type_itself_and_the_empty_name_included():
    # BT.CPP names a node after its type only when it has no name attribute; an explicit one is
    # what substitution rules and Groot2 see, whatever it says
    for name in ("Sequence", ""):
        tree = Node("Sequence", (), (named("Sequence", name, A, B), C))
        result = compress(doc(tree))
        assert result.document.root == tree and [k.name for k in result.kept] == [name or "Sequence"]


def test_of_two_forces_of_one_type_the_unnamed_outer_one_goes():
    # ForceSuccess(ForceSuccess(a)) is ForceSuccess(a) whichever of the two stays: the named one
    inner = named("ForceSuccess", "keep me", A)
    result = compress(doc(Node("ForceSuccess", (), (inner,), line=2, column=3)))
    assert result.document.root == inner and result.kept == ()
    assert [str(r) for r in result.rewrites] == ["2:3: forced: removed ForceSuccess"]
    # not when the outer one has a pre- or post-condition (it belongs to that node)
    guarded = Node("ForceSuccess", (("_onSuccess", "x:=1"),), (inner,))
    assert compress(doc(guarded)).document.root == guarded


def test_unnamed_nodes_around_named_ones_still_go():
    counting = named("Sequence", "counting", A, B)
    tree = Node("Sequence", (), (Node("Sequence", (), (Node("Fallback", (), (counting,)),)), C))
    result = compress(doc(tree))
    assert result.document.root == Node("Sequence", (), (counting, C))
    assert [r.rule for r in result.rewrites] == ["single", "single"]
    assert [(k.rule, k.name) for k in result.kept] == [("flatten", "counting")]


def test_a_named_node_is_said_once_though_two_rules_would_remove_it():
    # a named single-child Sequence inside a Sequence: `single` would remove it, then `flatten`
    tree = Node("Sequence", (), (named("Sequence", "one", A), C))
    result = compress(doc(tree))
    assert result.document.root == tree and [(k.rule, k.name) for k in result.kept] == [("single", "one")]


def test_a_guarded_or_refuted_node_is_not_said_to_be_kept_for_its_name():
    # kept for another reason (a pre-condition on it; the prover's keep set): no name is reported
    guarded = Node("Sequence", (), (Node("Sequence", (("name", "g"), ("_skipIf", "x")), (A, B)), C))
    assert compress(doc(guarded)).kept == ()
    inner = named("Sequence", "inner", A, B)
    tree = Node("Sequence", (), (inner, C))
    assert compress(doc(tree), keep=frozenset({id(inner)})).kept == ()


_LEAVES = st.sampled_from([A, B, C])
_TYPES = ["Sequence", "Fallback", "ReactiveSequence", "SequenceWithMemory", "Inverter", "ForceSuccess", "ForceFailure"]


def _named_trees(depth: int):
    if depth == 0:
        return _LEAVES

    def build(t, kids, name):
        kids = kids[:1] if t in ("Inverter", "ForceSuccess", "ForceFailure") else kids
        return Node(t, (("name", name),) if name is not None else (), tuple(kids))
    return st.one_of(_LEAVES, st.builds(build, st.sampled_from(_TYPES), st.lists(_named_trees(depth - 1), min_size=1,
                                                                                  max_size=3),
                                        st.one_of(st.none(), st.sampled_from(["n", "Sequence", ""]))))


@settings(max_examples=300, deadline=None)
@given(_named_trees(4))
def test_no_named_node_is_ever_removed_and_only_named_nodes_are_said(root):
    def names(node: Node) -> list[str]:
        return sorted(n.attr("name") for n in walk(node) if n.attr("name") is not None)

    result = compress(doc(root))
    assert names(result.document.root) == names(root)
    dropped = compress(doc(root), keep_names=False)
    assert dropped.kept == ()
    # each kept node is a named node of the original, said once (which ones dropping names
    # removes may differ: Fallback "x"(Fallback "y"(a, b)) keeps both, where dropping removes y
    # only, after which x has two children)
    kept_names = sorted(k.name if k.name != k.type else k.type for k in result.kept)
    assert len(result.kept) <= len(names(root))
    assert all(k in [n or t for n, t in _named_of(root)] for k in kept_names)
    assert not result.kept or dropped.rewrites


def _named_of(root: Node) -> list[tuple[str, str]]:
    return [(n.attr("name"), n.type) for n in walk(root) if n.attr("name") is not None]


def test_compress_tree_keeps_names_unless_told_and_proves_what_it_drops():
    from pathlib import Path

    from schemalog.api.behaviour_trees import compress_tree, read_tree

    t15 = Path(__file__).parent / "corpus" / "btcpp" / "tutorials" / "t15_nodes_mocking.xml"
    document = read_tree(t15, main="MainTree")
    kept = compress_tree(document)
    assert kept.compressed == document and kept.rewrites == () and kept.verdict is None
    assert [(k.rule, k.name, k.line, k.column) for k in kept.kept] == [("flatten", "counting", 13, 7)]
    dropped = compress_tree(document, drop_names=True)
    assert [(r.rule, r.name) for r in dropped.rewrites] == [("flatten", "counting")] and dropped.kept == ()
    assert dropped.verdict.equal and dropped.verdict.complete and dropped.nodes_after == 11
