"""Verification: soundness and completion of compressed trees, with counterexamples."""

import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st

from schemalog.task import conditions as cond
from schemalog.task.compress import Compressor, compress, with_origins
from schemalog.formats.documents import load_kb
from schemalog.evaluate.generate import generate
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import Behaviour, instantiate
from schemalog.run.verify import Verifier, all_states, constraints, free_atoms, verify_by_parts
from schemalog.run.world import World, initial_state

from conftest import COFFEE, MIX, settled, wide_task
from schemalog.testing.strategies import starts, task_trees, trees


def t(text):
    return parse_term(text)


def c(text):
    return cond.from_term(parse_term(text))


def loaded(path, label):
    kb = load_kb([path])
    return kb, instantiate(kb, t(label))


FIG2_KB, FIG2 = loaded(MIX, "use(spoon)")
COFFEE_KB, COFFEE_TREE = loaded(COFFEE, "prepareboth")


def verify(original, compressed, kb=None, states="default", **kw):
    world = World(original)
    if states == "all":
        initial = all_states(world, free_atoms(kb, original), constraints(kb))
    else:
        world.reset(initial_state(kb) if kb is not None else [])
        initial = [world.atoms]
    return Verifier(original, compressed, world, **kw).verify(initial)


@pytest.mark.parametrize("propagate", ["pre", "full"])
@pytest.mark.parametrize("states", ["default", "all"])
def test_figure_2_compressed_is_sound_and_complete(propagate, states):
    report = verify(FIG2, compress(FIG2, propagate).tree, FIG2_KB, states)
    assert report.sound and report.complete and report.exhaustive
    assert len(report.initial_states) == (4 if states == "all" else 1)


def test_figure_2_without_propagation_shows_the_aliasing():
    report = verify(FIG2, compress(FIG2, "none").tree, FIG2_KB)
    assert not report.sound
    ce = report.properties["soundness"].counterexample
    assert ce.path == () and term_to_text(ce.behaviour) == "a3_a4_a5_a6_a7(cup)"
    assert term_to_text(ce.action) == "a3(cup)"
    assert ce.reasons == ("use(spoon) > subtask(mix,spoon) > a3(cup): subtask(mix,spoon)'s pre-condition "
                          "spoon.taken is false (false: spoon.taken)",)


def test_coffee_and_tea_is_sound_with_full_propagation_from_every_allowed_state():
    report = verify(COFFEE_TREE, compress(COFFEE_TREE, "full").tree, COFFEE_KB, "all")
    assert report.sound and report.complete and report.exhaustive
    assert len(report.initial_states) == 64
    assert report.properties["flexibility"].holds


def test_coffee_and_tea_under_the_papers_rule_has_a_counterexample():
    """DESIGN.md section 4: propagating only the parent's pre-condition is not sound."""
    report = verify(COFFEE_TREE, compress(COFFEE_TREE, "pre").tree, COFFEE_KB)
    assert not report.sound and report.complete
    ce = report.properties["soundness"].counterexample
    assert term_to_text(ce.action) == "gripper(close)"
    steps = [term_to_text(s.behaviour) for s in ce.path]
    assert steps[-1] == "gripper(open)" and "a3_a4_a5_a6_a7(cup)" in steps
    assert any("add(water) is accomplished (water.used holds)" in r for r in ce.reasons)
    # the counterexample is a real run: replaying its actions through the compressed tree
    # reaches the reported state
    world = World(COFFEE_TREE, initial_state(COFFEE_KB))
    for step in ce.path:
        for action in step.actions:
            leaf = next(n for n in _leaves(COFFEE_TREE) if n.label == action)
            world.perform(leaf.post)
    assert world.atoms == ce.state


def _leaves(tree):
    from schemalog.task.tree import walk
    return [n for n in walk(tree) if not n.children]


def test_a_merged_action_and_sub_task_would_get_stuck():
    """What Definition 1's same-kind condition prevents: merging an action with a sub-task."""
    act = Behaviour(t("b3(cup)"), objects=(t("cup"),), post=c("b3.done"))
    sub = Behaviour(t("b4(cup)"), objects=(t("cup"),), releaser=c("b3.done"), post=c("b4.done"),
                    children=(Behaviour(t("b7(cup)"), objects=(t("cup"),), post=c("b7.done")),))
    original = Behaviour(t("r"), post=c("r.done"), children=(act, sub))
    assert compress(original).nodes_after == 4                  # r, b3, b4, b7: nothing merged
    stamped = with_origins(original)
    merged = Compressor().merge(list(stamped.children), t("b3_b4(cup)"))
    forced = Behaviour(t("r"), post=c("r.done"), children=(merged,), origins=stamped.origins)
    report = verify(original, forced)
    assert not report.complete
    ce = report.properties["completion"].counterexample
    assert ce.reasons[0] == "the original could still take: b3(cup)"


def test_trace_counts_and_a_lost_interleaving():
    two = Behaviour(t("r"), post=c("a.done and b.done"), children=(
        Behaviour(t("s"), post=c("a.done"), children=(Behaviour(t("a"), post=c("a.done")),)),
        Behaviour(t("u"), post=c("b.done"), children=(Behaviour(t("b"), post=c("b.done")),))))
    report = verify(two, compress(two).tree)
    assert report.properties["traces"].summary.startswith("the original has 2 complete trace(s), "
                                                          "the compressed tree 2")
    report = verify(COFFEE_TREE, compress(COFFEE_TREE).tree, COFFEE_KB)
    traces = report.properties["traces"]
    assert not traces.holds and traces.details["lost_example"]["trace"][0] == "a1(water)"


def test_the_state_limit_makes_the_result_no_proof():
    report = verify(COFFEE_TREE, compress(COFFEE_TREE).tree, COFFEE_KB, max_states=20)
    assert not report.exhaustive
    assert report.properties["soundness"].holds is None
    assert "not all" in report.properties["soundness"].summary


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(task_trees(max_children=3, levels=4))
def test_full_propagation_is_sound_and_complete_on_random_trees(tree):
    report = verify(tree, compress(tree, "full").tree, max_states=5_000)
    assume(report.exhaustive)
    assert report.sound, report.properties["soundness"].counterexample
    assert report.complete, report.properties["completion"].counterexample


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(st.integers(2, 6), st.integers(1, 4), st.sampled_from([0.0, 0.3, 0.5, 0.7]), st.integers(0, 10**6))
def test_generated_tasks_compress_soundly(depth, branching, rd, seed):
    """Depth 2-6, 1-4 children (15 to 1,365 behaviours), verified by independent parts."""
    assume(branching ** (depth - 1) <= 256)
    tree = generate(depth, branching, rd, seed)
    world = World(tree)
    report = verify_by_parts(tree, compress(tree).tree, world, [world.atoms], max_states=5_000) or \
        verify(tree, compress(tree).tree, max_states=5_000)
    assume(report.exhaustive)
    assert report.sound and report.complete


# --- independent parts and sequential phases: exact reductions (more in test_parts.py) ---

def test_generated_tasks_split_into_independent_parts_and_are_proved():
    tree = generate(5, 3, 0.5, seed=1)
    compressed = compress(tree).tree
    world = World(tree)
    report = verify_by_parts(tree, compressed, world, [world.atoms])
    assert report.parts == 37 and report.exhaustive and report.sound and report.complete
    # the whole task, explored at once, does not fit in the same budget
    assert not Verifier(tree, compressed, World(tree), max_states=20_000).verify([world.atoms]).exhaustive


def test_a_counterexample_in_a_part_is_a_run_of_the_whole_task():
    other = Behaviour(t("tidy"), post=c("tidy.done"), children=(Behaviour(t("wipe(table)"), post=c("wipe.done")),))
    both = Behaviour(t("both"), post=c("both.done"), children=(FIG2, other))
    world = World(both, [t("hand.free")])
    report = verify_by_parts(both, compress(both, "none").tree, world, [world.atoms])
    assert report is not None and report.parts == 2 and not report.sound
    ce = report.properties["soundness"].counterexample
    assert ce.initial == frozenset({t("hand.free")}) and term_to_text(ce.action) == "a3(cup)"


def test_a_task_whose_parts_share_an_atom_does_not_split():
    world = World(COFFEE_TREE, initial_state(COFFEE_KB))
    assert verify_by_parts(COFFEE_TREE, compress(COFFEE_TREE).tree, world, [world.atoms]) is None


@settings(max_examples=200, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(task_trees(max_children=3, levels=4), st.sampled_from(["none", "pre", "full"]))
def test_parts_and_the_whole_give_the_same_verdict(tree, propagate):
    compressed = compress(tree, propagate).tree
    world = World(tree)
    initial = [world.atoms]
    whole = Verifier(tree, compressed, world, max_states=5_000).verify(initial)
    parts = verify_by_parts(tree, compressed, World(tree), initial, max_states=5_000)
    assume(whole.exhaustive and parts is not None and parts.exhaustive)
    assert (parts.sound, parts.complete) == (whole.sound, whole.complete)


# --- regressions found in review ----------------------------------------------

def test_a_state_limit_never_invents_a_completion_counterexample():
    report = verify(COFFEE_TREE, compress(COFFEE_TREE).tree, COFFEE_KB, max_states=100)
    assert not report.exhaustive and not report.violated
    assert report.properties["completion"].holds is None


def test_a_part_stuck_while_another_part_loops_is_not_a_dead_end_of_the_whole():
    """Part A's merged behaviour is accomplished early; part B can toggle for ever."""
    a1 = Behaviour(t("b1(cup)"), objects=(t("cup"),), post=c("b1.done"))
    a2 = Behaviour(t("b2(cup)"), objects=(t("cup"),), releaser=c("b1.done"), post=c("b2.done"))
    part_a = Behaviour(t("pa"), post=c("pa.done"), children=(a1, a2))
    on = Behaviour(t("c1(y)"), objects=(t("y"),), releaser=c("not y.on"), post=c("y.on"))
    off = Behaviour(t("c2(y)"), objects=(t("y"),), releaser=c("y.on"), post=c("not y.on"))
    part_b = Behaviour(t("pb"), post=c("pb.done"), children=(on, off))
    root = Behaviour(t("r"), post=c("g.on"), children=(part_a, part_b))
    compressed = compress(root).tree
    for start in ([t("b2.done")], []):
        world = World(root, start)
        whole = Verifier(root, compressed, World(root, start)).verify([world.atoms])
        parts = verify_by_parts(root, compressed, world, [world.atoms])
        assert parts is not None
        assert (parts.sound, parts.complete) == (whole.sound, whole.complete)


def test_parts_check_the_compressed_behaviour_itself():
    """A compressed file whose unmerged sub-task got another releaser is not split away."""
    from dataclasses import replace
    tb = Behaviour(t("tb(y)"), objects=(t("y"),), post=c("tb.done"), children=(
        Behaviour(t("c1(y)"), objects=(t("y"),), post=c("c1.done")),))
    ta = Behaviour(t("ta(cup)"), objects=(t("cup"),), post=c("ta.done"), children=(
        Behaviour(t("a1(cup)"), objects=(t("cup"),), post=c("a1.done")),))
    root = Behaviour(t("r"), post=c("r.done"), children=(ta, tb))
    good = compress(root).tree
    edited = replace(good, children=(good.children[0], replace(good.children[1], releaser=c("zz.on"))))
    world = World(root)
    parts = verify_by_parts(root, edited, world, [world.atoms])
    whole = Verifier(root, edited, World(root)).verify([world.atoms])
    assert not whole.complete
    assert parts is None or not parts.complete


def test_2000_siblings_compress_to_one_merged_leaf_that_is_proved():
    kb, tree = wide_task(2000)
    compressed = compress(tree).tree
    world = World(tree)
    world.reset(initial_state(kb))
    report = Verifier(tree, compressed, world).verify([world.atoms])
    assert report.exhaustive and report.sound and report.complete and report.limit == ""


def test_a_chain_of_2000_steps_is_proved_at_the_default_limits():
    from schemalog.run.verify import prove

    kb, tree = wide_task(2000)
    world = World(tree, initial_state(kb))
    report = prove(tree, compress(tree).tree, world, [world.atoms])      # --method auto, default limits
    assert report.exhaustive and report.sound and report.complete and report.limit == ""
    assert (report.compressed_states, report.original_states) == (2, 2001)   # one state per step


def _chain_work(n: int) -> int:
    kb, tree = wide_task(n)
    world = World(tree, initial_state(kb))
    v = Verifier(tree, compress(tree).tree, world)
    assert v.verify([world.atoms]).complete
    return v.meter.work


def test_the_work_of_a_chain_grows_with_its_steps_not_their_square():
    """A state costs what its steps change (Walker): the N-step chain's N + 1 states, each of up
    to N atoms, once cost N^2 units (decoded, copied, every sibling tested)."""
    small, large = _chain_work(250), _chain_work(1000)
    assert large < 6 * small              # x4 the steps: x4 the work (x16 when it was quadratic)
    assert large < 30 * 1000


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])
@given(st.data(), trees(), st.sampled_from(["none", "pre", "full"]))
def test_enabled_sets_derived_step_by_step_equal_a_full_scan(data, tree, propagate):
    from schemalog.run.execute import enabled_indices

    compressed = compress(tree, propagate).tree
    initial = settled(tree, data.draw(starts(tree)))
    v = Verifier(tree, compressed, World(tree), max_states=2_000)
    report = v.verify(initial)
    assert report.compressed_states > 0
    for walk in (v.c_walk, v.o_walk):
        for k, leaves in walk._enabled.items():
            assert leaves == enabled_indices(walk.model.plan, v.codec.decode(k))
        for (k, leaf), (actions, codes) in walk._steps.items():     # the steps, against the frozenset model
            was, states = walk.model.step(v.codec.decode(k), leaf)
            assert (actions, codes) == (was, tuple(v.codec.encode(s) for s in states))


def test_the_state_limit_bounds_the_work_and_a_stopped_verify_proves_nothing():
    kb, tree = wide_task(300)
    compressed = compress(tree).tree
    world = World(tree)
    world.reset(initial_state(kb))
    v = Verifier(tree, compressed, world, max_states=1)   # 1,000 units: the merged leaf's 300 actions need ~1,200
    report = v.verify([world.atoms])
    assert not report.exhaustive and "units of work" in report.limit
    assert report.properties["soundness"].holds is None and report.properties["completion"].holds is None
    assert not report.violated
    assert v.meter.spent
    sampled = Verifier(tree, compressed, world, max_states=1).sample([world.atoms], 1_000_000)
    assert sampled.sampled and "units of work" in sampled.limit
    assert "stopped after 0 of 1,000,000 runs" in sampled.properties["soundness"].summary
