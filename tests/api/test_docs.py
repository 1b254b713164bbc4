"""docs/api.md's and docs/testing.md's examples run, and print what the pages say they print."""

from __future__ import annotations

import doctest
import os

from conftest import ROOT


def run_page(name: str) -> doctest.TestResults:
    cwd = os.getcwd()
    os.chdir(ROOT)               # the examples name files from the repository's root
    try:
        return doctest.testfile(str(ROOT / "docs" / name), module_relative=False,
                                optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    finally:
        os.chdir(cwd)


def test_the_api_page_runs_as_written():
    result = run_page("api.md")
    assert result.attempted > 30
    assert result.failed == 0


def test_the_testing_pages_tree_examples_run_as_written():
    result = run_page("testing.md")
    assert result.attempted >= 6          # the BT.CPP assertions' examples: a proof, a refutation, a limit
    assert result.failed == 0
