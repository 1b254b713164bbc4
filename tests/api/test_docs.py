"""docs/api.md's examples run, and print what the page says they print."""

from __future__ import annotations

import doctest
import os

from conftest import ROOT


def test_the_api_page_runs_as_written():
    cwd = os.getcwd()
    os.chdir(ROOT)               # the examples name files from the repository's root
    try:
        result = doctest.testfile(str(ROOT / "docs" / "api.md"), module_relative=False,
                                  optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    finally:
        os.chdir(cwd)
    assert result.attempted > 30
    assert result.failed == 0
