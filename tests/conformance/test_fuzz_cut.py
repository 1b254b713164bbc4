"""Cuts placed through variables, answered by schemalog and by SWI-Prolog 9 in one batch (issue 37).

A goal term is turned into a body when call/1 runs it (and findall/3, forall/2, \\+, catch/3,
which call it): a variable bound by then is its value there, so a `!` it holds cuts the call's own
alternatives, and one still unbound is call(V), whose cut is local. Each example is a list of
queries whose bodies nest `,` `;` `->` `\\+` call/1 and findall/3 around member/2 and p/1 goals,
with the cut written as `!` or as a variable C bound to `!` before the call, inside it, or never;
swipl runs the list through driver.pl and schemalog must give the same answers and ending for
each. Derandomized as test_fuzz_iso.py is; SCHEMALOG_FUZZ_EXAMPLES=50 draws fresh examples.
"""

from __future__ import annotations

from hypothesis import given, strategies as st

from test_fuzz_iso import LIVE, differences, swipl  # noqa: F401 (swipl: the live swipl fixture)

PROGRAM = "cut_through.pl"

LEAVES = ["p(X)", "p(Y)", "member(Y, [a, b])", "true", "fail", "C", "C", "!", "X = 1"]


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
        st.tuples(inner, inner).map(lambda ab: f"({ab[0]} -> {ab[1]})"),
        inner.map(lambda a: f"\\+ {a}"),
        inner.map(lambda a: f"call({a})"),
        inner.map(lambda a: f"findall(Z, {a}, _)"),
    )


@st.composite
def queries(draw) -> str:
    body = draw(bodies(3))
    where = draw(st.sampled_from(["before", "inside", "through s/2", "never"]))
    if where == "inside":
        body = f"(C = !, {body})"
    call = draw(st.sampled_from(["call({})", "{}", "forall({}, true)", "catch({}, E, true)"]))
    query = f"findall(X-Y, {call.format(body)}, L)"
    if where == "before":
        return f"C = !, {query}"
    if where == "through s/2":
        return f"s(C, !), {query}"
    return query


@LIVE
@given(st.lists(queries(), min_size=120, max_size=120))
def test_cuts_through_variables_answer_as_swipl_does(swipl, cases):
    differing = differences(PROGRAM, cases, swipl)
    assert not differing, f"{len(differing)} of {len(cases)} queries differ:\n" + "\n".join(differing)
