"""Fixtures the BT.CPP tests share: the real BT.CPP 4.8.2 harness (tests/bt/harness)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

BUILD = Path(__file__).resolve().parent / "harness" / "build.sh"


@pytest.fixture(scope="session")
def harness() -> str:
    """The harness binary, built (or found in the cache) by build.sh; with CI set, a harness that
    cannot be built fails the tests that need it (a skip would hide them)."""
    try:
        done = subprocess.run(["bash", str(BUILD)], capture_output=True, text=True, timeout=1800)
    except (OSError, subprocess.TimeoutExpired) as err:       # pragma: no cover - no bash
        done = None
        why = str(err)
    if done is not None and done.returncode == 0 and done.stdout.strip():
        return done.stdout.strip().splitlines()[-1]
    why = done.stderr[-2000:] if done is not None else why
    if os.environ.get("CI"):
        pytest.fail(f"the BT.CPP harness could not be built (tests/bt/harness/build.sh):\n{why}")
    pytest.skip(f"the BT.CPP harness could not be built (no compiler, cmake or network?): {why[-300:]}")
