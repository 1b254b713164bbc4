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
3. The paper's 36-cell grid (depth 4-6, 2-4 children, RD 0-0.7), full propagation: today's
   explicit explorer (by parts) beside the symbolic method (by parts, run/symbolic.py), each
   cell in its own process: states (symbolic: the reachable states counted from the sets,
   approximate above 2^53), decision-diagram nodes, seconds, peak RSS.
4. Growth from 1,365 to 97,656 behaviours: independent parts alone (the method before
   sequential phases) beside parts and phases, and the whole `schemalog verify` command.

    python benchmarks/bench_verify.py --only grid --only growth
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


GRID = [(d, b, rd) for d in (4, 5, 6) for b in (2, 3, 4) for rd in (0.0, 0.3, 0.5, 0.7)]
GROWTH = [(6, 4), (7, 4), (7, 5), (8, 5)]    # 1,365, 5,461, 19,531 and 97,656 behaviours
BASELINE = {(6, 4), (7, 4)}                  # where independent parts alone finish in minutes
TIMEOUT = 600                        # seconds per cell


def one_cell(depth: int, branching: int, rd: float, method: str, max_states: int, propagate: str,
             phases: bool = True) -> dict:
    """Verify one generated task as `schemalog verify --method METHOD` would (by parts where it
    splits); run in a child process, so that its peak memory is its own."""
    import resource

    from schemalog.run.verify import verify_symbolic

    tree = generate(depth, branching, rd, seed=1)
    compressed = compress(tree, propagate).tree
    initial = [World(tree).atoms]
    started = time.perf_counter()
    report = verify_by_parts(tree, compressed, World(tree), initial, max_states=max_states, method=method,
                             phases=phases)
    if report is None:
        report = (verify_symbolic(tree, compressed, World(tree), initial) if method == "symbolic" else
                  Verifier(tree, compressed, World(tree), max_states).verify(initial))
    seconds = time.perf_counter() - started
    return {"behaviours": count_nodes(tree), "compressed": count_nodes(compressed),
            "states": report.compressed_states + report.original_states, "nodes": report.nodes,
            "parts": report.parts, "seconds": seconds, "result": verdict(report),
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def in_child(*cell) -> dict:
    """one_cell in a fresh interpreter (its own peak RSS)."""
    import json
    import subprocess

    code = (f"import json, sys; sys.path.insert(0, {ROOT + '/benchmarks'!r}); import bench_verify as b; "
            f"print(json.dumps(b.one_cell{cell!r}))")
    try:
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                             timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return {"behaviours": 0, "compressed": 0, "states": 0, "nodes": 0, "parts": 0, "seconds": TIMEOUT,
                "result": f"stopped after {TIMEOUT} s", "peak_mb": 0}
    return json.loads(out.stdout.strip().splitlines()[-1])


def grid_table(max_states: int) -> None:
    print(f"## The paper's grid, full propagation: explicit (at most {max_states:,} states per part) "
          f"beside symbolic\n")
    print("| depth | children | RD | Bi | Bm | parts | explicit: states | s | MB | result "
          "| symbolic: states | BDD nodes | s | MB | result |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|")
    for depth, branching, rd in GRID:
        old = in_child(depth, branching, rd, "explicit", max_states, "full")
        new = in_child(depth, branching, rd, "symbolic", max_states, "full")
        print(f"| {depth} | {branching} | {rd} | {old['behaviours']:,} | {old['compressed']:,} | {new['parts']} "
              f"| {old['states']:,} | {old['seconds']:.2f} | {old['peak_mb']:.0f} | {old['result']} "
              f"| {new['states']:,} | {new['nodes']:,} | {new['seconds']:.2f} | {new['peak_mb']:.0f} "
              f"| {new['result']} |")
        sys.stdout.flush()
    print()


def growth_table(max_states: int) -> None:
    print("## Growth: RD 0.5, full propagation; symbolic by independent parts alone (the method before\n"
          "## phases) beside symbolic by parts and phases, and `schemalog verify` as a user runs it\n")
    print("| depth | children | Bi | method | parts | states | BDD nodes | s | MB | result |")
    print("|---:|---:|---:|---|---:|---:|---:|---:|---:|---|")
    for depth, branching in GROWTH:
        runs = [("parts + phases", True)]
        if (depth, branching) in BASELINE:
            runs.insert(0, ("parts only", False))
        for name, phases in runs:
            r = in_child(depth, branching, 0.5, "symbolic", max_states, "full", phases)
            print(f"| {depth} | {branching} | {r['behaviours']:,} | {name} | {r['parts']} | {r['states']:,} "
                  f"| {r['nodes']:,} | {r['seconds']:.2f} | {r['peak_mb']:.0f} | {r['result']} |")
            sys.stdout.flush()
        r = whole_command(depth, branching)
        print(f"| {depth} | {branching} | {r['behaviours']:,} | `schemalog verify` (read, compress, prove, "
              f"diagnostics) | | | | {r['seconds']:.2f} | {r['peak_mb']:.0f} | {r['result']} |")
        sys.stdout.flush()
    print()


def whole_command(depth: int, branching: int) -> dict:
    """`schemalog verify` on the generated file, timed from outside with its peak RSS."""
    import os
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "task.pl")
        subprocess.run([sys.executable, "-m", "schemalog", "generate", "--depth", str(depth), "--children",
                        str(branching), "--rd", "0.5", "--seed", "1", "-o", path], check=True, capture_output=True)
        # a fresh interpreter whose only child is the command: its children's peak RSS is the command's
        probe = ("import resource, subprocess, sys, time; t = time.perf_counter(); "
                 "r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL).returncode; "
                 "print(time.perf_counter() - t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, r)")
        out = subprocess.run([sys.executable, "-c", probe, sys.executable, "-m", "schemalog", "verify", path],
                             capture_output=True, text=True, timeout=TIMEOUT, check=True)
    seconds, peak_kb, code = out.stdout.split()
    seconds, peak = float(seconds), int(peak_kb) / 1024
    result = {0: "proved", 1: "counterexample", 3: "no proof"}.get(int(code), f"exit {code}")
    return {"behaviours": sum(branching ** level for level in range(depth)), "seconds": seconds,
            "peak_mb": peak, "result": result}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-states", type=int, default=50_000)
    parser.add_argument("--sample", type=int, default=1000)
    parser.add_argument("--only", choices=["paper", "generated", "grid", "growth"], action="append",
                        help="run only these tables (default: all)")
    args = parser.parse_args()
    tune_gc()
    only = set(args.only or ["paper", "generated", "grid", "growth"])
    print(f"python {sys.version.split()[0]}\n")
    if "paper" in only:
        paper_table(args.max_states)
    if "generated" in only:
        generated_table(args.max_states, args.sample)
    if "grid" in only:
        grid_table(args.max_states)
    if "growth" in only:
        growth_table(args.max_states)


if __name__ == "__main__":
    main()
