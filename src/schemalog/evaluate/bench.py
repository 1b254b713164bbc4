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

Every figure is a median over a tree's runs with its interquartile range (a Spread), and a
target is judged on the range, not on the median alone: met when even the least favourable
quartiles meet it, MISSED when even the most favourable miss it, and "too noisy to judge"
when the spread straddles the target.
"""

from __future__ import annotations

import csv
import gc
import io
import math
import signal
import statistics
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..task import conditions as cond
from ..task.compress import compress
from ..formats.documents import document_from_text, write_in_folder
from ..errors import SchemalogError
from ..run.execute import Executive
from .generate import TOLERANCE, generate, node_count, scene_for, shortfall
from ..run.scene import Scene, scene_from_yaml
from ..logic.opread import parse_term
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
    min_seconds: float = 0.0               # a cell's runs go round again until measured this long
    max_states: int = 20_000               # verification: beyond this a cell is "limit"
    verify_seconds: float | None = None    # verification: past this much CPU time a cell is "limit"
    seed: int = 1
    name: str = "paper"
    propagate: str = "full"                # how the cells are compressed (docs/compression.md)
    measures: tuple[str, ...] = ("compress", "prove", "time")    # what a generated cell does
    selectors: tuple[str, ...] = SELECTORS     # which selectors "time" runs (py_trees: with ticks)
    max_bdd_nodes: int = 5_000_000         # verification: symbolic past this is "limit"


PAPER_PLAN = BenchPlan(shapes=tuple((d, b) for d in (4, 5, 6) for b in (2, 3, 4)),
                       sizes=((6, 4), (7, 4), (8, 4), (9, 4), (8, 5), (6, 10)))
# Three runs: the fewest with a median and quartiles, in the minute the quick run is for
# (a scan run of 1,365 behaviours takes 0.7-1.8 s here); one CPU second of verification per
# cell keeps the proofs of the small cells and stops the large ones (up to 52 s each at
# 5,000 states per independent part) from taking most of the run.
QUICK_PLAN = BenchPlan(shapes=PAPER_PLAN.shapes, runs=3, min_seconds=0.1, sizes=((4, 4), (6, 4), (7, 4)), ticks=2,
                       max_states=5_000, verify_seconds=1.0, name="quick")


@dataclass(frozen=True)
class Spread:
    """A median with its quartiles (q1 = q3 = median for a single value)."""

    median: float
    q1: float
    q3: float

    @staticmethod
    def of(values: list[float], scale: float = 1.0) -> Spread:
        if not values:
            return Spread(math.nan, math.nan, math.nan)
        data = sorted(v * scale for v in values)
        if len(data) == 1:
            return Spread(data[0], data[0], data[0])
        q1, median, q3 = statistics.quantiles(data, n=4, method="inclusive")
        return Spread(median, q1, q3)

    @property
    def iqr(self) -> float:
        return self.q3 - self.q1

    def text(self, digits: int = 1) -> str:
        """`median (IQR q1-q3)`."""
        if math.isnan(self.median):
            return "n/a"
        return f"{self.median:,.{digits}f} (IQR {self.q1:,.{digits}f}-{self.q3:,.{digits}f})"


def judge(low: float, high: float, target: float) -> str:
    """met, MISSED, or too noisy to judge: whether a figure whose plausible range is
    [low, high] (from the quartiles) reaches `target`."""
    if math.isnan(low) or math.isnan(high):
        return "not measured"
    if low >= target:
        return "met"
    if high < target:
        return "MISSED"
    return "too noisy to judge"


def reduction_spread(a: Spread, b: Spread) -> Spread:
    """How much less `b` is than `a` (0.27 = 27% less), from the medians, and its range from the
    quartiles: the least (b's q3 against a's q1) and the most (b's q1 against a's q3)."""
    if not a.q1 or math.isnan(a.median) or math.isnan(b.median):
        return Spread(math.nan, math.nan, math.nan)
    return Spread(1 - b.median / a.median, 1 - b.q3 / a.q1, 1 - b.q1 / a.q3)


@dataclass
class Timing:
    """One tree under one selector, over a cell's runs."""

    decisions: list[int] = field(default_factory=list)          # per run
    per_run: list[float] = field(default_factory=list)          # seconds of selection per run
    per_decision: list[float] = field(default_factory=list)     # seconds, every decision timed
    traces: list[str] = field(default_factory=list)             # per run: a digest of its actions

    @property
    def run_ms(self) -> Spread:
        """Selection time per run (ms): median and quartiles over the runs."""
        return Spread.of(self.per_run, 1e3)

    @property
    def decision_us(self) -> Spread:
        """Time per decision (us), each run's mean: median and quartiles over the runs."""
        return Spread.of([t / n for t, n in zip(self.per_run, self.decisions) if n], 1e6)

    @property
    def us_per_decision(self) -> float:
        return self.decision_us.median

    @property
    def ms_per_run(self) -> float:
        return self.run_ms.median

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
    verify_limit: str = ""                    # "states" or "time": what stopped a "limit"
    timings: dict[tuple[str, str], Timing] = field(default_factory=dict)

    def timing(self, tree: str, selector: str) -> Timing:
        return self.timings.setdefault((tree, selector), Timing())

    def reduction(self, selector: str, per: str = "run") -> float:
        """How much less time the compressed tree takes than the original (0.27 = 27% less)."""
        return self.reduction_spread(selector, per).median

    def reduction_spread(self, selector: str, per: str = "run") -> Spread:
        """The reduction from the medians, and its range from the quartiles: the least
        (compressed q3 against original q1) and the most (q1 against q3)."""
        o, c = self.timing("original", selector), self.timing("compressed", selector)
        a, b = (o.run_ms, c.run_ms) if per == "run" else (o.decision_us, c.decision_us)
        return reduction_spread(a, b)


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
              initial: frozenset = frozenset(), ticks: int = 0, say=None, min_seconds: float = 0.0,
              selectors: tuple[str, ...] = SELECTORS) -> None:
    """Run each tree (original, compressed) once per scene with each selector; record the
    timings in `cell`. The trees take turns, first one then the other leading, so that a
    change in the machine's load falls on both alike; `say(text)` hears of each run."""
    tickers = {which: py_trees_ticker(tree) for which, tree in trees.items()} \
        if ticks and "py_trees" in selectors else {}
    own = [s for s in ("scan", "incremental") if s in selectors]
    order = list(trees)
    started = time.perf_counter()
    # A tree whose runs take microseconds goes round its configurations again, until it has
    # been measured for `min_seconds` (at most `MAX_ROUNDS` times): its median then rests on
    # enough runs that one preempted run cannot move it.
    with _no_collection():
        for run, scene in enumerate(_rounds(scenes, started, min_seconds)):
            if say is not None:
                say(f"run {run + 1}" + (f" of {len(scenes)}" if run < len(scenes) else " (repeating a fast tree)"))
            for which in (order if run % 2 == 0 else order[::-1]):
                tree = trees[which]
                ex = None
                for selector in own:
                    ex = Executive(tree, World(original, initial), scene, selector=selector, detect_loops=False)
                    seconds = [decision.seconds for decision in ex]
                    if not ex.outcome.completed:
                        raise SchemalogError(f"bench: the {which} tree of {cell.name} did not complete with the "
                                             f"{selector} selector: {ex.outcome.reason}")
                    timing = cell.timing(which, selector)
                    timing.decisions.append(len(seconds))
                    timing.per_run.append(sum(seconds))
                    timing.per_decision.extend(seconds)
                    timing.traces.append(trace_digest(ex.trace))
                ticker = tickers.get(which)
                if ticker is not None:
                    if ex is None:         # py_trees alone: the states of an untimed incremental run
                        ex = Executive(tree, World(original, initial), scene, selector="incremental",
                                       detect_loops=False)
                        seconds = [decision.seconds for decision in ex]
                    spent = tick_times(ticker, _replay_states(original, initial, ex.trace, ticks))
                    peer = cell.timing(which, "py_trees")
                    peer.per_decision.extend(spent)
                    peer.decisions.append(len(seconds))
                    peer.per_run.append(statistics.fmean(spent) * len(seconds))


MAX_ROUNDS = 10


def trace_digest(trace: list) -> str:
    """A run's actions, in order, as a short digest (the same run gives the same digest in any process)."""
    import hashlib

    from ..logic.terms import term_to_text

    return hashlib.sha256("\n".join(term_to_text(a) for a in trace).encode()).hexdigest()[:16]


def _rounds(scenes: list[Scene], started: float, min_seconds: float):
    """The scenes once, then again while less than `min_seconds` have passed (MAX_ROUNDS at most)."""
    for round_ in range(MAX_ROUNDS):
        if round_ and time.perf_counter() - started >= min_seconds:
            return
        yield from scenes


@contextmanager
def _no_collection():
    """No cyclic garbage collection during a cell's timed runs (collected once before them: a
    collection costs tens of milliseconds with this heap): a collection pause, which lands on
    whichever run happens to cross the threshold, made two identical trees differ 3.5x."""
    was_enabled = gc.isenabled()
    gc.collect()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


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

class _OutOfTime(BaseException):
    """The CPU-time budget of one cell's verification is spent (a BaseException: nothing in
    the verifier catches it)."""


@contextmanager
def cpu_budget(seconds: float | None):
    """Raise _OutOfTime once the process has used `seconds` of CPU time inside the context.
    CPU time, not wall-clock time: a loaded machine does not turn a proof into a limit, and
    SIGALRM stays free for --timeout. Outside the main thread (a Dask worker's task), where
    no signal can be caught, the thread's own CPU time is watched instead (thread_budget)."""
    if seconds is None or not hasattr(signal, "setitimer"):
        yield
        return
    if threading.current_thread() is not threading.main_thread():
        with thread_budget(seconds, _OutOfTime):
            yield
        return
    armed = [True]

    def expire(signum, frame) -> None:
        if armed[0]:             # a signal already pending as the context closes does nothing
            armed[0] = False
            raise _OutOfTime

    previous = signal.signal(signal.SIGPROF, expire)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        armed[0] = False
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, previous)


@contextmanager
def thread_budget(seconds: float | None, error: type[BaseException]):
    """Raise `error` in this thread once it has used `seconds` of its own CPU time inside the
    context: a watching thread reads this thread's CPU clock every 20 ms and raises the error
    into it (between two bytecodes, as Ctrl-C would). Works in any thread, the main one too."""
    if seconds is None or not hasattr(time, "pthread_getcpuclockid"):
        yield
        return
    import ctypes

    target = threading.get_ident()
    clock = time.pthread_getcpuclockid(target)
    start = time.clock_gettime(clock)
    stop = threading.Event()
    fired = []

    def watch() -> None:
        while not stop.wait(0.02):
            if time.clock_gettime(clock) - start >= seconds:
                fired.append(True)
                ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(target), ctypes.py_object(error))
                return

    watcher = threading.Thread(target=watch, name="cpu-budget", daemon=True)
    watcher.start()
    try:
        yield
    finally:
        stop.set()
        watcher.join()
        if fired:                 # raised too late to land inside: taken back, not left pending
            ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(target), None)


def verify_cell(original: Behaviour, compressed: Behaviour, initial: frozenset, max_states: int,
                cell: Cell, seconds: float | None = None, max_bdd_nodes: int = 5_000_000) -> None:
    """Prove the compressed tree against the original where that is exact within max_states
    (and, given `seconds`, within that much CPU time): proved, counterexample or limit."""
    world = World(original, initial)
    started = time.perf_counter()
    try:
        with cpu_budget(seconds):
            report = prove(original, compressed, world, [world.atoms], max_states=max_states,
                           max_nodes=max_bdd_nodes)
    except _OutOfTime:
        cell.verify_seconds = time.perf_counter() - started
        cell.verify_result, cell.verify_states, cell.verify_limit = "limit", 0, "time"
        return
    cell.verify_seconds = time.perf_counter() - started
    cell.verify_states = report.compressed_states + report.original_states
    cell.verify_result = ("counterexample" if report.violated else
                          "proved" if report.exhaustive and report.sound and report.complete else "limit")
    if cell.verify_result == "proved":      # a proof about a task that cannot complete proves nothing
        from ..run.vacuity import vacuity_of

        vacuity = vacuity_of(original, World(original), report.initial_states, max_states,
                             report.original_completes)
        cell.verify_result = "vacuous" if vacuity.vacuous else "limit" if vacuity.undecided else "proved"
    cell.verify_limit = "states" if cell.verify_result == "limit" else ""


def timed_compress(tree: Behaviour, repeat: int = 3, propagate: str = "full"):
    """Compress (propagate full); the best time of `repeat` (the first pays for warming up)."""
    best = math.inf
    for _ in range(repeat):
        started = time.perf_counter()
        result = compress(tree, propagate)
        best = min(best, time.perf_counter() - started)
    return result, best


def measure_cell(depth: int, children: int, rd: float, plan: BenchPlan, say=None) -> Cell:
    """Generate, compress, verify and time one cell of the grid; `say(text)` hears of each part."""
    tree = generate(depth, children, rd, plan.seed)
    result, seconds = timed_compress(tree, 3 if "time" in plan.measures else 1, plan.propagate)
    cell = Cell(f"depth {depth}, {children} children, RD {rd:g}", depth, children, result.nodes_before, rd,
                result.reduction_degree, result.nodes_after, seconds)
    scenes = [scene_for(children, seed=run) for run in range(plan.runs)]
    if "time" not in plan.measures:
        pass
    elif result.nodes_after == result.nodes_before:
        # Nothing merged (RD 0): the compressed tree is the original, so it is timed once and
        # its rows repeat the original's; timing it twice measured only the machine's noise.
        time_runs({"original": tree}, tree, scenes, cell, ticks=plan.ticks, say=say, min_seconds=plan.min_seconds,
                  selectors=plan.selectors)
        for selector in plan.selectors:
            cell.timings[("compressed", selector)] = cell.timing("original", selector)
    else:
        time_runs({"original": tree, "compressed": result.tree}, tree, scenes, cell, ticks=plan.ticks, say=say,
                  min_seconds=plan.min_seconds, selectors=plan.selectors)
    if "prove" in plan.measures:
        if say is not None:
            say("verifying")
        verify_cell(tree, result.tree, frozenset(), plan.max_states, cell, plan.verify_seconds, plan.max_bdd_nodes)
    return cell


COFFEE_FILE = "kb/tasks/prepare_coffee_and_tea.pl"
KITCHEN_FILE = "kb/scenes/kitchen.yaml"


def measure_coffee(plan: BenchPlan, say=None) -> Cell:
    """The paper's real task (Sec. IV-D): 10 runs in 10 object configurations of the kitchen."""
    kb = document_from_text(shipped_text(COFFEE_FILE), COFFEE_FILE).to_kb()
    tree = instantiate(kb, parse_term("prepareboth"))
    result, seconds = timed_compress(tree, propagate=plan.propagate)
    initial = frozenset(initial_state(kb))
    cell = Cell("coffee and tea", result.depth_before, 0, result.nodes_before, None, result.reduction_degree,
                result.nodes_after, seconds)
    kitchen = scene_from_yaml(shipped_text(KITCHEN_FILE), KITCHEN_FILE)
    scenes = [kitchen.jittered(run, 0.05) for run in range(plan.runs)]
    if "time" in plan.measures:
        time_runs({"original": tree, "compressed": result.tree}, tree, scenes, cell, initial, plan.ticks, say,
                  plan.min_seconds, plan.selectors)
    if "prove" in plan.measures:
        verify_cell(tree, result.tree, initial, plan.max_states, cell, plan.verify_seconds, plan.max_bdd_nodes)
    return cell


def measure_size(depth: int, children: int, plan: BenchPlan, sample: int = 20) -> SizeRow:
    """One large original tree (RD 0.5): a whole incremental run, a scan sample, and py_trees
    ticks at states spread over the run."""
    tree = generate(depth, children, 0.5, plan.seed)
    scene = scene_for(children)
    ex = Executive(tree, World(tree), scene, selector="incremental", detect_loops=False)
    with _no_collection():
        inc = [d.seconds for d in ex]
    if not ex.outcome.completed:
        raise SchemalogError(f"bench: depth {depth} x {children} did not complete: {ex.outcome.reason}")
    scan_ex = Executive(tree, World(tree), scene, selector="scan", detect_loops=False)
    scan = []
    with _no_collection():
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
    """Measure everything the plan asks for. `progress(done, total, description)` is told
    before each step (done steps so far, of `total`) and of each part of a step."""
    started = time.perf_counter()
    results = Results(plan, py_trees=py_trees_version())
    total = steps(plan)
    done = [0]

    def step(description: str):
        if progress is None:
            return None
        progress(done[0], total, description)
        return lambda part: progress(done[0], total, f"{description}: {part}")

    for depth, children in plan.shapes:
        for rd in plan.reductions:
            say = step(f"depth {depth}, {children} children ({node_count(depth, children):,} behaviours), RD {rd:g}")
            results.cells.append(measure_cell(depth, children, rd, plan, say))
            done[0] += 1
    say = step("coffee and tea")
    results.coffee = measure_coffee(plan, say)
    done[0] += 1
    for depth, children in plan.sizes:
        step(f"selectors at {node_count(depth, children):,} behaviours")
        results.sizes.append(measure_size(depth, children, plan))
        done[0] += 1
    if progress is not None:
        progress(done[0], total, "done")
    results.seconds = time.perf_counter() - started
    return results


def steps(plan: BenchPlan) -> int:
    """How many steps run_bench reports."""
    return len(plan.shapes) * len(plan.reductions) + 1 + len(plan.sizes)


# ---------------------------------------------------------------------------
# Reports

CSV_FIELDS = ["task", "depth", "children", "behaviours", "rd_asked", "rd_achieved", "behaviours_compressed",
              "tree", "selector", "runs", "decisions_per_run", "us_per_decision", "ms_per_run", "ms_per_run_q1",
              "ms_per_run_q3",
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
                "ms_per_run_q1": f"{t.run_ms.q1:.4f}", "ms_per_run_q3": f"{t.run_ms.q3:.4f}",
                "compress_ms": f"{cell.compress_seconds * 1e3:.3f}",
                "verify_s": "" if cell.verify_seconds is None else f"{cell.verify_seconds:.3f}",
                "verify_result": cell.verify_result, "verify_states": cell.verify_states})
    return out.getvalue()


def _all_cells(results: Results) -> list[Cell]:
    return results.cells + ([results.coffee] if results.coffee else [])


def _f(value: float, digits: int = 1) -> str:
    return "n/a" if value is None or math.isnan(value) else f"{value:,.{digits}f}"


def _pct(value: float) -> str:
    """A reduction as a change: 0.27 -> -27%, -0.1 -> +10%, and 0% (not +-0%) in between."""
    if math.isnan(value):
        return "n/a"
    if round(value * 100) == 0:
        return "0%"
    return f"-{value * 100:.0f}%" if value > 0 else f"+{-value * 100:.0f}%"


def _range_pct(spread: Spread) -> str:
    """A reduction and its range from the quartiles, least to most: `-88%, range -85% to -90%`."""
    if math.isnan(spread.median):
        return "n/a"
    return f"{_pct(spread.median)}, range {_pct(spread.q1)} to {_pct(spread.q3)}"


def headlines(results: Results) -> list[str]:
    """The summary: the paper's figures beside ours, and the targets of the evaluation, each
    judged on the spread of the runs (met, MISSED, or too noisy to judge)."""
    lines = []
    cells = results.cells
    by = {(c.depth, c.children, c.rd_asked): c for c in cells}
    runs = results.plan.runs
    if cells:
        worst = max(abs(c.rd_got - c.rd_asked) for c in cells)
        misses = [c for c in cells if shortfall(c.depth, c.children, c.rd_asked, c.rd_got)]
        lines.append(f"reduction degree: every cell within {worst:.3f} of the request "
                     f"(tolerance {TOLERANCE})" if not misses else
                     f"reduction degree: {len(misses)} cell(s) beyond {TOLERANCE}: " +
                     "; ".join(f"{c.name}: {shortfall(c.depth, c.children, c.rd_asked, c.rd_got)}" for c in misses))
    big0, big7 = by.get((6, 4, 0.0)), by.get((6, 4, 0.7))
    if big7:
        # The original and the compressed tree of one cell, measured side by side in turns.
        o, c = big7.timing("original", "scan"), big7.timing("compressed", "scan")
        cut = big7.reduction_spread("scan")
        lines.append(f"scan, 1,365 behaviours, RD 0.7, original -> compressed: {o.ms_per_run / 1e3:.3f} -> "
                     f"{c.ms_per_run / 1e3:.3f} s per run ({_range_pct(cut)}; paper 0.23 -> 0.03 s, -87%; "
                     f"target at least 87%: {judge(cut.q1, cut.q3, 0.87)}), per decision "
                     f"{o.us_per_decision:,.0f} -> {c.us_per_decision:,.0f} us "
                     f"({_pct(big7.reduction('scan', 'decision'))})")
    if big0:
        scan, inc = big0.timing("original", "scan").decision_us, big0.timing("original", "incremental").decision_us
        tick = big0.timing("original", "py_trees").decision_us
        vs_scan = scan.median / inc.median
        line = (f"incremental, 1,365 behaviours: {inc.text(1)} us per decision, {vs_scan:,.0f}x "
                f"faster than the scan ({judge(scan.q1 / inc.q3, scan.q3 / inc.q1, 100)}: target 100x)")
        if not math.isnan(tick.median):
            vs_tick = tick.median / inc.median
            line += (f", {vs_tick:,.0f}x faster than a py_trees tick of {tick.median:,.0f} us "
                     f"({judge(tick.q1 / inc.q3, tick.q3 / inc.q1, 100)}: target 100x)")
        lines.append(line)
    mid = by.get((4, 4, 0.3))
    if mid:
        lines.append(f"scan, 85 behaviours, RD 0.3: {mid.timing('original', 'scan').ms_per_run:.3f} -> "
                     f"{mid.timing('compressed', 'scan').ms_per_run:.3f} ms per run "
                     f"({_range_pct(mid.reduction_spread('scan'))}; paper 1.4 -> 1.1 ms, -20%)")
    if cells:
        best = max(cells, key=lambda c: (c.reduction("scan") if not math.isnan(c.reduction("scan")) else -1))
        lines.append(f"best reduction (scan, per run): {_range_pct(best.reduction_spread('scan'))} at {best.name} "
                     f"(paper: 93%)")
    if results.coffee:
        c = results.coffee
        o, m = c.timing("original", "scan"), c.timing("compressed", "scan")
        lines.append(f"coffee and tea, {c.behaviours} -> {c.merged} behaviours (RD {c.rd_got:.2f}): scan "
                     f"{o.ms_per_run:.3f} -> {m.ms_per_run:.3f} ms per run ({_range_pct(c.reduction_spread('scan'))}; "
                     f"paper 1.5 -> 1.1 ms, -27%); {o.mean_decisions:g} -> {m.mean_decisions:g} decisions; "
                     f"verification {c.verify_result} in {c.verify_seconds:.2f} s")
    reference = next((r for r in results.sizes if r.behaviours == 1365), None)
    for row in results.sizes:
        if reference and row.behaviours >= 50_000:
            growth = row.incremental_us / reference.incremental_us
            lines.append(f"incremental at {row.behaviours:,} behaviours: {row.incremental_us:,.1f} us per decision, "
                         f"x{growth:.2f} its cost at 1,365 ({'met' if growth < 2 else 'MISSED'}: target under 2x)")
    verified = [c for c in cells if c.verify_result == "proved"]
    if cells:
        limits = []
        if any(c.verify_limit == "states" for c in cells):
            limits.append(f"{results.plan.max_states:,} states")
        if any(c.verify_limit == "time" for c in cells):
            limits.append(f"{results.plan.verify_seconds:g} s of CPU time")
        lines.append(f"verification: {len(verified)} of {len(cells)} generated tasks proved exactly"
                     + (f" (the rest reached {' or '.join(limits)}: no proof, no counterexample)" if limits else "")
                     + ("" if not any(c.verify_result == "counterexample" for c in cells)
                        else "; COUNTEREXAMPLES FOUND"))
    noisy = [c for c in _all_cells(results)
             if any(_noisy(c.timing(t, "scan").run_ms) for t in TREES)]
    if noisy:
        lines.append(f"noise: {len(noisy)} of {len(_all_cells(results))} trees' scan runs spread more than "
                     f"{NOISY_IQR:.0%} of their median over {runs} or more runs (see the IQR columns): "
                     f"compare those rows with care")
    if not results.py_trees:
        lines.append("py_trees is not installed: the peer columns are empty (pip install py_trees)")
    return lines


NOISY_IQR = 0.25      # an IQR above a quarter of the median marks a noisy measurement


def _noisy(spread: Spread) -> bool:
    return not math.isnan(spread.median) and spread.median > 0 and spread.iqr > NOISY_IQR * spread.median


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
            "Per decision: one winner-take-all decision (py_trees: one tick). Every time is the median of "
            f"a tree's runs ({plan.runs} configurations, gone round again for fast trees up to "
            f"{plan.min_seconds:g} s); the IQR column gives the scan's interquartile range per run, and the "
            "change its range from the quartiles.", "",
            "| D | b | Bi | RD asked | RD got | Bm | decisions o -> c | scan ms/run o -> c | scan IQR o; c | change | "
            "scan us/dec o -> c | incremental us/dec o -> c | py_trees us/tick o -> c | compress ms | verify |",
            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
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
                   f"{o.mean_decisions:g} -> {m.mean_decisions:g} | {pair('scan', 'run')} | "
                   f"{_iqr(o.run_ms)}; {_iqr(m.run_ms)} | {_range_pct(c.reduction_spread('scan'))} | "
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


def _iqr(spread: Spread) -> str:
    return "n/a" if math.isnan(spread.median) else f"{spread.q1:,.3f}-{spread.q3:,.3f}"


def write_results(results: Results, out: Path, command: str) -> list[Path]:
    """CSV, Markdown and the figures into `out`, each file written atomically."""
    from . import figures

    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in (("results.csv", to_csv(results)), ("results.md", to_markdown(results, command))):
        write_in_folder(out / name, text)
        written.append(out / name)
    written += figures.figure4(results, out)
    written += figures.selectors_by_size(results, out)
    written += figures.figure3(out, seed=results.plan.seed)
    return written


__all__ = ["BenchPlan", "PAPER_PLAN", "QUICK_PLAN", "Cell", "Timing", "SizeRow", "Results", "run_bench",
           "Spread", "reduction_spread", "judge", "cpu_budget", "thread_budget", "verify_cell", "measure_cell", "measure_coffee",
           "measure_size", "trace_digest",
           "steps", "to_csv", "to_markdown", "headlines", "write_results", "py_trees_tree", "py_trees_ticker"]
