"""Terms over a declared operator table, written by schemalog and read back by both systems.

programs/operators.pl declares user operators of every class (`my_ins` xfx 700, `fact` xf 200,
`nicht` fy 900, `++` yfx 650, `===>` xfy 710). A random term over those and the standard
operators (`-` both ways, `+`, `*`, `=`, `:`, `^`, `,`, `;`, `\\+`), with negative numbers and
operator atoms as operands, is written with writeq/1 by schemalog; that text must read back
as the same term in schemalog (every example, no swipl needed), and in swipl too: one swipl
batch per example reads each text and writes it with write_canonical/1, which schemalog must
match (derandomized, as test_fuzz_iso.py; SCHEMALOG_FUZZ_EXAMPLES=50 draws fresh ones).

Left out, as documented deviations (docs/syntax.md): `not`, `and`, `or` and the `.` operator,
and `[]` as an operand.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings, strategies as st

from test_conformance import record
from test_fuzz_iso import differences

from schemalog.formats.documents import document_from_text
from schemalog.logic.opread import parse_term
from schemalog.logic.terms import Atom, Int, Struct, term_to_text

PROGRAM = "operators.pl"
_KB = document_from_text((record.PROGRAMS / PROGRAM).read_text(encoding="utf-8"),
                         str(record.PROGRAMS / PROGRAM)).to_kb()
OPS = _KB.operators

INFIX = ["my_ins", "++", "===>", "-", "+", "*", "=", ":", "^", ",", ";"]
PREFIX = ["nicht", "-", "\\+", "+"]
POSTFIX = ["fact"]
LEAVES = [Atom("a"), Atom("b"), Atom("my_ins"), Atom("nicht"), Atom("fact"), Atom("-"), Atom("++"),
          Int(0), Int(1), Int(-1), Int(-25), Atom("A b"), Atom("{}")]


@st.composite
def terms(draw, depth: int = 4):
    kind = draw(st.sampled_from(["leaf", "infix", "infix", "prefix", "postfix", "functional", "list", "curly"])) \
        if depth else "leaf"
    sub = lambda: draw(terms(depth - 1))  # noqa: E731
    if kind == "leaf":
        return draw(st.sampled_from(LEAVES))
    if kind == "infix":
        return Struct(draw(st.sampled_from(INFIX)), (sub(), sub()))
    if kind == "prefix":
        return Struct(draw(st.sampled_from(PREFIX)), (sub(),))
    if kind == "postfix":
        return Struct(draw(st.sampled_from(POSTFIX)), (sub(),))
    if kind == "functional":
        name = draw(st.sampled_from(["f", "my_ins", "nicht", "-", "=..", ";", "{}"]))
        return Struct(name, tuple(sub() for _ in range(draw(st.integers(1, 3)))))
    if kind == "list":
        return Struct("[|]", (sub(), Struct("[|]", (sub(), Atom("[]")))))
    return Struct("{}", (sub(),))


def written(term) -> str:
    return term_to_text(term, ops=OPS.view())


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(terms())
def test_writeq_reads_back_under_the_declared_operators(term):
    text = written(term)
    assert parse_term(text, "<t>", OPS) == term, text


@pytest.fixture(scope="module")
def swipl() -> str:
    path = record.swipl_path()
    if path is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but swipl is not on PATH: the operator terms cannot be checked")
        pytest.skip("swipl is not on PATH: the operator terms need it")
    return path


EXAMPLES = int(os.environ.get("SCHEMALOG_FUZZ_EXAMPLES", "0"))
LIVE = settings(max_examples=EXAMPLES or 3, derandomize=not EXAMPLES, deadline=None, phases=[Phase.generate],
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


@LIVE
@given(st.lists(terms(), min_size=100, max_size=100))
def test_swipl_reads_what_schemalog_writes(swipl, batch):
    queries = [f"X = ({written(t)}), write_canonical(X), nl" for t in batch]
    differing = differences(PROGRAM, queries, swipl)
    assert not differing, f"{len(differing)} of {len(queries)} terms differ:\n" + "\n".join(differing)
