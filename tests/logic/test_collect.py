"""The collection of unreachable bindings (logic/collect.py): memory that does not grow with a
loop's iterations, and answers that never change because a collection ran.

The stress mode collects at every third step whatever the trail's growth, so every
choicepoint kind (clauses, alternatives, a suspended built-in, catch frames, soft cuts) meets a
renumbered trail; its answers must be exactly those of a machine that never collects.
"""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings, strategies as st

from schemalog.logic import engine as machine
from schemalog.logic.engine import Engine
from schemalog.logic.exceptions import PrologError, StepLimitExceeded
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import term_to_text
from schemalog.logic.unify import Bindings

NREV = """
app([], L, L).
app([H|T], L, [H|R]) :- app(T, L, R).
nrev([], []).
nrev([H|T], R) :- nrev(T, RT), app(RT, [H], R).
range(N, N, [N]) :- !.
range(I, N, [I|T]) :- I < N, I1 is I + 1, range(I1, N, T).
loop(0, _) :- !.
loop(K, L) :- nrev(L, _), K1 is K - 1, loop(K1, L).
run(K, R) :- range(1, 30, L), loop(K, L), nrev(L, R).
count(N, N) :- !.
count(I, N) :- I1 is I + 1, count(I1, N).
"""


def bindings_left(program: str, query: str, growth: int) -> tuple[int, str]:
    """How many bindings the machine holds when `query`'s first answer is yielded, and the answer."""
    kb = KnowledgeBase()
    kb.consult_text(program)
    engine = Engine(kb, max_steps=10**9)
    engine.collect_growth = growth
    goal = parse_term(query)
    b = Bindings()
    for answer in engine.solve(goal, b):
        return len(answer.values), term_to_text(answer.resolve(goal))
    raise AssertionError(f"{query} failed")


@pytest.mark.parametrize("query", ["run({}, R)", "count(0, {})", "findall(R, run({}, R), Rs)",
                                   "forall(run({}, R), true)", "catch(run({}, R), _, true)",
                                   "setup_call_cleanup(true, run({}, R), true)"])
def test_a_deterministic_loop_holds_as_many_bindings_after_many_iterations_as_after_few(query):
    few, answer_few = bindings_left(NREV, query.format(40), growth=2_000)
    many, answer_many = bindings_left(NREV, query.format(4_000), growth=2_000)
    assert many <= 3 * 2_000 + 100, f"{many} bindings held after 4,000 iterations"
    assert many < 2 * few + 2_000
    assert numbered(answer_many.replace("4000", "40")) == numbered(answer_few)


def test_without_collection_the_same_loop_keeps_every_binding():
    # what the test above guards against: every binding of every finished call kept
    held, _ = bindings_left(NREV, "run(400, R)", growth=10**12)
    assert held > 400 * 400


def test_the_query_variables_survive_a_collection():
    _, answer = bindings_left(NREV, "range(1, 5, L), loop(3000, L), nrev(L, R)", growth=100)
    assert answer == "range(1,5,[1,2,3,4,5]),loop(3000,[1,2,3,4,5]),nrev([1,2,3,4,5],[5,4,3,2,1])"


# -- answers with and without collection ------------------------------------------------------

PROGRAM = """
:- dynamic d/1.
d(1). d(2). d(3).
p(1). p(2). p(3).
q(X, Y) :- p(X), p(Y), X < Y.
r(X) :- p(X), X > 1, !.
r(0).
chain(0, []) :- !.
chain(N, [N|T]) :- N1 is N - 1, chain(N1, T).
"""

LEAVES = ["p(X)", "p(Y)", "q(X, Y)", "r(X)", "member(Y, [a, b, c])", "between(1, 3, X)",
          "clause(d(X), true)", "retract(d(X))", "assertz(d(9))", "chain(4, Y)", "length(Y, 2)",
          "X = f(Y)", "true", "fail", "!", "throw(ball(X))", "nth1(X, [u, v], Y)", "select(X, [1, 2], Y)"]


def bodies(depth: int):
    leaf = st.sampled_from(LEAVES)
    if depth == 0:
        return leaf
    inner = bodies(depth - 1)
    return st.one_of(
        leaf,
        st.tuples(inner, inner).map(lambda ab: f"({ab[0]}, {ab[1]})"),
        st.tuples(inner, inner).map(lambda ab: f"({ab[0]} ; {ab[1]})"),
        st.tuples(inner, inner, inner).map(lambda abc: f"({abc[0]} -> {abc[1]} ; {abc[2]})"),
        st.tuples(inner, inner, inner).map(lambda abc: f"({abc[0]} *-> {abc[1]} ; {abc[2]})"),
        inner.map(lambda a: f"\\+ {a}"),
        inner.map(lambda a: f"call({a})"),
        inner.map(lambda a: f"catch({a}, ball(Z), true)"),
        inner.map(lambda a: f"findall(Z, {a}, Y)"),
    )


def numbered(text: str) -> str:
    """`text` with its fresh variables named in order of appearance (_G2130742 -> _1)."""
    names: dict[str, str] = {}
    return re.sub(r"_G\d+", lambda m: names.setdefault(m.group(), f"_{len(names) + 1}"), text)


def run_all(query: str, stress: bool, clause: str = "") -> tuple[list[str], str]:
    """Every answer of `query`, printed, and how the query ended."""
    kb = KnowledgeBase()
    kb.consult_text(PROGRAM + clause)
    engine = Engine(kb, max_steps=20_000)
    if stress:
        engine.collect_growth = 0
    goal = parse_term(query)
    answers: list[str] = []
    try:
        for b in engine.solve(goal):
            answers.append(numbered(term_to_text(b.resolve_finite(goal))))
            if len(answers) >= 30:
                return answers, "more"
    except PrologError as err:
        return answers, numbered(f"error {term_to_text(err.ball)}")
    except StepLimitExceeded:
        return answers, "step limit"
    return answers, "end"


@settings(max_examples=150, deadline=None)
@given(st.tuples(bodies(3), bodies(2)))
def test_answers_are_the_same_when_a_collection_runs_at_every_step(monkeypatch_poll, parts):
    query = f"({parts[0]}), ({parts[1]})"
    assert run_all(query, stress=True) == run_all(query, stress=False), query


@settings(max_examples=150, deadline=None)
@given(bodies(3))
def test_a_clause_s_own_variables_keep_their_bindings_through_a_collection(monkeypatch_poll, body):
    # X and Z are no query variable here: only the goals and choicepoints reach them
    clause = f"t(Y) :- {body}, L = [Y, Y], member(W, L), (W == Y -> true ; throw(lost(X, Y, Z))).\n"
    assert run_all("t(Y)", True, clause) == run_all("t(Y)", False, clause), clause


@pytest.fixture(scope="module")
def monkeypatch_poll():
    # the machine looks at its trail every _POLL steps: every step here
    saved = machine._POLL
    machine._POLL = 1
    yield
    machine._POLL = saved
