"""The fast reader (fastread.py) reads what lark reads, and fails where lark fails, alike.

    1. lark's lexer: every parser state takes the tokens of one of the two modes
    2. printed terms, laid out as clauses with comments: the same clauses, positions, variables
    3. token soup (mostly syntax errors, odd operators, quotes): the same clauses or the
       same error, message, file:line:column and source line
    4. mutated knowledge files: the same
    5. a clause lark must read (a clash, a bad escape, deep nesting) leaves the others fast
"""

from __future__ import annotations

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from schemalog.errors import SchemalogError
from schemalog.logic import fastread
from schemalog.logic.fastread import parse_text
from schemalog.logic.fastread import parse_text_slowly
from schemalog.logic.parse import MAX_NESTING, Clause, Directive, _reader
from schemalog.logic.terms import INFIX_OPS, Atom, Float, Int, Str, Struct, Var, term_to_text, variable_names

ROOT = Path(__file__).resolve().parents[2]
KB_FILES = sorted((ROOT / "kb").rglob("*.pl"))
SETTINGS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def canonical(term, seen: dict):
    """The term with each variable as its name and the order it first appeared in."""
    if isinstance(term, Var):
        return ("var", term.name, seen.setdefault(id(term), len(seen)))
    if isinstance(term, Struct):
        return (term.name, tuple(canonical(a, seen) for a in term.args))
    if isinstance(term, Float):
        return ("float", term.value.hex())
    return (type(term).__name__, getattr(term, "name", None), getattr(term, "value", None))


def read(reader, text: str):
    """What `reader` makes of `text`: its items as canonical data, or its error as printed."""
    try:
        items = reader(text, "t.pl")
    except SchemalogError as err:
        return ("error", str(err), err.pos)
    out = []
    for item in items:
        seen: dict = {}
        if isinstance(item, Directive):
            out.append(("directive", item.pos, canonical(item.goal, seen)))
        else:
            out.append(("clause", item.pos, canonical(item.head, seen), canonical(item.body, seen)))
    return out


def assert_same(text: str):
    assert read(parse_text, text) == read(parse_text_slowly, text), repr(text)


# ---------------------------------------------------------------------------
# 1. The two lexer modes cover lark's contextual lexer

def test_every_parser_state_lexes_in_one_mode():
    table = _reader("start").lark.parser.parser.parser.parse_table
    for actions in table.states.values():
        terminals = {name for name in actions if name.isupper() and name != "$END"}
        assert terminals <= fastread.OPERAND_TERMINALS or terminals <= fastread.OPERATOR_TERMINALS \
            or terminals == {"LPAR"}, sorted(terminals)  # LPAR: only after a functor, read with it
    assert fastread.scanners() is not None


# ---------------------------------------------------------------------------
# 2. Printed terms as clauses

LEAVES = st.one_of(
    st.sampled_from(["a", "[]", "{}", "!", "'hello world'", "'it''s'", "'\\n'", "+", "-", "'-'", ";",
                     "dynamic", "'not'", "cup", "hand"]).map(Atom),
    st.integers(-10**6, 10**6).map(Int), st.sampled_from([1.5, -0.0, 1e22, float("inf")]).map(Float),
    st.sampled_from(["", "x y", 'q"q', "\\"]).map(Str),
    st.sampled_from(["X", "Y", "_", "_Z", "Obj"]).map(Var))
OPERATORS = st.sampled_from([":-", ";", "->", ",", "or", "and", "=", "is", "<", "+", "-", "*", "mod", "**",
                             "^", ".", "\\+", "not", "-", "\\", "dynamic", "?-"])


def _compound(children):
    return st.one_of(
        st.tuples(OPERATORS, st.lists(children, min_size=1, max_size=2)).map(
            lambda p: Struct(p[0], tuple(p[1]))),
        st.tuples(st.sampled_from(["f", "schema", "'q r'", "[]", "{}"]), st.lists(children, min_size=1, max_size=3)).map(
            lambda p: Struct(p[0].strip("'"), tuple(p[1]))),
        st.lists(children, min_size=1, max_size=3).map(lambda items: _list(items)),
        children.map(lambda t: Struct("{}", (t,))))


def _list(items):
    out = Atom("[]")
    for item in reversed(items):
        out = Struct("[|]", (item, out))
    return out


TERMS = st.recursive(LEAVES, _compound, max_leaves=12)
LAYOUT = st.sampled_from(["\n", " ", "\n\n", "  % a comment\n", " /* block\n comment */ ", "\t"])


@SETTINGS
@given(st.lists(st.tuples(TERMS, LAYOUT), min_size=1, max_size=5))
def test_printed_clauses_read_alike(clauses):
    text = "".join(term_to_text(t, names=variable_names([t])) + "." + layout for t, layout in clauses)
    assert_same(text)


# ---------------------------------------------------------------------------
# 3. Token soup

TOKENS = st.sampled_from([
    "a", "b", "X", "_", "Y1", "f(", "g(", "'q'(", "-(", "(", ")", "[", "]", "{", "}", "|", ",", " ", " ", "\n",
    "-", "- ", "-1", "1", "0'a", "0'", "0x1F", "1.5", "2.0e3", "1.0Inf", "\"s\"", "\"a\\\"b\"", "'x\\z'",
    "'a b'", "'\\x41\\'", ":-", "?-", "-->", "is", "not", "\\+", "\\", "=..", ";", "+", "*", "**", "^", "=",
    "dynamic", "table", "and", "or", ".", ". ", ".\n", "b.c", "hand.free", "%c\n", "/*c*/", "/*", "*/",
    "[]", "{}", "!", "@", "#", "~", "`", "->", "*->", "\\=="])


@SETTINGS
@given(st.lists(TOKENS, max_size=25).map("".join))
def test_token_soup_reads_or_fails_alike(text):
    assert_same(text)


@SETTINGS
@given(st.lists(st.lists(TOKENS, max_size=10).map("".join), min_size=1, max_size=4))
def test_clauses_of_soup_read_or_fail_alike(parts):
    # Mostly good clauses around a bad one: the error is the first bad clause's.
    assert_same("".join(part + ".\n" for part in parts))
    assert_same("ok(1).\n" + "".join(part + ". " for part in parts) + "\nok(2).\n")


# Runs of tokens the fast reader matches at once (fastread.LANES: `f(a)`, `a.b`), next to
# what would make them other tokens: operator words, "(" after the second word, prefix
# operators before them, layout, quotes, digits and variables inside them.
LANE_TOKENS = st.sampled_from([
    "f", "b3", "cup", "not", "dynamic", "table", "is", "mod", "and", "or", "notx", "tablet", "a_1", "X", "_",
    "1", "'q'", "(", ")", ".", ". ", ".\n", ",", " ", "[", "]", "|", "-", "- ", "\\+", ":-", "done", "(a)",
    "f(a)", "b3(cup)", "a.b", "cup.taken", "not(a)", "f(not)", "a.not", "not.a", "x(table)", "a.b(c)",
    "(b3(cup), true)", "(f(a),x.y)", "( f(a) ,\n a.b )", "(f(a), not)", "(f(a), not.b)", "(f(a), a.not)",
    "(f(a), b", "(f(a),", "(f(a) %c\n, b)", "(f(a), b /* c */)", "(f(a), is)", "(f(a), a.b.c)", "(f(a), b(c))"])


@SETTINGS
@given(st.lists(LANE_TOKENS, max_size=20).map("".join))
def test_runs_read_at_once_read_or_fail_alike(text):
    assert_same(text)
    assert_same(f"x({text}).\n")
    assert_same(f"schema(t, [({text}, true)], t.done).\n")


INFIX = st.sampled_from(sorted(INFIX_OPS))
PRIMARY = st.sampled_from(["a", "f(a)", "X", "1", "[]", "(a, b)", "'q r'", "a.b"])


@SETTINGS
@given(st.lists(st.tuples(PRIMARY, INFIX), min_size=2, max_size=3), PRIMARY, st.sampled_from([" ", ""]))
def test_runs_of_two_operators_arrange_alike(pairs, last, space):
    # three primaries and two infix operators take a short cut past arrange (fastread._finish)
    run = "".join(f"{primary}{space}{op} " for primary, op in pairs) + last
    assert_same(f"x :- {run}.\n")
    assert_same(f"y(({run})).\n")
    assert_same(f"z([{run}]).\n")


def test_runs_read_at_once_are_on():
    # The lanes are used only for the grammar they were checked against (fastread.LANES_GRAMMAR);
    # after a change to grammar/schemalog.lark, check that what the lanes match is still read
    # token by token as their comment says, then update the fingerprint.
    assert "(?P<CALL>" in fastread.scanners()[0].pattern
    for text in ("schema(b2(cup), [(b3(cup), true), (b4(cup), b3.done)], b2.done).\n",
                 "x :- - (f(a), b), \\+ (f(a), b.c), -(f(a), b), [(f(a),b)|(g(c), not)], ( f(a) ,\n a.b ).\n",
                 "x :- - f(a), - a.b, \\+ a.b.c, a.b(c), f(not), x(dynamic), a.is, [f(a)|a.b].\n",
                 "y(not.a). z(a.not b). w(f(a)(b)).\n"):
        assert_same(text)


# ---------------------------------------------------------------------------
# 4. Mutated knowledge files

@st.composite
def mutated_texts(draw):
    text = KB_FILES[draw(st.integers(0, len(KB_FILES) - 1))].read_text(encoding="utf-8")
    for _ in range(draw(st.integers(0, 3))):
        at = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["delete", "insert", "truncate"]))
        if kind == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 20)):]
        elif kind == "insert":
            text = text[:at] + draw(TOKENS) + text[at:]
        else:
            text = text[:at]
    return text


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_texts())
def test_mutated_knowledge_reads_or_fails_alike(text):
    assert_same(text)


def test_every_shipped_knowledge_file_reads_alike():
    assert KB_FILES
    for path in KB_FILES:
        assert_same(path.read_text(encoding="utf-8"))


# ---------------------------------------------------------------------------
# 5. Clauses for lark

def test_a_clause_lark_reads_keeps_its_neighbours():
    text = "a(1).\nb :- X = 0'c, Y = \"\\x41\\\", Z = 'it''s'.\n  c(- 1, -1, - (1), [x|T], {y}).\n"
    items = parse_text(text, "t.pl")
    assert [type(i) for i in items] == [Clause, Clause, Clause]
    assert [i.pos.line for i in items] == [1, 2, 3] and items[2].pos.column == 3
    assert term_to_text(items[1].body) == "X=99,Y=\"A\",Z='it\\'s'"
    assert_same(text)


def test_errors_are_lark_s_with_their_positions():
    cases = {
        "ok.\na :- b :- c.\n": "t.pl:2:3: error: operator priority clash at ':-'",
        "ok.\nx('\\q').\n": "t.pl:2:4: error: syntax error: undefined escape sequence \\q",
        "ok.\nf(a b).\n": "t.pl:2:5: error: syntax error: unexpected 'b'; expected ')', ',' or an operator",
        "ok.\nf(a": "t.pl:2:4: error: unexpected end of file",
        "ok.\nx = 0'ab.\n": "t.pl:2:8: error: syntax error: unexpected 'b'; expected ',', '.'",
    }
    for text, start in cases.items():
        assert_same(text)
        try:
            parse_text(text, "t.pl")
        except SchemalogError as err:
            assert str(err).startswith(start), (text, str(err))
        else:
            raise AssertionError(f"{text!r} read")


def test_nesting_past_the_limit_is_lark_s_error():
    deep = "ok.\nx(" + "[" * (MAX_NESTING + 1) + "]" * (MAX_NESTING + 1) + ").\n"
    assert_same(deep)
    fine = "x(" + "[" * (MAX_NESTING - 2) + "]" * (MAX_NESTING - 2) + ").\n"
    assert len(parse_text(fine, "t.pl")) == 1
