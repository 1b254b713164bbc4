"""`schemalog bench`: reproduce the paper's evaluation (Sec. IV) beside py_trees."""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import SchemalogError, UsageError
from .options import Parents, length, positive


def register(sub, parents: Parents) -> None:
    """Add `schemalog bench` and its arguments to the command line."""
    p = sub.add_parser("bench", parents=[parents.resources],
                      help="reproduce the paper's evaluation (Sec. IV) beside py_trees: "
                           "CSV, Markdown and figures")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--paper", action="store_true",
                       help="the whole grid: depth 4-6 x 2-4 children x RD 0, 0.3, 0.5, 0.7, 10 runs each, "
                            "the coffee-and-tea task, and sizes up to 111,111 behaviours (several minutes)")
    which.add_argument("--quick", action="store_true",
                       help="the same grid with 3 runs per tree, verification bounded, and sizes to 5,461: "
                            "about 35 s of CPU time, a minute or two of wall-clock time on a busy machine")
    which.add_argument("--runtimes", action="store_true",
                       help="the grid's trees exported and run in BehaviorTree.CPP and py_trees, original "
                            "against compressed (per tick, per run; runtimes.csv and runtimes.md)")
    p.add_argument("--out", default="bench-results", metavar="DIR",
                   help="where to write results.csv, results.md and the figures (default bench-results)")
    p.add_argument("--runs", type=positive, metavar="N", help="runs per tree (default 10, --quick 3); "
                   "figures are medians with their interquartile range")
    p.add_argument("--seed", type=int, help="seed of the generated tasks (default 1)")
    p.add_argument("--max-states", type=positive, metavar="N",
                   help="verification stops (no proof) beyond N states (default 20,000, --quick 5,000)")
    p.add_argument("--verify-seconds", type=length, metavar="S",
                   help="verification of a task stops (no proof) past S seconds of CPU time "
                        "(default: no limit, --quick 1)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Reproduce the paper's evaluation (Sec. IV) beside py_trees; write tables and figures.
    --paper, --quick and --runtimes are the shipped grids of `schemalog sweep`, run in this
    process through the same path (evaluate/sweep.py), their results kept in memory."""
    from ..api import sweep as api

    name = "runtimes" if args.runtimes else "quick" if args.quick else "paper"
    grid = api.shipped(name, runs=args.runs, max_states=args.max_states,
                    verify_seconds=args.verify_seconds, seeds=None if args.seed is None else (args.seed,))
    with _out_dir(args) as staged:
        said = _runtimes(args, grid, staged) if args.runtimes else _measure(args, grid, staged)
    print(said)                          # once the results are in --out, not before
    return 0


def _sweep(grid, report):
    """The grid's cells, one after the other in this process: the store and the sweep's figures."""
    from ..api import sweep as api

    store = api.memory_store(grid)
    stats = api.sweep(grid, store, api.serial(), report)
    return store, stats


def _measure(args: argparse.Namespace, grid, out: Path) -> str:
    """Run the grid, write its results into `out` (--out's staging folder, _out_dir), and return
    what to say about them."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from ..api import sweep as api

    console = Console(stderr=True)
    cells = grid.cells()
    if console.is_terminal:              # a live bar, its line naming the cell last done
        with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                      console=console, transient=True) as progress:
            bar = progress.add_task(f"bench --{grid.name}", total=len(cells))

            def report(state) -> None:
                progress.update(bar, completed=state.done + state.failed, description=state.last or grid.name)

            store, stats = _sweep(grid, report)
    else:                                # a log or a pipe: one line per cell, no redrawing
        started = time.perf_counter()

        def report(state) -> None:
            if state.last:
                print(f"bench --{grid.name} [{state.done + state.failed}/{state.total}, "
                      f"{time.perf_counter() - started:.0f} s] {state.last}", file=sys.stderr, flush=True)

        store, stats = _sweep(grid, report)
    _no_failure(store, cells)
    command = "schemalog bench " + " ".join(sys.argv[2:] if sys.argv[1:2] == ["bench"] else [f"--{grid.name}"])
    try:
        results, written = api.bench_report(grid, store, out, command, stats.seconds)
    except OSError as err:
        raise SchemalogError(f"cannot write the results into {args.out}: {err.strerror or err}") from None
    return "\n".join([f"bench --{grid.name}: {len(results.cells)} generated tasks x {grid.runs} runs, the "
                      f"coffee-and-tea task, {len(results.sizes)} sizes; {results.seconds:,.0f} s",
                      *(f"- {line}" for line in api.headlines(results)),
                      "wrote " + ", ".join(str(Path(args.out) / p.name) for p in written)])


def _no_failure(store, cells) -> None:
    """bench stops at a failed cell, as it always has: its figures need every cell."""
    for row in store.in_order(cells):
        if row["status"] != "done":
            raise SchemalogError(f"bench: {row['key']}: {row['message']}")


def _runtimes(args: argparse.Namespace, grid, out: Path) -> str:
    """`bench --runtimes`: the paper's grid in BT.CPP and py_trees (evaluate/runtimes.py), its
    tables written into `out` (--out's staging folder, _out_dir)."""
    from ..api import sweep as api

    def step(state) -> None:
        if state.last:
            print(f"[{state.done + state.failed}/{state.total}] {state.last}", file=sys.stderr)

    store, stats = _sweep(grid, step)
    _no_failure(store, grid.cells())
    try:
        summary = api.runtimes_report(grid, store, out, "schemalog bench --runtimes")
    except OSError as err:
        raise SchemalogError(f"cannot write the results into {args.out}: {err.strerror or err}") from None
    rows = sum(1 for c in grid.cells() if store.done(c.key))
    # The whole table (medians, quartiles, ranges: 600 columns a row) goes to runtimes.md alone.
    return "\n".join([f"bench --runtimes: {rows} trees, {stats.seconds:,.0f} s", *summary,
                      f"wrote {Path(args.out) / 'runtimes.csv'}, {Path(args.out) / 'runtimes.md'} (the whole table)"])


@contextmanager
def _out_dir(args: argparse.Namespace) -> Iterator[Path]:
    """--out, made and checked writable before anything is measured; the results are written
    into a hidden folder inside it and moved in when the command ends well. A run stopped early
    (--timeout, Ctrl-C, an error, memory) leaves --out as it found it: the folders it made are
    removed, a folder that was there keeps its old results."""
    from .sweep import out_folder

    if not args.out.strip():             # Path('') is '.': the results would land among the user's files
        raise UsageError("--out needs a directory name (it is empty)")
    out = Path(args.out)
    made = [p for p in (out, *out.parents) if not os.path.lexists(p)]   # innermost first
    staging = None
    try:
        out_folder(args.out)             # made, and checked writable
        staging = Path(tempfile.mkdtemp(prefix=".bench-", suffix=".tmp", dir=out))
        yield staging
        for written in sorted(staging.iterdir()):
            os.replace(written, out / written.name)
        staging.rmdir()
    except BaseException:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)     # made by mkdtemp: only this run's files
        _remove_made(made)
        raise


def _remove_made(made: list[Path]) -> None:
    """Remove the folders this run made, innermost first; one that holds anything else stays."""
    for folder in made:
        try:
            folder.rmdir()
        except FileNotFoundError:        # never made: mkdir stopped before it
            continue
        except OSError:
            return
