"""Where schemalog keeps what it can always rebuild: the analysed grammar tables and the
parsed prelude, so that a plain query starts in a fraction of the time.

    cache_file(name) -> str | None                 a path in the user's own cache directory, or None
    remembered(kind, sources, build) -> value      build(), or what it returned last time for
                                                   the same sources (pickled under their hash)

The directory is `$SCHEMALOG_CACHE_DIR`, else `$XDG_CACHE_HOME/schemalog`, else
`~/.cache/schemalog`; `SCHEMALOG_CACHE_DIR=off` turns caching off. What is cached is
loaded with pickle, so a directory that another user could write into is never used:
it must be owned by this user and writable by nobody else. Without a usable directory
nothing is cached and everything still works, only slower to start.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import Callable, TypeVar

T = TypeVar("T")


def cache_dir() -> Path | None:
    """The cache directory, made if missing, or None when there is none this user owns alone."""
    explicit = os.environ.get("SCHEMALOG_CACHE_DIR")
    if explicit is not None and explicit.strip().lower() in ("", "off", "0", "no", "false"):
        return None
    if explicit:
        path = Path(explicit)
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        path = Path(base) / "schemalog"
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
        info = path.stat()
    except OSError:
        return None
    if not stat.S_ISDIR(info.st_mode) or info.st_mode & 0o022:
        return None
    if hasattr(os, "getuid") and info.st_uid != os.getuid():
        return None
    return path if os.access(path, os.W_OK) else None


def cache_file(name: str) -> str | None:
    """The path to cache `name` at, or None when nothing may be cached."""
    directory = cache_dir()
    return None if directory is None else str(directory / name)


def remembered(kind: str, sources: list[str], build: Callable[[], T]) -> T:
    """What `build()` returns, kept under a hash of `sources` (the texts it depends on, the
    code that reads them included): a changed source is a new name, an old file is ignored."""
    import hashlib  # here, not at the top: a command that caches nothing does not pay for them
    import pickle
    import tempfile

    digest = hashlib.sha256("\0".join(sources).encode("utf-8", "surrogatepass")).hexdigest()[:24]
    path = cache_file(f"{kind}-{digest}.pickle")
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
