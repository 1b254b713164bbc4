"""The Python API under odd arguments: every public call, given any value where any argument
goes, returns or raises a SchemalogError (docs/api.md), never Python's own errors, and writes
nothing but the file it was asked to save (issue 46, section 4; benchmarks/fuzz.py's `api`)."""

from __future__ import annotations

import math
import os
import pickle
import tempfile
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from harness import MIX, Case, Outcome, snapshot
from test_fuzz_cli import profile

import schemalog

pytestmark = pytest.mark.fuzz

ODD = [None, True, False, 0, -1, 1, 2**70, 1.5, math.nan, math.inf, "", "x", "x\x00y", "../../etc/passwd",
       "/dev/zero", "kb/tasks/mix_with_spoon.pl", str(MIX), b"task(t).", [], ["hand.free", 1], {}, {"a": 1},
       object(), Path("nowhere.pl"), "2G", "lots", "-1", "full", "pre", "explicit", "symbolic", "all",
       "hand.free, spoon.taken", "a1(spoon)", "use(spoon)", "task(t).\nschema(t, [], t.done).", "\udcff",
       (1, 2), ("a1(spoon)",)]

# (name, call): what a user writes; `v` is the drawn value, `kb`/`t` a loaded knowledge and task
CALLS = {
    "load": lambda kb, t, v: schemalog.load(v),
    "loads": lambda kb, t, v: schemalog.loads(v),
    "loads-name": lambda kb, t, v: schemalog.loads("task(t).\nschema(t, [], t.done).", name=v),
    "task": lambda kb, t, v: kb.task(v),
    "query": lambda kb, t, v: list(kb.query(v)),
    "query-limit": lambda kb, t, v: list(kb.query("member(X, [a, b])", max_steps=v)),
    "lint": lambda kb, t, v: kb.lint(task=v),
    "compress": lambda kb, t, v: t.compress(v),
    "compress-budget": lambda kb, t, v: t.compress(sympy_budget=v),
    "compress-memory": lambda kb, t, v: t.compress(max_memory=v),
    "verify": lambda kb, t, v: schemalog.verify(t, v),
    "verify-original": lambda kb, t, v: schemalog.verify(v, t.compress()),
    "verify-states": lambda kb, t, v: schemalog.verify(t, t.compress(), states=v),
    "verify-method": lambda kb, t, v: schemalog.verify(t, t.compress(), method=v),
    "verify-max-states": lambda kb, t, v: schemalog.verify(t, t.compress(), max_states=v),
    "verify-sample": lambda kb, t, v: schemalog.verify(t, t.compress(), sample=v),
    "task-verify": lambda kb, t, v: t.verify(v),
    "run-scene": lambda kb, t, v: t.run(scene=v),
    "run-state": lambda kb, t, v: t.run(state=v),
    "run-fail": lambda kb, t, v: t.run(fail=v),
    "run-selector": lambda kb, t, v: t.run(selector=v),
    "run-decisions": lambda kb, t, v: t.run(max_decisions=v),
    "start": lambda kb, t, v: list(t.start(seed=v)),
    "save": lambda kb, t, v: t.save(v),
    "to-btcpp": lambda kb, t, v: t.to_btcpp(v),
    "to-py-trees": lambda kb, t, v: t.to_py_trees(retries=v),
    "pickle": lambda kb, t, v: pickle.loads(pickle.dumps(t.run(state=v))).text(),   # a run sent to a worker
}


@dataclass(frozen=True)
class ApiCase(Case):
    """A public call with one odd argument: its reproducer is Python, not a shell line."""

    call: str = ""
    value: str = ""

    def reproducer(self, limit: int = 4000) -> str:
        return (f"import schemalog; kb = schemalog.load({str(MIX)!r}); t = kb.task()\n"
                f"# {self.call} with the value {self.value[:limit]}")


def probe_api(call, value):
    """Call `call` with `value` in a fresh folder (the save target's): its result, or what it raised."""
    kb = schemalog.load(MIX)
    task = kb.task()
    case = ApiCase(("api", call), call=call, value=repr(value))
    with tempfile.TemporaryDirectory(prefix="schemalog-api-") as tmp:
        cwd = os.getcwd()
        os.chdir(tmp)
        before = snapshot(Path(tmp))
        status, died, err = 0, "", ""
        try:
            CALLS[call](kb, task, value)
        except schemalog.SchemalogError as raised:
            status, err = 1, str(raised)
        except BaseException as raised:          # anything else is what a user would get as a traceback
            if isinstance(raised, KeyboardInterrupt):
                raise
            status, died = None, f"Traceback (most recent call last): {type(raised).__name__}: {raised}"[:300]
        finally:
            os.chdir(cwd)
        made = [n for n, h in snapshot(Path(tmp)).items() if before.get(n) != h
                and not (call == "save" and isinstance(value, (str, Path)) and os.path.normpath(str(value)) == n)]
    return case, Outcome(status, "", err + died, died=died, extra={"made": made})


def api_kept(case, outcome, **_) -> list[str]:
    found = []
    if outcome.died:
        found.append(f"{case.call}: not a SchemalogError: {outcome.died}")
    if outcome.extra.get("made"):
        found.append(f"{case.call}: written outside what the call named: {', '.join(outcome.extra['made'])}")
    return found


API = dict(call=st.sampled_from(sorted(CALLS)), value=st.sampled_from(ODD))


@profile(60)
@given(**API)
def test_the_api_under_odd_arguments(call, value):
    found = api_kept(*probe_api(call, value))
    assert not found, "\n".join(found)


PROBES = {"api": (API, probe_api, api_kept)}
