"""Time per decision of the attentional executive, beside py_trees, on generated tasks.

    python benchmarks/bench_execute.py [--quick] [--sample 20] [--ticks 3]

Two tables, one run:

1. The paper's evaluation (Sec. IV-B, Fig. 4): depth 4, 5, 6 with 2, 3, 4 children per
   behaviour (15 to 1,365 behaviours), reduction degree 0, 0.3, 0.5, 0.7. Each task is
   compressed (Algorithm 1, --propagate full or pre) and run to completion with the `scan` selector,
   the paper's cost model (every behaviour checked at every decision). Reported: mean time per
   decision, and against RD 0 the time ratio beside the node ratio Bm/Bi and the ratio of
   condition literals the scan evaluates (merged behaviours carry longer, inherited
   pre-conditions, so a node of a compressed tree costs more to check).

2. Selectors by size, 15 to 111,111 behaviours (RD 0.5, uncompressed): the `incremental`
   selector over a whole run (mean and median per decision), the `scan` selector over the first
   --sample decisions, and py_trees ticking a tree of the same shape (every composite a
   Parallel that ticks all its children, every leaf checking its releaser against the same
   state): one full tick is what a periodic behaviour-tree executive pays per decision.
   py_trees is the benchmark extra: pip install -e '.[bench]'.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

from schemalog import conditions as cond
from schemalog.cli import tune_gc
from schemalog.compress import compress
from schemalog.execute import Executive
from schemalog.generate import generate, scene_for
from schemalog.tree import Behaviour, count_nodes, walk
from schemalog.world import World

PAPER_SHAPES = [(d, b) for d in (4, 5, 6) for b in (2, 3, 4)]
SIZE_SHAPES = [(4, 2), (4, 4), (6, 4), (7, 4), (8, 4), (9, 4), (6, 10)]


def run_times(tree: Behaviour, original: Behaviour, selector: str, scene, limit: int | None = None):
    """Per-decision times of one run (the first `limit` decisions, or all)."""
    ex = Executive(tree, World(original), scene, selector=selector, detect_loops=False)
    times = []
    for decision in ex:
        times.append(decision.seconds)
        if limit is not None and len(times) >= limit:
            break
    if limit is None and not ex.outcome.completed:
        raise SystemExit(f"the run did not complete: {ex.outcome}")
    return times, ex.setup_seconds


def py_trees_tree(root: Behaviour, state: set):
    """The same shape as py_trees behaviours: Parallel composites, leaves reading the state."""
    import py_trees

    class Leaf(py_trees.behaviour.Behaviour):
        def __init__(self, name: str, pre, post) -> None:
            super().__init__(name)
            self.pre, self.post = pre, post

        def update(self):
            if cond.holds(self.post, state):
                return py_trees.common.Status.SUCCESS
            if cond.holds(self.pre, state):
                return py_trees.common.Status.RUNNING
            return py_trees.common.Status.FAILURE

    policy = py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=False)

    def build(node: Behaviour):
        if not node.children:
            return Leaf(node.name, node.pre, node.post)
        composite = py_trees.composites.Parallel(name=node.name, policy=policy, children=[])
        composite.add_children([build(c) for c in node.children])
        return composite

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    return build(root)


def tick_times(root: Behaviour, ticks: int) -> list[float] | None:
    try:
        import py_trees  # noqa: F401
    except ImportError:
        return None
    tree = py_trees_tree(root, set())
    times = []
    for _ in range(ticks):
        started = time.perf_counter()
        tree.tick_once()
        times.append(time.perf_counter() - started)
    return times


def literal_count(root: Behaviour) -> int:
    """How many literals a scan evaluates per decision: every pre- and post-condition."""
    return sum(len(cond.literals(n.pre)) + len(cond.literals(n.post)) for n in walk(root))


def us(seconds: float) -> str:
    return f"{seconds * 1e6:,.1f}"


def paper_table(shapes, reductions, seed: int, propagate: str) -> None:
    print(f"## The paper's evaluation: scan selector, compressed trees (propagate {propagate})\n")
    print("| depth | children | Bi | RD asked | RD got | Bm | Bm/Bi | literals vs RD 0 | decisions "
          "| us/decision | time vs RD 0 |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for depth, branching in shapes:
        base = base_literals = None
        for rd in reductions:
            tree = generate(depth, branching, rd, seed)
            result = compress(tree, propagate)
            times, _ = run_times(result.tree, tree, "scan", scene_for(branching))
            mean = statistics.fmean(times)
            lits = literal_count(result.tree)
            base = base or mean
            base_literals = base_literals or lits
            print(f"| {depth} | {branching} | {result.nodes_before:,} | {rd:.1f} | {result.reduction_degree:.2f} "
                  f"| {result.nodes_after:,} | {result.nodes_after / result.nodes_before:.2f} "
                  f"| {lits / base_literals:.2f} | {len(times):,} | {us(mean)} | {mean / base:.2f} |")
    print()


def size_table(shapes, sample: int, ticks: int, seed: int) -> None:
    print("## Selectors by size (RD 0.5, original trees) beside a py_trees tick of the same tree\n")
    print("| behaviours | depth x children | incremental mean us | median us | decisions | scan us (first "
          f"{sample}) | py_trees tick us | py_trees / incremental | scan / incremental |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    reference = None
    rows = []
    for depth, branching in shapes:
        tree = generate(depth, branching, 0.5, seed)
        scene = scene_for(branching)
        inc, _ = run_times(tree, tree, "incremental", scene)
        scan, _ = run_times(tree, tree, "scan", scene, limit=sample)
        tick = tick_times(tree, ticks)
        size = count_nodes(tree)
        mean_inc = statistics.fmean(inc)
        tick_mean = statistics.fmean(tick) if tick else None
        rows.append((size, mean_inc, statistics.median(inc)))
        if size == 1365:
            reference = rows[-1]
        print(f"| {size:,} | {depth} x {branching} | {us(mean_inc)} | {us(statistics.median(inc))} | {len(inc):,} "
              f"| {us(statistics.fmean(scan))} | {us(tick_mean) if tick else 'n/a'} "
              f"| {tick_mean / mean_inc:,.0f}x | {statistics.fmean(scan) / mean_inc:,.0f}x |"
              if tick else
              f"| {size:,} | {depth} x {branching} | {us(mean_inc)} | {us(statistics.median(inc))} | {len(inc):,} "
              f"| {us(statistics.fmean(scan))} | n/a | n/a | {statistics.fmean(scan) / mean_inc:,.0f}x |")
        sys.stdout.flush()
    if reference:
        print("\nGrowth of the incremental selector's time per decision from 1,365 behaviours:")
        for size, mean, median in rows:
            if size > reference[0]:
                print(f"- {size:,}: mean x{mean / reference[1]:.2f}, median x{median / reference[2]:.2f}")
    print()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small shapes only (a smoke run)")
    parser.add_argument("--sample", type=int, default=20, help="scan decisions timed per large tree")
    parser.add_argument("--ticks", type=int, default=3, help="py_trees ticks timed per tree")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", choices=["paper", "sizes"], help="run one table")
    parser.add_argument("--propagate", choices=["pre", "full"], default="full",
                        help="how the paper table compresses (default full)")
    args = parser.parse_args()
    tune_gc()
    print(f"python {sys.version.split()[0]}; seed {args.seed}\n")
    if args.only in (None, "paper"):
        shapes = PAPER_SHAPES[:3] if args.quick else PAPER_SHAPES
        paper_table(shapes, (0.0, 0.3, 0.5, 0.7), args.seed, args.propagate)
    if args.only in (None, "sizes"):
        shapes = SIZE_SHAPES[:3] if args.quick else SIZE_SHAPES
        size_table(shapes, args.sample, args.ticks, args.seed)


if __name__ == "__main__":
    main()
