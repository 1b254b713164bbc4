"""How fast `verify` explores, and where exact verification stops being practical.

    python benchmarks/bench_verify.py [--max-states 50000] [--sample 1000]

One run, two tables:

1. The paper's tasks (Figure 2, coffee and tea), default and all initial states, compressed
   with `full` and `pre`: states explored in the compressed tree and in the original, time,
   states per second, and the verdict.
2. Generated tasks in the paper's nine shapes (15 to 1,365 behaviours, RD 0.5): exhaustive
   exploration of the whole task (the baseline) beside the same exploration by independent
   parts (the exact reduction), each bounded by --max-states, and --sample runs of the same
   tree (random runs, every step checked: the fallback that proves nothing). States counts
   add the compressed tree's and the original's.
"""

from __future__ import annotations

import argparse
import sys
import time

from schemalog.cli.main import tune_gc
from schemalog.task.compress import compress
from schemalog.formats.documents import load_kb
from schemalog.evaluate.generate import generate
from schemalog.logic.parse import parse_term
from schemalog.task.tree import count_nodes, instantiate
from schemalog.run.verify import Verifier, all_states, constraints, free_atoms, verify_by_parts
from schemalog.run.world import World, initial_state

ROOT = __file__.rsplit("/benchmarks/", 1)[0]
PAPER = [("kb/tasks/mix_with_spoon.pl", "use(spoon)"), ("kb/tasks/prepare_coffee_and_tea.pl", "prepareboth")]
SHAPES = [(d, b) for d in (4, 5, 6) for b in (2, 3, 4)]


def verdict(report) -> str:
    if report.violated:
        return "counterexample"
    return "proved" if report.exhaustive else "limit reached"


def paper_table(max_states: int) -> None:
    print("## The paper's tasks\n")
    print("| task | initial states | propagate | compressed states | original states | seconds | states/s | result |")
    print("|---|---:|---|---:|---:|---:|---:|---|")
    for path, label in PAPER:
        kb = load_kb([f"{ROOT}/{path}"])
        tree = instantiate(kb, parse_term(label))
        for which in ("default", "all"):
            for propagate in ("full", "pre"):
                world = World(tree, initial_state(kb))
                initial = [world.atoms] if which == "default" else \
                    all_states(world, free_atoms(kb, tree), constraints(kb))
                started = time.perf_counter()
                report = Verifier(tree, compress(tree, propagate).tree, world, max_states).verify(initial)
                seconds = time.perf_counter() - started
                states = report.compressed_states + report.original_states
                print(f"| {label} | {len(initial)} | {propagate} | {report.compressed_states:,} | "
                      f"{report.original_states:,} | {seconds:.2f} | {states / seconds:,.0f} | {verdict(report)} |")
    print()


def generated_table(max_states: int, runs: int) -> None:
    print(f"## Generated tasks (RD 0.5, propagate full; at most {max_states:,} states per tree or part)\n")
    print("| depth | children | Bi | Bm | whole: states | s | result | parts | by parts: states | s | result "
          f"| {runs} sampled runs s |")
    print("|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---|---:|")
    for depth, branching in SHAPES:
        tree = generate(depth, branching, 0.5, seed=1)
        compressed = compress(tree).tree
        world = World(tree)
        initial = [world.atoms]
        started = time.perf_counter()
        whole = Verifier(tree, compressed, world, max_states).verify(initial)
        whole_s = time.perf_counter() - started
        started = time.perf_counter()
        parts = verify_by_parts(tree, compressed, World(tree), initial, max_states=max_states)
        parts_s = time.perf_counter() - started
        started = time.perf_counter()
        Verifier(tree, compressed, World(tree), max_states).sample(initial, runs, seed=1)
        sample_s = time.perf_counter() - started
        split = (f"{parts.parts} | {parts.compressed_states + parts.original_states:,} | {parts_s:.2f} "
                 f"| {verdict(parts)}") if parts else "1 | - | - | -"
        print(f"| {depth} | {branching} | {count_nodes(tree):,} | {count_nodes(compressed):,} "
              f"| {whole.compressed_states + whole.original_states:,} | {whole_s:.2f} | {verdict(whole)} "
              f"| {split} | {sample_s:.2f} |")
        sys.stdout.flush()
    print()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-states", type=int, default=50_000)
    parser.add_argument("--sample", type=int, default=1000)
    args = parser.parse_args()
    tune_gc()
    print(f"python {sys.version.split()[0]}\n")
    paper_table(args.max_states)
    generated_table(args.max_states, args.sample)


if __name__ == "__main__":
    main()
