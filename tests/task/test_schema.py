"""The schema language: entry forms, validation with positions, canonical text."""

import pytest

from schemalog.task import conditions as cond
from schemalog.errors import SchemalogError
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.fastread import parse_text
from schemalog.logic.parse import parse_term
from schemalog.task.schema import check_schemas, read_schema, schema_term, write_clause


def schema_of(text: str):
    (clause,) = parse_text(text, "s.pl")
    return read_schema(clause.head, clause.body, clause.pos)


def test_paper_pairs_seed_triples_and_weights_read_alike():
    a = schema_of("schema(add(O), [(subtask(take, O), hand.free), (subtask(pour, O), O.taken, 2)], O.used).")
    b = schema_of('schema(add(O), [[subtask(take, O), 1, [hand.free]], [subtask(pour, O), 2, [O.taken]]], O.used).')
    assert [e.importance for e in a.entries] == [1, 2] == [e.importance for e in b.entries]
    assert str(schema_term(a)) == str(schema_term(b))


def test_leaf_schema():
    s = schema_of("schema(gripper(close), [], not hand.free).")
    assert s.is_leaf and s.post == cond.Lit(parse_term("hand.free"), positive=False)


@pytest.mark.parametrize("text, message", [
    ("schema(a, notalist, a.done).", "must be a list"),
    ("schema(a, [(b, 42)], a.done).", "releaser of b is not a condition"),
    ("schema(a, [b], a.done).", "a sub-task must be"),
    ("schema(a, [(b, true)], a.done or c.d).", "post-condition must be literals"),
    ("schema(a, [(7, true)], a.done).", "behaviour must be an atom or compound"),
])
def test_malformed_schemas_name_the_problem_and_position(text, message):
    with pytest.raises(SchemalogError, match=message) as err:
        schema_of("\n\n   " + text)
    assert (err.value.pos.line, err.value.pos.column) == (3, 4)


def test_check_schemas_reports_first_bad_clause():
    kb = KnowledgeBase()
    kb.consult_text("schema(a, [], a.done).\nschema(b, [(c, \"maybe\")], b.done).\n", "k.pl")
    with pytest.raises(SchemalogError) as err:
        check_schemas(kb)
    assert str(err.value.pos) == "k.pl:2:1"


def test_canonical_text_lays_out_subtasks_and_reads_back():
    s = schema_of("schema(use(O),[(subtask(take,O),hand.free),(subtask(mix,O),O.taken)],O.used).")
    text = write_clause(schema_term(s))
    assert text == ("schema(use(O),\n"
                    "       [ (subtask(take,O), hand.free),\n"
                    "         (subtask(mix,O), O.taken) ],\n"
                    "       O.used).")
    assert str(schema_term(schema_of(text))) == str(schema_term(s))


def test_rule_schema_keeps_its_body():
    s = schema_of('schema(en(S), [(speech(stop), true, 2)], true) :- string(S).')
    assert str(s.body) == "string(S)"
    assert write_clause(schema_term(s), s.body).endswith(":-\n    string(S).")
