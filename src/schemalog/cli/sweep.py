"""`schemalog sweep GRID --out DIR`: a declared grid's cells as Dask tasks (or --serial), resumable."""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import UsageError
from .options import Parents, positive


def register(sub, parents: Parents) -> None:
    """Add `schemalog sweep` and its arguments to the command line."""
    p = sub.add_parser("sweep", parents=[parents.resources],
                       help="run an evaluation grid (GRID.yaml, or paper, quick, runtimes) as one sweep "
                            "on Dask: resumable, results in Parquet (pip install 'schemalog[distributed]')")
    p.add_argument("grid", metavar="GRID", help="a grid file (docs/evaluation.md), or a shipped grid: paper, "
                                                "quick, runtimes")
    p.add_argument("--out", default="sweep-results", metavar="DIR",
                   help="where results.parquet, sweep.md and the grid's tables and figures go (default "
                        "sweep-results); a rerun into the same DIR skips the cells already done")
    engine_options(p)
    p.add_argument("--fresh", action="store_true", help="forget the results already in DIR and measure every cell")
    p.set_defaults(run=run)


def engine_options(p: argparse.ArgumentParser) -> None:
    """--workers, --scheduler, --serial: where a sweep runs (sweep, verify --each)."""
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=positive, metavar="N",
                       help="a LocalCluster of N single-threaded worker processes (default: one per core)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on an existing Dask cluster, e.g. tcp://host:8786 (default: $SCHEMALOG_SCHEDULER)")
    where.add_argument("--serial", action="store_true", help="run in this process, one task after another "
                                                             "(no Dask needed)")


def run(args: argparse.Namespace) -> int:
    """Run the grid's cells not yet in DIR; write the reports; exit 1 if a cell failed."""
    from ..api import sweep as api

    grid = api.grid(args.grid)
    where = api.where(args.serial, args.workers, args.scheduler)  # says how to install Dask, before any work
    out = out_folder(args.out)
    store = api.store(out, grid, args.fresh)
    if all(store.done(c.key) for c in grid.cells()):
        where = api.serial()             # nothing left to run: no cluster to start
    command = "schemalog " + " ".join(sys.argv[1:]) if sys.argv[1:2] == ["sweep"] else f"schemalog sweep {args.grid}"
    try:
        with where, progress_display(f"sweep {grid.name}", len(grid.cells())) as show:
            stats = api.sweep(grid, store, where, show)
    except BaseException:
        if store.path is not None and store.saved:      # what the file holds, not what was computed
            print(f"stopped: {store.saved} cells stored in {store.path}; the same command resumes the sweep",
                  file=sys.stderr)
        raise
    written = api.reports(grid, store, out, command, stats)
    if store.path is not None:
        written.insert(0, store.path)
    done = stats.total - stats.failed
    print(f"sweep {grid.name}: {done} of {stats.total} cells done, {stats.failed} failed; {stats.computed} computed "
          f"in {stats.seconds:,.1f} s, {stats.stored} already stored; {stats.where}")
    for row in store.in_order(grid.cells()):
        if row["status"] != "done":
            print(f"  FAILED {row['key']}: {row['message']}")
    print("wrote " + ", ".join(str(p) for p in written))
    return 1 if stats.failed else 0


def out_folder(text: str) -> Path:
    """--out, made and checked writable before anything runs."""
    if not text.strip():
        raise UsageError("--out needs a directory name (it is empty)")
    out = Path(text)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise UsageError(f"--out {text} is a file, not a directory") from None
    except OSError as err:
        raise UsageError(f"--out {text}: cannot make the directory: {err.strerror or err}") from None
    if not os.access(out, os.W_OK):
        raise UsageError(f"--out {text}: the directory is not writable")
    return out


@contextmanager
def progress_display(title: str, total: int) -> Iterator:
    """A callback for run_sweep's Progress: a live bar at a terminal (done, running, failed, time
    left), one line per finished task otherwise."""
    from rich.console import Console

    console = Console(stderr=True)
    if console.is_terminal:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                      TextColumn("running {task.fields[running]}, failed {task.fields[failed]}"),
                      TextColumn("left"), TimeRemainingColumn(), console=console, transient=True) as bar:
            task = bar.add_task(title, total=total, running=0, failed=0)

            def show(state) -> None:
                bar.update(task, completed=state.done + state.failed, running=state.running, failed=state.failed,
                           description=f"{title}: {state.last}" if state.last else title)

            yield show
        return
    started = time.perf_counter()
    first = []

    def say(state) -> None:
        finished = state.done + state.failed
        if not first:
            first.append(finished)
            if finished:
                print(f"{title}: {finished} of {total} already stored", file=sys.stderr, flush=True)
            return
        elapsed = time.perf_counter() - started
        new = finished - first[0]
        left = f", about {elapsed / new * (total - finished):,.0f} s left" if new and finished < total else ""
        print(f"{title} [{finished}/{total}, {elapsed:,.0f} s{left}; running {state.running}, failed "
              f"{state.failed}] {state.last}", file=sys.stderr, flush=True)

    yield say
