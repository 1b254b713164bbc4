"""Where schemalog keeps what it can always rebuild: the analysed grammar tables and the
parsed prelude, so that a plain query starts in a fraction of the time.

    cache_file(kind, sources, suffix) -> str | None   a path named by a hash of `sources` in the
                                                      user's own cache directory, or None
    remembered(kind, sources, build) -> value         build(), or what it returned last time for
                                                      the same sources (pickled under their hash)

The directory is `$SCHEMALOG_CACHE_DIR`, else `$XDG_CACHE_HOME/schemalog`, else
`~/.cache/schemalog`; `SCHEMALOG_CACHE_DIR=off` turns caching off. It is made only inside a
directory that exists (a missing HOME is not created). What is cached is loaded with pickle,
so a directory that another user could write into, or replace, is never used: it and its
parent must belong to this user (or root) and be writable by nobody else (a parent such as
/tmp, whose sticky bit keeps others from renaming what is not theirs, will do). An entry is named
by a hash of everything it was made from, so a changed grammar or reader is a new name; the
entries of other versions are removed when a new one is written. Without a usable directory
nothing is cached and everything still works, only slower to start.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import Callable, TypeVar

T = TypeVar("T")


def _private(path: Path) -> bool:
    """Whether `path` is a directory only this user (or root) can change."""
    try:
        info = path.stat()
    except OSError:
        return False
    owners = {0, os.getuid()} if hasattr(os, "getuid") else None
    return (stat.S_ISDIR(info.st_mode) and not info.st_mode & 0o022
            and (owners is None or info.st_uid in owners))


def _sticky(path: Path) -> bool:
    """Whether `path` is a shared directory like /tmp, where only an entry's owner may
    rename or remove it (the sticky bit)."""
    try:
        return bool(path.stat().st_mode & stat.S_ISVTX)
    except OSError:
        return False


def cache_dir() -> Path | None:
    """The cache directory, made if missing, or None when there is none this user owns alone."""
    explicit = os.environ.get("SCHEMALOG_CACHE_DIR")
    if explicit is not None and explicit.strip().lower() in ("", "off", "0", "no", "false"):
        return None
    if explicit:
        path = Path(explicit).absolute()
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        path = Path(base).absolute() / "schemalog"
    anchor = path.parent if explicit else path.parent.parent   # HOME, or what holds the cache
    if not anchor.is_dir():
        return None
    try:
        for missing in [p for p in (path.parent, path) if not p.exists()]:   # outer first
            missing.mkdir(mode=0o700)
    except OSError:
        return None
    if not (_private(path) and (_private(path.parent) or _sticky(path.parent))):
        return None
    return path if os.access(path, os.W_OK) else None


def _digest(sources: list[str]) -> str:
    import hashlib  # here, not at the top: a command that caches nothing does not pay for it

    return hashlib.sha256("\0".join(sources).encode("utf-8", "surrogatepass")).hexdigest()[:24]


def cache_file(kind: str, sources: list[str], suffix: str) -> str | None:
    """The path to cache what `sources` make at, or None when nothing may be cached; when
    there is no entry for these sources yet, the entries of this kind for others go."""
    directory = cache_dir()
    if directory is None:
        return None
    path = directory / f"{kind}-{_digest(sources)}{suffix}"
    if not path.exists():
        for stale in directory.glob(f"{kind}-*{suffix}"):
            try:
                stale.unlink()
            except OSError:
                pass
    return str(path)


def remembered(kind: str, sources: list[str], build: Callable[[], T]) -> T:
    """What `build()` returns, kept under a hash of `sources` (the texts it depends on, the
    code that reads them included): a changed source is a new name, an old file is ignored."""
    import pickle
    import tempfile

    path = cache_file(kind, sources, ".pickle")
    if path is not None:
        try:
            with open(path, "rb") as f:
                return pickle.load(f)
        except Exception:  # missing, torn by a concurrent writer, or from another Python: rebuild
            pass
    value = build()
    if path is not None:
        try:
            fd, temporary = tempfile.mkstemp(prefix=f".{kind}-", dir=os.path.dirname(path))
            try:
                with os.fdopen(fd, "wb") as f:
                    pickle.dump(value, f, protocol=pickle.HIGHEST_PROTOCOL)
                os.replace(temporary, path)
            finally:
                if os.path.exists(temporary):
                    os.unlink(temporary)
        except (OSError, pickle.PicklingError, RecursionError):
            pass
    return value
