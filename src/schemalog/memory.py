"""How close the process is to its memory ceiling, cheaply enough to ask every few thousand steps.

    data_in_use()   -> int | None    the bytes of data and stack the process holds now (Linux:
                                     /proc/self/statm's data field; elsewhere None)
    near_ceiling()  -> bool          within HEADROOM of RLIMIT_DATA's soft limit (a ceiling set)
    data_limits()   -> (soft, hard)  RLIMIT_DATA's limits, None for unlimited or unknown

Why stop *before* the ceiling: at RLIMIT_DATA itself every allocation fails, those Python needs
to raise and handle the MemoryError included, and CPython with glibc's malloc can then spin in
failing mmap calls instead of unwinding (seen: a query under `max_memory="100M"` in a process
already holding 296 MiB, malloc retrying its arenas for minutes). A long computation that looks
here stops while there is still room to say so.
"""

from __future__ import annotations

import os

MIB = 2**20


class CeilingReached(MemoryError):
    """Raised by a computation that found itself near the ceiling: it ends the whole call, as a
    MemoryError at the ceiling would (never turned into a catchable Prolog resource error)."""


def headroom(ceiling: int) -> int:
    """The room kept free below a ceiling: 1/16 of it, at least 16 MiB."""
    return max(16 * MIB, ceiling // 16)


_PAGE = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096
_statm: list[int] = []        # an open descriptor on /proc/self/statm, read with pread


def data_in_use() -> int | None:
    """The process's data and stack in bytes now, None where /proc/self/statm is not there."""
    try:
        if not _statm:
            _statm.append(os.open("/proc/self/statm", os.O_RDONLY | getattr(os, "O_CLOEXEC", 0)))
        fields = os.pread(_statm[0], 128, 0).split()
        return int(fields[5]) * _PAGE
    except (OSError, ValueError, IndexError, AttributeError):
        return None


def data_limits() -> tuple[int | None, int | None]:
    """RLIMIT_DATA's soft and hard limits, each None when unlimited or unknown."""
    try:
        import resource
    except ImportError:
        return None, None
    soft, hard = resource.getrlimit(resource.RLIMIT_DATA)
    return (None if soft == resource.RLIM_INFINITY else soft, None if hard == resource.RLIM_INFINITY else hard)


def ceiling() -> int | None:
    """RLIMIT_DATA's soft limit, None when there is none."""
    return data_limits()[0]


def near_ceiling() -> bool:
    """Whether the process holds more than its ceiling less the headroom (False: no ceiling,
    or no way to tell)."""
    limit = ceiling()
    if limit is None:
        return False
    used = data_in_use()
    return used is not None and used > limit - headroom(limit)
