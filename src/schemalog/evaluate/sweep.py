"""Sweeps: a grid's cells (or many task files' proofs) run as independent tasks, on Dask or in-process.

    store = Store.open(out / "results.parquet", grid.settings())   # resumes what is stored
    with engine(workers=2) as where:                                # LocalCluster, --scheduler, or Serial()
        stats = run_sweep(grid, store, where, progress)             # each cell: generate, compress, prove, time
    write_reports(grid, store, out, command, stats)                 # sweep.md, results.md, figures, runtimes

Every cell is one task (run_cell), which never raises: a failure (an exception, a limit) comes
back as a row with its message, and the sweep goes on. Rows land in the store as each cell
finishes; the store is rewritten atomically (a temporary file and a rename) at most every half
second and when the sweep ends or is stopped, so a crash or Ctrl-C leaves a file that a rerun
resumes, skipping every cell already done. Dask is imported only by DaskEngine: a serial sweep
runs with no Dask installed, and stores JSON Lines where pyarrow is missing.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import socket
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable, Iterator

from ..errors import SchemalogError, UsageError
from ..formats.documents import write_in_folder
from . import bench
from .grid import CellSpec, Grid

INSTALL = "pip install 'schemalog[distributed]'"
FLUSH_EVERY = 0.5          # seconds between two rewrites of the results file, at most


class CellOutOfTime(BaseException):
    """A cell used up its CPU budget (limits: cell_seconds)."""


# ---------------------------------------------------------------------------
# One cell: what runs on a worker

def measure(spec: CellSpec, grid: Grid) -> dict:
    """Generate, compress, prove and time one cell as the grid says: the result as plain data."""
    plan = bench.BenchPlan(shapes=(), runs=grid.runs, ticks=grid.ticks, min_seconds=grid.min_seconds,
                           max_states=grid.max_states, verify_seconds=grid.verify_seconds, seed=spec.seed,
                           name=grid.name, propagate=spec.propagate, measures=grid.measures,
                           selectors=grid.selectors, max_bdd_nodes=grid.max_bdd_nodes)
    if spec.kind == "size":
        return {"size": asdict(bench.measure_size(spec.depth, spec.children, plan))}
    if spec.kind == "coffee":
        return {"cell": cell_data(bench.measure_coffee(plan))}
    cell = bench.measure_cell(spec.depth, spec.children, spec.rd, plan)
    out = {"cell": cell_data(cell)}
    if "runtimes" in grid.measures:
        from .runtimes import measure_row

        out["runtimes"] = runtime_data(measure_row(spec.depth, spec.children, spec.rd, spec.seed))
    return out


def run_cell(spec: CellSpec, grid: Grid) -> dict:
    """One cell, measured: its row for the results file. Never raises an Exception."""
    started, cpu = time.perf_counter(), time.thread_time()
    status, message, payload = "done", "", {}
    try:
        with bench.thread_budget(grid.cell_seconds, CellOutOfTime):
            payload = measure(spec, grid)
    except CellOutOfTime:
        status, message = "failed", f"limit: the cell used more than {grid.cell_seconds:g} s of CPU time (cell_seconds)"
    except MemoryError:
        status, message = "failed", "out of memory"
    except RecursionError:
        status, message = "failed", "too deep for Python's recursion limit"
    except SchemalogError as err:
        status, message = "failed", str(err)
    except Exception as err:       # any other failure is this cell's, not the sweep's
        status, message = "failed", f"{type(err).__name__}: {err}"
    return cell_row(spec, grid, status, message, payload, time.perf_counter() - started,
                    time.thread_time() - cpu)


def cell_row(spec: CellSpec, grid: Grid, status: str, message: str, payload: dict, seconds: float,
             cpu: float = math.nan) -> dict:
    cell = payload.get("cell") or {}
    return {"key": spec.key, "kind": spec.kind, "depth": spec.depth, "children": spec.children, "rd": spec.rd,
            "seed": spec.seed, "propagate": spec.propagate, "behaviours": spec.behaviours,
            "behaviours_compressed": cell.get("merged"), "rd_achieved": cell.get("rd_got"),
            "verify_result": cell.get("verify_result"), "verify_states": cell.get("verify_states"),
            "status": status, "message": message, "seconds": seconds, "cpu_seconds": cpu,
            "worker": f"{socket.gethostname()}:{os.getpid()}", "finished": time.time(),
            "settings": grid.settings(), "result": json.dumps(payload)}


def cell_data(cell: bench.Cell) -> dict:
    data = {k: v for k, v in asdict(cell).items() if k != "timings"}
    data["timings"] = [{"tree": tree, "selector": selector, **asdict(t)}
                       for (tree, selector), t in cell.timings.items()]
    return data


def cell_from_data(data: dict) -> bench.Cell:
    fields = {k: v for k, v in data.items() if k != "timings"}
    cell = bench.Cell(**fields)
    for t in data["timings"]:
        cell.timings[(t["tree"], t["selector"])] = bench.Timing(
            **{k: v for k, v in t.items() if k not in ("tree", "selector")})
    return cell


def runtime_data(row) -> dict:
    data = {k: v for k, v in asdict(row).items() if k != "times"}
    data["times"] = [{"runtime": r, "tree": w, **asdict(t)} for (r, w), t in row.times.items()]
    return data


def runtime_from_data(data: dict):
    from .runtimes import RuntimeRow, Timed

    times = {(t["runtime"], t["tree"]): Timed.from_data(t) for t in data["times"]}
    return RuntimeRow(**{k: v for k, v in data.items() if k != "times"}, times=times)


def non_timing(row: dict) -> dict:
    """What a cell's row says that does not depend on the machine's speed: sizes, the reduction
    degree, the verdict, and per run the decisions and the trace (tests compare these)."""
    payload = json.loads(row["result"]) if row.get("result") else {}
    cell = payload.get("cell") or {}
    out = {"status": row["status"], "behaviours": cell.get("behaviours"), "merged": cell.get("merged"),
           "rd": cell.get("rd_got"), "verify": cell.get("verify_result"), "states": cell.get("verify_states"),
           "runs": {f"{t['tree']}/{t['selector']}": (t["decisions"], t["traces"]) for t in cell.get("timings", [])}}
    if "runtimes" in payload:
        out["ticks"] = {f"{t['runtime']}/{t['tree']}": t["ticks"] for t in payload["runtimes"]["times"]}
    if "size" in payload:
        out["decisions"] = payload["size"]["decisions"]
    return out


# ---------------------------------------------------------------------------
# The results file

COLUMNS = {"key": "string", "kind": "string", "depth": "int64", "children": "int64", "rd": "float64",
           "seed": "int64", "propagate": "string", "behaviours": "int64", "behaviours_compressed": "int64",
           "rd_achieved": "float64", "verify_result": "string", "verify_states": "int64", "status": "string",
           "message": "string", "seconds": "float64", "cpu_seconds": "float64", "worker": "string",
           "finished": "float64", "settings": "string", "result": "string"}


def have_pyarrow() -> bool:
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


class Store:
    """The rows of a sweep by key, in a Parquet file (JSON Lines without pyarrow), or in memory
    (path None: bench, which keeps no results file)."""

    def __init__(self, path: Path | None, settings: str, rows: dict | None = None) -> None:
        self.path, self.settings = path, settings
        self.rows: dict[str, dict] = rows or {}
        self.saved = 0                      # rows the results file holds: read back, or last written
        self._dirty, self._flushed = False, 0.0

    @staticmethod
    def open(folder: Path, settings: str, fresh: bool = False) -> "Store":
        """The store of `folder`: results.parquet (or results.jsonl), what it holds read back."""
        parquet, jsonl = folder / "results.parquet", folder / "results.jsonl"
        path = parquet if have_pyarrow() else jsonl
        if not have_pyarrow() and parquet.exists() and not fresh:
            raise UsageError(f"{parquet} needs pyarrow to be read: {INSTALL}")
        store = Store(path, settings)
        if fresh or not path.exists():
            return store
        for row in _read_rows(path):
            if row.get("settings") != settings:
                raise UsageError(f"{path} holds results measured with other settings (runs, measures, limits) "
                                 f"than this grid's: use another --out, or --fresh to measure again")
            store.rows[row["key"]] = row
        store.saved = len(store.rows)
        return store

    def done(self, key: str) -> bool:
        row = self.rows.get(key)
        return row is not None and row["status"] == "done"

    def add(self, row: dict) -> None:
        self.rows[row["key"]] = row
        self._dirty = True
        self.flush(force=False)

    def flush(self, force: bool = True) -> None:
        if self.path is None or not self._dirty or (not force and time.monotonic() - self._flushed < FLUSH_EVERY):
            return
        rows = list(self.rows.values())
        if self.path.suffix == ".parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            schema = pa.schema([(name, getattr(pa, kind)()) for name, kind in COLUMNS.items()])
            table = pa.Table.from_pylist([{c: r.get(c) for c in COLUMNS} for r in rows], schema=schema)
            write_in_folder(self.path, lambda handle: pq.write_table(table, handle))
        else:
            write_in_folder(self.path, "".join(json.dumps({c: r.get(c) for c in COLUMNS}) + "\n" for r in rows))
        self._dirty, self._flushed = False, time.monotonic()
        self.saved = len(rows)

    def in_order(self, cells: list[CellSpec]) -> list[dict]:
        """The stored rows of these cells, in the cells' order."""
        return [self.rows[c.key] for c in cells if c.key in self.rows]


def _read_rows(path: Path) -> list[dict]:
    try:
        if path.suffix == ".parquet":
            import pyarrow.parquet as pq

            with open(path, "rb") as handle:          # pyarrow takes only UTF-8 names; Python any name
                return pq.read_table(handle).to_pylist()
        return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]
    except (OSError, ValueError, UnicodeDecodeError, Exception) as err:   # pyarrow's errors are its own
        raise SchemalogError(f"cannot read {path} as a sweep's results ({type(err).__name__}: {err}): remove it, "
                             f"or use another --out") from None


# ---------------------------------------------------------------------------
# Where cells run

def local_cores() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


class Serial:
    """In this process, one task after the other: no Dask imported. `why` is what the summary
    says of it (--serial), `note` what the command says before it runs (None: nothing)."""

    workers = 1

    def __init__(self, why: str = "--serial", note: str | None = None) -> None:
        self.where = f"in this process ({why})"
        self.note = note

    def __enter__(self) -> "Serial":
        return self

    def __exit__(self, *exc) -> None:
        return None

    def map(self, fn, items: list, *args, priority=None) -> Iterator[tuple]:
        for item in items:
            yield item, fn(item, *args)

    def running(self, left: int) -> int:
        return min(1, left)


SCRATCH = "schemalog-dask-"       # + the pid of the sweep that owns the folder


def _remove_orphaned_scratch() -> None:
    """Remove the scratch folders of sweeps that were killed (SIGKILL leaves no chance to): a
    folder of this user's whose process is gone."""
    base = Path(tempfile.gettempdir())
    for folder in base.glob(f"{SCRATCH}*-*"):
        pid = folder.name[len(SCRATCH):].split("-", 1)[0]
        try:
            if not pid.isdigit() or folder.is_symlink() or folder.stat().st_uid != os.getuid():
                continue
            os.kill(int(pid), 0)
        except ProcessLookupError:
            shutil.rmtree(folder, ignore_errors=True)
        except (OSError, OverflowError):
            continue


def _start_resource_tracker() -> None:
    """Start multiprocessing's resource tracker, which the cluster's processes share, before
    SIGINT is blocked: starting it unblocks SIGINT (resource_tracker.ensure_running), and the
    processes made after that would take Ctrl-C again. It removes the semaphores of processes that were
    killed (a SIGKILL of the sweep) and then warns about each "leaked" one on stderr; it takes
    its warning filters from this process's -W options when it starts, so it is told to do the
    cleaning quietly."""
    from multiprocessing import resource_tracker

    quiet = "ignore:resource_tracker:UserWarning"
    if quiet not in sys.warnoptions:
        sys.warnoptions.append(quiet)
    resource_tracker.ensure_running()


class DaskEngine:
    """A dask.distributed Client: on a LocalCluster of `workers` single-threaded worker processes
    (default one per core), or on the scheduler at `scheduler` (tcp://host:8786)."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None) -> None:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise UsageError(f"this needs Dask: {INSTALL} (or run in this process with --serial)") from None
        self.requested, self.scheduler = workers, scheduler
        self.client = self.cluster = None
        self.scratch: str | None = None
        self._keys: set = set()

    def __enter__(self) -> "DaskEngine":
        import logging

        import dask.config
        from distributed import Client, LocalCluster

        if self.scheduler:
            try:
                self.client = Client(self.scheduler, timeout="20s")
            except (OSError, TimeoutError, ValueError) as err:
                raise SchemalogError(f"cannot reach the Dask scheduler at {self.scheduler}: {err}") from None
            return self
        # Ctrl-C at a terminal reaches every process of the group: a worker still starting (before
        # IgnoreInterrupt reaches it) died with a traceback. The processes are made while this
        # thread blocks SIGINT, and a child keeps a blocked signal across exec, so they never
        # take it; this process still does (Python runs its handler in the main thread whichever
        # thread the signal reaches). Their files go in a folder of this run's, removed as it
        # ends (Dask's default is $TMPDIR/dask-scratch-space, left behind).
        _remove_orphaned_scratch()
        self.scratch = tempfile.mkdtemp(prefix=f"{SCRATCH}{os.getpid()}-")
        self._config = dask.config.set({"temporary-directory": self.scratch})   # the scheduler's too
        _start_resource_tracker()
        held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            # No dashboard; the scheduler's HTTP server (its JSON and Prometheus routes), which it
            # starts anyway, on a free port of this machine's loopback: on its default, 8787,
            # a second sweep (or any server there) made distributed warn "Port 8787 is already
            # in use" with its own source path (issue 45)
            self.cluster = LocalCluster(n_workers=self.requested or local_cores(), threads_per_worker=1,
                                        processes=True, dashboard_address=None, silence_logs=logging.ERROR,
                                        scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})
            self.client = Client(self.cluster)
            from .workers import IgnoreInterrupt

            self.client.register_plugin(IgnoreInterrupt())
        except BaseException:
            self.__exit__()
            raise
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)      # a Ctrl-C held back arrives now
        return self

    def __exit__(self, *exc) -> None:
        for closing in (self.client, self.cluster):
            if closing is not None:
                try:
                    closing.close(timeout=10) if closing is self.cluster else closing.close()
                except Exception:          # already gone: nothing left to close
                    pass
        if self.scratch is not None:
            self._config.__exit__(None, None, None)
            shutil.rmtree(self.scratch, ignore_errors=True)
            self.scratch = None

    @property
    def workers(self) -> int:
        info = self.client.scheduler_info()["workers"]
        return sum(w.get("nthreads", 1) for w in info.values()) or len(info)

    @property
    def where(self) -> str:
        info = self.client.scheduler_info()["workers"]
        hosts = {w.get("host") for w in info.values()}
        threads = sum(w.get("nthreads", 1) for w in info.values())
        place = f"a LocalCluster on this machine ({local_cores()} cores)" if self.cluster else \
            f"the scheduler at {self.scheduler}, {len(hosts)} host{'s' if len(hosts) != 1 else ''}"
        return f"on {len(info)} Dask worker processes, {threads} thread{'s' if threads != 1 else ''} in all, on {place}"

    def map(self, fn, items: list, *args, priority=None) -> Iterator[tuple]:
        """Submit every item; yield (item, result or the exception) as each finishes."""
        from distributed import as_completed

        token = os.urandom(4).hex()
        futures = {}
        for i, item in enumerate(items):
            future = self.client.submit(fn, item, *args, key=f"schemalog-{token}-{i}", pure=False,
                                        priority=priority(item) if priority else 0)
            futures[future] = item
        self._keys = {f.key for f in futures}
        try:
            for future in as_completed(futures):
                item = futures[future]
                try:
                    result = future.result()
                except Exception as err:   # the task itself failed in Dask: a killed worker, too often
                    result = err
                self._keys.discard(future.key)
                yield item, result
        finally:
            for future in futures:
                if not future.done():
                    future.cancel()

    def running(self, left: int) -> int:
        try:
            processing = self.client.processing()
        except Exception:
            return min(left, self.workers)
        # a worker holds more than it runs (Dask sends a few ahead): at most one per thread runs
        return min(self.workers, sum(1 for keys in processing.values() for k in keys if k in self._keys))


def engine(serial: bool = False, workers: int | None = None, scheduler: str | None = None,
           or_serial: bool = False):
    """Serial(), or a DaskEngine on --scheduler / $SCHEMALOG_SCHEDULER / a LocalCluster.

    Without Dask installed, a DaskEngine is refused, saying how to install it; with `or_serial`
    (verify --each, whose results do not depend on where it runs) a LocalCluster asked for
    becomes Serial() with a note saying so. A scheduler named still needs Dask to reach it."""
    if serial:
        return Serial()
    scheduler = scheduler or os.environ.get("SCHEMALOG_SCHEDULER") or None
    if or_serial and scheduler is None and not have_dask():
        unused = f"; --workers {workers} needs it" if workers else ""
        return Serial("Dask is not installed", f"Dask is not installed ({INSTALL}{unused}): running in this "
                                               f"process, one task after another")
    return DaskEngine(workers, scheduler)


def have_dask() -> bool:
    """Whether dask.distributed can be imported."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


# ---------------------------------------------------------------------------
# A sweep

@dataclass
class Progress:
    """What a progress display shows: cells done (stored before or now), running and failed."""

    total: int
    done: int = 0
    failed: int = 0
    running: int = 0
    last: str = ""


@dataclass
class SweepStats:
    total: int
    stored: int = 0                 # done before this run: skipped
    computed: int = 0               # finished in this run (done or failed)
    failed: int = 0
    seconds: float = 0.0
    workers: int = 1
    cores: int = field(default_factory=local_cores)
    where: str = ""


def run_sweep(grid: Grid, store: Store, where, progress: Callable[[Progress], None] | None = None,
              cells: list[CellSpec] | None = None) -> SweepStats:
    """Run every cell not yet done in `store` on `where` (Serial or DaskEngine)."""
    cells = grid.cells() if cells is None else cells
    todo = [c for c in cells if not store.done(c.key)]
    stats = SweepStats(len(cells), stored=len(cells) - len(todo), workers=where.workers, where=where.where)
    state = Progress(len(cells), done=stats.stored, running=where.running(len(todo)))
    if progress:
        progress(state)
    started = time.perf_counter()
    try:
        # Largest first on a cluster, so the long cells do not end the sweep alone on one worker.
        for spec, row in where.map(run_cell, todo, grid, priority=lambda c: c.behaviours):
            if isinstance(row, BaseException):
                row = cell_row(spec, grid, "failed", f"{type(row).__name__}: {row}", {}, math.nan)
            store.add(row)
            stats.computed += 1
            state.done += row["status"] == "done"
            state.failed += row["status"] != "done"
            state.running = where.running(len(todo) - stats.computed)
            state.last = spec.title + ("" if row["status"] == "done" else f": FAILED ({row['message']})")
            if progress:
                progress(state)
    finally:
        store.flush()
        stats.seconds = time.perf_counter() - started
    stats.failed = sum(1 for c in cells if c.key in store.rows and store.rows[c.key]["status"] != "done")
    return stats


# ---------------------------------------------------------------------------
# Reports, rebuilt from the results file

def bench_results(grid: Grid, rows: list[dict], seconds: float = 0.0) -> bench.Results:
    """bench's Results from stored rows (done ones): its CSV, Markdown and figures follow."""
    plan = bench.BenchPlan(shapes=grid.shapes, reductions=grid.reductions, runs=grid.runs, sizes=grid.sizes,
                           ticks=grid.ticks, min_seconds=grid.min_seconds, max_states=grid.max_states,
                           verify_seconds=grid.verify_seconds, seed=grid.seeds[0], name=grid.name,
                           propagate=grid.propagate[0], measures=grid.measures, selectors=grid.selectors,
                           max_bdd_nodes=grid.max_bdd_nodes)
    results = bench.Results(plan, py_trees=bench.py_trees_version(), seconds=seconds)
    for row in rows:
        if row["status"] != "done":
            continue
        payload = json.loads(row["result"])
        if row["kind"] == "size":
            results.sizes.append(bench.SizeRow(**payload["size"]))
        elif row["kind"] == "coffee":
            results.coffee = results.coffee or cell_from_data(payload["cell"])
        else:
            results.cells.append(cell_from_data(payload["cell"]))
    return results


def runtime_rows(rows: list[dict]) -> list:
    return [runtime_from_data(json.loads(r["result"])["runtimes"]) for r in rows
            if r["status"] == "done" and r["kind"] == "generated" and "runtimes" in json.loads(r["result"])]


def sweep_markdown(grid: Grid, rows: list[dict], command: str, stats: SweepStats) -> str:
    """Every cell of the grid: its sizes, reduction, verdict and time, or why it failed."""
    done = sum(r["status"] == "done" for r in rows)
    out = [f"# schemalog sweep: {grid.name}", "",
           f"Command: `{command}`.", "",
           f"{done} of {stats.total} cells done, {stats.failed} failed, {stats.total - len(rows)} not run; "
           f"this run computed {stats.computed} in {stats.seconds:,.1f} s and skipped {stats.stored} already stored.",
           f"Ran {stats.where}: up to {stats.workers} cell{'s' if stats.workers != 1 else ''} at once on "
           f"{stats.cores} core{'s' if stats.cores != 1 else ''} of this machine"
           + (" (timings of cells that ran at once share the machine: compare with care)."
              if grid.timed and stats.workers > 1 else "."), "",
           "| cell | Bi | Bm | RD got | verify | states | s | status |",
           "|---|---:|---:|---:|---|---:|---:|---|"]
    for r in rows:
        def num(value, fmt: str) -> str:
            return "" if value is None or (isinstance(value, float) and math.isnan(value)) else format(value, fmt)
        status = "done" if r["status"] == "done" else f"FAILED: {r['message']}".replace("|", "\\|").replace("\n", " ")
        out.append(f"| {r['key']} | {r['behaviours']:,} | {num(r['behaviours_compressed'], ',')} | "
                   f"{num(r['rd_achieved'], '.2f')} | {r['verify_result'] or ''} | {num(r['verify_states'], ',')} | "
                   f"{num(r['seconds'], '.2f')} | {status} |")
    return "\n".join(out) + "\n"


def write_reports(grid: Grid, store: Store, out: Path, command: str, stats: SweepStats) -> list[Path]:
    """sweep.md; with `time`, bench's results.csv, results.md and figures; with `runtimes`, its tables."""
    rows = store.in_order(grid.cells())
    written = [out / "sweep.md"]
    write_in_folder(out / "sweep.md", sweep_markdown(grid, rows, command, stats))
    if grid.timed and any(r["status"] == "done" for r in rows):
        written += bench.write_results(bench_results(grid, rows, stats.seconds), out, command)
    if "runtimes" in grid.measures:
        from .runtimes import runtimes_csv, runtimes_markdown

        table = runtime_rows(rows)
        write_in_folder(out / "runtimes.csv", runtimes_csv(table))
        write_in_folder(out / "runtimes.md", runtimes_markdown(table, command))
        written += [out / "runtimes.csv", out / "runtimes.md"]
    return written


__all__ = ["Store", "Serial", "DaskEngine", "engine", "run_sweep", "run_cell", "measure", "SweepStats", "Progress",
           "write_reports", "bench_results", "runtime_rows", "non_timing", "have_pyarrow", "have_dask", "INSTALL"]
