"""The paper's evaluation (Sec. IV), reproduced, and set beside py_trees in the same run.

    run_bench(plan, out) -> Results          # measures, then writes CSV, Markdown and figures

A Cell is one point of the grid: a generated task (depth, children, reduction degree asked),
compressed by Algorithm 1, and timed original against compressed. A Timing is one tree under
one executive over the cell's runs:

    selector    scan        every behaviour checked at every decision (the paper's cost model)
                incremental what the last action touched, priority queues per object
                py_trees    one tick of an equivalent py_trees tree per decision (the peer)
    per decision the selector's work for one decision (for py_trees: one tick)
    per run      the sum over a run: the paper's "execution time" of a task, with the robot
                 manager acknowledging every action at once (for py_trees: ticks x decisions)

Runs differ in the object configuration (the paper's protocol: 10 runs per tree). Every run of
a compressed tree goes to completion against the world of the original task; a run that does
not is an error, not a data point.
"""

from __future__ import annotations

import csv
import io
import math
import statistics
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..task import conditions as cond
from ..task.compress import compress
from ..formats.documents import document_from_text, write_atomically
from ..errors import SchemalogError
from ..run.execute import Executive
from .generate import TOLERANCE, generate, node_count, scene_for, shortfall
from ..run.scene import Scene, scene_from_yaml
from ..logic.parse import parse_term
from ..shipped import shipped_text
from ..task.tree import Behaviour, count_nodes, instantiate, walk
from ..run.verify import prove
from ..run.world import World, initial_state

Shape = tuple[int, int]                     # (depth, children)
TREES = ("original", "compressed")
SELECTORS = ("scan", "incremental", "py_trees")

# The paper's own figures (Sec. IV-C, IV-D), set beside ours in every report.
PAPER = {
    "85 nodes, RD 0.3": "1.4 -> 1.1 ms (-20%)",
    "1,365 nodes, RD 0 -> 0.7": "0.23 -> 0.03 s (-87%)",
    "best reduction": "93%",
    "coffee and tea (63 -> 33)": "1.5 -> 1.1 ms (-27%)",
}


@dataclass(frozen=True)
class BenchPlan:
    """What to measure."""

    shapes: tuple[Shape, ...]
    reductions: tuple[float, ...] = (0.0, 0.3, 0.5, 0.7)
    runs: int = 10
    sizes: tuple[Shape, ...] = ()          # scaling of the selectors beyond the grid
    ticks: int = 5                         # py_trees ticks timed per run (spread over the run)
    max_states: int = 20_000               # verification: beyond this a cell is "limit"
    seed: int = 1
    name: str = "paper"


PAPER_PLAN = BenchPlan(shapes=tuple((d, b) for d in (4, 5, 6) for b in (2, 3, 4)),
                       sizes=((6, 4), (7, 4), (8, 4), (9, 4), (8, 5), (6, 10)))
QUICK_PLAN = BenchPlan(shapes=PAPER_PLAN.shapes, runs=2, sizes=((4, 4), (6, 4), (7, 4)), ticks=2,
                       max_states=5_000, name="quick")


@dataclass
class Timing:
    """One tree under one selector, over a cell's runs."""

    decisions: list[int] = field(default_factory=list)          # per run
    per_run: list[float] = field(default_factory=list)          # seconds of selection per run
    per_decision: list[float] = field(default_factory=list)     # seconds, every decision timed

    @property
    def us_per_decision(self) -> float:
        return statistics.fmean(self.per_decision) * 1e6 if self.per_decision else math.nan

    @property
    def ms_per_run(self) -> float:
        return statistics.fmean(self.per_run) * 1e3 if self.per_run else math.nan

    @property
    def mean_decisions(self) -> float:
        return statistics.fmean(self.decisions) if self.decisions else math.nan


@dataclass
class Cell:
    """One generated task of the grid (or the coffee-and-tea task), measured."""

    name: str
    depth: int
    children: int
    behaviours: int
    rd_asked: float | None
    rd_got: float
    merged: int                               # Bm
    compress_seconds: float
    verify_seconds: float | None = None
    verify_result: str = "not run"
    verify_states: int = 0
    timings: dict[tuple[str, str], Timing] = field(default_factory=dict)

    def timing(self, tree: str, selector: str) -> Timing:
        return self.timings.setdefault((tree, selector), Timing())

    def reduction(self, selector: str, per: str = "run") -> float:
        """How much less time the compressed tree takes than the original (0.27 = 27% less)."""
        o, c = self.timing("original", selector), self.timing("compressed", selector)
        a, b = (o.ms_per_run, c.ms_per_run) if per == "run" else (o.us_per_decision, c.us_per_decision)
        return 1 - b / a if a and not math.isnan(a) and not math.isnan(b) else math.nan


@dataclass
class SizeRow:
    """The selectors on one large original tree: per-decision cost against size."""

    depth: int
    children: int
    behaviours: int
    decisions: int
    incremental_us: float
    incremental_median_us: float
    scan_us: float                            # over the first `sample` decisions
    py_trees_us: float                        # one tick of the whole tree


@dataclass
class Results:
    plan: BenchPlan
    cells: list[Cell] = field(default_factory=list)
    coffee: Cell | None = None
    sizes: list[SizeRow] = field(default_factory=list)
    py_trees: str = ""                        # its version, or why it is missing
    seconds: float = 0.0


# ---------------------------------------------------------------------------
# Timing one tree

def time_runs(trees: dict[str, Behaviour], original: Behaviour, scenes: list[Scene], cell: Cell,
              initial: frozenset = frozenset(), ticks: int = 0) -> None:
    """Run each tree (original, compressed) once per scene with each selector; record the
    timings in `cell`. The trees take turns, first one then the other leading, so that a
    change in the machine's load falls on both alike."""
    tickers = {which: py_trees_ticker(tree) for which, tree in trees.items()} if ticks else {}
    order = list(trees)
    for run, scene in enumerate(scenes):
        for which in (order if run % 2 == 0 else order[::-1]):
            tree = trees[which]
            for selector in ("scan", "incremental"):
                ex = Executive(tree, World(original, initial), scene, selector=selector, detect_loops=False)
                seconds = [decision.seconds for decision in ex]
                if not ex.outcome.completed:
                    raise SchemalogError(f"bench: the {which} tree of {cell.name} did not complete with the "
                                         f"{selector} selector: {ex.outcome.reason}")
                timing = cell.timing(which, selector)
                timing.decisions.append(len(seconds))
                timing.per_run.append(sum(seconds))
                timing.per_decision.extend(seconds)
            ticker = tickers.get(which)
            if ticker is not None:
                spent = tick_times(ticker, _replay_states(original, initial, ex.trace, ticks))
                peer = cell.timing(which, "py_trees")
                peer.per_decision.extend(spent)
                peer.decisions.append(len(seconds))
                peer.per_run.append(statistics.fmean(spent) * len(seconds))


def tick_times(ticker: Callable[[frozenset], float], states: list[frozenset]) -> list[float]:
    """One timed tick per state, after an untimed one (the first tick initialises every node)."""
    ticker(states[0])
    return [ticker(state) for state in states]


def _replay_states(original: Behaviour, initial: frozenset, trace: list, ticks: int) -> list[frozenset]:
    """`ticks` world states spread over a run: the state before each sampled action."""
    world = World(original, initial)
    posts = {n.label: n.post for n in walk(original) if not n.children}   # a label names one schema
    every = max(1, len(trace) // max(1, ticks))
    states = []
    for i, action in enumerate(trace):
        if i % every == 0 and len(states) < ticks:
            states.append(world.atoms)
        world.perform(posts[action])
    return states or [world.atoms]


def py_trees_tree(root: Behaviour, state: set):
    """A py_trees tree of the same shape as `root`, its leaves reading `state` (a set of atoms).

    Composites are Parallel (a tick visits every child, as the attentional system checks
    every behaviour). A leaf succeeds when its post-condition holds and otherwise runs,
    having checked its pre-condition (`enabled`: the work the scan selector does per leaf);
    a leaf waiting for its releaser runs rather than fails, since a failure would make its
    Parallel stop its siblings. None when py_trees is not installed.
    """
    try:
        import py_trees
    except ImportError:
        return None

    class Leaf(py_trees.behaviour.Behaviour):
        def __init__(self, name: str, pre: cond.Condition, post: cond.Condition) -> None:
            super().__init__(name)
            self.pre, self.post = pre, post
            self.enabled = False

        def update(self):
            if cond.holds(self.post, state):
                return py_trees.common.Status.SUCCESS
            self.enabled = cond.holds(self.pre, state)
            return py_trees.common.Status.RUNNING

    policy = py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=False)
    built: dict[int, object] = {}
    stack: list[tuple[Behaviour, bool]] = [(root, False)]
    while stack:                       # iterative: 100,000-behaviour trees are deeper than recursion likes
        node, ready = stack.pop()
        if not node.children:
            built[id(node)] = Leaf(node.name, node.pre, node.post)
        elif ready:
            composite = py_trees.composites.Parallel(name=node.name, policy=policy, children=[])
            composite.add_children([built.pop(id(c)) for c in node.children])
            built[id(node)] = composite
        else:
            stack.append((node, True))
            stack.extend((c, False) for c in node.children)
    return built[id(root)]


def py_trees_ticker(root: Behaviour) -> Callable[[frozenset], float] | None:
    """A function timing one tick of `root`'s py_trees tree in a given state (None without py_trees)."""
    state: set = set()
    tree = py_trees_tree(root, state)
    if tree is None:
        return None

    def tick(atoms: frozenset) -> float:
        state.clear()
        state.update(atoms)
        started = time.perf_counter()
        tree.tick_once()
        return time.perf_counter() - started

    return tick


def py_trees_version() -> str:
    """The installed py_trees version, or "" when it is missing."""
    from importlib import metadata
    try:
        return metadata.version("py_trees")
    except metadata.PackageNotFoundError:
        return ""


# ---------------------------------------------------------------------------
# The grid

def verify_cell(original: Behaviour, compressed: Behaviour, initial: frozenset, max_states: int,
                cell: Cell) -> None:
    """Prove the compressed tree against the original where that is exact within max_states."""
    world = World(original, initial)
    started = time.perf_counter()
    report = prove(original, compressed, world, [world.atoms], max_states=max_states)
    cell.verify_seconds = time.perf_counter() - started
    cell.verify_states = report.compressed_states + report.original_states
    cell.verify_result = ("counterexample" if report.violated else
                          "proved" if report.exhaustive and report.sound and report.complete else "limit")


def timed_compress(tree: Behaviour, repeat: int = 3):
    """Compress (propagate full); the best time of `repeat` (the first pays for warming up)."""
    best = math.inf
    for _ in range(repeat):
        started = time.perf_counter()
        result = compress(tree)
        best = min(best, time.perf_counter() - started)
    return result, best


def measure_cell(depth: int, children: int, rd: float, plan: BenchPlan) -> Cell:
    """Generate, compress, verify and time one cell of the grid."""
    tree = generate(depth, children, rd, plan.seed)
    result, seconds = timed_compress(tree)
    cell = Cell(f"depth {depth}, {children} children, RD {rd:g}", depth, children, result.nodes_before, rd,
                result.reduction_degree, result.nodes_after, seconds)
    scenes = [scene_for(children, seed=run) for run in range(plan.runs)]
    time_runs({"original": tree, "compressed": result.tree}, tree, scenes, cell, ticks=plan.ticks)
    verify_cell(tree, result.tree, frozenset(), plan.max_states, cell)
    return cell


COFFEE_FILE = "kb/tasks/prepare_coffee_and_tea.pl"
KITCHEN_FILE = "kb/scenes/kitchen.yaml"


def measure_coffee(plan: BenchPlan) -> Cell:
    """The paper's real task (Sec. IV-D): 10 runs in 10 object configurations of the kitchen."""
    kb = document_from_text(shipped_text(COFFEE_FILE), COFFEE_FILE).to_kb()
    tree = instantiate(kb, parse_term("prepareboth"))
    result, seconds = timed_compress(tree)
    initial = frozenset(initial_state(kb))
    cell = Cell("coffee and tea", result.depth_before, 0, result.nodes_before, None, result.reduction_degree,
                result.nodes_after, seconds)
    kitchen = scene_from_yaml(shipped_text(KITCHEN_FILE), KITCHEN_FILE)
    scenes = [kitchen.jittered(run, 0.05) for run in range(plan.runs)]
    time_runs({"original": tree, "compressed": result.tree}, tree, scenes, cell, initial, plan.ticks)
    verify_cell(tree, result.tree, initial, plan.max_states, cell)
    return cell


def measure_size(depth: int, children: int, plan: BenchPlan, sample: int = 20) -> SizeRow:
    """One large original tree (RD 0.5): a whole incremental run, a scan sample, and py_trees
    ticks at states spread over the run."""
    tree = generate(depth, children, 0.5, plan.seed)
    scene = scene_for(children)
    ex = Executive(tree, World(tree), scene, selector="incremental", detect_loops=False)
    inc = [d.seconds for d in ex]
    if not ex.outcome.completed:
        raise SchemalogError(f"bench: depth {depth} x {children} did not complete: {ex.outcome.reason}")
    scan_ex = Executive(tree, World(tree), scene, selector="scan", detect_loops=False)
    scan = []
    for decision in scan_ex:
        scan.append(decision.seconds)
        if len(scan) >= sample:
            break
    ticker = py_trees_ticker(tree)
    ticks = tick_times(ticker, _replay_states(tree, frozenset(), ex.trace, max(1, min(plan.ticks, 3)))) \
        if ticker else []
    return SizeRow(depth, children, count_nodes(tree), len(inc), statistics.fmean(inc) * 1e6,
                   statistics.median(inc) * 1e6, statistics.fmean(scan) * 1e6,
                   statistics.fmean(ticks) * 1e6 if ticks else math.nan)


def run_bench(plan: BenchPlan, progress=None) -> Results:
    """Measure everything the plan asks for; `progress(description)` is told of each step."""
    started = time.perf_counter()
    results = Results(plan, py_trees=py_trees_version())
    say = progress or (lambda description: None)
    for depth, children in plan.shapes:
        for rd in plan.reductions:
            say(f"depth {depth}, {children} children ({node_count(depth, children):,} behaviours), RD {rd:g}")
            results.cells.append(measure_cell(depth, children, rd, plan))
    say("coffee and tea")
    results.coffee = measure_coffee(plan)
    for depth, children in plan.sizes:
        say(f"selectors at {node_count(depth, children):,} behaviours")
        results.sizes.append(measure_size(depth, children, plan))
    results.seconds = time.perf_counter() - started
    return results


def steps(plan: BenchPlan) -> int:
    """How many progress steps run_bench reports."""
    return len(plan.shapes) * len(plan.reductions) + 1 + len(plan.sizes)


# ---------------------------------------------------------------------------
# Reports

CSV_FIELDS = ["task", "depth", "children", "behaviours", "rd_asked", "rd_achieved", "behaviours_compressed",
              "tree", "selector", "runs", "decisions_per_run", "us_per_decision", "ms_per_run",
              "compress_ms", "verify_s", "verify_result", "verify_states"]


def to_csv(results: Results) -> str:
    """One row per task, tree and selector."""
    out = io.StringIO()
    writer = csv.DictWriter(out, CSV_FIELDS, lineterminator="\n")
    writer.writeheader()
    for cell in _all_cells(results):
        for (tree, selector), t in sorted(cell.timings.items()):
            if not t.per_decision:
                continue
            writer.writerow({
                "task": "generated" if cell.rd_asked is not None else cell.name, "depth": cell.depth,
                "children": cell.children or "", "behaviours": cell.behaviours,
                "rd_asked": "" if cell.rd_asked is None else cell.rd_asked, "rd_achieved": f"{cell.rd_got:.4f}",
                "behaviours_compressed": cell.merged, "tree": tree, "selector": selector,
                "runs": len(t.per_run), "decisions_per_run": f"{t.mean_decisions:g}",
                "us_per_decision": f"{t.us_per_decision:.3f}", "ms_per_run": f"{t.ms_per_run:.4f}",
                "compress_ms": f"{cell.compress_seconds * 1e3:.3f}",
                "verify_s": "" if cell.verify_seconds is None else f"{cell.verify_seconds:.3f}",
                "verify_result": cell.verify_result, "verify_states": cell.verify_states})
    return out.getvalue()


def _all_cells(results: Results) -> list[Cell]:
    return results.cells + ([results.coffee] if results.coffee else [])


def _f(value: float, digits: int = 1) -> str:
    return "n/a" if value is None or math.isnan(value) else f"{value:,.{digits}f}"


def _pct(value: float) -> str:
    return "n/a" if math.isnan(value) else f"{value * 100:+.0f}%".replace("+", "-", 1) if value > 0 \
        else f"+{-value * 100:.0f}%"


def headlines(results: Results) -> list[str]:
    """The summary: the paper's figures beside ours, and the targets of the evaluation."""
    lines = []
    cells = results.cells
    by = {(c.depth, c.children, c.rd_asked): c for c in cells}
    if cells:
        worst = max(abs(c.rd_got - c.rd_asked) for c in cells)
        misses = [c for c in cells if shortfall(c.depth, c.children, c.rd_asked, c.rd_got)]
        lines.append(f"reduction degree: every cell within {worst:.3f} of the request "
                     f"(tolerance {TOLERANCE})" if not misses else
                     f"reduction degree: {len(misses)} cell(s) beyond {TOLERANCE}: " +
                     "; ".join(f"{c.name}: {shortfall(c.depth, c.children, c.rd_asked, c.rd_got)}" for c in misses))
    big0, big7 = by.get((6, 4, 0.0)), by.get((6, 4, 0.7))
    if big0 and big7:
        o, c = big0.timing("original", "scan"), big7.timing("compressed", "scan")
        cut = 1 - c.ms_per_run / o.ms_per_run
        lines.append(f"scan, 1,365 behaviours, RD 0 -> 0.7: {o.ms_per_run / 1e3:.3f} -> {c.ms_per_run / 1e3:.3f} s "
                     f"per run ({_pct(cut)}; paper 0.23 -> 0.03 s, -87%; target at least 87%: "
                     f"{'met' if cut >= 0.87 else 'MISSED'}), per decision {o.us_per_decision:,.0f} -> "
                     f"{c.us_per_decision:,.0f} us ({_pct(1 - c.us_per_decision / o.us_per_decision)})")
        inc = big0.timing("original", "incremental")
        tick = big0.timing("original", "py_trees")
        vs_scan = o.us_per_decision / inc.us_per_decision
        line = (f"incremental, 1,365 behaviours: {inc.us_per_decision:,.1f} us per decision, {vs_scan:,.0f}x "
                f"faster than the scan ({'met' if vs_scan >= 100 else 'MISSED'}: target 100x)")
        if tick.per_decision:
            vs_tick = tick.us_per_decision / inc.us_per_decision
            line += (f", {vs_tick:,.0f}x faster than a py_trees tick of {tick.us_per_decision:,.0f} us "
                     f"({'met' if vs_tick >= 100 else 'MISSED'}: target 100x)")
        lines.append(line)
    mid = by.get((4, 4, 0.3))
    if mid:
        lines.append(f"scan, 85 behaviours, RD 0.3: {mid.timing('original', 'scan').ms_per_run:.3f} -> "
                     f"{mid.timing('compressed', 'scan').ms_per_run:.3f} ms per run "
                     f"({_pct(mid.reduction('scan'))}; paper 1.4 -> 1.1 ms, -20%)")
    if cells:
        best = max(cells, key=lambda c: (c.reduction("scan") if not math.isnan(c.reduction("scan")) else -1))
        lines.append(f"best reduction (scan, per run): {_pct(best.reduction('scan'))} at {best.name} "
                     f"(paper: 93%)")
    if results.coffee:
        c = results.coffee
        o, m = c.timing("original", "scan"), c.timing("compressed", "scan")
        lines.append(f"coffee and tea, {c.behaviours} -> {c.merged} behaviours (RD {c.rd_got:.2f}): scan "
                     f"{o.ms_per_run:.3f} -> {m.ms_per_run:.3f} ms per run ({_pct(c.reduction('scan'))}; paper "
                     f"1.5 -> 1.1 ms, -27%); {o.mean_decisions:g} -> {m.mean_decisions:g} decisions; "
                     f"verification {c.verify_result} in {c.verify_seconds:.2f} s")
    reference = next((r for r in results.sizes if r.behaviours == 1365), None)
    for row in results.sizes:
        if reference and row.behaviours >= 50_000:
            growth = row.incremental_us / reference.incremental_us
            lines.append(f"incremental at {row.behaviours:,} behaviours: {row.incremental_us:,.1f} us per decision, "
                         f"x{growth:.2f} its cost at 1,365 ({'met' if growth < 2 else 'MISSED'}: target under 2x)")
    verified = [c for c in cells if c.verify_result == "proved"]
    if cells:
        lines.append(f"verification: {len(verified)} of {len(cells)} generated tasks proved exactly "
                     f"(the rest reached {results.plan.max_states:,} states: no proof, no counterexample)"
                     + ("" if not any(c.verify_result == "counterexample" for c in cells)
                        else "; COUNTEREXAMPLES FOUND"))
    if not results.py_trees:
        lines.append("py_trees is not installed: the peer columns are empty (pip install py_trees)")
    return lines


def to_markdown(results: Results, command: str) -> str:
    """The tables of a run, with the command that produced them and the paper's figures."""
    plan = results.plan
    out = [f"# schemalog bench --{plan.name}", "",
           f"Command: `{command}`; {plan.runs} runs per tree (object configurations), seed {plan.seed}, "
           f"py_trees {results.py_trees or 'not installed'}; {results.seconds:,.0f} s in all.", "",
           "## Headlines", ""]
    out += [f"- {line}" for line in headlines(results)]
    out += ["", "The paper's figures: " + "; ".join(f"{k}: {v}" for k, v in PAPER.items()) + ".", "",
            "## The grid (Sec. IV-B, Fig. 4)", "",
            "Per run: selection time summed over a run to completion (the paper's execution time). "
            "Per decision: one winner-take-all decision (py_trees: one tick).", "",
            "| D | b | Bi | RD asked | RD got | Bm | decisions o -> c | scan ms/run o -> c | change | "
            "scan us/dec o -> c | incremental us/dec o -> c | py_trees us/tick o -> c | compress ms | verify |",
            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for c in _all_cells(results):
        def pair(selector: str, unit: str) -> str:
            o, m = c.timing("original", selector), c.timing("compressed", selector)
            get = (lambda t: t.ms_per_run) if unit == "run" else (lambda t: t.us_per_decision)
            digits = 3 if unit == "run" else 1
            return f"{_f(get(o), digits)} -> {_f(get(m), digits)}"
        o = c.timing("original", "scan")
        m = c.timing("compressed", "scan")
        verify = f"{c.verify_result} ({c.verify_seconds:.2f} s)" if c.verify_seconds is not None else c.verify_result
        out.append(f"| {c.depth} | {c.children or 'coffee'} | {c.behaviours:,} | "
                   f"{'-' if c.rd_asked is None else f'{c.rd_asked:.1f}'} | {c.rd_got:.2f} | {c.merged:,} | "
                   f"{o.mean_decisions:g} -> {m.mean_decisions:g} | {pair('scan', 'run')} | {_pct(c.reduction('scan'))} | "
                   f"{pair('scan', 'decision')} | {pair('incremental', 'decision')} | "
                   f"{pair('py_trees', 'decision')} | {c.compress_seconds * 1e3:.1f} | {verify} |")
    if results.sizes:
        out += ["", "## Selectors by size (RD 0.5, original trees)", "",
                "| behaviours | D x b | decisions | incremental us | median us | scan us (first 20) | "
                "py_trees tick us | py_trees / incremental | scan / incremental |",
                "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for r in results.sizes:
            out.append(f"| {r.behaviours:,} | {r.depth} x {r.children} | {r.decisions:,} | {r.incremental_us:,.1f} | "
                       f"{r.incremental_median_us:,.1f} | {r.scan_us:,.1f} | {_f(r.py_trees_us)} | "
                       f"{_f(r.py_trees_us / r.incremental_us, 0)}x | {r.scan_us / r.incremental_us:,.0f}x |")
    return "\n".join(out) + "\n"


def write_results(results: Results, out: Path, command: str) -> list[Path]:
    """CSV, Markdown and the figures into `out`, each file written atomically."""
    from . import figures

    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in (("results.csv", to_csv(results)), ("results.md", to_markdown(results, command))):
        write_atomically(out / name, text)
        written.append(out / name)
    written += figures.figure4(results, out)
    written += figures.selectors_by_size(results, out)
    written += figures.figure3(out, seed=results.plan.seed)
    return written


__all__ = ["BenchPlan", "PAPER_PLAN", "QUICK_PLAN", "Cell", "Timing", "SizeRow", "Results", "run_bench",
           "steps", "to_csv", "to_markdown", "headlines", "write_results", "py_trees_tree", "py_trees_ticker"]
