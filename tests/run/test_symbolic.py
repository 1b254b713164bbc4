"""The symbolic method against the explicit explorer: the same verdicts, real counterexamples.

SCHEMALOG_VERIFY_EXAMPLES sets how many random trees the cross-check draws (300 by default).
"""

import os
import warnings

import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st

from schemalog.evaluate.generate import generate
from schemalog.formats.documents import load_kb
from schemalog.logic.parse import parse_term
from schemalog.run import parts
from schemalog.logic.kb import KnowledgeBase
from schemalog.run.symbolic import OutOfNodes, SymbolicModel, Unsupported, monotone_settling
from schemalog.run.verify import Verifier, all_states, constraints, free_atoms, verify_by_parts, verify_symbolic
from schemalog.run.world import World, initial_state
from schemalog.task import conditions as cond
from schemalog.task.compress import compress
from schemalog.task.tree import Behaviour, instantiate

from conftest import COFFEE, MIX, assert_replays, settled
from schemalog.testing.strategies import starts, trees

EXAMPLES = int(os.environ.get("SCHEMALOG_VERIFY_EXAMPLES", "300"))


def c(text):
    return cond.from_term(parse_term(text))


def both(original, compressed, initial):
    explicit = Verifier(original, compressed, World(original), max_states=5_000).verify(initial)
    symbolic = verify_symbolic(original, compressed, World(original), initial)
    return explicit, symbolic


@settings(max_examples=EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])
@given(st.data(), trees(), st.sampled_from(["none", "pre", "full"]))
def test_symbolic_and_explicit_agree_on_random_trees(data, tree, propagate):
    compressed = compress(tree, propagate).tree
    initial = settled(tree, data.draw(starts(tree)))
    assume(monotone_settling(World(tree)) is None)
    explicit, symbolic = both(tree, compressed, initial)
    assume(explicit.exhaustive)
    assert (symbolic.sound, symbolic.complete) == (explicit.sound, explicit.complete)
    assert symbolic.compressed_states == explicit.compressed_states      # the same reachable set
    ce = symbolic.properties["soundness"].counterexample
    if ce is not None:                  # a shortest run to a bad step: every step before it is sound
        assert_replays(tree, compressed, ce, initial)
    ce = symbolic.properties["completion"].counterexample
    if ce is not None:                  # in an unsound tree, the way to a dead end may need a bad step
        assert_replays(tree, compressed, ce, initial, sound_run=symbolic.sound)
    if len(initial) == 1:     # by parts, the same verdict again
        try:
            parts = verify_by_parts(tree, compressed, World(tree), initial, method="symbolic")
        except Unsupported:         # a part's root (its children's posts together) may not settle monotonically
            parts = None
        if parts is not None:
            assert (parts.sound, parts.complete) == (explicit.sound, explicit.complete)


@pytest.mark.parametrize("path,label", [(MIX, "use(spoon)"), (COFFEE, "prepareboth")])
@pytest.mark.parametrize("propagate", ["none", "pre", "full"])
def test_the_papers_tasks_from_every_allowed_state(path, label, propagate):
    kb = load_kb([path])
    tree = instantiate(kb, parse_term(label))
    world = World(tree)
    initial = all_states(world, free_atoms(kb, tree), constraints(kb))
    explicit, symbolic = both(tree, compress(tree, propagate).tree, initial)
    assert explicit.exhaustive and symbolic.exhaustive and symbolic.method == "symbolic"
    assert (symbolic.sound, symbolic.complete) == (explicit.sound, explicit.complete)
    assert symbolic.compressed_states == explicit.compressed_states
    assert symbolic.sound == (propagate == "full" or label == "use(spoon)" and propagate == "pre")
    ce = symbolic.properties["soundness"].counterexample
    if ce is not None:
        assert_replays(tree, compress(tree, propagate).tree, ce, initial)


def test_a_generated_task_beyond_the_explorer_is_proved():
    """Depth 6, 4 children: 1,365 behaviours, whose parts the explorer cannot finish."""
    tree = generate(6, 4, 0.5, seed=1)
    compressed = compress(tree).tree
    world = World(tree)
    report = verify_by_parts(tree, compressed, world, [world.atoms], method="symbolic")
    assert report.exhaustive and report.sound and report.complete
    assert report.parts == len(parts.parts_of(parts.decompose(tree, compressed, world.atoms))) > 100
    assert not Verifier(tree, compressed, World(tree), max_states=2_000).verify([world.atoms]).exhaustive


def test_a_generated_task_without_propagation_is_refuted_with_a_real_run():
    tree = generate(4, 3, 0.5, seed=1)
    compressed = compress(tree, "none").tree
    initial = [World(tree).atoms]
    symbolic = verify_symbolic(tree, compressed, World(tree), initial)
    explicit = Verifier(tree, compressed, World(tree)).verify(initial)
    assert not symbolic.sound and not explicit.sound
    assert_replays(tree, compressed, symbolic.properties["soundness"].counterexample, initial)


def test_the_node_limit_stops_with_no_proof_and_says_where():
    tree = generate(5, 3, 0.5, seed=1)
    world = World(tree)
    with pytest.raises(OutOfNodes, match="grew past 500 nodes while"):
        verify_symbolic(tree, compress(tree).tree, world, [world.atoms], max_nodes=500)


def test_non_monotone_settling_is_left_to_the_explorer():
    """Completing `s` sets hand.free, which completing `t` reads false: the settled state
    would depend on the order, so the symbolic encoding is not used."""
    s = Behaviour(parse_term("s"), post=c("s.done and hand.free"), children=(
        Behaviour(parse_term("a"), post=c("a.done")),))
    u = Behaviour(parse_term("u"), post=c("u.done"), children=(
        Behaviour(parse_term("g"), post=c("not hand.free")),))
    root = Behaviour(parse_term("r"), post=c("r.done"), children=(s, u))
    world = World(root)
    assert "hand.free" in monotone_settling(world)
    with pytest.raises(Unsupported, match="not a monotone closure"):
        verify_symbolic(root, compress(root).tree, world, [world.atoms])


def test_auto_leaves_a_long_merged_behaviour_to_the_explorer():
    from conftest import wide_task
    from schemalog.run.verify import LONGEST_SYMBOLIC_STEP, prove

    kb, tree = wide_task(LONGEST_SYMBOLIC_STEP + 1)
    world = World(tree, initial_state(kb))
    report = prove(tree, compress(tree).tree, world, [world.atoms])
    assert report.method == "explicit" and report.sound and report.complete and report.exhaustive
    assert f"a merged behaviour of {LONGEST_SYMBOLIC_STEP + 1} actions" in report.note


def test_initial_states_of_the_file_are_covered_at_once():
    kb = load_kb([COFFEE])
    tree = instantiate(kb, parse_term("prepareboth"))
    world = World(tree, initial_state(kb))
    initial = all_states(world, free_atoms(kb, tree), constraints(kb))
    report = verify_symbolic(tree, compress(tree).tree, world, initial)
    assert len(report.initial_states) == 64 and report.sound and report.complete
    assert "40 of 64 initial state(s) can complete" in report.properties["completion"].summary


# --- the command line, as a user runs it ----------------------------------------

def schemalog(*args):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "schemalog", *args], capture_output=True, text=True, timeout=300)


def test_verify_proves_symbolically_by_default_and_explicitly_on_request():
    default = schemalog("verify", COFFEE, "--states", "all")
    explicit = schemalog("verify", COFFEE, "--states", "all", "--method", "explicit")
    assert default.returncode == explicit.returncode == 0
    assert "explored 474 states of the compressed tree as sets" in default.stdout
    assert "explored 474 states of the compressed tree and 1,659 of the original" in explicit.stdout
    refuted = schemalog("verify", COFFEE, "--propagate", "pre", "--json")
    assert refuted.returncode == 1
    import json
    data = json.loads(refuted.stdout)
    assert data["explored"]["method"] == "symbolic" and data["sound"] is False
    assert data["counterexample"]["action"] == "gripper(close)"


def test_a_blow_up_says_where_and_proves_nothing(tmp_path):
    """Under the paper's propagation a chain of sub-tasks is explored as one part (docs/semantics.md,
    "Sequential phases"): 40 atoms, past 300 nodes."""
    task = tmp_path / "g.pl"
    assert schemalog("generate", "--depth", "5", "--children", "3", "--rd", "0.5", "--seed", "1",
                     "-o", str(task)).returncode == 0
    pre = ("--propagate", "pre", "--max-bdd-nodes", "300")
    out = schemalog("verify", str(task), *pre, "--method", "symbolic")
    assert out.returncode == 3 and "Traceback" not in out.stderr
    assert "in the part of b1 made of b2(obj1) (40 atoms)" in out.stdout and "grew past 300 nodes" in out.stdout
    assert "result: no proof" in out.stdout
    whole = schemalog("verify", str(task), *pre, "--no-split", "--method", "symbolic")
    assert whole.returncode == 3 and "grew past 300 nodes while" in whole.stdout
    assert "in the part" not in whole.stdout
    auto = schemalog("verify", str(task), *pre)     # auto: the explorer takes over
    assert auto.returncode == 0 and "note: explored one state at a time: in the part of" in auto.stdout


def test_symbolic_refuses_what_it_cannot_encode_and_auto_falls_back(tmp_path):
    task = tmp_path / "t.pl"
    task.write_text("task(r).\n"
                    "schema(r, [(s, true), (u, true)], r.done).\n"
                    "schema(s, [(a, true)], (s.done, hand.free)).\n"
                    "schema(u, [(g, true)], u.done).\n"
                    "schema(a, [], a.done).\n"
                    "schema(g, [], -hand.free).\n")
    auto = schemalog("verify", str(task))
    assert auto.returncode in (0, 1, 3) and "note: explored one state at a time: settling is not a monotone" \
        in auto.stdout
    strict = schemalog("verify", str(task), "--method", "symbolic")
    assert strict.returncode == 2 and "--method symbolic cannot verify this task exactly" in strict.stderr
    assert "Traceback" not in strict.stderr


def tree_of(text):
    kb = KnowledgeBase()
    kb.consult_text(text, "t.pl")
    return instantiate(kb, parse_term("t"))


@settings(max_examples=200, deadline=None)
@given(st.data())
def test_a_state_is_in_a_set_as_the_set_says(data):
    # member walks one path down the diagram; CUDD's substitution is the reference
    names = ["go", "a.done", "b.done", "c.done", "d.done"]
    tree = tree_of("schema(t, [(a, go), (b, a.done)], t.done).\nschema(a, [], a.done).\nschema(b, [], b.done).\n")
    m = SymbolicModel(
        tree, tree, World(tree), extra_atoms=[parse_term(n) for n in names])
    literals = st.builds(lambda n, p: n if p else f"not {n}", st.sampled_from(names), st.booleans())
    text = data.draw(st.recursive(literals, lambda inner: st.builds(
        lambda a, op, b: f"({a} {op} {b})", inner, st.sampled_from(["and", "or"]), inner), max_leaves=8))
    u = m.condition(c(text))
    state = frozenset(parse_term(n) for n in data.draw(st.sets(st.sampled_from(names))))
    values = {f"x{i}": a in state for i, a in enumerate(m.atoms) if f"x{i}" in m.bdd.support(u)}
    assert m.member(state, u) == (m.bdd.let(values, u) == m.bdd.true) == cond.holds(c(text), state)


def test_a_long_condition_costs_diagram_operations_linear_in_its_literals():
    # joined bottom-up: a literal above the diagram so far is one operation (issue 32; the
    # other order walked the whole diagram per literal: 20,000 literals took 106 s)
    tree = tree_of("schema(t, [(a, true)], t.done).\nschema(a, [], a.done).\n")
    n = 5_000
    atoms = [parse_term(f"p{i}") for i in range(n)]
    m = SymbolicModel(tree, tree, World(tree), extra_atoms=atoms)
    for join in (cond.And, cond.Or):
        with warnings.catch_warnings():        # dd's note that 'mem' is now in bytes
            warnings.simplefilter("ignore")
            before = m.bdd.statistics()["cache_lookups"]
            u = m.condition(join(tuple(cond.Lit(a, True) for a in atoms)))   # top of the order first
            lookups = m.bdd.statistics()["cache_lookups"] - before
        assert lookups < 4 * n, lookups          # n * n / 2 joined top-down
        assert len(u) == n + 1                   # its nodes and the constant
        assert m.member(frozenset(atoms), u) and m.member(frozenset(atoms[1:]), u) == (join is cond.Or)


@pytest.mark.parametrize("path,label", [(MIX, "use(spoon)"), (COFFEE, "prepareboth")])
def test_a_compressed_tree_as_the_original_is_encoded_whole(path, label):
    """Compressing a compressed task gives leaves whose constituents set atoms (a1.done) that no
    node's own condition mentions; the symbolic model encodes them, and agrees with the
    explorer (issue 46: a KeyError on Struct('.', (a1, done)))."""
    tree = instantiate(load_kb([path]), parse_term(label))
    small = compress(tree).tree
    world = World(tree)
    explicit = Verifier(small, small, world, max_states=5_000).verify([world.atoms])
    symbolic = verify_symbolic(small, small, world, [world.atoms])
    assert (symbolic.sound, symbolic.complete) == (explicit.sound, explicit.complete)
