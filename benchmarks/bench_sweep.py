"""The proof-only sweep on Dask against the same sweep in one process (issue 36).

    python benchmarks/bench_sweep.py [--seeds 5] [--large 7x5,8x5] [--no-four]

Cells: the paper's grid (depth 4-6 x 2-4 children x RD 0, 0.3, 0.5, 0.7) and the large shapes
at RD 0.5, each for seeds 1..N; every cell generated, compressed (propagate full) and proved
(verify --method auto, 20,000 states). Run three times in this one process's run: serially
(no Dask), on a LocalCluster of 2 single-threaded workers, and on a simulated cluster of 4
workers on the same 2 cores. Each cluster's start is timed apart from its sweep. The scheduler's
overhead per task is measured on the 4-worker cluster with tasks that do nothing, submitted
and gathered exactly as cells are. The three runs must agree on every non-timing result.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from dataclasses import replace

from schemalog.evaluate.grid import CellSpec, named_grid
from schemalog.evaluate.sweep import DaskEngine, Serial, Store, non_timing, run_sweep


def nothing(item, *args):
    return item


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--large", default="7x5,8x5", help="large shapes at RD 0.5 (depth x children)")
    parser.add_argument("--no-four", action="store_true", help="skip the simulated 4-worker cluster")
    parser.add_argument("--noop-tasks", type=int, default=1000)
    args = parser.parse_args()

    grid = replace(named_grid("paper"), measures=("compress", "prove"), coffee=False, sizes=(),
                   seeds=tuple(range(1, args.seeds + 1)), name="proofs")
    large = [tuple(int(x) for x in s.split("x")) for s in args.large.split(",") if s]
    cells = grid.cells() + [CellSpec("generated", d, b, 0.5, seed) for d, b in large for seed in grid.seeds]
    print(f"{len(cells)} cells: {len(grid.cells())} of the paper's grid and {len(cells) - len(grid.cells())} "
          f"large ({', '.join(f'{d}x{b}' for d, b in large)}, RD 0.5), seeds 1-{args.seeds}; Python "
          f"{platform.python_version()}", file=sys.stderr)

    runs = {}

    def sweep(label: str, where) -> None:
        store = Store(None, grid.settings())
        started = time.perf_counter()
        stats = run_sweep(grid, store, where, cells=cells)
        wall = time.perf_counter() - started
        busy = sum(r["seconds"] for r in store.rows.values())
        load = os.getloadavg()[0]
        runs[label] = {"wall": wall, "busy": busy, "failed": stats.failed,
                       "results": {k: non_timing(r) for k, r in store.rows.items()},
                       "large": sum(r["seconds"] for r in store.rows.values() if r["behaviours"] > 5000),
                       "load": load}
        print(f"{label}: {wall:,.1f} s wall, {busy:,.1f} s in cells, {stats.failed} failed; load average "
              f"{load:.2f} at the end", file=sys.stderr)

    sweep("serial", Serial())
    starts = {}
    for workers in (2,) if args.no_four else (2, 4):
        started = time.perf_counter()
        with DaskEngine(workers=workers) as where:
            starts[workers] = time.perf_counter() - started
            sweep(f"{workers} workers", where)
            if workers == 4:
                items = list(range(args.noop_tasks))
                begun = time.perf_counter()
                for _ in where.map(nothing, items):
                    pass
                noop = (time.perf_counter() - begun) / len(items)

    serial = runs["serial"]
    same = all(r["results"] == serial["results"] for r in runs.values())
    proved = sum(1 for r in serial["results"].values() if r["verify"] == "proved")
    print(f"\n`python benchmarks/bench_sweep.py --seeds {args.seeds} --large {args.large}`: {len(cells)} cells, "
          f"{proved} proved, {len(cells) - proved} not (a limit or a counterexample); non-timing results identical in every run: "
          f"{'yes' if same else 'NO'}\n")
    print("| run | cluster start s | sweep wall s | speed-up vs serial | time inside cells s | of which large cells s "
          "| load average (1 min) at its end |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for label, r in runs.items():
        workers = int(label.split()[0]) if label != "serial" else None
        start = f"{starts[workers]:.1f}" if workers else "-"
        print(f"| {label} | {start} | {r['wall']:,.1f} | x{serial['wall'] / r['wall']:.2f} | {r['busy']:,.1f} | "
              f"{r['large']:,.1f} | {r['load']:.2f} |")
    if "4 workers" in runs:
        four = runs["4 workers"]
        print(f"\n4 workers on 2 cores: scheduler overhead per task {noop * 1e3:.2f} ms (round trip of "
              f"{args.noop_tasks} tasks that do nothing, submitted and gathered as cells are); per cell in the "
              f"sweep, wall x workers minus the time inside cells over the cells: "
              f"{(four['wall'] * 4 - four['busy']) / len(cells) * 1e3:,.0f} ms (idle workers at the end included)")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
