"""How a Task, a Report and a Run show themselves in a notebook (api/notebook.py).

With Graphviz's `dot` on PATH, a Task is an SVG (and no HTML, which notebooks would prefer to
it), a Report and a Run HTML with the picture inside and an SVG; without it (PATH emptied here),
text only. With CI set, a missing `dot` fails the picture tests; elsewhere they skip.
"""

from __future__ import annotations

import base64
import os
import re
import shutil
import subprocess
import sys

import pytest

import schemalog
from schemalog.api import notebook

from conftest import COFFEE, MIX, ROOT

KITCHEN = ROOT / "kb" / "scenes" / "kitchen.yaml"
SPOON_SCENE = ROOT / "kb" / "scenes" / "mix_with_spoon.yaml"


@pytest.fixture
def dot():
    if shutil.which("dot") is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but Graphviz's dot is not on PATH (apt-get install graphviz)")
        pytest.skip("Graphviz's dot is not installed")


@pytest.fixture
def no_dot(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))      # an empty directory: no `dot` to find
    assert shutil.which("dot") is None


@pytest.fixture(scope="module")
def spoon():
    return schemalog.load(MIX).task()


@pytest.fixture(scope="module")
def both():
    return schemalog.load(COFFEE).task("prepareboth")


def width(svg: str) -> float:
    return float(re.search(r'<svg width="([\d.]+)pt"', svg).group(1))


def texts(svg: str) -> str:
    """The words an SVG shows, in one string."""
    return " ".join(re.findall(r"<text[^>]*>([^<]*)</text>", svg)).replace("&#45;", "-")


# -- with Graphviz ------------------------------------------------------------------------
def test_a_task_is_its_tree_drawn_to_a_notebooks_width(dot, spoon):
    svg = spoon._repr_svg_()
    assert svg.lstrip().startswith("<?xml") and "<svg" in svg
    words = texts(svg)
    assert "use(spoon): 12 behaviours, depth 3" in words and "a1(spoon)" in words and "Legend" in words
    assert width(svg) <= notebook.NOTEBOOK_POINTS
    assert spoon._repr_html_() is None      # else a notebook would show the HTML, not the picture


def test_a_compressed_task_is_drawn_beside_its_original_when_both_fit(dot, spoon):
    svg = spoon.compress()._repr_svg_()
    words = texts(svg)
    assert "12 behaviours" in words and "6 behaviours from 12" in words and "no perceptual aliasing" in words
    assert "a1_a2(spoon)" in words and "a1(spoon)" in words
    assert width(svg) <= notebook.NOTEBOOK_POINTS


def test_a_large_compressed_task_is_drawn_alone_its_aliased_behaviours_marked(dot, both):
    svg = both.compress("none")._repr_svg_()
    words = texts(svg)
    assert "33 behaviours from 63" in words and "aliased" in words
    assert "original: 63 behaviours" not in words       # side by side would not fit a notebook


def test_a_proof_shows_its_text_and_no_picture(dot, spoon):
    report = schemalog.verify(spoon, spoon.compress())
    assert report._repr_svg_() is None
    page = report._repr_html_()
    assert "proved" in page and "sound and complete" in page and "<img" not in page


def test_a_counterexample_is_numbered_on_the_compressed_tree(dot, both):
    report = schemalog.verify(both, both.compress("pre"))
    ce = report.counterexample
    assert ce is not None and len(ce.steps) == 5
    words = texts(report._repr_svg_())
    for k in range(1, 6):
        assert f"#{k}" in words
    assert "#6: not allowed" in words and "aliased" in words
    page = report._repr_html_()
    assert "refuted" in page and "after 5 steps" in page and "data:image/svg+xml;base64," in page
    picture = base64.b64decode(re.search(r"base64,([A-Za-z0-9+/=]+)", page).group(1)).decode()
    assert "#6: not allowed" in texts(picture)
    assert "the original would not take gripper(close)" in page


def test_a_counterexample_at_the_start_marks_the_behaviour_taken(dot, both):
    report = schemalog.verify(both, both.compress("none"))
    assert "#1: not allowed" in texts(report._repr_svg_())
    assert "at the start" in report._repr_html_()


def test_a_run_numbers_its_decisions_on_the_tree(dot, both):
    run = both.compress().run(scene=KITCHEN)
    words = texts(run._repr_svg_())
    assert "completed after 16 decisions" in words
    assert all(f"#{k}" in words for k in range(1, 17))
    page = run._repr_html_()
    assert page.count("<tr><td>") == 16 and "data:image/svg+xml" in page and "completed" in page


def test_a_run_not_started_is_not_started_by_showing_it(dot, spoon):
    run = spoon.start(scene=SPOON_SCENE)
    assert run._repr_svg_() is None and "not started" in run._repr_html_()
    assert run.status == "not started" and not run.completed and run.trace == []    # reading runs nothing
    assert run.finish().completed           # it can still be run


def test_a_run_half_iterated_is_shown_as_far_as_it_has_gone(dot, spoon):
    """Issue 45: showing a half-iterated run in a notebook ran it to the end."""
    run = spoon.start(scene=SPOON_SCENE)
    taken = [next(run) for _ in range(3)]
    page, words = run._repr_html_(), texts(run._repr_svg_())
    assert page.count("<tr><td>") == 3 and "running: 3 decisions taken so far" in page
    assert "running after 3 decisions" in words and "#3" in words and "#4" not in words
    assert len(run.decisions) == 3 and run.status == "running"          # still where it was
    assert next(run).index == 4 and [d.behaviour for d in run.decisions[:3]] == [d.behaviour for d in taken]


def test_ipython_picks_the_picture(dot, spoon):
    formatters = pytest.importorskip("IPython.core.formatters")
    shown, _ = formatters.DisplayFormatter().format(spoon)
    assert "image/svg+xml" in shown and "text/html" not in shown
    shown, _ = formatters.DisplayFormatter().format(schemalog.verify(spoon, spoon.compress("none")))
    assert {"text/html", "image/svg+xml"} <= set(shown)


# -- without Graphviz ---------------------------------------------------------------------
def test_without_dot_a_task_is_text(no_dot, spoon):
    assert spoon._repr_svg_() is None and spoon.compress()._repr_svg_() is None
    page = spoon._repr_html_()
    assert page.startswith("<pre>") and "use(spoon): 12 behaviours, depth 3" in page and "a1(spoon)" in page


def test_without_dot_a_report_and_a_run_are_text(no_dot, spoon):
    report = schemalog.verify(spoon, spoon.compress("none"))
    assert report._repr_svg_() is None
    page = report._repr_html_()
    assert "refuted" in page and "<img" not in page and "a3_a4_a5_a6_a7(cup)" in page
    run = spoon.compress().run(scene=SPOON_SCENE)
    assert run._repr_svg_() is None
    page = run._repr_html_()
    assert "<img" not in page and "<table>" in page and "completed" in page


def test_import_schemalog_loads_no_notebook_code():
    code = ("import sys, schemalog; t = schemalog.load(sys.argv[1]).task(); t.compress(); "
            "print(sorted(m for m in sys.modules if m in ('schemalog.api.notebook', 'schemalog.formats.graphviz',"
            " 'IPython', 'matplotlib')))")
    done = subprocess.run([sys.executable, "-c", code, str(MIX)], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
