"""Random ISO built-in calls, answered by schemalog and by SWI-Prolog 9 in one batch.

Each example is a list of calls of ISO built-ins (text, term construction and
inspection, comparison, sorting, clause/2, op/3, retract/1...) with arguments drawn
from a pool of awkward terms: unbound variables, partial and improper lists, code and
char lists, strings, floats, a big integer, operators and control constructs. swipl
runs the whole list through driver.pl (one process, each call inside snapshot/1) and
schemalog must give the same answers, ending and output for every call: a wrong success,
a silent failure or another error term shows here as a differing call.

The pool leaves out what docs/queries.md documents as deliberate differences: `[]`
(an atom here, a reserved symbol in SWI-Prolog 7) and integers past 64 bits where
swipl answers representation_error. No shrinking: each example costs one swipl run,
and the failure lists every differing call. The examples are the same on every run
(derandomized), so CI does not flake on a new corner; SCHEMALOG_FUZZ_EXAMPLES=50 draws
that many fresh ones, the way to hunt for more.
"""

from __future__ import annotations

import os

import pytest
from hypothesis import HealthCheck, Phase, given, settings, strategies as st

from test_conformance import record, run_schemalog

PROGRAM = "iso_terms.pl"

PREDICATES = {
    "atom_length": 2, "atom_chars": 2, "atom_codes": 2, "char_code": 2, "number_codes": 2,
    "number_chars": 2, "atom_concat": 3, "sub_atom": 5, "functor": 3, "arg": 3, "=..": 2,
    "copy_term": 2, "compare": 3, "msort": 2, "sort": 2, "keysort": 2, "length": 2,
    "clause": 2, "current_op": 3, "op": 3, "retract": 1, "plus": 3, "between": 3,
    "unify_with_occurs_check": 2, "==": 2, "@<": 2, "atom": 1, "callable": 1, "is_list": 1,
}

LEAVES = ["_", "X", "Y", "a", "ab", "''", "'1'", "' '", "0", "1", "-1", "3", "2.5", "-0.0",
          '"s"', '"12"', '" 3"', "f(a)", "f(X)", "[a]", "[a,b]", "[a|_]", "[0'a]", "[0'1, 0'2]",
          "['1']", "[a-1, b-2]", "[X|Y]", "[a|b]", "xfx", "fy", "700", "1201", "p(_)", "p/1",
          "foo/0", "q", "(a;b)", "(a:-b)", "true", "fail", "X^p(X)"]

leaf = st.sampled_from(LEAVES)
argument = st.one_of(leaf, st.tuples(leaf, leaf).map(lambda ab: f"f({ab[0]}, {ab[1]})"))


@st.composite
def calls(draw) -> str:
    name = draw(st.sampled_from(sorted(PREDICATES)))
    args = ", ".join(draw(argument) for _ in range(PREDICATES[name]))
    functor = "'=..'" if name == "=.." else name if name[0].isalpha() else f"'{name}'"
    return f"{functor}({args})"


@pytest.fixture(scope="module")
def swipl() -> str:
    path = record.swipl_path()
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but swipl is not on PATH: the random calls cannot be checked")
        pytest.skip("swipl is not on PATH: the random ISO calls need it")
    return path


EXAMPLES = int(os.environ.get("SCHEMALOG_FUZZ_EXAMPLES", "0"))
# Three examples, the same on every run, unless SCHEMALOG_FUZZ_EXAMPLES asks for fresh ones.
LIVE = settings(max_examples=EXAMPLES or 3, derandomize=not EXAMPLES, deadline=None, phases=[Phase.generate],
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


@LIVE
@given(st.lists(calls(), min_size=150, max_size=150))
def test_random_iso_calls_answer_as_swipl_does(swipl, queries):
    differing = differences(PROGRAM, queries, swipl)
    assert not differing, f"{len(differing)} of {len(queries)} calls differ:\n" + "\n".join(differing)


def differences(program: str, queries: list[str], swipl: str) -> list[str]:
    """Run `queries` against `program` in one swipl batch and in schemalog: each that differs."""
    cases = [record.Case(f"live-{i}", program, q) for i, q in enumerate(queries)]
    theirs = record.run_program(program, cases, swipl)
    differing = []
    for case, expected in zip(cases, theirs):
        expected = {k: expected[k] for k in ("answers", "end", "output")}
        ours = run_schemalog(program, case.query)
        if ours != expected:
            differing.append(f"?- {case.query}\n  swipl:     {expected}\n  schemalog: {ours}")
    return differing
