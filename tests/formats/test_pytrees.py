"""py_trees: an exported module builds the tree with py_trees 2.x, runs to completion against the
emulated world, and its trace replays through the ORIGINAL tree (original and compressed)."""

import subprocess
import sys

import pytest

from hypothesis import given, settings

from conftest import COFFEE, MIX
from schemalog.testing.strategies import task_trees
from schemalog.evaluate.generate import generate
from schemalog.formats.documents import read_document
from schemalog.formats.pytrees import export_pytrees, load_module, run_pytrees
from schemalog.logic.parse import parse_term
from schemalog.run.execute import Executive, replay
from schemalog.run.world import World, initial_state
from schemalog.task.compress import compress
from schemalog.task.tree import instantiate


def shipped(path, task):
    kb = read_document(path).to_kb()
    tree = instantiate(kb, parse_term(task))
    return tree, World(tree, initial_state(kb)).atoms


CASES = [("figure 2", *shipped(MIX, "use(spoon)")), ("coffee and tea", *shipped(COFFEE, "prepareboth"))]
for depth, children, rd in ((4, 2, 0.5), (4, 3, 0.3), (5, 2, 0.7)):
    g = generate(depth, children, rd, seed=5)
    CASES.append((f"generated {depth}x{children} RD {rd}", g, World(g, ()).atoms))


@pytest.mark.parametrize("name, original, initial", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("which", ["original", "compressed"])
def test_exported_module_runs_to_completion_and_replays_through_the_original(name, original, initial, which):
    tree = original if which == "original" else compress(original).tree
    run = run_pytrees(export_pytrees(tree, initial), original, initial)
    assert run.status == "completed"
    assert replay(original, initial, run.trace).valid
    executive = Executive(tree, World(original, initial))
    assert executive.run().completed
    assert run.ticks == len(executive.decisions)
    assert sorted(map(str, run.trace)) == sorted(map(str, executive.trace))


def test_the_api_returns_a_live_py_trees_tree_of_py_trees_composites():
    import py_trees

    original, initial = shipped(MIX, "use(spoon)")
    module = load_module(export_pytrees(compress(original).tree, initial))
    tree = module.create_tree(lambda atom: False, lambda action: None)
    assert isinstance(tree, py_trees.trees.BehaviourTree)
    assert isinstance(tree.root, py_trees.composites.Sequence) and tree.root.name == "use(spoon)"
    assert module.run(lambda atom: False, lambda action: None) == "stuck"   # nothing released: hand not free


def test_module_runs_standalone_and_prints_its_tree(tmp_path):
    original, initial = shipped(MIX, "use(spoon)")
    path = tmp_path / "tree.py"
    path.write_text(export_pytrees(original, initial))
    r = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and "a3(cup)" in r.stdout and "first that acts" in r.stdout


def test_module_run_into_a_reader_that_stopped_ends_quietly_as_cat_does(tmp_path):
    import os
    import signal

    original, initial = shipped(COFFEE, "prepareboth")
    path = tmp_path / "tree.py"
    path.write_text(export_pytrees(original, initial))
    read, write = os.pipe()
    os.close(read)                       # `python tree.py | head -5` once head has gone
    try:
        r = subprocess.run([sys.executable, str(path)], stdout=write, stderr=subprocess.PIPE, text=True, timeout=60)
    finally:
        os.close(write)
    assert r.stderr == "" and r.returncode == -signal.SIGPIPE, r.stderr


@settings(max_examples=30, deadline=None)
@given(task_trees(max_children=4, levels=3))
def test_every_action_py_trees_takes_is_an_enabled_leaf_of_the_original(tree):
    run = run_pytrees(export_pytrees(tree, []), tree, [])
    assert replay(tree, [], run.trace).valid
    if Executive(tree, World(tree, ())).run().completed:
        assert run.status == "completed"
