"""Definition 1 and Algorithm 1: the paper's results, properties, provenance, bad input."""

import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from schemalog.task import conditions as cond
from schemalog.task.compress import compress, decompress, maximal_paths, merged_label, sequential_pairs
from schemalog.formats.documents import document_from_text, read_document, to_pl
from schemalog.logic.engine import Engine
from schemalog.task.facts import compression_kb
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.formats.render import tree_document
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import Behaviour, count_nodes, instantiate, walk

from conftest import COFFEE, MIX
from schemalog.testing.strategies import task_trees


def tree_of(path, task):
    return instantiate(read_document(path).to_kb(), parse_term(task))


def by_label(tree):
    return {term_to_text(n.label): n for n in walk(tree)}


MIX_TREE = tree_of(MIX, "use(spoon)")
COFFEE_TREE = tree_of(COFFEE, "prepareboth")


def test_figure_2_under_the_papers_rule():
    result = compress(MIX_TREE, "pre")
    assert (result.nodes_before, result.nodes_after) == (12, 6)
    nodes = by_label(result.tree)
    assert cond.to_text(nodes["subtask(take_mix,spoon)"].pre) == "hand.free or spoon.taken"
    assert cond.to_text(nodes["a1_a2(spoon)"].pre) == "hand.free"
    assert cond.to_text(nodes["a3_a4_a5_a6_a7(cup)"].pre) == "spoon.taken"
    assert cond.to_text(nodes["a1_a2(spoon)"].post) == "a2.done"  # the last constituent's
    assert nodes["gripper(close)"].k == 1 and nodes["gripper(open)"].k == 1  # another agent: unmerged
    assert [n.k for n in walk(result.tree)] == [1, 2, 2, 1, 5, 1]
    assert [term_to_text(m) for m in nodes["a3_a4_a5_a6_a7(cup)"].merged_from] == \
        ["a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"]


def test_figure_2_with_full_propagation_adds_not_post():
    nodes = by_label(compress(MIX_TREE, "full").tree)
    assert cond.to_text(nodes["a1_a2(spoon)"].pre) == "hand.free and not spoon.taken"
    assert cond.to_text(nodes["a3_a4_a5_a6_a7(cup)"].pre) == "spoon.taken and not spoon.used"
    assert cond.to_text(nodes["gripper(close)"].pre) == "hand.free and not spoon.taken and a2.done"


def test_figure_2_without_propagation_shows_the_aliasing():
    nodes = by_label(compress(MIX_TREE, "none").tree)
    # Figure 2 (middle): both merged actions always enabled.
    assert cond.to_text(nodes["a1_a2(spoon)"].pre) == "true"
    assert cond.to_text(nodes["a3_a4_a5_a6_a7(cup)"].pre) == "true"


def test_coffee_and_tea_63_to_33():
    result = compress(COFFEE_TREE)
    assert (result.nodes_before, result.nodes_after) == (63, 33)
    assert (result.depth_before, result.depth_after) == (5, 5)
    assert result.reduction_degree == pytest.approx(30 / 58)
    labels = {term_to_text(n.label) for n in walk(result.tree)}
    assert {"subtask(take_pour,water)", "subtask(take_mix,spoon)", "a1_a2(water)", "a3_a4_a5_a6_a7(cup)"} <= labels
    assert result.simplifier.sympy_calls == 0  # the fast exact path handles every merge here


def test_chain_is_merged_whatever_the_sibling_order():
    # a3..a7 shuffled: still one a3_a4_a5_a6_a7, never a3_a4 + a5_a6_a7.
    mix = by_label(MIX_TREE)["subtask(mix,spoon)"]
    for seed in range(20):
        kids = list(mix.children)
        random.Random(seed).shuffle(kids)
        shuffled = Behaviour(label=mix.label, releaser=mix.releaser, post=mix.post, children=tuple(kids))
        labels = sorted(term_to_text(c.label) for c in compress(shuffled).tree.children)
        assert labels == ["a3_a4_a5_a6_a7(cup)", "gripper(open)"]


def kb_tree(text, task="t"):
    kb = KnowledgeBase()
    kb.consult_text(text, "t.pl")
    return kb, instantiate(kb, parse_term(task))


def test_branching_gives_one_merged_behaviour_per_successor():
    kb, tree = kb_tree("""
        schema(t, [(b(x), true), (j(x), b.done), (k(x), b.done)], t.done).
        schema(b(x), [], b.done). schema(j(x), [], j.done). schema(k(x), [], k.done).""")
    result = compress(tree)
    assert [term_to_text(c.label) for c in result.tree.children] == ["b_j(x)", "b_k(x)"]
    assert decompress(result.tree) == tree  # b appears twice, and comes back once


def test_releaser_cycle_is_left_unmerged_with_a_note():
    kb, tree = kb_tree("""
        schema(t, [(a(x), b.done), (b(x), a.done), (c(x), true), (d(x), c.done)], t.done).
        schema(a(x), [], a.done). schema(b(x), [], b.done). schema(c(x), [], c.done). schema(d(x), [], d.done).""")
    result = compress(tree)
    assert sorted(term_to_text(c.label) for c in result.tree.children) == ["a(x)", "b(x)", "c_d(x)"]
    assert any("cycle" in n and "a(x), b(x)" in n for n in result.notes)


def test_no_merge_protects_a_behaviour():
    from schemalog.task.compress import protected_labels
    text = MIX.read_text() + "\nno_merge(a2(spoon)).\n"
    kb = document_from_text(text, "mix.pl").to_kb()
    tree = instantiate(kb, parse_term("use(spoon)"))
    result = compress(tree, protected=protected_labels(kb, tree))
    labels = {term_to_text(n.label) for n in walk(result.tree)}
    assert "a1(spoon)" in labels and "a2(spoon)" in labels and "a1_a2(spoon)" not in labels


def test_merged_labels_follow_the_paper():
    p = parse_term
    assert merged_label([p("a1(spoon)"), p("a2(spoon)")]) == p("a1_a2(spoon)")
    assert merged_label([p("subtask(take,spoon)"), p("subtask(mix,spoon)")]) == p("subtask(take_mix,spoon)")
    assert merged_label([p("go"), p("stop")]) == p("go_stop")
    assert merged_label([p("pick(a, spoon)"), p("place(b, spoon)")]) == p("pick_place(a,spoon)")


def test_merged_label_is_unique_among_siblings():
    kb, tree = kb_tree("""
        schema(t, [(a1_a2(x), true), (a1(x), true), (a2(x), a1.done)], t.done).
        schema(a1_a2(x), [], q.done). schema(a1(x), [], a1.done). schema(a2(x), [], a2.done).""")
    labels = [term_to_text(c.label) for c in compress(tree).tree.children]
    assert sorted(labels) == ["a1_a2(x)", "a1_a2_2(x)"]


def test_forty_variable_condition_is_kept_and_said():
    atoms = " or ".join(f"(v{i}.x and not v{i + 1}.x)" for i in range(40))
    simplifier = cond.Simplifier()
    c = cond.from_term(parse_term(atoms))
    out = simplifier.simplify(cond.disjoin([c, cond.from_term(parse_term("v0.x"))]))
    assert simplifier.sympy_calls == 0 and simplifier.notes and "over the sympy budget" in simplifier.notes[0]
    assert cond.equivalent(out, cond.disjoin([c, cond.from_term(parse_term("v0.x"))]))


def test_a_100k_sibling_chain_compresses_without_recursion():
    from schemalog.logic.terms import Atom, Struct

    def done(i):
        return cond.Lit(Struct(".", (Atom(f"s{i}"), Atom("done"))))

    n = 100_000
    kids = tuple(Behaviour(label=Struct(f"s{i}", (Atom("x"),)), objects=(Atom("x"),),
                           releaser=cond.TRUE if i == 0 else done(i - 1), post=done(i)) for i in range(n))
    root = Behaviour(label=parse_term("t"), post=cond.Lit(parse_term("t.done")), children=kids)
    result = compress(root)
    assert result.nodes_after == 2 and result.tree.children[0].k == n
    assert decompress(result.tree) == root


def test_written_compressed_file_loads_back_and_decompresses():
    result = compress(COFFEE_TREE)
    text = to_pl(tree_document(result.tree))
    again = instantiate(document_from_text(text, "c.pl").to_kb(), parse_term("prepareboth"))
    assert [n.pre for n in walk(again)] == [n.pre for n in walk(result.tree)]
    assert [n.k for n in walk(again)] == [n.k for n in walk(result.tree)]
    assert decompress(again) == COFFEE_TREE
    assert compress(again).nodes_after == 33  # idempotent through the file too


# --- properties over generated trees ---------------------------------------

@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_trees(), st.sampled_from(["none", "pre", "full"]))
def test_decompress_undoes_compress(tree, propagate):
    assert decompress(compress(tree, propagate).tree) == tree


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_trees())
def test_compression_is_idempotent(tree):
    once = compress(tree).tree
    twice = compress(once).tree
    assert count_nodes(twice) == count_nodes(once)
    assert [n.label for n in walk(twice)] == [n.label for n in walk(once)]


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_trees(), st.randoms(use_true_random=False))
def test_result_does_not_depend_on_sibling_order(tree, rnd):
    def shuffled(b):
        kids = [shuffled(c) for c in b.children]
        rnd.shuffle(kids)
        return Behaviour(label=b.label, agent=b.agent, objects=b.objects, releaser=b.releaser,
                         post=b.post, children=tuple(kids))
    a, b = compress(tree).tree, compress(shuffled(tree)).tree
    assert count_nodes(a) == count_nodes(b)
    assert sorted(term_to_text(n.label) for n in walk(a)) == sorted(term_to_text(n.label) for n in walk(b))


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_trees())
def test_prolog_rule_and_indexed_rule_agree(tree):
    kb = compression_kb(tree)
    engine = Engine(kb)
    from schemalog.logic.terms import Var, Struct
    x, y = Var("X"), Var("Y")
    by_prolog = {(b.resolve(x).value, b.resolve(y).value)
                 for b in engine.solve(Struct("sequential", (x, y)))}
    by_index = set()
    ids = {}
    for i, node in enumerate(walk(tree)):
        ids[id(node)] = i
    for node in walk(tree):
        for i, j in sequential_pairs(node.children):
            by_index.add((ids[id(node.children[i])], ids[id(node.children[j])]))
    assert by_prolog == by_index


def test_maximal_paths_on_a_diamond_and_isolated_nodes():
    paths, cycles = maximal_paths(5, [(0, 1), (0, 2), (1, 3), (2, 3)])
    assert paths == [[0, 1, 3], [0, 2, 3], [4]] and cycles == []


def test_duplicate_labels_with_different_conditions():
    # Two a(x) siblings, released differently: a -> a -> c and a -> c (a join), so the
    # branching rule gives two merged behaviours, with distinct labels.
    kb, tree = kb_tree("""
        schema(t, [(a(x), true), (a(x), a.done), (c(x), a.done)], t.done).
        schema(a(x), [], a.done). schema(c(x), [], c.done).""")
    result = compress(tree)
    assert [term_to_text(c.label) for c in result.tree.children] == ["a_a_c(x)", "a_c(x)"]
    assert [c.k for c in result.tree.children] == [3, 2]
    assert decompress(result.tree) == tree
    again = instantiate(document_from_text(to_pl(tree_document(result.tree)), "d.pl").to_kb(),
                        parse_term("t"))
    assert decompress(again) == tree


def test_branching_that_would_grow_the_tree_merges_only_unbranched_chains():
    # A composite hub released-before 30 sibling sub-tasks: the branching rule would copy
    # its sub-tree 30 times. Bm must stay <= Bi (RD >= 0, Sec. IV-A).
    leaves = " ".join(f"schema(h{i}(cup), [], h{i}.done)." for i in range(5))
    subs = ", ".join(f"(s{i}(cup), hub.done)" for i in range(30))
    kb, tree = kb_tree(f"""
        schema(t, [(hub(cup), true), {subs}], t.done).
        schema(hub(cup), [{', '.join(f'(h{i}(cup), true)' for i in range(5))}], hub.done).
        {leaves} {" ".join(f"schema(s{i}(cup), [(x{i}(cup), true)], s{i}.done)." for i in range(30))}
        {" ".join(f"schema(x{i}(cup), [], x{i}.done)." for i in range(30))}""")
    result = compress(tree)
    assert result.nodes_after <= result.nodes_before and result.reduction_degree >= 0
    assert any("would grow the tree" in n for n in result.notes)
    assert decompress(result.tree) == tree
    assert compress(result.tree).nodes_after == result.nodes_after


def test_a_lattice_does_not_explode():
    # 8 layers of 2 siblings, each layer released by the previous one's post: 2^8 paths.
    entries, leaves = [], []
    for layer in range(8):
        for k in range(2):
            entries.append(f"(x{layer}_{k}(cup), {'true' if layer == 0 else f'l{layer - 1}.done'})")
            leaves.append(f"schema(x{layer}_{k}(cup), [], l{layer}.done).")
    kb, tree = kb_tree(f"schema(t, [{', '.join(entries)}], t.done).\n" + "\n".join(leaves))
    result = compress(tree)
    assert result.nodes_after <= result.nodes_before


def test_decompress_refuses_a_behaviour_without_provenance():
    from schemalog.errors import SchemalogError
    result = compress(MIX_TREE)
    text = to_pl(tree_document(result.tree))
    edited = "\n".join(line for line in text.splitlines() if not line.startswith("origins(subtask(take_mix"))
    again = instantiate(document_from_text(edited, "edited.pl").to_kb(), parse_term("use(spoon)"))
    with pytest.raises(SchemalogError, match="has no provenance"):
        decompress(again)


def test_merged_label_suffixes_do_not_depend_on_sibling_order():
    kb, tree = kb_tree("""
        schema(t, [(a(cup), true), (a(cup), x.done), (b(cup), a.done)], t.done).
        schema(a(cup), [], a.done). schema(b(cup), [], b.done).""")
    forward = {term_to_text(c.label): cond.to_text(c.pre) for c in compress(tree).tree.children}
    backward_tree = Behaviour(label=tree.label, post=tree.post, children=tuple(reversed(tree.children)))
    backward = {term_to_text(c.label): cond.to_text(c.pre) for c in compress(backward_tree).tree.children}
    assert forward == backward


def test_long_chain_with_conjunctive_posts_stays_fast_and_exact():
    # The merged pre-condition is an OR of 5,000 conjunctions: absorption must not be quadratic.
    from schemalog.logic.terms import Atom, Struct

    def lit(name):
        return cond.Lit(Struct(".", (Atom(name), Atom("done"))))

    n = 5_000
    kids = []
    for i in range(n):
        post = cond.conjoin([lit(f"a{i}"), lit("h")])
        releaser = lit("s") if i == 0 else cond.conjoin([lit(f"a{i - 1}"), lit("h")])
        kids.append(Behaviour(label=Struct(f"a{i}", (Atom("cup"),)), objects=(Atom("cup"),),
                              releaser=releaser, post=post))
    root = Behaviour(label=Atom("t"), post=lit("t"), children=tuple(kids))
    result = compress(root)
    assert result.nodes_after == 2 and decompress(result.tree) == root
