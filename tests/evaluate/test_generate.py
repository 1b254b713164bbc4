"""Generated tasks in the shape of the paper's evaluation (Sec. IV-B)."""

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from schemalog.task import conditions as cond
from schemalog.task.compress import compress
from schemalog.evaluate.generate import TOLERANCE, done, generate, max_links, max_reduction, node_count, shortfall
from schemalog.task.tree import count_nodes, depth, walk


@pytest.mark.parametrize("d, b, size", [(4, 2, 15), (5, 3, 121), (6, 4, 1365)])
def test_the_papers_shapes(d, b, size):
    tree = generate(d, b)
    assert count_nodes(tree) == node_count(d, b) == size and depth(tree) == d
    assert len({n.label for n in walk(tree)}) == size           # labels are unique
    assert all(child.releaser == cond.TRUE for child in tree.children)   # level 2: always released
    assert len({child.objects for child in tree.children}) == b          # ... each on its own object


@pytest.mark.parametrize("rd", [0.0, 0.3, 0.5, 0.7])
def test_compression_reaches_the_requested_reduction_degree(rd):
    tree = generate(6, 4, rd, seed=3)
    result = compress(tree)
    links = round(rd * (1365 - 6))
    assert result.nodes_after == 1365 - links
    assert abs(result.reduction_degree - rd) < 0.001


@pytest.mark.parametrize("d, b", [(d, b) for d in (4, 5, 6) for b in (2, 3, 4)])
def test_every_cell_of_the_papers_grid_is_within_tolerance(d, b):
    """Sec. IV-B: 9 shapes x RD 0, 0.3, 0.5, 0.7, achieved after compressing."""
    for rd in (0.0, 0.3, 0.5, 0.7):
        got = compress(generate(d, b, rd, seed=d * b), "none").reduction_degree
        assert abs(got - rd) <= TOLERANCE, (d, b, rd, got)
        assert shortfall(d, b, rd, got) is None


def test_sibling_links_alone_cap_binary_trees_below_the_papers_07():
    tree = generate(4, 2, 0.9, cousins=False)
    assert compress(tree).nodes_after == 15 - max_links(4, 2, cousins=False) == 9
    why = shortfall(4, 2, 0.7, 6 / 11, cousins=False)
    assert why is not None and "at most 0.55" in why


def test_cousin_links_merge_a_level_down_to_one_behaviour_per_second_level_subtree():
    tree = generate(4, 2, 1.0)
    result = compress(tree)
    assert result.nodes_after == 1 + 2 + 2 + 2 == 15 - max_links(4, 2)
    assert abs(max_reduction(4, 2) - 8 / 11) < 1e-9
    assert shortfall(4, 2, 1.0, result.reduction_degree) is not None


def test_a_cousin_is_released_only_by_the_last_behaviour_of_a_linked_parents_group():
    tree = generate(5, 2, 0.8, seed=4)
    parent_of = {c.label: n for n in walk(tree) for c in n.children}
    by_name = {n.label.name: n for n in walk(tree)}
    cousins = 0
    for node in walk(tree):
        for child in node.children:
            if child.releaser == cond.TRUE:
                continue
            (literal,) = cond.literals(child.releaser)
            released_by = by_name[literal.atom.args[0].name]
            if parent_of[released_by.label] is node:
                continue                                  # a sibling link
            uncle = parent_of[released_by.label]          # a cousin link: the parents are linked
            assert released_by is uncle.children[-1] and child is node.children[0]
            assert node.releaser == done(uncle.label)       # linked (as siblings or cousins)
            cousins += 1
    assert cousins > 0


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 6), st.integers(1, 4), st.floats(0, 1), st.integers(0, 10**6), st.booleans())
def test_compression_merges_exactly_the_links_drawn(depth, branching, rd, seed, cousins):
    assume(node_count(depth, branching) <= 1365)
    tree = generate(depth, branching, rd, seed, cousins)
    total = node_count(depth, branching)
    wanted = min(max_links(depth, branching, cousins), round(rd * (total - depth))) if total > depth else 0
    assert compress(tree, "none").nodes_after == total - wanted


def test_seeds_give_different_chains_and_the_same_seed_the_same_tree():
    assert generate(5, 3, 0.5, seed=1) == generate(5, 3, 0.5, seed=1)
    assert generate(5, 3, 0.5, seed=1) != generate(5, 3, 0.5, seed=2)


def test_bad_shapes_are_refused():
    with pytest.raises(ValueError):
        generate(0, 2)
    with pytest.raises(ValueError):
        generate(3, 2, 1.5)
