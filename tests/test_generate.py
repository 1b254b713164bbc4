"""Generated tasks in the shape of the paper's evaluation (Sec. IV-B)."""

import pytest

from schemalog import conditions as cond
from schemalog.compress import compress
from schemalog.generate import generate, max_links, node_count
from schemalog.tree import count_nodes, depth, walk


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


def test_reduction_is_capped_by_the_shape():
    tree = generate(4, 2, 0.9)
    assert compress(tree).nodes_after == 15 - max_links(4, 2) == 9


def test_seeds_give_different_chains_and_the_same_seed_the_same_tree():
    assert generate(5, 3, 0.5, seed=1) == generate(5, 3, 0.5, seed=1)
    assert generate(5, 3, 0.5, seed=1) != generate(5, 3, 0.5, seed=2)


def test_bad_shapes_are_refused():
    with pytest.raises(ValueError):
        generate(0, 2)
    with pytest.raises(ValueError):
        generate(3, 2, 1.5)
