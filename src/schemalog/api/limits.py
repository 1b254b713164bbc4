"""The process's resource limits: a wall-clock time limit and a memory ceiling, for the
command line (--timeout, --max-memory) and for API calls (timeout=, max_memory=).

    time_limit(seconds)        a context: past `seconds` (None: no limit), TimeLimitExceeded is raised
                               wherever the process is (the engine, sympy, a blocking read)
    memory_ceiling(text, env)  the ceiling in bytes (None: none) from --max-memory, else the
                               environment's SCHEMALOG_MAX_MEMORY, else a fraction of physical memory
    apply_memory_ceiling(n)    set it as the process's RLIMIT_DATA soft limit
    restored_memory_limit()    a context that puts the soft limit back as it was on leaving
                               (main() called in-process, by tests or a host program, leaves
                               no ceiling behind)
    ceiling_in_force()         the soft limit now (None: none): what a message about memory names

The ceiling is RLIMIT_DATA, not RLIMIT_AS: RLIMIT_AS counts address space that is only
reserved, and glibc reserves 64 MiB per thread for its malloc arenas (16 threads with numpy
imported: 1.2 GiB of VmSize for 0.2 GiB of VmData), so a thread pool would hit it long before
memory is short. RLIMIT_DATA counts the memory that can actually be written, large
allocations (mmap) included, and Python raises MemoryError at it.

    within(timeout, max_memory) a context for one API call: both limits set on entry and put back
                               as they were on leaving, what stops the call raised as
                               LimitExceeded (a SchemalogError)

Nothing here loads the engine; signal and resource are built into the interpreter.
"""

from __future__ import annotations

import math
import os
import re
import signal
from fractions import Fraction
from collections.abc import Iterator, Mapping
from contextlib import contextmanager

import threading
import time

from .. import defaults
from ..errors import SchemalogError, UsageError, shown_number

TIMEOUT_EXIT = 124          # as GNU timeout(1) exits


class TimeLimitExceeded(BaseException):
    """--timeout's time ran out. A BaseException, like KeyboardInterrupt, so that no
    `except Exception` swallows it and what cleans up after Ctrl-C cleans up after it."""

    def __init__(self, seconds: float):
        super().__init__(seconds)
        self.seconds = seconds

    def __str__(self) -> str:
        return f"error: time limit of {self.seconds:g} s exceeded (raise it with --timeout)"


@contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise TimeLimitExceeded in the main thread once `seconds` of wall-clock time have passed
    inside the context; disarmed on leaving it, so it never fires after the work is done.

    The process has one ITIMER_REAL timer. One already running (a caller's, or an outer
    time_limit's) is shared, not refused: the context runs under the earlier of the two
    deadlines, an expiry of the caller's timer inside it goes to the caller's handler when it
    falls due (which may raise, and so end the call), and on leaving, the caller's handler and
    timer are put back with what they have left and their interval; an expiry due by then
    (it fell with ours) is delivered at once."""
    if seconds is None or not hasattr(signal, "setitimer"):
        yield
        return
    previous = signal.getsignal(signal.SIGALRM)
    if previous is None:         # a handler set outside Python: signal() could not put it back
        raise UsageError("timeout= needs SIGALRM, and a handler installed outside Python holds it: "
                         "leave timeout= out, or bound the work with max_steps/max_states")
    left, interval = signal.getitimer(signal.ITIMER_REAL)
    now = time.monotonic()
    ours = now + seconds
    theirs = [now + left] if left > 0 else []      # the caller's next expiry, if any
    armed = [True]

    def arm() -> None:
        due = min([ours, *theirs])
        signal.setitimer(signal.ITIMER_REAL, max(due - time.monotonic(), _SOON))

    def expire(signum, frame) -> None:
        if not armed[0]:         # a signal already pending as the context closes does nothing
            return
        now = time.monotonic() + _SLACK
        ours_due = ours <= now
        theirs_due = bool(theirs) and theirs[0] <= now
        if theirs_due:
            # its next expiry; late, a timer skips the periods it missed (one signal)
            theirs[:] = [theirs[0] + interval * math.ceil((now - theirs[0]) / interval + 1e-9)] \
                if interval > 0 else []
        if not ours_due:
            arm()
        if theirs_due or not ours_due:
            # the caller's timer fell due, or a SIGALRM came from kill, not from a timer: the
            # caller's handler gets it now, as it would have (it may raise: the call ends)
            _deliver(previous, signum, frame)
        if ours_due:
            armed[0] = False
            raise TimeLimitExceeded(seconds)

    signal.signal(signal.SIGALRM, expire)
    arm()
    try:
        yield
    finally:
        armed[0] = False
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if theirs:
            # an expiry already due (it fell with ours, or while we closed) comes at once
            signal.setitimer(signal.ITIMER_REAL, max(theirs[0] - time.monotonic(), _SOON), interval)


_SOON = 1e-6       # setitimer's 0 disarms: the shortest time that arms
_SLACK = 1e-3      # an expiry within this of a deadline is that deadline's (the clocks differ)


def _deliver(handler, signum: int, frame) -> None:
    """What the process would have done with the signal under `handler`: call it, ignore the
    signal, or (SIG_DFL, SIGALRM's default) end the process."""
    if callable(handler):
        handler(signum, frame)
    elif handler == signal.SIG_DFL:
        signal.signal(signum, signal.SIG_DFL)
        signal.raise_signal(signum)


_UNITS = {"": 1, "b": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}
# The largest ceiling RLIMIT_DATA takes (a C long): one above it holds as trivially as this one,
# since no process can hold 8 EiB, so a larger ceiling asked for is this one
MAX_CEILING = 2**63 - 1
_OFF = ("off", "none", "unlimited")


def parse_size(text: str, source: str) -> int | None:
    """A size as written on the command line: bytes, or with K, M, G or T (binary units, an
    optional `iB`/`B`); `off` for no ceiling (None). A UsageError naming `source` otherwise."""
    cleaned = text.strip().lower()
    if cleaned in _OFF:
        return None
    found = re.fullmatch(r"([0-9]+(?:\.[0-9]+)?)\s*([kmgt]?)(?:i?b)?", cleaned)
    if not found:
        raise UsageError(f"{source} {shown_number(text)!r} is not a size: write bytes, or e.g. 512M, 4G, or off")
    whole, _, fraction = found.group(1).partition(".")
    # a whole part past 30 digits is past any ceiling, and a fraction past 30 digits below a
    # byte (a float of them is inf or rounded; int() refuses 4,300 digits)
    value = MAX_CEILING if len(whole) > 30 else \
        min(MAX_CEILING, int(Fraction(f"{whole}.{fraction[:30] or 0}") * _UNITS[found.group(2)]))
    if value < defaults.MIN_MEMORY:
        raise UsageError(f"{source} {shown_number(text)!r}: at least {size_text(defaults.MIN_MEMORY)} "
                         f"(Python and the engine need that much to start)")
    return value


def size_text(n: int) -> str:
    """A memory size as users read it: GiB from one GiB up, else MiB."""
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / 2**20:.0f} MiB"


def physical_memory() -> int | None:
    """The machine's physical memory in bytes, when the system says."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def memory_ceiling(option: str | None, environ: Mapping[str, str]) -> int | None:
    """The ceiling asked for: --max-memory, else $SCHEMALOG_MAX_MEMORY, else
    defaults.MEMORY_FRACTION of physical memory; None for none."""
    if option is not None:
        return parse_size(option, "--max-memory")
    if environ.get(defaults.MEMORY_ENV):
        return parse_size(environ[defaults.MEMORY_ENV], defaults.MEMORY_ENV)
    physical = physical_memory()
    if not physical:
        return None
    default = int(physical * defaults.MEMORY_FRACTION)
    hard = _hard_limit()
    return default if hard is None else min(default, hard)    # a default never refused (ulimit -d)


def _hard_limit() -> int | None:
    """RLIMIT_DATA's hard limit, None when unlimited or unknown."""
    from ..memory import data_limits
    return data_limits()[1]


def apply_memory_ceiling(ceiling: int | None) -> int | None:
    """Lower the process's RLIMIT_DATA to `ceiling` (never raise it past the hard limit, never
    above a lower limit already set); return the ceiling in force, None for none."""
    try:
        import resource
    except ImportError:          # not a POSIX system: no ceiling
        return None
    soft, hard = resource.getrlimit(resource.RLIMIT_DATA)
    inherited = None if soft == resource.RLIM_INFINITY else soft
    if ceiling is None:
        return inherited
    if hard != resource.RLIM_INFINITY and ceiling > hard:
        raise UsageError(f"--max-memory {size_text(ceiling)} is above this process's hard limit "
                         f"of {size_text(hard)} (ulimit -d)")
    if inherited is not None and inherited < ceiling:
        return inherited
    resource.setrlimit(resource.RLIMIT_DATA, (ceiling, hard))
    return ceiling


@contextmanager
def restored_memory_limit() -> Iterator[None]:
    """Restore RLIMIT_DATA's soft limit, as it was on entry, when the context closes."""
    try:
        import resource
    except ImportError:
        yield
        return
    before = resource.getrlimit(resource.RLIMIT_DATA)
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_DATA, before)


def ceiling_in_force() -> int | None:
    """The memory ceiling the process runs under now (RLIMIT_DATA's soft limit), None for none:
    --max-memory's, the environment's, the default or an inherited lower one, whichever won."""
    from ..memory import ceiling

    return ceiling()


def out_of_memory_text(ceiling: int | None) -> str:
    """What to say when memory ran out."""
    if ceiling is None:
        return "error: out of memory (the system refused more)"
    return (f"error: out of memory: the {size_text(ceiling)} ceiling was reached (raise it with "
            f"--max-memory or {defaults.MEMORY_ENV}, or set it to off)")


class LimitExceeded(SchemalogError):
    """An API call ran out of the time or the memory it was given: `.limit` says which."""

    def __init__(self, message: str, limit: str) -> None:
        super().__init__(message)
        self.limit = limit


DEFAULT = "default"     # max_memory's default: the command line's (SCHEMALOG_MAX_MEMORY, else half the memory)
_inside = threading.local()


@contextmanager
def governed() -> Iterator[None]:
    """Mark the calls inside as running under limits already set (the command line's
    --timeout and --max-memory): within() with its defaults then adds none."""
    _inside.depth = getattr(_inside, "depth", 0) + 1
    try:
        yield
    finally:
        _inside.depth -= 1


@contextmanager
def within(timeout: float | None = None, max_memory: int | str | None = DEFAULT) -> Iterator[None]:
    """Run one API call under a time limit (seconds; None: none) and a memory ceiling (bytes,
    a size such as '2G', None or 'off' for none, DEFAULT for the command line's), both put
    back as they were when it ends. A call inside another's limits adds none of its own unless
    given some. The time limit is the interval timer's signal: it needs the main thread, and
    shares the timer with one already running (time_limit). The ceiling is the process's: calls in several threads
    share the lowest of theirs, and the last to end puts back what was there before the first."""
    nested = getattr(_inside, "depth", 0) > 0
    if nested and timeout is None and max_memory == DEFAULT:
        yield
        return
    # timeout's and max_memory's types are checked where the API is called (arguments.checked)
    if timeout is not None:
        if not (defaults.MIN_TIMEOUT <= timeout <= defaults.MAX_TIMEOUT):
            raise UsageError(f"timeout={timeout!r}: from {defaults.MIN_TIMEOUT} to {defaults.MAX_TIMEOUT:,} seconds")
        if threading.current_thread() is not threading.main_thread():
            raise UsageError("timeout= needs the main thread (it is a signal): limit the call from there, "
                             "or bound its work with max_steps/max_states")
    if isinstance(max_memory, int):
        ceiling: int | None = min(max_memory, MAX_CEILING)
        if ceiling < defaults.MIN_MEMORY:
            shown = str(max_memory) if max_memory > -10**30 else "-10**30 or less"
            raise UsageError(f"max_memory={shown}: at least {size_text(defaults.MIN_MEMORY)}")
    elif max_memory == DEFAULT:
        ceiling = memory_ceiling(None, os.environ) if not nested else None
    elif max_memory is None:
        ceiling = None
    else:
        ceiling = parse_size(max_memory, "max_memory=")
    hard = _hard_limit()
    if ceiling is not None and hard is not None and ceiling > hard:
        raise UsageError(f"max_memory= {size_text(ceiling)} is above this process's hard limit of "
                         f"{size_text(hard)} (ulimit -d)")
    if ceiling is not None:
        from ..memory import data_in_use, headroom
        used = data_in_use()
        if used is not None and used > ceiling - headroom(ceiling):
            # RLIMIT_DATA is the process's: a ceiling under what it already holds would fail
            # every allocation of the call (memory.py), so the call does not start.
            raise LimitExceeded(f"out of memory: the {size_text(ceiling)} ceiling is below what this process "
                                f"already holds ({size_text(used)} of data, and {size_text(headroom(ceiling))} "
                                f"are kept free); raise max_memory=", "memory")
    _inside.depth = getattr(_inside, "depth", 0) + 1
    _enter_ceiling(ceiling)
    try:
        with time_limit(timeout):
            yield
    except TimeLimitExceeded as stop:
        raise LimitExceeded(f"time limit of {stop.seconds:g} s exceeded (raise it with timeout=)", "time") from None
    except MemoryError:
        raise LimitExceeded(out_of_memory_text(ceiling_in_force()).removeprefix("error: ").replace(
            "--max-memory", "max_memory="), "memory") from None
    finally:
        _leave_ceiling(ceiling)
        _inside.depth -= 1


# The ceilings of the API calls running now, in every thread, and RLIMIT_DATA as it was before
# the first of them: the process has one limit, so the lowest applies and the last call to end
# puts the old one back (a save and restore per call would leave one thread's ceiling behind).
_ceilings: list[int] = []
_before: list = []
_lock = threading.Lock()


def _enter_ceiling(ceiling: int | None) -> None:
    if ceiling is None:
        return
    with _lock:
        if not _ceilings:
            _before[:] = [_rlimit()]
        _ceilings.append(ceiling)
        _set_lowest()


def _leave_ceiling(ceiling: int | None) -> None:
    if ceiling is None:
        return
    with _lock:
        _ceilings.remove(ceiling)
        if _ceilings:
            _set_lowest()
        elif _before and _before[0] is not None:
            import resource

            resource.setrlimit(resource.RLIMIT_DATA, _before[0])


def _rlimit():
    try:
        import resource
    except ImportError:
        return None
    return resource.getrlimit(resource.RLIMIT_DATA)


def _set_lowest() -> None:
    """RLIMIT_DATA's soft limit to the lowest ceiling asked for, never above the one before."""
    before = _before[0] if _before else None
    if before is None:
        return
    import resource

    soft, hard = before
    lowest = min(_ceilings)
    if soft != resource.RLIM_INFINITY:
        lowest = min(lowest, soft)
    resource.setrlimit(resource.RLIMIT_DATA, (lowest, hard))


__all__ = ["LimitExceeded", "within", "governed", "DEFAULT", "TimeLimitExceeded", "TIMEOUT_EXIT", "time_limit", "parse_size", "memory_ceiling",
           "apply_memory_ceiling", "restored_memory_limit", "ceiling_in_force", "out_of_memory_text", "size_text"]
