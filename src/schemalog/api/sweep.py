"""Sweeps, as the command line calls them (`schemalog sweep`, `bench`, `verify --each`):
grids, the results file, where cells run, and the reports rebuilt from it. Private: the
public API is `import schemalog`; this is what cli/sweep.py, cli/bench.py and
cli/verify_each.py reach below the API through.

    grid(path_or_name) / shipped(name, runs=..., seeds=...) -> Grid
    where(serial, workers, scheduler, or_serial) -> Serial | DaskEngine  # says how to install Dask
                                                                  # (or_serial: in-process without it)
    store(out, grid, fresh) -> Store; memory_store(grid) -> Store  # the results file, or none (bench)
    sweep(grid, store, where, progress) -> SweepStats             # evaluate/sweep.py's run_sweep
    reports(...), bench_report(...), runtimes_report(...)         # what is written from the store
    prove_files(files, options, where, progress) -> rows          # verify --each
"""

from __future__ import annotations

from pathlib import Path

from ..evaluate import bench as _bench
from ..evaluate import sweep as _sweep
from ..evaluate.grid import Grid, named_grid, override, read_grid
from ..evaluate.proofs import ProofOptions, exit_status, prove_file
from ..formats.documents import write_atomically, write_in_folder


def grid(path_or_name: str) -> Grid:
    """A grid file, checked (file:line:column), or a shipped grid's name."""
    return read_grid(path_or_name)


def shipped(name: str, **changes) -> Grid:
    """A shipped grid (paper, quick, runtimes), with settings changed (None: unchanged)."""
    return override(named_grid(name), **changes)


def where(serial: bool = False, workers: int | None = None, scheduler: str | None = None,
          or_serial: bool = False):
    return _sweep.engine(serial, workers, scheduler, or_serial)


def serial():
    return _sweep.Serial()


def store(out: Path, g: Grid, fresh: bool = False):
    return _sweep.Store.open(out, g.settings(), fresh)


def memory_store(g: Grid):
    return _sweep.Store(None, g.settings())


def sweep(g: Grid, s, place, progress=None):
    return _sweep.run_sweep(g, s, place, progress)


def progress(total: int):
    return _sweep.Progress(total)


def reports(g: Grid, s, out: Path, command: str, stats) -> list[Path]:
    return _sweep.write_reports(g, s, out, command, stats)


def bench_report(g: Grid, s, out: Path, command: str, seconds: float):
    """bench's results.csv, results.md and figures from the store: (results, files written)."""
    results = _sweep.bench_results(g, s.in_order(g.cells()), seconds)
    return results, _bench.write_results(results, out, command)


def headlines(results) -> list[str]:
    return _bench.headlines(results)


def runtimes_report(g: Grid, s, out: Path, command: str) -> list[str]:
    """bench --runtimes' runtimes.csv and runtimes.md from the store; the summary a terminal
    is given (runtimes_summary: lines of at most 100 columns)."""
    from ..evaluate.runtimes import runtimes_csv, runtimes_markdown, runtimes_summary

    rows = _sweep.runtime_rows(s.in_order(g.cells()))
    write_in_folder(out / "runtimes.csv", runtimes_csv(rows))
    write_in_folder(out / "runtimes.md", runtimes_markdown(rows, command))
    return runtimes_summary(rows)


def proof_options(**options) -> ProofOptions:
    return ProofOptions(**options)


def prove_files(files: list[str], options: ProofOptions, place, report=None) -> dict[str, list[dict]]:
    """Every task of every file, one sweep task per file: rows by file (verify --each)."""
    state = _sweep.Progress(len(files), running=place.running(len(files)))
    if report:
        report(state)
    by_file: dict[str, list[dict]] = {}
    for path, rows in place.map(prove_file, files, options, priority=_size):
        if isinstance(rows, BaseException):        # the task failed in Dask itself (a killed worker)
            rows = [{"file": path, "task": "", "verdict": "error", "detail": f"{type(rows).__name__}: {rows}",
                     "seconds": 0.0, "original": None, "compressed": None, "states": None}]
        by_file[path] = rows
        bad = any(r["verdict"] != "proved" for r in rows)
        state.done += not bad
        state.failed += bad
        state.running = place.running(len(files) - len(by_file))
        state.last = f"{path}: " + ", ".join(f"{r['task'] or '-'} {r['verdict']}" for r in rows)
        if report:
            report(state)
    return by_file


def proofs_exit_status(rows: list[dict]) -> int:
    return exit_status(rows)


def write_text(path: str, text: str) -> None:
    write_atomically(path, text)


def _size(path: str) -> int:
    import os

    try:
        return os.path.getsize(path)
    except OSError:
        return 0
