"""The classic benchmark programs (benchmarks/classic/*.pl) give swipl's answers here.

The answer check of `python benchmarks/bench_classic.py --smoke`, one test per program; no
timing (benchmarks/README.md has the timings). A program listed as not loadable yet must
still fail to load, so the list is kept true when the reader learns its syntax."""

from __future__ import annotations

import importlib.util
import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("bench_classic", ROOT / "benchmarks" / "bench_classic.py")
bench_classic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench_classic)

PROGRAMS = sorted((ROOT / "benchmarks" / "classic").glob("*.pl"))


def _swipl() -> str:
    swipl = shutil.which("swipl")
    if swipl is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but swipl is not on PATH: the classic programs' answers cannot be checked")
        pytest.skip("swipl is not installed: the classic programs' answers are swipl's")
    return swipl


def test_the_suite_is_there():
    assert len(PROGRAMS) >= 20
    assert set(bench_classic.NOT_LOADABLE) <= {p.stem for p in PROGRAMS}


@pytest.mark.parametrize("program", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_classic_program_answers_as_swipl_does(program):
    assert bench_classic.smoke(_swipl(), [program]) == []


def test_canonical_form_is_swipls():
    from schemalog.logic.parse import parse_term
    term = parse_term("f([a, 'B'|c], 1 + 2, 'hello world', [], -(1), not(p), and, 'don''t', x - -1)")
    assert bench_classic.canonical(term) == \
        "f([a,'B'|c],+(1,2),'hello world',[],-(1),not(p),and,'don\\'t',-(x,-1))"
