"""Shared paths and helpers for the tests."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from schemalog.logic.engine import Engine
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import term_to_text

from schemalog.cli.main import tune_gc

# The tests run with the garbage-collector setting the schemalog command uses, so that
# the 100k-behaviour cases measure schemalog, not Python's default GC thresholds.
tune_gc()

ROOT = Path(__file__).resolve().parents[1]
MIX = ROOT / "kb" / "tasks" / "mix_with_spoon.pl"
COFFEE = ROOT / "kb" / "tasks" / "prepare_coffee_and_tea.pl"
SEED_COFFEE = ROOT / "examples" / "coffee_and_tea_seed.prolog"


def ask(program: str, query: str, limit: int | None = 50) -> list[str]:
    """The answers of `query` against `program`, as printed instances of the query."""
    kb = KnowledgeBase()
    kb.consult_text(program)
    return [term_to_text(a) for a in Engine(kb).answers(parse_term(query), limit)]


@pytest.fixture
def kb_of():
    def make(text: str) -> KnowledgeBase:
        kb = KnowledgeBase()
        kb.consult_text(text, "test.pl")
        return kb
    return make


def read_fifo_in_thread(fifo):
    """Start reading `fifo` from a thread; join() and then got[0] is what was read."""
    got = []
    reader = threading.Thread(target=lambda: got.append(open(fifo, "rb").read()), daemon=True)
    reader.start()
    return reader, got
