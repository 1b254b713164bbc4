"""The example project's code: its robot tasks, compressed with schemalog's public API."""

from __future__ import annotations

import os

import schemalog


def compressed(path: str | os.PathLike, propagate: str = "full") -> schemalog.Task:
    """The first task of the task file at `path`, compressed: what this project runs on its robot."""
    return schemalog.load(os.fspath(path)).task().compress(propagate=propagate)
