"""op/3 directives change how the clauses after them read (logic/opread.py), in that file,
the files read after it and queries; what the writers write follows the same table."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from schemalog.errors import SchemalogError
from schemalog.formats.documents import load_kb
from schemalog.logic.engine import Engine
from schemalog.logic.fastread import parse_text
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.opread import parse_term
from schemalog.logic.terms import Atom, Int, Struct, term_to_text

ROOT = Path(__file__).resolve().parents[2]


def body(item):
    return item.body.args[1]          # p(X) :- X = (...): the right side of =


def test_clauses_after_an_op_directive_read_the_operator():
    items = parse_text(":- op(700, xfx, my_ins).\n"
                       "p(X) :- X = (a my_ins b).\n"
                       ":- op(200, xf, fact).\n:- op(900, fy, nicht).\n"
                       "q(X) :- X = (nicht 3 fact).\n", "f.pl")
    assert body(items[1]) == Struct("my_ins", (Atom("a"), Atom("b")))
    assert body(items[4]) == Struct("nicht", (Struct("fact", (Int(3),)),))


def test_before_its_directive_an_operator_is_a_syntax_error_at_its_place():
    with pytest.raises(SchemalogError) as caught:
        parse_text("p(X) :- X = (a my_ins b).\n:- op(700, xfx, my_ins).\n", "f.pl")
    assert (caught.value.pos.file, caught.value.pos.line, caught.value.pos.column) == ("f.pl", 1, 16)


def test_priority_zero_removes_an_operator():
    text = ":- op(700, xfx, my_ins).\np(a my_ins b).\n:- op(0, xfx, my_ins).\nq(X) :- X = (a my_ins b).\n"
    with pytest.raises(SchemalogError) as caught:
        parse_text(text, "f.pl")
    assert "syntax error" in caught.value.message and caught.value.pos.line == 4
    ok = parse_text(text.replace("q(X) :- X = (a my_ins b)", "q(X) :- X = my_ins(a, b)"), "f.pl")
    assert ok[1].head == Struct("p", (Struct("my_ins", (Atom("a"), Atom("b"))),))


def test_an_operator_declared_by_one_file_holds_in_the_files_read_after_it(tmp_path):
    (tmp_path / "ops.pl").write_text(":- op(700, xfx, my_ins).\n")
    (tmp_path / "use.pl").write_text("p(X) :- X = (a my_ins b).\n")
    kb = load_kb([tmp_path / "ops.pl", tmp_path / "use.pl"])
    answer = Engine(kb).first(parse_term("p(X), current_op(P, T, my_ins)", "<q>", kb.operators))
    assert answer is not None
    with pytest.raises(SchemalogError):     # read first, the other file's operator is unknown
        load_kb([tmp_path / "use.pl", tmp_path / "ops.pl"])


def test_consulted_file_reads_with_the_consulting_files_operators(tmp_path):
    (tmp_path / "main.pl").write_text(":- op(700, xfx, my_ins).\n:- [part].\n")
    (tmp_path / "part.pl").write_text("p(a my_ins b).\n")
    kb = KnowledgeBase()
    kb.consult(tmp_path / "main.pl")
    assert kb.clauses("p", 1)[0].head == Struct("p", (Struct("my_ins", (Atom("a"), Atom("b"))),))


def test_writers_follow_the_table_and_write_canonical_ignores_it():
    kb = KnowledgeBase()
    kb.consult_text(":- op(700, xfx, my_ins).\n:- op(200, xf, fact).\n")
    out: list[str] = []
    goal = parse_term("X = f(a my_ins b, 3 fact), writeq(X), nl, print(X), nl, write_canonical(X), nl, "
                      "write_term(X, [ignore_ops(true)])", "<q>", kb.operators)
    assert Engine(kb, output=out.append).first(goal) is not None
    assert "".join(out) == "f(a my_ins b,3 fact)\nf(a my_ins b,3 fact)\nf(my_ins(a,b),fact(3))\nf(my_ins(a,b),fact(3))"


def test_an_operator_atom_before_a_bracket_is_a_functor():
    for text, term in [("=..(a, [b])", Struct("=..", (Atom("a"), Struct("[|]", (Atom("b"), Atom("[]")))))),
                       (";(a, b)", Struct(";", (Atom("a"), Atom("b")))),
                       ("-(1)", Struct("-", (Int(1),))), ("- (1)", Struct("-", (Int(1),))),
                       ("-1", Int(-1)), ("+a", Struct("+", (Atom("a"),))),
                       ("a:b:c", Struct(":", (Atom("a"), Struct(":", (Atom("b"), Atom("c")))))),
                       ("{}(x)", Struct("{}", (Atom("x"),)))]:
        assert parse_term(text) == term, text


def test_a_module_qualified_goal_is_still_refused_but_a_colon_term_reads():
    from schemalog.api.answers import read_query
    with pytest.raises(SchemalogError, match="modules are not supported"):
        read_query("lists:append(X, Y, [a])")
    with pytest.raises(SchemalogError, match="modules are not supported"):
        parse_text("p :- \\+ lists:member(a, [a]).\n", "f.pl")
    assert read_query("X = a:b").goal.args[1] == Struct(":", (Atom("a"), Atom("b")))


def test_query_after_a_file_declared_operators(tmp_path):
    (tmp_path / "ops.pl").write_text(":- op(700, xfx, my_ins).\n:- op(200, xf, fact).\np(a my_ins b).\n")
    done = subprocess.run([sys.executable, "-m", "schemalog", "query", str(tmp_path / "ops.pl"),
                           "p(X), Y = (3 fact), Z = f(c my_ins d)"],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "X = (a my_ins b), Y = 3 fact, Z = f(c my_ins d)"   # swipl's top level


def test_a_bad_clause_under_user_operators_is_a_message_not_a_traceback(tmp_path):
    (tmp_path / "bad.pl").write_text(":- op(700, xfx, my_ins).\np(a my_ins).\n")
    done = subprocess.run([sys.executable, "-m", "schemalog", "query", str(tmp_path / "bad.pl"), "true"],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode != 0
    assert "bad.pl:2:" in done.stderr and "syntax error" in done.stderr and "Traceback" not in done.stderr


def test_writeq_of_a_user_operator_reads_back_in_a_file():
    kb = KnowledgeBase()
    kb.consult_text(":- op(650, yfx, ++).\n:- op(710, xfy, ===>).\n")
    term = parse_term("a ++ b ++ (c ===> d ===> e)", "<t>", kb.operators)
    text = term_to_text(term, ops=kb.operators.view())
    assert text == "a++b++(c===>d===>e)"
    again = parse_text(f":- op(650, yfx, ++).\n:- op(710, xfy, ===>).\nt({text}).\n", "f.pl")
    assert again[2].head.args[0] == term


# The table-driven reader agrees with the grammar wherever the grammar reads: what lark reads
# from any written term (and from token soup), opread reads the same under the default table.
# (Not for a word operator as an operand after a prefix operator, `- is = a`: lark reads -(is)=a
# where swipl and opread find a syntax error; lark is tried first, so its reading stays.)
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

from schemalog.logic.opread import read_term  # noqa: E402
from schemalog.logic.parse import parse_term as lark_term  # noqa: E402
from schemalog.logic.terms import DEFAULT_OPERATORS, variable_names  # noqa: E402
from schemalog.logic.unify import variant  # noqa: E402
from test_parse_properties import terms  # noqa: E402

SOUP = st.lists(st.sampled_from(["a", "X", "_", "1", "-1", "- 1", "-", "+", "(", ")", "[", "]", "{", "}", ",", "|",
                                 "=", "=..", ":-", "\\+", "not", "f(", "'q r'", '"s"', ";", "!", "a.b",
                                 " ", "0'c", "1.5", "*", "^", "->", "dynamic"]), max_size=12).map("".join)


def _agree(text: str) -> None:
    try:
        expected = lark_term(text, "<t>")
    except SchemalogError:
        return                                 # lark reads nothing: opread may read more
    got = read_term(text, "<t>", DEFAULT_OPERATORS)
    assert variant(got, expected), f"{text!r}: lark {expected!r}, opread {got!r}"


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(terms)
def test_opread_reads_written_terms_as_lark_does(term):
    _agree(term_to_text(term, names=variable_names([term])))


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(SOUP)
def test_opread_reads_token_soup_as_lark_does(text):
    _agree(text)


def test_op_directives_written_without_layout_or_in_a_conjunction_are_followed():
    items = parse_text(":-op(700,xfx,my_ins).\n:- op(200, xf, fact), op(900, fy, nicht).\n"
                       "p(a my_ins b).\nq(nicht 3 fact).\n", "f.pl")
    assert items[2].head.args[0] == Struct("my_ins", (Atom("a"), Atom("b")))
    assert items[3].head.args[0] == Struct("nicht", (Struct("fact", (Int(3),)),))


def test_after_an_op_directive_long_chains_read_and_deep_nesting_is_refused_where_lark_refuses_it():
    directive = ":- op(700, xfx, my_ins).\n"
    chain = ", ".join(f"g{i}(X)" for i in range(10000))
    assert len(parse_text(f"{directive}p(X) :- {chain}.\n", "f.pl")) == 2
    deep = "p(" + "f(" * 2001 + "a" + ")" * 2001 + ").\n"
    messages = []
    for text in (f"{directive}{deep}", f"\n{deep}"):   # opread's, then lark's
        with pytest.raises(SchemalogError) as caught:
            parse_text(text, "f.pl")
        messages.append(str(caught.value).splitlines()[0])
    assert messages[0] == messages[1] == "f.pl:2:4002: error: brackets nested deeper than 2000 levels"
