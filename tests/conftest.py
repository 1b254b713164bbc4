"""Shared paths and helpers for the tests."""

from __future__ import annotations

import signal
import threading
from pathlib import Path

import pytest
from hypothesis import Phase, settings

from schemalog.logic.engine import Engine
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import term_to_text
from schemalog.run.execute import enabled_leaves, replay
from schemalog.run.world import World

from schemalog.cli.main import tune_gc

# The tests run with the garbage-collector setting the schemalog command uses, so that
# the 100k-behaviour cases measure schemalog, not Python's default GC thresholds.
tune_gc()

# Hypothesis's explain phase traces every line a failing property runs again (sys.settrace).
# Over the reader and the writer that turned one failure, found in seconds, into a CI run that
# did not end in 90 minutes (stop 40: test_term_round_trip_with_clause_variable_names). The
# failure and its shrunk example are what a reader of the log needs; the profile loaded (CI's
# included) is kept, without that phase.
settings.register_profile("schemalog", settings(settings.default,
                                                phases=[p for p in Phase if p is not Phase.explain]))
settings.load_profile("schemalog")

# A shell runs a background job with SIGINT ignored, and a child inherits an ignored signal:
# the Ctrl-C tests would then test nothing a user can meet (`.ci/run &` failed them). A
# handler of this process's own resets to the default in every command the tests start.
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def _hangup_ignored(signum, frame) -> None:
    """Under nohup the suite keeps ignoring a hangup, and the commands it starts do not inherit that."""


# nohup starts the suite with SIGHUP ignored, which every command the tests start would inherit:
# the SIGHUP test then saw its command ignore the signal (issue 45). A handler, unlike SIG_IGN, is
# reset to the default in a child; this one ignores the hangup here as nohup meant.
if hasattr(signal, "SIGHUP") and signal.getsignal(signal.SIGHUP) == signal.SIG_IGN:
    signal.signal(signal.SIGHUP, _hangup_ignored)

# tests/example_project is a separate project (its own pyproject.toml and tests), installed and
# run in a fresh virtual environment by tests/testing/test_example_project.py, not collected here
collect_ignore = ["example_project"]

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


# A schemalog process whose writes stop after the first kilobyte and hang: a signal or the time
# limit then arrives during a write (python -c SLOW_WRITE ARGS... runs the command line ARGS).
SLOW_WRITE = """
import sys, time
import schemalog.formats.documents as documents
def slow(handle, text):
    handle.write(text[:1000]); handle.flush(); time.sleep(60)
documents._write_text = slow
sys.argv[0] = "schemalog"
from schemalog.cli.main import run
run()
"""


def wide_task(n: int):
    """A knowledge base with one task, t0, of n sub-tasks in sequence (c0 released by `go`, each
    next by the one before), and its tree: the wide shape of benchmarks/bench_scale.py."""
    from schemalog.task.tree import instantiate

    kb = KnowledgeBase()
    entries = ", ".join(f"(c{i}, {'go' if i == 0 else f'c{i - 1}.done'})" for i in range(n))
    kb.consult_text(f"initial(go).\nschema(t0, [{entries}], t0.done).\n"
                    + "\n".join(f"schema(c{i}, [], c{i}.done)." for i in range(n)), "w.pl")
    return kb, instantiate(kb, parse_term("t0"))


def read_fifo_in_thread(fifo):
    """Start reading `fifo` from a thread; join() and then got[0] is what was read."""
    got = []
    reader = threading.Thread(target=lambda: got.append(open(fifo, "rb").read()), daemon=True)
    reader.start()
    return reader, got


# --- verification: counterexamples replayed as runs --------------------------------

def settled(tree, states):
    world = World(tree)
    found = []
    for atoms in states:
        world.reset(atoms)
        if world.atoms not in found:
            found.append(world.atoms)
    return found


def assert_replays(original, compressed, ce, initial, sound_run=True):
    """A counterexample is a real run: each decision an enabled leaf of the compressed tree
    doing those actions, each action one the original takes (`sound_run`), ending in the
    reported state."""
    assert ce.initial in initial
    world = World(original)
    world.load(ce.initial)
    trace = []
    for step in ce.path:
        leaf = next((n for n in enabled_leaves(compressed, world) if n.label == step.behaviour), None)
        assert leaf is not None, f"{term_to_text(step.behaviour)} is not enabled"
        for label, post in _constituents(leaf):
            if not world.holds(post):
                world.perform(post)
                trace.append(label)
        assert tuple(trace[len(trace) - len(step.actions):]) == step.actions
    if sound_run:
        assert replay(original, ce.initial, trace).valid, "a step before the counterexample is not a run of the original"
    if ce.action is not None:                     # soundness: the original refuses the last action
        leaf = next(n for n in enabled_leaves(compressed, world) if n.label == ce.behaviour)
        done = []
        for label, post in _constituents(leaf):
            if world.holds(post):
                continue
            if label == ce.action:
                break
            world.perform(post)
            done.append(label)
        assert tuple(done) == ce.done_first and world.atoms == ce.state
        result = replay(original, ce.initial, [*trace, *done, ce.action])
        assert not result.valid and result.index == len(trace) + len(done)
    else:
        assert world.atoms == ce.state


def _constituents(leaf):
    return [(o.label, o.post) for o in leaf.origins] if len(leaf.origins) > 1 else \
        [(leaf.origins[0].label if leaf.origins else leaf.label, leaf.post)]


# A task that cannot complete: the gripper closes and opens again forever (verify: vacuous).
GRIPPER = """task(t).
object(cup).
agent(gripper(_), gripper).
initial(hand.free).
schema(t, [(subtask(move, cup), hand.free)], cup.moved).
schema(subtask(move, cup),
       [ (a1(cup), true), (gripper(close), a1.done), (a2(cup), not hand.free), (gripper(open), a2.done) ],
       cup.moved).
schema(a1(cup), [], a1.done).
schema(a2(cup), [], a2.done).
schema(gripper(close), [], not hand.free).
schema(gripper(open), [], hand.free).
"""


# -- the real BT.CPP 4.8.2 harness (tests/bt/harness), shared by the BT.CPP test modules ----------

@pytest.fixture(scope="session")
def harness() -> str:
    """The harness binary, built (or found in the cache) by tests/bt/harness/build.sh; with CI set,
    a harness that cannot be built fails the tests that need it (a skip would hide them)."""
    import os
    import subprocess

    build = Path(__file__).resolve().parent / "bt" / "harness" / "build.sh"
    try:
        done = subprocess.run(["bash", str(build)], capture_output=True, text=True, timeout=1800)
    except (OSError, subprocess.TimeoutExpired) as err:       # pragma: no cover - no bash
        done = None
        why = str(err)
    if done is not None and done.returncode == 0 and done.stdout.strip():
        return done.stdout.strip().splitlines()[-1]
    why = done.stderr[-2000:] if done is not None else why
    if os.environ.get("CI"):
        pytest.fail(f"the BT.CPP harness could not be built (tests/bt/harness/build.sh):\n{why}")
    pytest.skip(f"the BT.CPP harness could not be built (no compiler, cmake or network?): {why[-300:]}")
