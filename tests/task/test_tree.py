"""Instantiation (loadTaskFromLTM): golden figures of the paper's tasks, and its errors."""

import pytest
from hypothesis import given, strategies as st

from schemalog.task import conditions as cond
from schemalog.formats.documents import read_document
from schemalog.errors import SchemalogError
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import Atom, term_to_text
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
    kb = kb_of('schema(en(S), [(speech(x), true)], p.q) :- sprintf(_, "%s", [S]).')
    with pytest.raises(SchemalogError, match=r"calls sprintf/3, which neither the file nor schemalog defines"):
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


def _counting(monkeypatch):
    """Count schema look-ups and behaviours built (each built node asks for its agent)."""
    from schemalog.task.tree import Instantiator
    counts = {"lookups": 0, "built": 0}
    lookup, agent = Instantiator._find, Instantiator.agent

    def counted_lookup(self, *a):
        counts["lookups"] += 1
        return lookup(self, *a)

    def counted_agent(self, *a):
        counts["built"] += 1
        return agent(self, *a)
    monkeypatch.setattr(Instantiator, "_find", counted_lookup)
    monkeypatch.setattr(Instantiator, "agent", counted_agent)
    return counts


def test_a_5000_deep_chain_is_refused_at_max_depth_after_as_many_lookups(monkeypatch):
    kb = kb_of("\n".join(f"schema(t{i}, [(t{i + 1}, true)], t{i}.done)." for i in range(5000))
               + "\nschema(t5000, [], t5000.done).")
    counts = _counting(monkeypatch)
    with pytest.raises(SchemalogError, match=r"deeper than 256 levels at t256 \(raise the limit with --max-depth\)"):
        instantiate(kb, parse_term("t0"))
    assert counts["lookups"] <= 257 and counts["built"] == 0


def test_a_binary_explosion_is_refused_at_max_nodes_without_building_it(monkeypatch):
    # t0 has two uses of t1, t1 two of t2, ...: 2^41 - 1 behaviours, counted over 41 schemas
    kb = kb_of("\n".join(f"schema(t{i}, [(t{i + 1}, true), (t{i + 1}, a.b)], t{i}.done)." for i in range(40))
               + "\nschema(t40, [], t40.done).")
    counts = _counting(monkeypatch)
    with pytest.raises(SchemalogError, match=r"more than 2,000,000 behaviours .*--max-nodes") as err:
        instantiate(kb, parse_term("t0"))
    assert counts["lookups"] == 41 and counts["built"] == 0
    assert str(err.value.pos).startswith("t.pl:")
    with pytest.raises(SchemalogError, match=r"more than 1,000 behaviours"):
        instantiate(kb, parse_term("t30"), max_nodes=1000)


@given(st.lists(st.integers(1, 4), min_size=1, max_size=6))
def test_a_shared_sub_task_is_counted_and_built_once_per_use(fanouts):
    # level i uses level i+1 fanouts[i] times: the tree has sum of the running products nodes
    lines = [f"schema(s{i}, [{', '.join(f'(s{i + 1}, true)' for _ in range(k))}], s{i}.done)."
             for i, k in enumerate(fanouts)]
    kb = kb_of("\n".join(lines) + f"\nschema(s{len(fanouts)}, [], s{len(fanouts)}.done).")
    expected, width = 1, 1
    for k in fanouts:
        width *= k
        expected += width
    tree = instantiate(kb, parse_term("s0"))
    assert count_nodes(tree) == expected and depth(tree) == len(fanouts) + 1
    if expected > 1:
        with pytest.raises(SchemalogError, match=f"more than {expected - 1:,} behaviours"):
            instantiate(kb, parse_term("s0"), max_nodes=expected - 1)
    with pytest.raises(SchemalogError, match="deeper than"):
        instantiate(kb, parse_term("s0"), max_depth=len(fanouts))


def test_a_looping_look_up_stops_at_the_knowledge_bases_step_limit_and_names_itself():
    # a mutated file (found by the fuzz suite): `object(X) :- object(X).` ran 5,000,000 steps
    # whatever --max-steps said, then ended with a message naming no goal
    kb = KnowledgeBase()
    kb.max_steps = 20_000
    kb.consult_text("schema(t, [(a(cup), true)], a.done).\nschema(a(cup), [], a.done).\n"
                    "object(X) :- object(X).\n", "loop.pl")
    with pytest.raises(SchemalogError) as stopped:
        instantiate(kb, Atom("t"))
    assert "object(" in str(stopped.value), str(stopped.value)
    assert "exceeded the step limit of 20,000 steps (raise it with --max-steps N)" in str(stopped.value)


def test_a_rule_schemas_body_runs_under_the_step_limit_with_its_place():
    kb = KnowledgeBase()
    kb.max_steps = 20_000
    kb.consult_text("schema(t, [(u, true)], u.done).\nschema(u, [], u.done) :- loop.\nloop :- loop.\n", "rule.pl")
    with pytest.raises(SchemalogError) as stopped:
        instantiate(kb, Atom("t"))
    assert "while instantiating u, the schema's body exceeded the step limit of 20,000 steps" in str(stopped.value)
    assert stopped.value.pos is not None and stopped.value.pos.line == 2


# A SEED memory whose rule schema reads only the words it knows: asked for en(dance), no
# clause applies. SEED says "no semantic for ..." and leaves the node out; schema text errs.
SEED_RULE = ('task(greet).\n'
             'schema(greet, [[en(hello), 1, ["TRUE"]], [en(dance), 2, ["TRUE"]], [wave, 1, ["TRUE"]]]).\n'
             'schema(en(S), [[say(S), 1, ["TRUE"]]]) :- member(S, [hello, bye]).\n'
             'schema(say(_), []).\nschema(wave, []).\n')


def seed_kb(text=SEED_RULE, file="m.prolog"):
    from schemalog.formats.documents import document_from_text
    return document_from_text(text, file).to_kb()


def test_a_seed_sub_task_no_rule_applies_to_is_left_out_with_a_warning_at_its_parent():
    from schemalog.task.tree import Instantiator
    instantiator = Instantiator(seed_kb())
    tree = instantiator.instantiate(parse_term("greet"))
    assert [term_to_text(c.label) for c in tree.children] == ["en(hello)", "wave"]
    assert [term_to_text(c.label) for c in tree.children[0].children] == ["say(hello)"]
    assert instantiator.warnings == ["m.prolog:2:1: warning: no semantic for en(dance) (a sub-task of greet): "
                                     "no schema applies to it; left out, as SEED does"]
    # each instantiation says its own, once
    instantiator.instantiate(parse_term("greet"))
    assert len(instantiator.warnings) == 1
    assert Instantiator(seed_kb()).instantiate(parse_term("en(bye)")).children[0].label == parse_term("say(bye)")


def test_a_seed_task_no_rule_applies_to_is_still_an_error():
    with pytest.raises(SchemalogError, match=r"no schema for en\(dance\)"):
        instantiate(seed_kb(), parse_term("en(dance)"))


def test_the_same_knowledge_as_schema_text_keeps_the_error():
    text = ('schema(greet, [(en(hello), true), (en(dance), true)], greet.done).\n'
            'schema(en(S), [(say(S), true)], en(S).done) :- member(S, [hello, bye]).\n'
            'schema(say(_), [], said).\n')
    with pytest.raises(SchemalogError, match=r"no schema for en\(dance\) \(a sub-task in the schema at t.pl:1:1\)"):
        instantiate(kb_of(text), parse_term("greet"))


def test_a_seed_body_that_raises_is_still_an_error():
    text = SEED_RULE.replace("member(S, [hello, bye])", "sprintf(S, x, y)")
    with pytest.raises(SchemalogError, match=r"while instantiating en\(hello\), the schema's body calls "
                                             r"sprintf/3, which neither the file nor schemalog defines"):
        instantiate(seed_kb(text), parse_term("greet"))
