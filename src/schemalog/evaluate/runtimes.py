"""The paper's claim in real runtimes: exported trees ticked in BehaviorTree.CPP and py_trees.

    measure_runtimes(shapes, reductions, seed) -> list[RuntimeRow]
    runtimes_markdown(rows, command) -> str;  runtimes_csv(rows) -> str

A row is one generated task of the paper's grid (Sec. IV-B), original against compressed, each
exported (formats/btcpp.py, formats/pytrees.py) and run once to completion in each runtime, its
actions performed in the emulated world of the original task. Per tick is the run's ticking
median over its ticks (one tick, one decision); per run is ticks x that median, a completed run
at steady state. The first ticks of a BT.CPP tree also parse the guards' scripts: that is
reported apart (warm-up), since it is paid once per loaded tree, not per run. Both leave out
the time spent in the actions' callbacks (the emulated robot and world: the same actions for
both trees), so they are the runtime's own work, and neither counts loading the tree into the
runtime (the paper times execution). Each tree is run REPEAT times and the fastest run kept
(the machine is shared: the slower ones measure other processes). A run that does not complete
is an error, not a data point.
"""

from __future__ import annotations

import csv
import io
import statistics
from dataclasses import dataclass

from ..errors import SchemalogError
from ..formats.btcpp import export_btcpp, run_btcpp
from ..formats.pytrees import export_pytrees, run_pytrees
from ..run.world import World
from ..task.compress import compress
from ..task.tree import count_nodes
from .generate import generate

PAPER_SHAPES = tuple((d, b) for d in (4, 5, 6) for b in (2, 3, 4))
PAPER_REDUCTIONS = (0.0, 0.3, 0.5, 0.7)
RUNTIMES = ("btcpp", "py_trees")
REPEAT = 3


@dataclass(frozen=True)
class Timed:
    """One tree's run in one runtime: its ticks, their total and their median."""

    ticks: int
    seconds: float
    median_tick: float

    @property
    def us_per_tick(self) -> float:
        return self.median_tick * 1e6

    @property
    def ms_per_run(self) -> float:
        """A completed run at steady state: its ticks at the median tick."""
        return self.ticks * self.median_tick * 1e3

    @property
    def warmup_ms(self) -> float:
        """What the run took beyond that: the first ticks parse the guards' scripts (BT.CPP)."""
        return max(0.0, self.seconds * 1e3 - self.ms_per_run)


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

    def reduction(self, runtime: str) -> float:
        """How much shorter the compressed run is than the original's (per run)."""
        o, c = self.times[(runtime, "original")].ms_per_run, self.times[(runtime, "compressed")].ms_per_run
        return 1 - c / o if o > 0 else 0.0


def measure_row(depth: int, children: int, rd: float, seed: int = 1, repeat: int = REPEAT) -> RuntimeRow:
    """Generate, compress, export and run one cell in both runtimes."""
    tree = generate(depth, children, rd, seed)
    result = compress(tree)
    initial = sorted(World(tree, ()).atoms, key=str)
    times = {}
    for which, t in (("original", tree), ("compressed", result.tree)):
        for runtime, export, run in (("btcpp", export_btcpp, run_btcpp), ("py_trees", export_pytrees, run_pytrees)):
            text = export(t, initial)
            best = None
            for _ in range(repeat):
                outcome = run(text, tree, initial)
                if outcome.status != "completed":
                    raise SchemalogError(f"the {which} tree of depth {depth}, {children} children, RD {rd:g} did "
                                         f"not complete in {runtime} ({outcome.status} after {outcome.ticks} ticks)")
                timed = Timed(outcome.ticks, outcome.control_seconds, statistics.median(outcome.tick_seconds))
                best = timed if best is None or timed.seconds < best.seconds else best
            times[(runtime, which)] = best
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
                "ticks", "us_per_tick", "ms_per_run", "warmup_ms"])
    for r in rows:
        for (runtime, which), t in r.times.items():
            w.writerow([r.depth, r.children, r.rd_asked, f"{r.rd:.3f}", r.nodes_before, r.nodes_after, runtime,
                        which, t.ticks, f"{t.us_per_tick:.1f}", f"{t.ms_per_run:.3f}", f"{t.warmup_ms:.3f}"])
    return out.getvalue()


def _pct(x: float) -> str:
    return f"{-x * 100:+.0f}%"


def runtimes_markdown(rows: list[RuntimeRow], command: str) -> str:
    """The table benchmarks/README.md shows: per tick and per run, original -> compressed."""
    import platform

    from importlib import metadata

    versions = ", ".join(f"{p} {metadata.version(p)}" for p in ("behaviortreepy", "py_trees"))
    lines = [f"`{command}` ({versions}; Python {platform.python_version()}): per tick the median tick, "
             f"per run ticks x the median tick, the fastest of {REPEAT} runs per tree, the actions' callbacks left out; ticks = decisions + 1 in BT.CPP "
             f"(the last finds the task accomplished).", "",
             "| shape | Bi -> Bm | RD | ticks o -> c | BT.CPP us/tick o -> c | BT.CPP ms/run o -> c | "
             "BT.CPP warm-up ms o -> c | py_trees us/tick o -> c | py_trees ms/run o -> c |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        bo, bc = r.times[("btcpp", "original")], r.times[("btcpp", "compressed")]
        po, pc = r.times[("py_trees", "original")], r.times[("py_trees", "compressed")]
        lines.append(f"| {r.depth}x{r.children} RD {r.rd_asked:g} | {r.nodes_before:,} -> {r.nodes_after:,} | "
                     f"{r.rd:.2f} | {bo.ticks:,} -> {bc.ticks:,} | {bo.us_per_tick:,.0f} -> {bc.us_per_tick:,.0f} | "
                     f"{bo.ms_per_run:,.1f} -> {bc.ms_per_run:,.1f} ({_pct(r.reduction('btcpp'))}) | "
                     f"{bo.warmup_ms:,.1f} -> {bc.warmup_ms:,.1f} | "
                     f"{po.us_per_tick:,.0f} -> {pc.us_per_tick:,.0f} | "
                     f"{po.ms_per_run:,.1f} -> {pc.ms_per_run:,.1f} ({_pct(r.reduction('py_trees'))}) |")
    return "\n".join(lines) + "\n"


__all__ = ["measure_runtimes", "measure_row", "runtimes_csv", "runtimes_markdown", "RuntimeRow", "Timed",
           "PAPER_SHAPES", "PAPER_REDUCTIONS"]
