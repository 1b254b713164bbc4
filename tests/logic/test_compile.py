"""Compiled clauses (logic/compile.py) answer as the clause copied and unified does."""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings, strategies as st

from schemalog.formats.documents import document_from_text
from schemalog.logic.compile import COMPILE_AFTER, activate_by_copy, body_goals, compile_clause
from schemalog.logic.engine import Engine
from schemalog.logic.exceptions import PrologError
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import Atom, Float, Struct, term_to_text
from schemalog.logic.unify import Bindings


def answers(program: str, goal: str, times: int = 1) -> list[list[str]]:
    """The answers to `goal`, asked `times` times of one knowledge base (so that the later
    asks run the compiled clauses)."""
    kb = document_from_text(program, "t.pl").to_kb()
    return [[term_to_text(t) for t in Engine(kb).answers(parse_term(goal))] for _ in range(times)]


def test_a_variable_goal_bound_to_a_cut_cuts_only_itself_once_compiled():
    # `p(G) :- G, fail.` with G = ! is call(!), local: the second clause still runs (swipl:
    # true). The compiled head used to name the goal's `!` in the body, cutting p itself.
    program = "p(G) :- G, fail.\np(_).\nq(G) :- (G ; true), fail.\nq(_).\n"
    assert answers(program, "p(!)", times=COMPILE_AFTER + 3) == [["p(!)"]] * (COMPILE_AFTER + 3)
    assert answers(program, "q(!)", times=COMPILE_AFTER + 3) == [["q(!)"]] * (COMPILE_AFTER + 3)


def test_a_body_of_100000_goals_is_called():
    body = ", ".join(["true"] * 100_000)
    program = f"p(X) :- {body}, X = done.\n"
    assert answers(program, "p(X)", times=COMPILE_AFTER + 2)[-1] == ["p(done)"]


def test_nested_conjunctions_are_flattened_in_order():
    goals = body_goals(parse_term("((a, b), (c, (d, e)))"))
    assert [term_to_text(g) for g in goals] == ["a", "b", "c", "d", "e"]
    assert body_goals(parse_term("true")) == []


# Arithmetic the compiler computes inline must agree with the general built-in on every
# operand: small and big integers, floats, unbound variables, atoms. A clause's first calls
# copy and unify (the general built-in); the later ones run the compiled clause.
OPERANDS = st.one_of(st.integers(-5, 5), st.integers(-(1 << 70), 1 << 70), st.sampled_from([1 << 62, -(1 << 62)]),
                     st.floats(allow_nan=False, allow_infinity=False, width=32), st.just("_"),
                     st.just("foo"))
GOALS = ["R is X + Y", "R is X - Y", "R is X * Y", "R is -(X) + Y * 2", "R is X - 1",
         "X < Y", "X =< Y", "X > Y + 1", "X >= Y", "X =:= Y - 0", "X =\\= Y", "R is X + Y, R > 0"]


def _text(x) -> str:
    return term_to_text(Float(x)) if isinstance(x, float) else str(x)


def _ask_repeatedly(goal: str, x, y, target) -> list[str]:
    kb = document_from_text(f"t(X, Y, R) :- {goal}.\n", "t.pl").to_kb()
    call = parse_term(f"t({_text(x)}, {_text(y)}, {_text(target)})")
    out = []
    for _ in range(COMPILE_AFTER + 2):
        try:
            out.append(",".join(term_to_text(t) for t in Engine(kb).answers(call)) or "fail")
        except PrologError as err:
            out.append(f"error {term_to_text(err.ball)}")
    return [re.sub(r"_G[0-9]+", "_", answer) for answer in out]


@settings(max_examples=500, deadline=None)
@given(goal=st.sampled_from(GOALS), x=OPERANDS, y=OPERANDS, target=st.sampled_from(["_", 0, 3, "foo"]))
def test_inline_arithmetic_answers_as_the_general_builtin(goal, x, y, target):
    first, *compiled = _ask_repeatedly(goal, x, y, target)
    assert compiled == [first] * len(compiled)


def test_the_compiled_clause_is_the_one_that_answers_after_its_first_calls():
    # So the test above compares two paths, not one path with itself.
    kb = document_from_text("t(X, R) :- R is X + 1.\n", "t.pl").to_kb()
    engine = Engine(kb)
    for _ in range(COMPILE_AFTER + 1):
        engine.first(parse_term("t(1, R)"))
    (clause,) = kb.clauses("t", 2)
    assert clause._activation is not None


def test_compiled_and_copied_activations_give_the_same_goal_list():
    head, body = parse_term("(t(X, [Y|Z]) :- (q(X), R is Y + 1), r(Z))").args
    goal = parse_term("t(a, [1, 2])")
    lists = []
    for make in (activate_by_copy, compile_clause):
        b = Bindings()
        goals, entries = make(head, body)(goal.args, b, 7, None), []
        while goals is not None:
            entry, height, goals = goals
            assert height == 7
            if isinstance(entry, tuple) and isinstance(entry[0], tuple):   # a UserCall: its goal
                entry = Struct(entry[0][0], entry[1])
            entries.append(entry if isinstance(entry, tuple) else term_to_text(b.resolve(entry)))
        lists.append(entries)
    by_copy, compiled = lists
    assert by_copy[0::2] == compiled[0::2] == ["q(a)", "r([2])"]
    assert re.fullmatch(r"_G[0-9]+ is 1\+1", by_copy[1])                    # the goal, as a term
    assert isinstance(compiled[1], tuple)                                 # a Call, found when compiled


# Control constructs inside a compiled body (engine.Or, IfThenElse, IfThen, Not) must answer
# as the interpreted terms do: the clause's first calls copy and unify, pushing `;`, `->`
# and `\+` as terms; the later ones run the compiled constructs.
CONTROL_PROGRAM = "p(a). p(b). q(b). q(c).\n"
LEAVES = st.sampled_from(["p(X)", "q(X)", "p(Y)", "q(Y)", "X == Y", "X = a", "!", "true", "fail",
                          "(Y = c ; Y = a)", "call(G)"])


def _bodies(leaf):
    def binary(op):
        return st.tuples(leaf, leaf).map(lambda pair: f"({pair[0]} {op} {pair[1]})")
    return st.one_of(binary(","), binary(";"), binary("->"), binary("*->"),
                     st.tuples(leaf, leaf, leaf).map(lambda t: f"({t[0]} -> {t[1]} ; {t[2]})"),
                     st.tuples(leaf, leaf, leaf).map(lambda t: f"({t[0]} *-> {t[1]} ; {t[2]})"),
                     leaf.map(lambda g: f"\\+ {g}"), leaf.map(lambda g: f"not({g})"))


BODIES = st.recursive(LEAVES, _bodies, max_leaves=8)


def _all_answers(program: str, goal: str, times: int) -> list[list[str]]:
    kb = document_from_text(program, "t.pl").to_kb()
    out = []
    for _ in range(times):
        try:
            out.append([re.sub(r"_G[0-9]+", "_", term_to_text(t)) for t in Engine(kb).answers(parse_term(goal))])
        except PrologError as err:
            out.append([re.sub(r"_G[0-9]+", "_", f"error {term_to_text(err.ball)}")])
    return out


@settings(max_examples=300, deadline=None)
@given(body=BODIES, g=st.sampled_from(["true", "!", "fail", "p(X)", "(p(X), !)"]))
def test_compiled_control_constructs_answer_as_the_interpreted_terms(body, g):
    # A second clause shows whether a cut reached the clause; G is a meta-called goal.
    program = CONTROL_PROGRAM + f"t(X, Y, G) :- {body}, Y = Y.\nt(z, z, _).\n"
    first, *compiled = _all_answers(program, f"t(X, Y, {g})", COMPILE_AFTER + 2)
    assert compiled == [first] * len(compiled)


def test_the_compiled_body_holds_control_constructs_not_terms():
    # So the test above compares two paths: the compiled clause pushes an engine.Or.
    from schemalog.logic.engine import Or
    head, body = parse_term("(t(X) :- (X = a ; X = b))").args
    entry, _, _ = compile_clause(head, body)(parse_term("t(Y)").args, Bindings(), 0, None)
    assert isinstance(entry, Or)


CUTS = [("a cut in an if-then-else condition is local to it",
         "t(X) :- ((p(X), !) -> true ; X = none).\nt(last).\n", "t(X)", ["t(a)", "t(last)"]),
        ("a cut in a disjunction's branch cuts the clause",
         "t(X) :- (p(X), ! ; X = other).\nt(last).\n", "t(X)", ["t(a)"]),
        ("a cut in a then-branch cuts the clause",
         "t(X) :- (true -> p(X), ! ; X = other).\nt(last).\n", "t(X)", ["t(a)"]),
        ("a cut inside negation is local to it",
         "t(X) :- \\+ (p(_), !, fail), X = yes.\nt(last).\n", "t(X)", ["t(yes)", "t(last)"]),
        ("an if-then without else fails when its condition fails",
         "t(X) :- (X == q -> true), X = q.\nt(last).\n", "t(X)", ["t(last)"]),
        ("a soft cut keeps the condition's alternatives",
         "t(X) :- (p(X) *-> true ; X = none).\nt(last).\n", "t(X)", ["t(a)", "t(b)", "t(last)"])]


def test_cuts_inside_compiled_control_constructs_reach_as_interpreted():
    for what, program, goal, expected in CUTS:
        for answer in _all_answers(CONTROL_PROGRAM + program, goal, COMPILE_AFTER + 2):
            assert answer == expected, what


# `X = Y` in a compiled body binds an unbound side itself (compile.unify_goal): the same
# answers as the general unification, whichever side is bound, shared or cyclic.
SIDES = st.sampled_from(["_", "A", "a", "1", "f(_)", "f(A)", "f(a)", "g(A, B)", "[A|B]", "A-A"])


@settings(max_examples=200, deadline=None)
@given(left=SIDES, right=SIDES, pattern=st.sampled_from(["X = Y", "Y = X", "X = f(Y)", "X = Y, Y = X"]))
def test_compiled_unification_answers_as_the_general_one(left, right, pattern):
    program = f"t(X, Y) :- {pattern}.\n"
    first, *compiled = _all_answers(program, f"B = b, t({left}, {right})", COMPILE_AFTER + 2)
    assert compiled == [first] * len(compiled)


# A first body goal comparing the head's integers is tested in the activation (a guard):
# failing, the clause fails before a choicepoint is left; on anything but integers the
# goal runs as the body's first, with its errors.
@settings(max_examples=300, deadline=None)
@given(test=st.sampled_from(["X < Y", "X =< Y", "X > Y + 1", "X - 1 >= Y * 2", "X =:= Y", "X =\\= Y"]),
       cut=st.sampled_from(["!, ", "", "fail ; "]), x=OPERANDS, y=OPERANDS)
def test_a_guard_answers_as_the_comparison_in_the_body(test, cut, x, y):
    program = f"t(X, Y, R) :- {test}, {cut}R = first.\nt(_, _, second).\n"
    goal = f"t({_text(x)}, {_text(y)}, R)"
    first, *compiled = _all_answers(program, goal, COMPILE_AFTER + 2)
    assert compiled == [first] * len(compiled)


# A compiled body calls a user predicate through a UserCall (its key made once, no goal term);
# what else a body calls must still reach the machine as it does interpreted: a
# nondeterministic built-in, a library predicate, an atom goal, an unknown procedure, and a
# relation an engine adds, which answers before a clause of the same name.
KINDS_PROGRAM = ("p(a). p(b).\ngo.\n"
                 "t(user, X) :- p(X).\n"
                 "t(atom, done) :- go.\n"
                 "t(nondet, N) :- between(1, 3, N).\n"
                 "t(length, L) :- length(L, 2).\n"
                 "t(library, L) :- append(L, [z], [y, z]).\n"
                 "t(output, x) :- nl.\n"
                 "t(unknown, X) :- nope(X).\n")


@pytest.mark.parametrize("kind, expected", [
    ("user", ["t(user,a)", "t(user,b)"]), ("atom", ["t(atom,done)"]),
    ("nondet", ["t(nondet,1)", "t(nondet,2)", "t(nondet,3)"]), ("length", ["t(length,[_,_])"]),
    ("library", ["t(library,[y])"]), ("output", ["t(output,x)"]),
    ("unknown", ["error error(existence_error(procedure,nope/1),_)"])])
def test_every_kind_of_body_goal_answers_alike_before_and_after_compiling(kind, expected):
    answers = _all_answers(KINDS_PROGRAM, f"t({kind}, X)", COMPILE_AFTER + 2)
    assert answers == [expected] * (COMPILE_AFTER + 2)


def test_a_relation_of_the_engine_answers_before_a_clause_of_its_name_once_compiled():
    def relation(engine, args, b):
        return b.unify(args[0], Atom("relation"))

    kb = document_from_text("p(clause).\nt(X) :- p(X).\n", "t.pl").to_kb()
    for _ in range(COMPILE_AFTER + 2):
        plain = [term_to_text(t) for t in Engine(kb).answers(parse_term("t(X)"))]
        extended = [term_to_text(t) for t in Engine(kb, builtins={("p", 1): relation}).answers(parse_term("t(X)"))]
        assert (plain, extended) == (["t(clause)"], ["t(relation)"])
