"""The attentional executive: enabling, emphasis, winner-take-all, failures, both selectors."""

from collections import Counter

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from schemalog.task import conditions as cond
from schemalog.task.compress import compress
from schemalog.formats.documents import load_kb
from schemalog.errors import SchemalogError
from schemalog.run.execute import Executive, IncrementalSelector, Plan, RobotManager, Status, replay
from schemalog.evaluate.generate import generate, scene_for
from schemalog.logic.parse import parse_term
from schemalog.run.scene import Scene, read_scene
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import Behaviour, Origin, count_nodes, instantiate, walk
from schemalog.run.world import World, initial_state

from conftest import COFFEE, MIX, ROOT, wide_task

KITCHEN = read_scene(ROOT / "kb" / "scenes" / "kitchen.yaml")
FIG2_SCENE = read_scene(ROOT / "kb" / "scenes" / "mix_with_spoon.yaml")


def t(text):
    return parse_term(text)


def c(text):
    return cond.from_term(parse_term(text))


def names(labels):
    return [term_to_text(x) for x in labels]


def task(path, label):
    kb = load_kb([path])
    return instantiate(kb, t(label)), initial_state(kb)


FIG2, FIG2_INIT = task(MIX, "use(spoon)")
COFFEE_TREE, COFFEE_INIT = task(COFFEE, "prepareboth")
FIG2_ORDER = ["a1(spoon)", "a2(spoon)", "gripper(close)", "a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)",
              "a7(cup)", "gripper(open)"]


def execute(tree, original, initial, scene, selector="incremental", **kw):
    ex = Executive(tree, World(original, initial), scene, selector=selector, **kw)
    ex.run()
    return ex


# --- the paper's tasks ------------------------------------------------------

def test_figure_2_runs_in_the_demonstrated_order():
    ex = execute(FIG2, FIG2, FIG2_INIT, FIG2_SCENE)
    assert ex.outcome.status is Status.COMPLETED
    assert names(ex.trace) == FIG2_ORDER
    assert len(ex.decisions) == 9


@pytest.mark.parametrize("propagate", ["pre", "full"])
def test_compressed_figure_2_takes_four_decisions_for_the_same_actions(propagate):
    tree = compress(FIG2, propagate).tree
    ex = execute(tree, FIG2, FIG2_INIT, FIG2_SCENE)
    assert ex.outcome.completed
    assert names(d.behaviour for d in ex.decisions) == [
        "a1_a2(spoon)", "gripper(close)", "a3_a4_a5_a6_a7(cup)", "gripper(open)"]
    assert names(ex.trace) == FIG2_ORDER


def test_without_propagation_the_aliasing_shows_in_the_trace():
    """Figure 2 (middle): both merged actions are released by true; mixing wins before the grasp."""
    tree = compress(FIG2, "none").tree
    ex = execute(tree, FIG2, FIG2_INIT, FIG2_SCENE)
    check = replay(FIG2, FIG2_INIT, ex.trace)
    assert not check.valid
    # the cup is nearer than the spoon: mixing starts before the spoon is taken
    assert check.reason.startswith("action 1, a3(cup), is not enabled")


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("original, initial, scene", [
    (FIG2, FIG2_INIT, FIG2_SCENE), (COFFEE_TREE, COFFEE_INIT, KITCHEN)], ids=["figure2", "coffee"])
def test_paper_tasks_complete_original_and_compressed_in_ten_configurations(original, initial, scene, seed):
    """The paper's protocol (Sec. IV-C): 10 object configurations; every compressed run's
    trace is also a run of the original tree."""
    moved = scene.jittered(seed, 0.15)
    plain = execute(original, original, initial, moved)
    assert plain.outcome.completed, plain.outcome
    assert replay(original, initial, plain.trace).valid
    for propagate in ("pre", "full"):
        merged = execute(compress(original, propagate).tree, original, initial, moved)
        assert merged.outcome.completed, merged.outcome
        check = replay(original, initial, merged.trace)
        assert check.valid, check.reason
        assert len(merged.decisions) < len(plain.decisions)
        assert sorted(names(merged.trace)) == sorted(names(plain.trace))


def test_coffee_and_tea_finishes_each_object_before_the_next():
    ex = execute(COFFEE_TREE, COFFEE_TREE, COFFEE_INIT, KITCHEN)
    trace = names(ex.trace)
    assert len(trace) == 36 and len(ex.decisions) == 36
    # the gripper closes right after each grasp (it attends to its sub-task's object, where the
    # hand is), so no second object is approached with the first one still loose
    closes = [i for i, action in enumerate(trace) if action == "gripper(close)"]
    assert [trace[i - 1] for i in closes] == ["a2(water)", "a9(coffee)", "a23(tea)", "a16(spoon)"]
    compressed = execute(compress(COFFEE_TREE).tree, COFFEE_TREE, COFFEE_INIT, KITCHEN)
    assert len(compressed.decisions) == 16 and names(compressed.trace) == trace


def test_another_initial_state_skips_what_is_done():
    """Sec. III-B: with the spoon already in hand, the merged take_mix runs only the mixing."""
    state = [t("spoon.taken")]
    tree = compress(FIG2, "pre").tree
    ex = execute(tree, FIG2, state, FIG2_SCENE)
    assert ex.outcome.completed
    assert names(ex.trace) == ["a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)", "gripper(open)"]
    assert replay(FIG2, state, ex.trace).valid


# --- emphasis ----------------------------------------------------------------

def two_leaves(weight_cup=1):
    spoon = Behaviour(t("a(spoon)"), objects=(t("spoon"),), post=c("a.done"))
    cup = Behaviour(t("b(cup)"), objects=(t("cup"),), post=c("b.done"), importance=weight_cup)
    return Behaviour(t("r"), post=c("a.done and b.done"), children=(spoon, cup))


def test_the_nearer_object_wins_and_emphasis_is_mu_over_lambda():
    scene = Scene(objects={"spoon": (0.5, 0.0), "cup": (0.2, 0.0)}, end_effector=(0.0, 0.0))
    tree = two_leaves()
    ex = Executive(tree, World(tree), scene)
    first = ex.step()
    assert term_to_text(first.behaviour) == "b(cup)"
    assert first.emphasis == pytest.approx(1 / 0.2)          # mu = 1 (nothing done yet), lambda = 0.2
    assert term_to_text(first.runner_up[0]) == "a(spoon)" and first.runner_up[1] == pytest.approx(1 / 0.5)
    second = ex.step()
    # the hand is now at the cup (0.3 from the spoon); one sub-behaviour of the root is done
    assert second.emphasis == pytest.approx(2 / 0.3)
    assert ex.step() is None and ex.outcome.completed


def test_importance_weighs_emphasis():
    scene = Scene(objects={"spoon": (0.2, 0.0), "cup": (0.3, 0.0)}, end_effector=(0.0, 0.0))
    tree = two_leaves(weight_cup=2)
    first = Executive(tree, World(tree), scene).step()
    assert term_to_text(first.behaviour) == "b(cup)" and first.emphasis == pytest.approx(2 / 0.3)


def test_ties_go_to_the_earlier_behaviour():
    tree = two_leaves()
    first = Executive(tree, World(tree)).step()     # no scene: every lambda is neutral
    assert term_to_text(first.behaviour) == "a(spoon)" and first.emphasis == first.runner_up[1]


def test_a_runner_up_with_the_winners_label_is_told_apart_by_where_it_is():
    def branch(name):        # one behaviour, add(water), used in two sub-tasks
        leaf = Behaviour(t("add(water)"), post=c(f"{name}.water"))
        return Behaviour(t(name), post=c(f"{name}.water"), children=(leaf,))

    tree = Behaviour(t("r"), post=c("coffee.water and tea.water"), children=(branch("coffee"), branch("tea")))
    first = Executive(tree, World(tree)).step()
    assert term_to_text(first.behaviour) == term_to_text(first.runner_up[0]) == "add(water)"
    assert first.apart == ("in coffee", "in tea")
    # two siblings of one label, in sub-trees of one label: their pre-order ids
    twins = Behaviour(t("r"), post=c("a.done and b.done"), children=(
        Behaviour(t("s"), post=c("a.done"), children=(Behaviour(t("x"), post=c("a.done")),)),
        Behaviour(t("s"), post=c("b.done"), children=(Behaviour(t("x"), post=c("b.done")),))))
    assert Executive(twins, World(twins)).step().apart == ("node 2", "node 4")
    # labels that differ need no telling apart
    assert Executive(two_leaves(), World(two_leaves())).step().apart is None


def test_a_shared_constituent_counts_once():
    """Branching gives b_i_b_j and b_i_b_k; accomplished, they stand for 3 originals, not 4."""
    o = lambda name, pos: Origin(t(name), cond.TRUE, c(f"{name}.done"), position=pos)
    bij = Behaviour(t("bi_bj"), post=c("bj.done"), origins=(o("bi", 0), o("bj", 1)))
    bik = Behaviour(t("bi_bk"), post=c("bk.done"), origins=(o("bi", 0), o("bk", 2)))
    root = Behaviour(t("r"), post=c("never"), children=(bij, bik), origins=(o("r", 0),))
    world = World(Behaviour(t("r"), post=c("never")), [t("bj.done"), t("bk.done")])
    selector = IncrementalSelector(Plan.of(root), world, Scene())
    assert selector.n[0] == 3


# --- failures, loops, limits ---------------------------------------------------

def test_a_persistent_failure_is_retried_then_inhibited():
    robot = RobotManager(FIG2_SCENE, {t("a5(cup)"): None})
    ex = Executive(FIG2, World(FIG2, FIG2_INIT), FIG2_SCENE, robot=robot, retries=2)
    ex.run()
    assert ex.outcome.status is Status.STUCK
    assert [term_to_text(d.failed) for d in ex.decisions if d.failed] == ["a5(cup)"] * 3
    assert any("a5(cup): its command failed 3 times; inhibited" in b for b in ex.outcome.blocked)


def test_a_merged_behaviour_resumes_at_the_failed_action():
    tree = compress(FIG2).tree
    robot = RobotManager(FIG2_SCENE, {t("a5(cup)"): 1})
    ex = Executive(tree, World(FIG2, FIG2_INIT), FIG2_SCENE, robot=robot, recovery="resume")
    ex.run()
    assert ex.outcome.completed
    failed = next(d for d in ex.decisions if d.failed)
    retry = ex.decisions[failed.index]
    assert names(failed.executed) == ["a3(cup)", "a4(cup)"]
    assert names(retry.skipped) == ["a3(cup)", "a4(cup)"] and names(retry.executed)[0] == "a5(cup)"
    assert names(ex.trace) == FIG2_ORDER


def toggler():
    on = Behaviour(t("on"), releaser=c("not x"), post=c("x"))
    off = Behaviour(t("off"), releaser=c("x"), post=c("not x"))
    return Behaviour(t("r"), post=c("goal"), children=(on, off))


@pytest.mark.parametrize("selector", ["scan", "incremental"])
def test_a_livelock_is_found_and_named(selector):
    tree = toggler()
    ex = execute(tree, tree, [], Scene(), selector=selector)
    assert ex.outcome.status is Status.LIVELOCK
    assert ex.outcome.blocked == ("loop: on -> off",)
    assert len(ex.decisions) == 2


def test_the_decision_limit_stops_a_long_run():
    tree = toggler()
    ex = execute(tree, tree, [], Scene(), max_decisions=5, detect_loops=False)
    assert ex.outcome.status is Status.LIMIT and len(ex.decisions) == 5


def test_stuck_names_the_false_conditions():
    ex = execute(FIG2, FIG2, [], FIG2_SCENE)
    assert ex.outcome.status is Status.STUCK and not ex.decisions
    assert ex.outcome.blocked == (
        "subtask(take,spoon): pre-condition hand.free is false (false: hand.free)",
        "subtask(mix,spoon): pre-condition spoon.taken is false (false: spoon.taken)")


def test_the_run_is_an_iterator_of_decisions():
    ex = Executive(FIG2, World(FIG2, FIG2_INIT), FIG2_SCENE)
    decisions = list(ex)
    assert [d.index for d in decisions] == list(range(1, 10))
    assert ex.step() is None and ex.outcome.completed
    assert all(d.seconds >= 0 for d in decisions)


# --- both selectors decide alike ---------------------------------------------

ATOMS = ["p", "q", "r", "s"]


@st.composite
def conditions(draw, depth=2):
    if depth == 0 or draw(st.integers(0, 2)) == 0:
        choice = draw(st.integers(0, 9))
        if choice == 0:
            return cond.TRUE
        return cond.Lit(t(f"{draw(st.sampled_from(ATOMS))}.on"), draw(st.booleans()))
    items = tuple(draw(st.lists(conditions(depth=depth - 1), min_size=2, max_size=3)))
    return cond.And(items) if draw(st.booleans()) else cond.Or(items)


@st.composite
def posts(draw):
    lits = draw(st.lists(st.tuples(st.sampled_from(ATOMS + ["u", "v", "w"]), st.booleans()),
                         min_size=1, max_size=2, unique_by=lambda x: x[0]))
    items = tuple(cond.Lit(t(f"{a}.on"), v) for a, v in lits)
    return items[0] if len(items) == 1 else cond.And(items)


@st.composite
def random_trees(draw, levels=3):
    ids = iter(range(10_000))

    def node(level):
        n = next(ids)
        kids = ()
        if level < levels:
            kids = tuple(node(level + 1) for _ in range(draw(st.integers(0, 3))))
        obj = draw(st.sampled_from(["cup", "spoon", "none"]))
        return Behaviour(t(f"b{n}({obj})") if obj != "none" else t(f"b{n}"),
                         objects=(t(obj),) if obj != "none" else (), releaser=draw(conditions()),
                         post=draw(posts()), children=kids, importance=draw(st.sampled_from([1, 1, 2, 0.5])))
    return Behaviour(t("root"), post=c("goal.on"), children=tuple(node(2) for _ in range(draw(st.integers(1, 3)))))


def decisions_of(tree, original, initial, scene, selector, robot_failures):
    try:
        ex = Executive(tree, World(original, initial), scene, selector=selector, max_decisions=40,
                       robot=RobotManager(scene, dict(robot_failures)))
        ex.run()
    except SchemalogError as err:   # completion rules that contradict each other: said alike
        return str(err)
    return [(d.behaviour, d.emphasis, d.runner_up, d.enabled, d.executed, d.failed) for d in ex.decisions], \
        ex.outcome, ex.trace


SCENE = Scene(objects={"cup": (0.4, 0.1), "spoon": (0.1, 0.3)}, end_effector=(0.0, 0.0))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_trees(), st.sets(st.sampled_from([f"{a}.on" for a in ATOMS])), st.booleans(), st.data())
def test_scan_and_incremental_take_the_same_decisions(tree, initial, merged, data):
    initial = [t(a) for a in sorted(initial)]
    run_tree = compress(tree, data.draw(st.sampled_from(["none", "pre", "full"]))).tree if merged else tree
    failing = data.draw(st.sets(st.sampled_from([f"b{i}" for i in range(12)]), max_size=2))
    failures = {t(f"{name}({o})"): 1 for name in failing for o in ("cup", "spoon")}
    scan = decisions_of(run_tree, tree, initial, SCENE, "scan", failures)
    incremental = decisions_of(run_tree, tree, initial, SCENE, "incremental", failures)
    assert scan == incremental


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 5), st.integers(1, 4), st.sampled_from([0.0, 0.3, 0.5, 0.7]), st.integers(0, 10**6))
def test_generated_tasks_complete_alike_with_both_selectors_and_compressed(depth, branching, rd, seed):
    tree = generate(depth, branching, rd, seed)
    scene = scene_for(branching, seed=seed)
    runs = {}
    for name, run_tree in (("original", tree), ("compressed", compress(tree).tree)):
        for selector in ("scan", "incremental"):
            ex = execute(run_tree, tree, [], scene, selector)
            assert ex.outcome.completed, (name, selector, ex.outcome)
            runs[name, selector] = ex.trace
    assert runs["original", "scan"] == runs["original", "incremental"]
    assert runs["compressed", "scan"] == runs["compressed", "incremental"]
    assert replay(tree, [], runs["compressed", "incremental"]).valid


# --- regressions found in review ---------------------------------------------

def test_an_atom_set_and_cleared_within_a_merged_decision_is_no_change():
    """b1_b2 sets x.on then clears it; the loop b1_b2 -> t is found after two decisions."""
    b1 = Behaviour(t("b1"), post=c("x.on"))
    b2 = Behaviour(t("b2"), releaser=c("x.on"), post=c("y.on and not x.on"))
    toggle = Behaviour(t("t"), releaser=c("y.on"), post=c("not y.on"))
    original = Behaviour(t("root"), post=c("goal.on"), children=(b1, b2, toggle))
    ex = execute(compress(original).tree, original, [], Scene())
    assert ex.outcome.status is Status.LIVELOCK
    assert ex.outcome.blocked == ("loop: b1_b2 -> t",)


def test_a_failure_of_the_merged_label_does_not_mask_the_actions_own():
    tree = compress(FIG2).tree
    robot = RobotManager(FIG2_SCENE, {t("a1_a2(spoon)"): 1, t("a1(spoon)"): 1})
    ex = Executive(tree, World(FIG2, FIG2_INIT), FIG2_SCENE, robot=robot)
    ex.run()
    assert [term_to_text(d.failed) for d in ex.decisions if d.failed] == ["a1(spoon)", "a1(spoon)"]
    assert ex.outcome.completed


# --- failure-local recovery: decompress only the merged leaf that failed --------

def merged_leaves(tree):
    return Counter(term_to_text(n.label) for n in walk(tree) if not n.children and n.merged_from)


@pytest.mark.parametrize("selector", ["scan", "incremental"])
def test_a_failure_inside_a_merged_leaf_decompresses_only_that_leaf(selector):
    tree = compress(COFFEE_TREE).tree
    plain = execute(tree, COFFEE_TREE, COFFEE_INIT, KITCHEN, selector)
    robot = RobotManager(KITCHEN, {t("a4(cup)"): 1})
    ex = execute(tree, COFFEE_TREE, COFFEE_INIT, KITCHEN, selector, robot=robot)
    assert ex.outcome.completed, ex.outcome
    split = [d for d in ex.decisions if d.decompressed]
    assert len(split) == 1
    failed = split[0]
    assert term_to_text(failed.behaviour) == "a3_a4_a5_a6_a7(cup)" and term_to_text(failed.failed) == "a4(cup)"
    assert names(failed.decompressed) == ["a3_a4_a5_a6_a7(cup)", "a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)",
                                          "a7(cup)"]
    assert failed.inhibited is None
    # the failed constituent is retried on its own, then its successors one by one
    after = ex.decisions[failed.index:failed.index + 4]
    assert names(d.behaviour for d in after) == ["a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"]
    assert [names(d.executed) for d in after] == [["a4(cup)"], ["a5(cup)"], ["a6(cup)"], ["a7(cup)"]]
    # only that behaviour is decompressed: 33 -> 37 behaviours, the other merged ones intact
    assert count_nodes(ex.given_tree) == 33 and count_nodes(ex.tree) == 37
    before, now = merged_leaves(tree), merged_leaves(ex.tree)
    before.subtract({"a3_a4_a5_a6_a7(cup)": 1})
    assert now == +before
    parts = {term_to_text(n.label): n for n in walk(ex.tree) if not n.children and not n.merged_from
             and term_to_text(n.label) in {"a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"}}
    assert len(parts) == 5 and all(n.k == 1 for n in parts.values())
    assert cond.to_text(parts["a5(cup)"].pre) == "water.taken and not water.used and a4.done"
    # the trace: every action once, a4(cup) included, in the order of the failure-free run
    assert names(ex.trace).count("a4(cup)") == 1
    assert names(ex.trace) == names(plain.trace)
    assert replay(COFFEE_TREE, COFFEE_INIT, ex.trace).valid
    # the accomplished a3(cup) now counts in its parent's mu: a4(cup) alone is more emphasised
    # than the merged behaviour resuming at it
    resume = execute(tree, COFFEE_TREE, COFFEE_INIT, KITCHEN, selector,
                     robot=RobotManager(KITCHEN, {t("a4(cup)"): 1}), recovery="resume")
    assert resume.outcome.completed and count_nodes(resume.tree) == 33
    assert not any(d.decompressed for d in resume.decisions)
    assert after[0].emphasis > resume.decisions[failed.index].emphasis


def inhibited_labels(ex):
    return {term_to_text(ex.plan.nodes[i].label) for i in ex.selector.inhibited}


def test_a_persistent_failure_inhibits_only_the_failed_constituent():
    tree = compress(COFFEE_TREE).tree
    ex = execute(tree, COFFEE_TREE, COFFEE_INIT, KITCHEN, robot=RobotManager(KITCHEN, {t("a4(cup)"): None}))
    assert ex.outcome.status is Status.STUCK
    assert inhibited_labels(ex) == {"a4(cup)"}
    assert "a4(cup): its command failed 3 times; inhibited" in ex.outcome.blocked
    assert not any("a3_a4_a5_a6_a7" in b for b in ex.outcome.blocked)
    inhibited = [d for d in ex.decisions if d.inhibited is not None]
    assert inhibited and all(term_to_text(d.inhibited) == "a4(cup)" for d in inhibited)
    # the actions before it stay done and are not commanded again
    assert names(ex.trace).count("a3(cup)") == 1 and "a4(cup)" not in names(ex.trace)
    # resume, for comparison, inhibits the whole merged behaviour
    old = execute(tree, COFFEE_TREE, COFFEE_INIT, KITCHEN, robot=RobotManager(KITCHEN, {t("a4(cup)"): None}),
                  recovery="resume")
    assert inhibited_labels(old) == {"a3_a4_a5_a6_a7(cup)"}
    assert "a3_a4_a5_a6_a7(cup): its command failed 3 times; inhibited" in old.outcome.blocked


def test_each_constituent_gets_its_own_retries():
    """a3, a4 and a5 each fail once: three failures of one merged behaviour in a row exhaust
    --retries 1 under resume; decompressed, each action is retried once and the task completes."""
    tree = compress(FIG2).tree
    once = {t("a3(cup)"): 1, t("a4(cup)"): 1, t("a5(cup)"): 1}
    old = execute(tree, FIG2, FIG2_INIT, FIG2_SCENE, robot=RobotManager(FIG2_SCENE, once), retries=1,
                  recovery="resume")
    assert old.outcome.status is Status.STUCK
    new = execute(tree, FIG2, FIG2_INIT, FIG2_SCENE, robot=RobotManager(FIG2_SCENE, once), retries=1)
    assert new.outcome.completed, new.outcome
    assert names(new.trace) == FIG2_ORDER
    assert [term_to_text(d.failed) for d in new.decisions if d.failed] == ["a3(cup)", "a4(cup)", "a5(cup)"]
    assert sum(1 for d in new.decisions if d.decompressed) == 1


def test_no_retries_inhibits_the_constituent_at_once_and_an_unknown_recovery_is_refused():
    tree = compress(FIG2).tree
    ex = execute(tree, FIG2, FIG2_INIT, FIG2_SCENE, robot=RobotManager(FIG2_SCENE, {t("a5(cup)"): None}),
                 retries=0)
    first = next(d for d in ex.decisions if d.failed)
    assert first.decompressed and term_to_text(first.inhibited) == "a5(cup)"
    assert inhibited_labels(ex) == {"a5(cup)"} and ex.outcome.status is Status.STUCK
    with pytest.raises(SchemalogError, match="unknown recovery"):
        Executive(tree, World(FIG2, FIG2_INIT), FIG2_SCENE, recovery="replan")


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 4), st.integers(1, 3), st.sampled_from([0.0, 0.3, 0.5, 0.7]), st.integers(0, 10**6),
       st.data())
def test_one_transient_failure_is_recovered_by_decompressing(depth, branching, rd, seed, data):
    """Any one action of a generated task fails once: the decompressed run completes whenever
    the failure-free one does, runs every action once, and is a run of the original tree."""
    tree = generate(depth, branching, rd, seed)
    scene = scene_for(branching, seed=seed)
    compressed = compress(tree).tree
    action = data.draw(st.sampled_from([n.label for n in walk(tree) if not n.children]))
    plain = execute(compressed, tree, [], scene)
    traces = {}
    for selector in ("scan", "incremental"):
        ex = execute(compressed, tree, [], scene, selector, robot=RobotManager(scene, {action: 1}))
        if plain.outcome.completed:
            assert ex.outcome.completed, (term_to_text(action), ex.outcome)
            assert sorted(names(ex.trace)) == sorted(names(plain.trace))
        check = replay(tree, [], ex.trace)
        assert check.valid, check.reason
        failed = [d for d in ex.decisions if d.failed is not None]
        assert [d.failed for d in failed] == [action]
        leaf = next(n for n in walk(compressed) if not n.children and n.label == failed[0].behaviour)
        assert count_nodes(ex.tree) - count_nodes(compressed) == leaf.k - 1
        assert bool(failed[0].decompressed) == (leaf.k > 1)
        traces[selector] = ex.trace
    assert traces["scan"] == traces["incremental"]


def test_inhibitions_and_failure_counts_follow_their_leaves_into_the_new_tree():
    """z(spoon), after the merged x_y(cup) in the tree, is inhibited first; splitting x_y moves
    it in the flattened tree, and it must stay inhibited while y(cup) alone is retried."""
    x = Behaviour(t("x(cup)"), objects=(t("cup"),), post=c("x.done"))
    y = Behaviour(t("y(cup)"), objects=(t("cup"),), releaser=c("x.done"), post=c("y.done"))
    z = Behaviour(t("z(spoon)"), objects=(t("spoon"),), post=c("z.done"))
    original = Behaviour(t("r"), post=c("y.done"), children=(x, y, z))
    tree = compress(original).tree
    assert [term_to_text(n.label) for n in tree.children] == ["x_y(cup)", "z(spoon)"]
    scene = Scene(objects={"spoon": (0.1, 0.0), "cup": (0.5, 0.0)}, end_effector=(0.0, 0.0))
    for selector in ("scan", "incremental"):
        robot = RobotManager(scene, {t("z(spoon)"): None, t("y(cup)"): 1})
        ex = execute(tree, original, [], scene, selector, robot=robot)
        assert [(term_to_text(d.behaviour), d.failed and term_to_text(d.failed)) for d in ex.decisions] == [
            ("z(spoon)", "z(spoon)")] * 3 + [("x_y(cup)", "y(cup)"), ("y(cup)", None)]
        assert ex.outcome.completed and inhibited_labels(ex) == {"z(spoon)"}
        z_index = next(i for i, n in enumerate(ex.plan.nodes) if n.label == t("z(spoon)"))
        assert ex.failures == Counter({z_index: 3})


def test_the_loop_detector_forgets_the_configurations_of_the_tree_before_a_split():
    """Leaf indices name other behaviours after a split: the configurations seen before it
    (which record inhibited and failed leaves by index) cannot be compared with later ones."""
    tree = compress(FIG2).tree
    ex = Executive(tree, World(FIG2, FIG2_INIT), FIG2_SCENE, robot=RobotManager(FIG2_SCENE, {t("a4(cup)"): 1}))
    seen_before = None
    for d in ex:
        if d.decompressed:
            assert seen_before >= 3 and len(ex._seen) == 1
        seen_before = len(ex._seen)
    assert ex.outcome.completed and len(ex._seen) == len(ex.decisions) - 2


@pytest.mark.parametrize("compressed", [False, True])
def test_activation_ranks_leaves_as_the_selector_does(compressed):
    # Along a whole run, the plain rule (teaching uses it) picks the selector's winner.
    from schemalog.run.execute import ScanSelector, activation, emphasis
    tree = instantiate(load_kb([COFFEE]), parse_term("prepareboth"))
    world = World(tree, initial_state(load_kb([COFFEE])))
    run_tree = compress(tree).tree if compressed else tree
    scene = read_scene(ROOT / "kb" / "scenes" / "kitchen.yaml")
    ex = Executive(run_tree, world, scene, selector="scan")
    plan = ex.plan
    while True:
        live, mu = activation(plan, world.atoms)
        ranked = sorted(((emphasis(plan.weight[i] * mu[i], scene.lambda_at(plan.obj[i], ex.robot.hand)),
                          plan.weight[i] * mu[i], -i) for i in plan.leaves if live[i]), reverse=True)
        best, _ = ScanSelector(plan, world, scene).select(ex.robot.hand)
        assert ranked[:2] == best
        if ex.step() is None:
            break
    assert ex.outcome.completed


def test_2000_siblings_run_in_order_original_and_compressed_refreshing_only_live_leaves():
    kb, tree = wide_task(2000)

    class Visits(list):
        count = 0

        def __getitem__(self, i):
            Visits.count += 1
            return list.__getitem__(self, i)

    ex = Executive(tree, World(tree, initial_state(kb)))
    assert isinstance(ex.selector, IncrementalSelector)
    ex.plan.children = Visits(ex.plan.children)    # the selector's refresh reads it per visited node
    outcome = ex.run()
    assert outcome.completed and ex.trace == [c.label for c in tree.children]
    assert Visits.count <= 10 * 2000    # not 2000 * 2000: a sibling's completion moves only live leaves
    result = compress(tree)
    assert count_nodes(result.tree) == 2
    ex = Executive(result.tree, World(tree, initial_state(kb)))
    assert ex.run().completed and ex.trace == [c.label for c in tree.children] and len(ex.decisions) == 1
