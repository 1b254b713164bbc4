"""The paper's claim in real runtimes: exported trees ticked in BehaviorTree.CPP and py_trees.

    measure_runtimes(shapes, reductions, seed) -> list[RuntimeRow]
    runtimes_markdown(rows, command) -> str;  runtimes_csv(rows) -> str
    noise_floor(rows, runtime) -> float | None

A row is one generated task of the paper's grid (Sec. IV-B), original against compressed, each
exported (formats/btcpp.py, formats/pytrees.py) and run to completion REPEAT (5) times in each
runtime (after one untimed warm-up run each, original and compressed runs alternated so that a
shared machine's drift falls on both), its actions performed in the emulated world of the
original task. Per run is a whole
run timed, from its first tick to the task accomplished: the runtime's own time
(BtRun.control_seconds), the median over the REPEAT runs with its IQR. Per tick is the median
over every tick of those runs (one tick, one decision), with its IQR. Both leave out the time
spent in the actions' callbacks (the emulated robot and world: the same actions for both trees),
and neither counts loading the tree into the runtime (the paper times execution). The medians
and quartiles are bench.py's Spread, and a saving per run is bench.py's reduction_spread: from
the medians, its range from the quartiles.

There is no warm-up column any more: BT.CPP parses each guard's script the first time it is
evaluated, and every run here loads its tree afresh, so every timed run pays that parsing and
the per-run figure includes it; it used to be estimated as the run's time minus ticks x median
tick, which is not a measurement. The noise floor (noise_floor) is, per runtime, the largest
|saving| between rows whose original and compressed trees are identical (RD 0, nodes before ==
nodes after): the table states it, and marks a saving within it as "within noise". A run that
does not complete is an error, not a data point.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass

from ..errors import SchemalogError
from ..formats.btcpp import export_btcpp, run_btcpp
from ..formats.pytrees import export_pytrees, run_pytrees
from ..run.world import World
from ..task.compress import compress
from ..task.tree import count_nodes
from .bench import Spread, _pct, reduction_spread
from .generate import generate

PAPER_SHAPES = tuple((d, b) for d in (4, 5, 6) for b in (2, 3, 4))
PAPER_REDUCTIONS = (0.0, 0.3, 0.5, 0.7)
RUNTIMES = ("btcpp", "py_trees")
NAMES = {"btcpp": "BT.CPP", "py_trees": "py_trees"}
REPEAT = 5


@dataclass(frozen=True)
class Timed:
    """One tree in one runtime over its REPEAT whole runs: the ticks of a run, each run's control
    time (s), and the median and quartiles of every tick of those runs (s)."""

    ticks: int
    run_seconds: tuple[float, ...]
    tick_median: float
    tick_q1: float
    tick_q3: float

    @property
    def run_ms(self) -> Spread:
        """A whole run's control time (ms): median and quartiles over the runs."""
        return Spread.of(list(self.run_seconds), 1e3)

    @property
    def tick_us(self) -> Spread:
        """A tick's control time (us): median and quartiles over every tick of every run."""
        return Spread(self.tick_median * 1e6, self.tick_q1 * 1e6, self.tick_q3 * 1e6)

    @property
    def ms_per_run(self) -> float:
        return self.run_ms.median

    @property
    def us_per_tick(self) -> float:
        return self.tick_median * 1e6

    @staticmethod
    def from_data(data: dict) -> Timed:
        """From asdict's fields (JSON turns the tuple into a list). A row stored before whole runs
        were kept (ticks, seconds, median_tick: one run's time) reads as one run, its tick
        median without quartiles."""
        if "run_seconds" not in data:
            m = data["median_tick"]
            return Timed(data["ticks"], (data["seconds"],), m, m, m)
        return Timed(data["ticks"], tuple(data["run_seconds"]), data["tick_median"], data["tick_q1"],
                     data["tick_q3"])


@dataclass(frozen=True)
class RuntimeRow:
    """One cell of the grid in both runtimes, original and compressed."""

    depth: int
    children: int
    rd_asked: float
    rd: float
    nodes_before: int
    nodes_after: int
    times: dict          # (runtime, "original" | "compressed") -> Timed

    @property
    def identical(self) -> bool:
        """Nothing merged: the compressed tree is the original (RD 0, the same nodes)."""
        return self.rd == 0 and self.nodes_before == self.nodes_after

    def reduction_spread(self, runtime: str) -> Spread:
        """How much less a compressed run takes than an original one (0.27 = 27% less), from the
        medians of the whole runs, its range from their quartiles."""
        return reduction_spread(self.times[(runtime, "original")].run_ms,
                                self.times[(runtime, "compressed")].run_ms)

    def reduction(self, runtime: str) -> float:
        """How much shorter the compressed run is than the original's (per run, the medians)."""
        return self.reduction_spread(runtime).median


def measure_row(depth: int, children: int, rd: float, seed: int = 1, repeat: int = REPEAT) -> RuntimeRow:
    """Generate, compress, export and run one cell in both runtimes, each tree `repeat` times."""
    tree = generate(depth, children, rd, seed)
    result = compress(tree)
    initial = sorted(World(tree, ()).atoms, key=str)
    trees = (("original", tree), ("compressed", result.tree))
    times = {}
    for runtime, export, run in (("btcpp", export_btcpp, run_btcpp), ("py_trees", export_pytrees, run_pytrees)):
        texts = {which: export(t, initial) for which, t in trees}
        runs: dict[str, list] = {which: [] for which, _ in trees}

        def timed(which: str):
            outcome = run(texts[which], tree, initial)
            if outcome.status != "completed":
                raise SchemalogError(f"the {which} tree of depth {depth}, {children} children, RD {rd:g} did "
                                     f"not complete in {runtime} ({outcome.status} after {outcome.ticks} ticks)")
            return outcome

        for which, _ in trees:
            timed(which)                 # a warm-up run each, not kept: first imports and caches
        for _ in range(repeat):
            for which, _ in trees:       # alternated, so that drift on a shared machine falls on both
                outcome = timed(which)
                done = runs[which]
                if done and outcome.ticks != done[0].ticks:
                    raise SchemalogError(f"the {which} tree of depth {depth}, {children} children, RD {rd:g} took "
                                         f"{done[0].ticks} then {outcome.ticks} ticks in {runtime}")
                done.append(outcome)
        for which, done in runs.items():
            tick = Spread.of([s for r in done for s in r.tick_seconds])
            times[(runtime, which)] = Timed(done[0].ticks, tuple(r.control_seconds for r in done),
                                            tick.median, tick.q1, tick.q3)
    return RuntimeRow(depth, children, rd, result.reduction_degree, count_nodes(tree), result.nodes_after, times)


def measure_runtimes(shapes=PAPER_SHAPES, reductions=PAPER_REDUCTIONS, seed: int = 1, progress=None,
                     repeat: int = REPEAT) -> list[RuntimeRow]:
    """Every cell of the grid, in one run."""
    rows = []
    for depth, children in shapes:
        for rd in reductions:
            if progress:
                progress(f"depth {depth}, {children} children, RD {rd:g}")
            rows.append(measure_row(depth, children, rd, seed, repeat))
    return rows


def runtimes_csv(rows: list[RuntimeRow]) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["depth", "children", "rd_asked", "rd", "nodes_before", "nodes_after", "runtime", "tree",
                "ticks", "runs", "us_per_tick", "us_per_tick_q1", "us_per_tick_q3",
                "ms_per_run", "ms_per_run_q1", "ms_per_run_q3"])
    for r in rows:
        for (runtime, which), t in r.times.items():
            tick, run = t.tick_us, t.run_ms
            w.writerow([r.depth, r.children, r.rd_asked, f"{r.rd:.3f}", r.nodes_before, r.nodes_after, runtime,
                        which, t.ticks, len(t.run_seconds), f"{tick.median:.1f}", f"{tick.q1:.1f}", f"{tick.q3:.1f}",
                        f"{run.median:.4f}", f"{run.q1:.4f}", f"{run.q3:.4f}"])
    return out.getvalue()


def noise_floor(rows: list[RuntimeRow], runtime: str) -> float | None:
    """The largest |saving per run| among rows whose two trees are identical: what the machine's
    noise alone gives. None when no row has identical trees."""
    seen = [abs(r.reduction(runtime)) for r in rows if r.identical and not math.isnan(r.reduction(runtime))]
    return max(seen) if seen else None


def _floor_text(floor: float) -> str:
    return f"\u00b1{floor * 100:.0f}%"


def _saving(spread: Spread, floor: float | None) -> str:
    """`-48%, range -40% to -55%`, or `-3% (within noise ±7%), range ...` when within the floor."""
    if math.isnan(spread.median):
        return "n/a"
    within = f" (within noise {_floor_text(floor)})" if floor is not None and abs(spread.median) <= floor else ""
    return f"{_pct(spread.median)}{within}, range {_pct(spread.q1)} to {_pct(spread.q3)}"


def _pair(o: Spread, c: Spread, digits: int) -> str:
    return f"{o.text(digits)} -> {c.text(digits)}"


def runtimes_markdown(rows: list[RuntimeRow], command: str) -> str:
    """The table benchmarks/README.md shows: per tick and per run, original -> compressed, medians
    with their IQR, each saving judged against the identical-tree noise floor."""
    import platform

    from importlib import metadata

    versions = ", ".join(f"{p} {metadata.version(p)}" for p in ("behaviortreepy", "py_trees"))
    counts = sorted({len(t.run_seconds) for r in rows for t in r.times.values()})
    runs = " or ".join(str(n) for n in counts) or str(REPEAT)
    floors = {rt: noise_floor(rows, rt) for rt in RUNTIMES}
    identical = sum(r.identical for r in rows)
    if identical:
        floor = (f"Noise floor, the largest saving between identical trees ({identical} rows of RD 0 where "
                 f"nothing merged): " + ", ".join(f"{NAMES[rt]} {_floor_text(f)}" for rt, f in floors.items())
                 + "; a saving within it is marked \"within noise\".")
    else:
        floor = "No row has identical trees, so there is no noise floor: judge each saving by its range."
    lines = [f"`{command}` ({versions}; Python {platform.python_version()}): {runs} whole runs per tree; "
             f"per run the median of their control time (first tick to the task accomplished, the actions' "
             f"callbacks left out) with its IQR, per tick the median of every tick of those runs with its IQR; "
             f"a saving is per run, from the medians, its range from the quartiles. {floor} "
             f"Ticks = decisions + 1 in BT.CPP (the last finds the task accomplished).", "",
             "| shape | Bi -> Bm | RD | ticks o -> c | BT.CPP us/tick o -> c | BT.CPP ms/run o -> c | "
             "BT.CPP saving per run | py_trees us/tick o -> c | py_trees ms/run o -> c | py_trees saving per run |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        bo, bc = r.times[("btcpp", "original")], r.times[("btcpp", "compressed")]
        po, pc = r.times[("py_trees", "original")], r.times[("py_trees", "compressed")]
        lines.append(f"| {r.depth}x{r.children} RD {r.rd_asked:g} | {r.nodes_before:,} -> {r.nodes_after:,} | "
                     f"{r.rd:.2f} | {bo.ticks:,} -> {bc.ticks:,} | {_pair(bo.tick_us, bc.tick_us, 0)} | "
                     f"{_pair(bo.run_ms, bc.run_ms, 2)} | {_saving(r.reduction_spread('btcpp'), floors['btcpp'])} | "
                     f"{_pair(po.tick_us, pc.tick_us, 0)} | {_pair(po.run_ms, pc.run_ms, 2)} | "
                     f"{_saving(r.reduction_spread('py_trees'), floors['py_trees'])} |")
    return "\n".join(lines) + "\n"


SUMMARY_COLUMNS = 100      # what a terminal is given: the full table goes to runtimes.md


def runtimes_summary(rows: list[RuntimeRow]) -> list[str]:
    """What `bench --runtimes` prints: per tree its shape, behaviours, ticks and the saving per
    completed run in each runtime (median, `~` within the noise floor), each line at most
    SUMMARY_COLUMNS wide; runtimes.md has the medians, quartiles and ranges beside them."""
    floors = {rt: noise_floor(rows, rt) for rt in RUNTIMES}

    def saving(r: RuntimeRow, runtime: str) -> str:
        spread = r.reduction_spread(runtime)
        within = floors[runtime] is not None and abs(spread.median) <= floors[runtime]
        return _pct(spread.median) + ("~" if within and not math.isnan(spread.median) else "")

    header = f"{'tree':<12} {'Bi -> Bm':>15} {'RD':>5} {'ticks o -> c':>15}  {'BT.CPP':>8}  {'py_trees':>8}"
    lines = ["saving per completed run, original -> compressed (median of the runs; ~ within the noise "
             "floor):", header]
    for r in rows:
        bo, bc = r.times[("btcpp", "original")], r.times[("btcpp", "compressed")]
        lines.append(f"{f'{r.depth}x{r.children} RD {r.rd_asked:g}':<12} "
                     f"{f'{r.nodes_before:,} -> {r.nodes_after:,}':>15} {r.rd:5.2f} "
                     f"{f'{bo.ticks:,} -> {bc.ticks:,}':>15}  {saving(r, 'btcpp'):>8}  {saving(r, 'py_trees'):>8}")
    if any(f is not None for f in floors.values()):
        lines.append("noise floor (identical trees): " + ", ".join(
            f"{NAMES[rt]} {_floor_text(f)}" for rt, f in floors.items() if f is not None))
    return lines


__all__ = ["measure_runtimes", "measure_row", "runtimes_csv", "runtimes_markdown", "runtimes_summary",
           "noise_floor", "RuntimeRow",
           "Timed", "PAPER_SHAPES", "PAPER_REDUCTIONS", "REPEAT"]
