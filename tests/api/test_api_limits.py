"""The limits a user names on an API call (timeout=, max_memory=) hold, and leave nothing behind."""

from __future__ import annotations

import resource
import signal
import threading
import time
from types import SimpleNamespace

import pytest

import schemalog
from conftest import COFFEE


def test_a_timeout_stops_a_proof_and_the_process_is_as_before():
    before = (signal.getsignal(signal.SIGALRM), signal.getitimer(signal.ITIMER_REAL),
              resource.getrlimit(resource.RLIMIT_DATA))
    task = schemalog.load(COFFEE).task()
    with pytest.raises(schemalog.LimitExceeded, match=r"time limit of 0.01 s exceeded") as err:
        schemalog.verify(task, task.compress(), method="explicit", states="all", timeout=0.01)
    assert err.value.limit == "time" and isinstance(err.value, schemalog.SchemalogError)
    assert (signal.getsignal(signal.SIGALRM), signal.getitimer(signal.ITIMER_REAL),
            resource.getrlimit(resource.RLIMIT_DATA)) == before
    assert schemalog.verify(task, task.compress(), timeout=600).proved    # the limit is per call


def test_a_query_that_loops_stops_at_its_timeout():
    kb = schemalog.loads("loop :- loop.\n")
    with pytest.raises(schemalog.LimitExceeded, match="time limit of 0.2 s"):
        list(kb.query("loop", timeout=0.2, max_steps=10**12))


def test_a_memory_ceiling_stops_a_query_and_is_lifted_after():
    before = resource.getrlimit(resource.RLIMIT_DATA)
    kb = schemalog.loads("fact.\n")
    with pytest.raises(schemalog.LimitExceeded, match="out of memory: the 100 MiB ceiling") as err:
        list(kb.query("numlist(1, 10000000, L), length(L, N)", max_memory="100M", max_steps=10**9))
    assert err.value.limit == "memory"
    assert resource.getrlimit(resource.RLIMIT_DATA) == before


@pytest.fixture
def your_timer():
    """A SIGALRM handler of the caller's, as a program of yours installs one: `.fired` holds
    the signals it got; set the timer with signal.setitimer. Both are stopped after the test."""
    timer = SimpleNamespace(fired=[])
    timer.handler = lambda signum, frame: timer.fired.append(signum)
    previous = signal.signal(signal.SIGALRM, timer.handler)
    yield timer
    signal.setitimer(signal.ITIMER_REAL, 0)
    signal.signal(signal.SIGALRM, previous)


def test_a_timeout_under_a_timer_of_yours_leaves_it_as_it_was(your_timer):
    """kb.query("true", timeout=5) was a UsageError while a timer of the caller ran (issue 46);
    docs/api.md says that timer goes on afterwards with what it had left."""
    signal.setitimer(signal.ITIMER_REAL, 30, 0.5)
    kb = schemalog.load(COFFEE, timeout=5)
    assert list(kb.query("true", timeout=5)) == [{}]
    with pytest.raises(schemalog.LimitExceeded, match="time limit of 0.2 s"):
        list(schemalog.loads("loop :- loop.\n").query("loop", timeout=0.2, max_steps=10**12))
    left, interval = signal.getitimer(signal.ITIMER_REAL)
    assert 25 < left <= 30 and interval == 0.5 and not your_timer.fired
    assert signal.getsignal(signal.SIGALRM) is your_timer.handler


def test_your_timer_expiring_during_a_call_reaches_your_handler_then_and_after(your_timer):
    signal.setitimer(signal.ITIMER_REAL, 0.02, 0.02)     # every 20 ms, through a call stopped at 300 ms
    with pytest.raises(schemalog.LimitExceeded, match="time limit of 0.3 s"):
        list(schemalog.loads("loop :- loop.\n").query("loop", timeout=0.3, max_steps=10**12))
    during = len(your_timer.fired)
    assert during >= 1
    assert signal.getitimer(signal.ITIMER_REAL)[1] == 0.02 and signal.getsignal(signal.SIGALRM) is your_timer.handler
    time.sleep(0.5)                         # and it goes on ticking after the call
    assert len(your_timer.fired) > during


def test_your_deadline_before_the_calls_ends_the_call_with_your_exception(your_timer):
    class YourDeadline(Exception):
        pass

    def give_up(signum, frame):
        raise YourDeadline

    signal.signal(signal.SIGALRM, give_up)
    signal.setitimer(signal.ITIMER_REAL, 0.1)
    with pytest.raises(YourDeadline):
        list(schemalog.loads("loop :- loop.\n").query("loop", timeout=600, max_steps=10**12))
    assert signal.getsignal(signal.SIGALRM) is give_up and signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    schemalog.load(COFFEE)                         # without timeout=, no timer is needed


def test_ceilings_of_calls_in_threads_are_all_lifted_after():
    before = resource.getrlimit(resource.RLIMIT_DATA)
    task = schemalog.load(COFFEE).task()
    workers = [threading.Thread(target=task.compress, kwargs={"max_memory": f"{n}G"}) for n in (1, 2, 3) * 2]
    workers.append(threading.Thread(target=task.compress))     # the default ceiling too
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert resource.getrlimit(resource.RLIMIT_DATA) == before


def test_the_default_ceiling_stays_under_a_hard_limit():
    # ulimit -d below half the memory (CI containers, HPC jobs): the default is capped, never refused
    import subprocess
    import sys

    code = ("import resource, schemalog\n"
            "resource.setrlimit(resource.RLIMIT_DATA, (2**31, 2**31))\n"
            "print(len(schemalog.load('kb/tasks/mix_with_spoon.pl').task().compress()))\n")
    from conftest import ROOT

    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert (out.returncode, out.stdout, out.stderr) == (0, "6\n", "")
    cli = subprocess.run(["bash", "-c", "ulimit -d 2097152 && python -m schemalog check kb/tasks/mix_with_spoon.pl"],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert cli.returncode == 0, cli.stderr


def test_bad_limits_are_usage_errors():
    task = schemalog.load(COFFEE).task()
    with pytest.raises(schemalog.UsageError, match="timeout"):
        task.compress(timeout=-1)
    with pytest.raises(schemalog.UsageError, match="not a size"):
        task.compress(max_memory="lots")
    with pytest.raises(schemalog.UsageError, match="a number of seconds"):
        task.compress(timeout="5")
    errors = []

    def in_a_thread():
        try:
            task.compress(timeout=5)
        except schemalog.UsageError as err:
            errors.append(str(err))

    worker = threading.Thread(target=in_a_thread)
    worker.start()
    worker.join()
    assert errors and "main thread" in errors[0]
    task.compress()                     # without a timeout, any thread may call (no signal)


def test_a_ceiling_past_what_the_system_takes_is_the_largest_it_takes():
    """max_memory=10**30 raised OverflowError, and `--max-memory 999999999T` was "a number is too
    large to process" (issue 46): no process can hold that much, so it is the largest ceiling
    RLIMIT_DATA takes, which holds as trivially."""
    import resource

    from schemalog.api.limits import MAX_CEILING, parse_size

    task = schemalog.load(COFFEE).task()
    before = resource.getrlimit(resource.RLIMIT_DATA)
    assert len(task.compress(max_memory=10**30)) == 33
    assert resource.getrlimit(resource.RLIMIT_DATA) == before
    assert parse_size("999999999T", "--max-memory") == parse_size("9" * 5000, "--max-memory") == MAX_CEILING
    assert parse_size("1.5G", "--max-memory") == 3 * 2**29
    assert parse_size("100." + "0" * 5000 + "1M", "--max-memory") == 100 * 2**20     # a fraction of a byte
    with pytest.raises(schemalog.UsageError, match="at least 64 MiB"):
        parse_size("1." + "0" * 40 + "1", "--max-memory")                             # 1 byte, not 8 EiB
    with pytest.raises(schemalog.UsageError, match=r"max_memory=-10\*\*30 or less: at least"):
        task.compress(max_memory=-10**40)


def test_a_ceiling_under_what_the_process_already_holds_stops_the_call_at_once():
    """RLIMIT_DATA is the process's: a long-lived process (a notebook, this test run) may hold
    more than the ceiling a call asks for. Then every allocation would fail, and CPython can
    spin in failing mallocs instead of raising (seen: minutes in mmap); the call does not start."""
    from schemalog.memory import data_in_use
    before = resource.getrlimit(resource.RLIMIT_DATA)
    ballast = [bytearray(2**20) for _ in range(160)]        # 160 MiB held, over a 100 MiB ceiling
    assert data_in_use() > 160 * 2**20
    kb = schemalog.loads("fact.\n")
    started = time.monotonic()
    with pytest.raises(schemalog.LimitExceeded, match="the 100 MiB ceiling is below what this process already holds"):
        list(kb.query("numlist(1, 10000000, L), length(L, N)", max_memory="100M", max_steps=10**9))
    assert time.monotonic() - started < 5 and resource.getrlimit(resource.RLIMIT_DATA) == before
    del ballast


def test_a_findall_over_a_built_ins_endless_solutions_stops_at_its_limits():
    """findall(X, between(1, inf, X), L) runs no goal between two solutions of between/3; each
    solution is a step, where the step limit and the memory ceiling are looked at. Before, it
    ran to the real ceiling, and there answered a list of unbound variables (found in review)."""
    kb = schemalog.loads("fact.\n")
    goal = "catch(findall(X, between(1, inf, X), L), E, true)"
    with pytest.raises(schemalog.LimitExceeded) as err:
        list(kb.query(goal, max_memory="64M", max_steps=10**10))
    assert err.value.limit == "memory"
    with pytest.raises(schemalog.SchemalogError, match="step limit of 100,000"):
        list(kb.query(goal, max_steps=100_000))
