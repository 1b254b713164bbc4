"""memory.py: how close the process is to its ceiling, asked by the engine every ~2,048 steps."""

import resource
import subprocess
import sys

import pytest

from schemalog import memory


def test_data_in_use_grows_with_what_the_process_holds():
    """In a fresh interpreter: a process that has held and freed much (the whole suite before
    this test) lets malloc serve 64 MiB from heap it already counts, and nothing grows."""
    script = (
        "from schemalog import memory\n"
        "before = memory.data_in_use()\n"
        "ballast = bytearray(64 * 2**20)\n"
        "ballast[::4096] = b'x' * len(ballast[::4096])\n"
        "print(memory.data_in_use() - before)\n")
    grown = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                           check=True).stdout
    assert int(grown) >= 60 * 2**20


def test_the_headroom_is_a_sixteenth_and_at_least_16_mib():
    assert memory.headroom(100 * 2**20) == 16 * 2**20
    assert memory.headroom(2**30) == 64 * 2**20


@pytest.mark.parametrize("above", [0, 8, 64])
def test_near_ceiling_within_the_headroom_and_not_below_it(above):
    soft, hard = resource.getrlimit(resource.RLIMIT_DATA)
    used = memory.data_in_use()
    ceiling = used + 40 * 2**20 + above * 2**20 if above else used + 8 * 2**20
    try:
        resource.setrlimit(resource.RLIMIT_DATA, (ceiling, hard))
        assert memory.near_ceiling() == (ceiling - used <= memory.headroom(ceiling))
    finally:
        resource.setrlimit(resource.RLIMIT_DATA, (soft, hard))
    assert not memory.near_ceiling() or soft != resource.RLIM_INFINITY


def test_the_engine_stops_a_query_near_the_ceiling_and_a_catch_does_not_take_it():
    """A query that builds without end under a ceiling 80 MiB above what the process holds stops
    with CeilingReached (a MemoryError: the call's LimitExceeded) before the ceiling itself,
    and catch/3 does not catch it (it ends the call, as a MemoryError at the ceiling would)."""
    import schemalog
    kb = schemalog.loads("grow(L) :- numlist(1, 100000000, L).\n")
    ceiling = memory.data_in_use() + 80 * 2**20
    for goal in ("grow(L)", "catch(grow(L), _, true)"):
        with pytest.raises(schemalog.LimitExceeded) as err:
            list(kb.query(goal, max_memory=ceiling, max_steps=10**10))
        assert err.value.limit == "memory"
