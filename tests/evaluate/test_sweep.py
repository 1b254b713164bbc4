"""Sweeps on Dask: a LocalCluster of 2 workers gives the serial results, survives a killed
worker, and a resumed sweep recomputes nothing already stored. No timing is asserted."""

from __future__ import annotations

import json
import os
import signal
import threading
import time

import pytest

from schemalog.errors import SchemalogError, UsageError
from schemalog.evaluate import bench, sweep
from schemalog.evaluate.grid import grid_from_yaml, named_grid
from schemalog.evaluate.sweep import DaskEngine, Serial, Store, non_timing, run_sweep

GRID = """\
name: small
shapes: [4x2, 3x3]
reductions: [0, 0.5]
seeds: [1, 2]
propagate: [full]
measures: [compress, prove, time]
selectors: [scan, incremental, py_trees]
runs: 2
ticks: 2
coffee: true
limits:
  max_states: 5000
"""


@pytest.fixture(scope="module")
def grid():
    return grid_from_yaml(GRID, "small.yaml")


@pytest.fixture(scope="module")
def serial(grid):
    store = Store(None, grid.settings())
    stats = run_sweep(grid, store, Serial())
    assert stats.computed == stats.total == 9 and stats.failed == 0
    return {key: non_timing(row) for key, row in store.rows.items()}


@pytest.fixture(scope="module")
def cluster():
    with DaskEngine(workers=2) as where:
        yield where


def test_the_grid_has_its_cells_and_the_shipped_grids_read(grid):
    assert [c.key for c in grid.cells()][:2] == ["generated/4x2/rd0/seed1/full", "generated/4x2/rd0/seed2/full"]
    assert grid.cells()[-1].key == "coffee/seed1/full"
    paper = named_grid("paper")
    assert len(paper.cells()) == 36 + 1 + 6 and paper.runs == 10 and paper.verify_seconds is None
    quick = named_grid("quick")
    assert (quick.runs, quick.max_states, quick.verify_seconds) == (3, 5000, 1.0)
    assert named_grid("runtimes").measures == ("compress", "runtimes")


@pytest.mark.parametrize("text, where, message", [
    ("shapes: [4x2, 4y2]\n", "g.yaml:1:15", "depth x children"),
    ("shapes: [4x2]\nreductions: [0, 1.5]\n", "g.yaml:2:17", "between 0 and 1"),
    ("shapes: [4x2]\nmeasures: [prove, plot]\n", "g.yaml:2:19", "unknown measure 'plot'"),
    ("shapes: [4x2]\nseeds: [1, 1]\n", "g.yaml:2:12", "appears twice"),
    ("shapes: [4x2]\nlimits:\n  max_sates: 3\n", "g.yaml:3:3", "unknown limit 'max_sates'"),
    ("shapes: [4x2]\nrunz: 3\n", "g.yaml:2:1", "unknown key 'runz'"),
    ("shapes: [4x2\n", "g.yaml:2:1", "YAML syntax error"),
    ("shapes: [12x10]\n", "g.yaml:1:10", "over 2,000,000 behaviours"),
    ("runs: 3\n", "g.yaml:1:1", "no cells"),
    # issue 46: a 5,000-digit shape was an internal error (int() stops at 4,300 digits), Unicode
    # digits were read as numbers, and whole numbers were printed with %g
    ("shapes: [" + "9" * 5000 + "x2]\n", "g.yaml:1:10", "(5,000 digits)x2 is over 2,000,000 behaviours"),
    ("shapes: [[" + "9" * 5000 + ", 2]]\n", "g.yaml:1:10", "(5,000 digits)x2 is over 2,000,000 behaviours"),
    ("shapes: [4x2]\nseeds: [" + "9" * 5000 + "]\n", "g.yaml:2:9", "not 99999999999999999999...9999999999"),
    ("shapes: [\u0663x\u0662]\n", "g.yaml:1:10", "depth x children"),
    ("shapes: [4x2]\nreductions: [\u0660.5]\n", "g.yaml:2:14", "must be a number"),
    ("shapes: [4x2]\nseeds: [99999999999]\n", "g.yaml:2:9", "between 0 and 4294967295, not 99999999999"),
])
def test_a_bad_grid_is_told_with_its_place(text, where, message):
    with pytest.raises(SchemalogError) as err:
        grid_from_yaml(text, "g.yaml")
    assert str(err.value).startswith(where + ": error: ") and message in str(err.value), str(err.value)


def test_a_local_cluster_of_two_workers_gives_the_serial_results(grid, serial, cluster):
    store = Store(None, grid.settings())
    stats = run_sweep(grid, store, cluster)
    assert stats.workers == 2 and stats.computed == 9 and stats.failed == 0
    assert {key: non_timing(row) for key, row in store.rows.items()} == serial
    # what is compared is there: sizes, the reduction degree, verdicts, decisions and traces per run
    cell = serial["generated/4x2/rd0.5/seed1/full"]
    assert cell["verify"] == "proved" and cell["merged"] < cell["behaviours"] == 15
    decisions, traces = cell["runs"]["compressed/scan"]
    assert len(decisions) == len(traces) == 2 and all(decisions)
    assert {r["worker"] for r in store.rows.values()} != {f"{os.uname().nodename}:{os.getpid()}"}


def test_the_sweep_completes_when_a_worker_is_killed_mid_sweep(grid, serial, cluster):
    client = cluster.client
    pids = client.run(os.getpid)                 # worker address -> its process
    killed = []

    def kill_one(state) -> None:
        if killed or state.done < 1:
            return
        busy = [w for w, keys in client.processing().items() if keys and w in pids] or list(pids)
        killed.append(busy[0])
        os.kill(pids[busy[0]], signal.SIGKILL)   # the nanny starts another; its task is run again

    store = Store(None, grid.settings())
    stats = run_sweep(grid, store, cluster, kill_one)
    assert killed and stats.failed == 0 and stats.computed == 9
    assert {key: non_timing(row) for key, row in store.rows.items()} == serial


def test_a_resumed_sweep_recomputes_nothing_already_stored(grid, serial, cluster, tmp_path):
    def stop_after(n):
        def progress(state):
            if state.done >= n:
                raise KeyboardInterrupt
        return progress

    store = Store.open(tmp_path, grid.settings())
    with pytest.raises(KeyboardInterrupt):           # Ctrl-C on the cluster after 3 cells
        run_sweep(grid, store, cluster, stop_after(3))
    assert (tmp_path / "results.parquet").is_file()
    first = Store.open(tmp_path, grid.settings()).rows
    assert len(first) == 3 and all(r["status"] == "done" for r in first.values())

    resumed = Store.open(tmp_path, grid.settings())
    stats = run_sweep(grid, resumed, Serial())
    assert (stats.stored, stats.computed) == (3, 6)
    again = Store.open(tmp_path, grid.settings())
    assert {k: again.rows[k] for k in first} == first            # the stored cells were not measured again
    assert {key: non_timing(row) for key, row in again.rows.items()} == serial
    stats = run_sweep(grid, again, cluster)
    assert (stats.stored, stats.computed) == (9, 0)


def test_a_results_file_of_other_settings_is_not_resumed(grid, tmp_path):
    store = Store.open(tmp_path, grid.settings())
    run_sweep(grid, store, Serial(), cells=grid.cells()[:1])
    other = grid_from_yaml(GRID.replace("runs: 2", "runs: 3"), "small.yaml")
    with pytest.raises(UsageError, match="other settings"):
        Store.open(tmp_path, other.settings())
    assert Store.open(tmp_path, other.settings(), fresh=True).rows == {}
    (tmp_path / "results.parquet").write_text("not parquet")
    with pytest.raises(SchemalogError, match="cannot read"):
        Store.open(tmp_path, grid.settings())


def test_without_pyarrow_a_serial_sweep_stores_json_lines(grid, tmp_path, monkeypatch):
    monkeypatch.setattr(sweep, "have_pyarrow", lambda: False)
    store = Store.open(tmp_path, grid.settings())
    run_sweep(grid, store, Serial(), cells=grid.cells()[:2])
    lines = (tmp_path / "results.jsonl").read_text().splitlines()
    assert len(lines) == 2 and json.loads(lines[0])["status"] == "done"
    assert len(Store.open(tmp_path, grid.settings()).rows) == 2


def test_a_failed_cell_is_recorded_with_its_message_and_the_sweep_goes_on(grid, monkeypatch):
    real = bench.measure_cell

    def measure_cell(depth, children, rd, plan, say=None):
        if (depth, rd, plan.seed) == (3, 0.5, 2):
            raise ValueError("a cell that breaks")
        return real(depth, children, rd, plan, say)

    monkeypatch.setattr(bench, "measure_cell", measure_cell)
    store = Store(None, grid.settings())
    stats = run_sweep(grid, store, Serial())
    assert stats.failed == 1 and stats.computed == 9
    row = store.rows["generated/3x3/rd0.5/seed2/full"]
    assert row["status"] == "failed" and row["message"] == "ValueError: a cell that breaks"
    assert sum(r["status"] == "done" for r in store.rows.values()) == 8
    assert "FAILED: ValueError: a cell that breaks" in sweep.sweep_markdown(grid, store.in_order(grid.cells()),
                                                                           "x", stats)


def test_a_cell_past_its_cpu_budget_fails_as_a_limit():
    limited = grid_from_yaml("shapes: [6x4]\nreductions: [0.7]\nmeasures: [time]\nruns: 10\n"
                             "limits:\n  cell_seconds: 0.05\n", "l.yaml")
    store = Store(None, limited.settings())
    stats = run_sweep(limited, store, Serial())
    row = next(iter(store.rows.values()))
    assert stats.failed == 1 and row["message"].startswith("limit: the cell used more than 0.05 s of CPU time")


def test_a_cpu_budget_holds_outside_the_main_thread():
    # A Dask worker runs its task in a thread, where no signal can be caught: a verification's
    # verify_seconds is then watched on the thread's own CPU clock.
    caught = []

    def spin():
        try:
            with bench.cpu_budget(0.05):
                deadline = time.monotonic() + 20
                while time.monotonic() < deadline:
                    sum(range(1000))
        except BaseException as err:          # _OutOfTime is a BaseException on purpose
            caught.append(type(err).__name__)

    thread = threading.Thread(target=spin)
    thread.start()
    thread.join(30)
    assert caught == ["_OutOfTime"]


def test_a_runtimes_grid_writes_bench_runtimes_tables(tmp_path):
    grid = grid_from_yaml("shapes: [3x2]\nreductions: [0.5]\nmeasures: [runtimes]\n", "r.yaml")
    store = Store.open(tmp_path, grid.settings())
    stats = run_sweep(grid, store, Serial())
    written = sweep.write_reports(grid, store, tmp_path, "schemalog sweep r.yaml", stats)
    assert [p.name for p in written] == ["sweep.md", "runtimes.csv", "runtimes.md"]
    assert "| 3x2 RD 0.5 | 7 -> " in (tmp_path / "runtimes.md").read_text()
    assert non_timing(store.rows["generated/3x2/rd0.5/seed1/full"])["ticks"]["btcpp/original"] > 0


def test_a_link_in_the_output_folder_is_replaced_never_written_through(tmp_path):
    """--out's files are the run's: sweep.md or results.parquet linked to a file elsewhere are
    replaced by the files, and the file the link named is untouched (issue 46)."""
    from schemalog.api import sweep as api
    from schemalog.evaluate.sweep import Serial, run_sweep, write_reports

    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_text("victim\n")
    for name in ("sweep.md", "results.parquet", "results.jsonl"):
        (out / name).symlink_to(victim)
    g = grid_from_yaml("shapes: [2x2]\nreductions: [0.5]\nmeasures: [compress]\n", "g.yaml")
    store = api.store(out, g, fresh=True)
    stats = run_sweep(g, store, Serial())
    write_reports(g, store, out, "test", stats)
    assert victim.read_text() == "victim\n"
    assert not (out / "sweep.md").is_symlink() and "schemalog sweep" in (out / "sweep.md").read_text()
    assert not store.path.is_symlink() and store.saved == 1


def test_a_name_that_is_not_utf8_holds_the_results(tmp_path):
    """--out $'\\xff': pyarrow refused the name (UnicodeEncodeError, an internal error, after
    "1 cells stored"); the results are written, and read back by a rerun."""
    from schemalog.api import sweep as api
    from schemalog.evaluate.sweep import Serial, run_sweep

    out = tmp_path / os.fsdecode(b"\xff")
    out.mkdir()
    g = grid_from_yaml("shapes: [2x2]\nreductions: [0.5]\nmeasures: [compress]\n", "g.yaml")
    store = api.store(out, g)
    run_sweep(g, store, Serial())
    assert store.saved == 1 and api.store(out, g).done(g.cells()[0].key)


def test_stopped_says_how_many_cells_the_file_holds_not_how_many_ran(tmp_path):
    from schemalog.api import sweep as api
    from schemalog.errors import CannotWrite
    from schemalog.evaluate.sweep import Serial, run_sweep

    out = tmp_path / "gone"
    out.mkdir()
    g = grid_from_yaml("shapes: [2x2]\nreductions: [0.5]\nmeasures: [compress]\n", "g.yaml")
    store = api.store(out, g)
    out.rmdir()                              # the results file can no longer be written
    with pytest.raises(CannotWrite):
        run_sweep(g, store, Serial())
    assert len(store.rows) == 1 and store.saved == 0


def test_a_folder_named_after_a_shipped_grid_does_not_shadow_it(tmp_path, monkeypatch):
    from schemalog.evaluate.grid import read_grid

    monkeypatch.chdir(tmp_path)
    (tmp_path / "paper").mkdir()
    assert read_grid("paper") == named_grid("paper")


def test_a_timed_grid_without_original_trees_draws_no_empty_figure(tmp_path):
    """measures: [time] without an RD 0 cell printed matplotlib's "No artists with labels found"
    with its source path, over an empty selectors figure (issue 46)."""
    import warnings

    from schemalog.api import sweep as api
    from schemalog.evaluate.sweep import Serial, run_sweep, write_reports

    g = grid_from_yaml("shapes: [3x2]\nreductions: [0.5]\nmeasures: [time]\nruns: 1\nticks: 1\n", "g.yaml")
    store = api.store(tmp_path, g)
    stats = run_sweep(g, store, Serial())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        written = write_reports(g, store, tmp_path, "test", stats)
    assert {p.name for p in written} >= {"figure4.png", "results.md"}
    assert not (tmp_path / "selectors.png").exists()
