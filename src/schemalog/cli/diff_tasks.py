"""`schemalog diff A.pl B.pl`: two versions of a task (schema knowledge), compared on runs."""

from __future__ import annotations

import argparse


def run_tasks(args: argparse.Namespace, fmt: str) -> int:
    """Compare two versions of a task; not written yet for task knowledge."""
    from ..errors import UsageError

    raise UsageError("diff compares BT.CPP trees; for task knowledge use `schemalog verify ORIGINAL COMPRESSED`")
