"""The emulated world: leaf effects, composite completion, initial states."""

import pytest
from hypothesis import given, settings, strategies as st

from schemalog.task import conditions as cond
from schemalog.formats.documents import load_kb
from schemalog.errors import SchemalogError
from schemalog.logic.parse import parse_term
from schemalog.task.tree import instantiate, walk
from schemalog.run.world import World, effect_of, initial_state, state_atoms

from conftest import COFFEE, MIX


def t(text):
    return parse_term(text)


def c(text):
    return cond.from_term(parse_term(text))


@pytest.fixture(scope="module")
def figure2():
    kb = load_kb([MIX])
    return kb, instantiate(kb, t("use(spoon)"))


def test_effects_of_post_conditions():
    assert effect_of(c("a1.done")) == ((t("a1.done"),), ())
    assert effect_of(c("not hand.free")) == ((), (t("hand.free"),))
    assert effect_of(c("true")) == ((), ())
    with pytest.raises(SchemalogError):
        effect_of(c("a or b"))


def test_a_leaf_applies_its_post_and_the_world_completes_the_take(figure2):
    kb, tree = figure2
    world = World(tree, initial_state(kb))
    assert world.atoms == {t("hand.free")}
    world.perform(c("a1.done"))
    world.perform(c("a2.done"))
    assert t("spoon.taken") not in world
    change = world.perform(c("not hand.free"))   # gripper(close): the take's children are all done
    assert change.removed == {t("hand.free")}
    assert change.added == {t("spoon.taken")}     # perception: the spoon is taken
    assert world.holds(c("spoon.taken and not hand.free"))


def test_completion_reaches_up_the_tree(figure2):
    _, tree = figure2
    world = World(tree, [t("spoon.taken")] + [t(f"a{i}.done") for i in range(3, 8)])
    world.perform(c("hand.free"))
    # mix's children are all accomplished -> spoon.used; use(spoon)'s too -> its post, the same atom
    assert t("spoon.used") in world


def test_reset_settles_a_state_that_already_completes_a_composite(figure2):
    _, tree = figure2
    world = World(tree, [t("a1.done"), t("a2.done")])   # hand not free: the grasp is done
    assert t("spoon.taken") in world


def test_net_change_ignores_what_an_action_undoes():
    from schemalog.task.tree import Behaviour
    leaf = Behaviour(t("a"), post=c("x"))
    root = Behaviour(t("r"), post=c("not x"), children=(leaf,))
    world = World(root)
    change = world.perform(c("x"))  # x is set, then the completed root clears it again
    assert t("x") not in world
    assert change.added == frozenset() and change.removed == frozenset()


def test_one_rule_for_repeated_composites():
    kb = load_kb([COFFEE])
    tree = instantiate(kb, t("prepareboth"))
    world = World(tree, initial_state(kb))
    composites = sum(1 for n in walk(tree) if n.children)
    assert len(world.completions) < composites  # add(water) under coffee and under tea: one rule


def test_initial_state_and_state_text():
    kb = load_kb([COFFEE])
    assert initial_state(kb) == [t("kukahand.free")]
    assert state_atoms(t("(hand.free, spoon.taken)"), "--state") == [t("hand.free"), t("spoon.taken")]
    assert state_atoms(t("true"), "--state") == []
    with pytest.raises(SchemalogError, match="closed world"):
        state_atoms(t("not hand.free"), "--state")
    with pytest.raises(SchemalogError, match="variables"):
        state_atoms(t("X.free"), "--state")


def test_unknown_atoms_are_reported(figure2):
    _, tree = figure2
    world = World(tree)
    assert world.unknown([t("hand.free"), t("hand.fre")]) == [t("hand.fre")]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["p", "q", "r", "s"]), st.booleans()), max_size=20))
def test_state_hash_depends_only_on_the_state(steps):
    from schemalog.task.tree import Behaviour
    root = Behaviour(t("r"), post=c("goal"), children=(Behaviour(t("a"), post=c("p")),))
    world = World(root)
    for atom, value in steps:
        world.perform(cond.Lit(t(f"{atom}.on"), value))
    fresh = World(root, world.atoms)
    assert fresh.hash == world.hash and fresh.atoms == world.atoms


def test_completions_that_undo_each_other_are_an_error_whatever_the_history():
    """c1 asserts y and clears z, c2 the reverse: once both complete, the world cannot settle."""
    from schemalog.task.tree import Behaviour
    c1 = Behaviour(t("c1"), post=c("y.on and not z.on"), children=(Behaviour(t("a"), post=c("x.on")),))
    c2 = Behaviour(t("c2"), post=c("z.on and not y.on"), children=(Behaviour(t("b"), post=c("w.on")),))
    root = Behaviour(t("t"), post=c("goal"), children=(c1, c2))
    with pytest.raises(SchemalogError, match="does not settle"):
        World(root, [t("x.on"), t("w.on")])
    world = World(root)
    world.perform(c("x.on"))
    with pytest.raises(SchemalogError, match="does not settle"):
        world.perform(c("w.on"))


def test_initial_facts_are_located(kb_of):
    kb = kb_of("initial(hand.free).\ninitial(not spoon.taken).\n")
    with pytest.raises(SchemalogError) as err:
        initial_state(kb)
    assert (err.value.pos.line, err.value.pos.column) == (2, 1)
    assert initial_state(kb_of("initial(a.on).\ninitial(a.on).\n")) == [t("a.on")]


def test_settling_after_each_of_2000_siblings_tests_a_constant_number_of_children():
    from schemalog.formats.documents import read_document  # noqa: F401 (load_kb reads files)
    from schemalog.logic.kb import KnowledgeBase
    n = 2000
    kb = KnowledgeBase()
    entries = ", ".join(f"(c{i}, {'true' if i == 0 else f'c{i - 1}.done'})" for i in range(n))
    kb.consult_text(f"schema(t0, [{entries}], t0.done).\n"
                    + "\n".join(f"schema(c{i}, [], c{i}.done)." for i in range(n)), "w.pl")
    tree = instantiate(kb, parse_term("t0"))
    world = World(tree)
    tests = [0]
    for rule, checks in enumerate(world._child_checks):
        world._child_checks[rule] = [(lambda f: (lambda s: tests.__setitem__(0, tests[0] + 1) or f(s)))(f)
                                     for f in checks]
    for child in tree.children:
        assert not world.holds(tree.post)
        world.perform(child.post)
    assert world.holds(tree.post)
    assert tests[0] <= 3 * n      # not n * n / 2: each rule resumes at the child it last found false
