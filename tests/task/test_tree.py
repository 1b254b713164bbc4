"""Instantiation (loadTaskFromLTM): golden figures of the paper's tasks, and its errors."""

import pytest

from schemalog.task import conditions as cond
from schemalog.formats.documents import read_document
from schemalog.errors import SchemalogError
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import count_nodes, declared_tasks, depth, instantiate, walk

from conftest import COFFEE, MIX


def tree_of(path, task=None):
    kb = read_document(path).to_kb()
    return instantiate(kb, parse_term(task) if task else declared_tasks(kb)[0])


def test_figure_2_has_12_behaviours_and_depth_3():
    t = tree_of(MIX)
    assert (count_nodes(t), depth(t)) == (12, 3)
    labels = [term_to_text(n.label) for n in walk(t)]
    assert labels[:5] == ["use(spoon)", "subtask(take,spoon)", "a1(spoon)", "a2(spoon)", "gripper(close)"]


def test_figure_2_conditions_agents_and_objects():
    nodes = {term_to_text(n.label): n for n in walk(tree_of(MIX))}
    take = nodes["subtask(take,spoon)"]
    assert cond.to_text(take.pre) == "hand.free" and cond.to_text(take.post) == "spoon.taken"
    assert nodes["gripper(close)"].agent == "gripper" and nodes["a1(spoon)"].agent == "arm"
    assert [str(o) for o in nodes["a3(cup)"].objects] == ["cup"]
    assert nodes["gripper(close)"].objects == ()  # `close` is not a declared object
    assert cond.to_text(nodes["gripper(close)"].post) == "not hand.free"


def test_coffee_and_tea_has_63_behaviours_and_depth_5():
    t = tree_of(COFFEE)
    assert (count_nodes(t), depth(t)) == (63, 5)


def test_two_uses_of_a_sub_task_are_distinct_nodes():
    t = tree_of(COFFEE)
    adds = [n for n in walk(t) if term_to_text(n.label) == "add(water)"]
    assert len(adds) == 2 and adds[0] is not adds[1]
    assert count_nodes(adds[0]) == count_nodes(adds[1]) == 12


def test_parameterised_schema_unifies_with_its_use():
    t = tree_of(COFFEE, "add(tea)")
    assert [term_to_text(c.label) for c in t.children] == ["subtask(take,tea)", "subtask(pour,tea)"]
    assert cond.to_text(t.children[1].releaser) == "tea.taken"


def kb_of(text):
    kb = KnowledgeBase()
    kb.consult_text(text, "t.pl")
    return kb


def test_cycle_is_reported_with_its_path_and_position():
    kb = kb_of("schema(a, [(b, true)], a.done).\nschema(b, [(c, true)], b.done).\nschema(c, [(a, true)], c.done).")
    with pytest.raises(SchemalogError, match=r"recursive schema: a -> b -> c -> a") as err:
        instantiate(kb, parse_term("a"))
    assert str(err.value.pos) == "t.pl:3:1"


def test_undefined_sub_task_is_an_error_unless_declared_a_behaviour():
    with pytest.raises(SchemalogError, match=r"no schema for b \(a sub-task in the schema at t.pl:1:1\)"):
        instantiate(kb_of("schema(a, [(b, true)], a.done)."), parse_term("a"))
    t = instantiate(kb_of("schema(a, [(b(x), true)], a.done).\nbehaviour(b(_))."), parse_term("a"))
    assert cond.to_text(t.children[0].post) == "b(x).done"


def test_depth_and_size_limits():
    chain = "\n".join(f"schema(s{i}, [(s{i + 1}, true)], s{i}.done)." for i in range(40)) + "\nschema(s40, [], d)."
    kb = kb_of(chain)
    assert depth(instantiate(kb, parse_term("s0"))) == 41
    with pytest.raises(SchemalogError, match="deeper than 10 levels"):
        instantiate(kb, parse_term("s0"), max_depth=10)
    with pytest.raises(SchemalogError, match="more than 5 behaviours"):
        instantiate(kb, parse_term("s0"), max_nodes=5)


def test_rule_schema_body_runs_at_instantiation():
    kb = kb_of("schema(go(N), L, go.done) :- N > 0, M is N - 1, L = [(go(M), true)].\nschema(go(0), [], at.goal).")
    assert depth(instantiate(kb, parse_term("go(3)"))) == 4


def test_rule_schema_needing_a_missing_builtin_names_it():
    kb = kb_of("schema(en(S), [(speech(x), true)], p.q) :- concat_string([S], _).")
    with pytest.raises(SchemalogError, match=r"concat_string/2"):
        instantiate(kb, parse_term('en("a b")'))


def test_explicit_objects_and_default_objects():
    kb = kb_of("objects(move(_, To), [To]).\nschema(t, [(move(a, b), true), (pick(c, 1), true)], t.done).\n"
               "schema(move(_, _), [], m.done).\nschema(pick(_, _), [], p.done).")
    t = instantiate(kb, parse_term("t"))
    assert [[str(o) for o in c.objects] for c in t.children] == [["b"], ["c", "1"]]


def test_sub_task_variables_must_be_bound_by_the_schema():
    kb = kb_of("schema(t, [(take(X), true), (pour(X), true)], t.done).\n"
               "schema(take(cup), [], a.done).\nschema(pour(jug), [], b.done).")
    with pytest.raises(SchemalogError, match=r"sub-task take\(_G\d+\) of t has variables") as err:
        instantiate(kb, parse_term("t"))
    assert str(err.value.pos) == "t.pl:1:1"
