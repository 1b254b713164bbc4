"""examples/tour.ipynb runs from top to bottom, and shows its pictures.

The notebook is executed with nbclient in a Python kernel (ipykernel) from examples/, as a reader
opens it. The test fails if a cell fails, or if a cell that draws a picture (a Task, a Report with
a counterexample, a Run: Graphviz's SVG; the plot: matplotlib's PNG) has none in its output.
With CI set, a missing nbclient, nbformat, ipykernel or Graphviz `dot` fails the test (CI installs
them: `pip install -e '.[test]'`, and .ci/run installs Graphviz); elsewhere it skips, saying which.
"""

from __future__ import annotations

import os
import shutil
import time

import pytest

from conftest import ROOT

NOTEBOOK = ROOT / "examples" / "tour.ipynb"
IMAGES = ("image/svg+xml", "image/png")


def required(module: str):
    try:
        return pytest.importorskip(module, reason=f"{module} is not installed (pip install -e '.[test]')")
    except pytest.skip.Exception:
        if os.environ.get("CI"):
            pytest.fail(f"CI is set but {module} is not installed: the tour notebook cannot be executed "
                        f"(pip install -e '.[test]')")
        raise


def test_the_committed_notebook_has_no_outputs():
    # Outputs are made by running it (here, in CI, or in Jupyter), never stale in the repository.
    nbformat = required("nbformat")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and not any(c.outputs or c.execution_count for c in code)


def test_the_tour_runs_and_shows_its_pictures():
    nbformat = required("nbformat")
    nbclient = required("nbclient")
    required("ipykernel")
    if shutil.which("dot") is None:
        message = "Graphviz's dot is not on PATH: the notebook's tasks would show as text, not pictures"
        if os.environ.get("CI"):
            pytest.fail(f"CI is set but {message} (apt-get install graphviz)")
        pytest.skip(message)
    nb = nbformat.read(NOTEBOOK, as_version=4)
    started = time.monotonic()
    # The kernel inherits this process's environment (PYTHONPATH too), so it imports the same schemalog.
    client = nbclient.NotebookClient(nb, timeout=120, kernel_name="python3",
                                     resources={"metadata": {"path": str(NOTEBOOK.parent)}})
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as err:
        pytest.fail(f"a cell of {NOTEBOOK.name} failed:\n{err}")
    elapsed = time.monotonic() - started
    code = [c for c in nb.cells if c.cell_type == "code"]
    errors = [o for c in code for o in c.outputs if o.output_type == "error"]
    assert not errors, errors
    # Every cell that ends with a Task, a Report with a counterexample, a Run, or plt.show()
    # must have drawn it: which cells those are is read from the source, not counted by hand.
    for cell in code:
        last = cell.source.strip().splitlines()[-1].strip()
        pictured = last in ("spoon", "small", "refuted", "run", "both", "full", "plt.show()") \
            or last.startswith("runs[") or (last == "report" and "none)" in cell.source)
        if not pictured:
            continue
        shown = {mime for o in cell.outputs for mime in o.get("data", {})}
        assert shown & set(IMAGES), f"no picture in the output of the cell ending {last!r}: {sorted(shown)}"
    images = [o for c in code for o in c.outputs if set(o.get("data", {})) & set(IMAGES)]
    assert sum("image/png" in o["data"] for o in images) >= 1, "the plot is missing"
    assert len(images) >= 9, f"only {len(images)} outputs with a picture"
    assert elapsed < 60, f"the tour took {elapsed:.0f} s"
