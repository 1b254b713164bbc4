"""The public API's overhead: schemalog.load / Task / verify against the internal calls they wrap.

    python benchmarks/bench_api.py [--rounds 3] [--depth 8] [--children 5] [--stages load,compress,verify]

It writes `schemalog generate --depth 8 --children 5 --rd 0.5 --seed 1` (97,656 behaviours)
to a temporary file, then, in one process, takes turns (the order alternating per round):

- internal: read_document + to_kb, Instantiator.instantiate, compress(), prove() and
  vacuity_of(), the calls the command line made before it was built on the API;
- api: schemalog.load(path), kb.task(), task.compress(), schemalog.verify(task, small).

Each stage's CPU seconds (time.process_time; the machine may be shared) are printed per
round, then the medians and the ratio api / internal. Both paths run with the command line's
garbage-collector thresholds (cli.main.tune_gc) and build the same trees (checked).
"""

from __future__ import annotations

import argparse
import gc
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

STAGES = ("load", "task", "compress", "verify")


def internal(path: str, stages: tuple[str, ...]) -> tuple[dict[str, float], tuple]:
    """The stages through the modules below the API."""
    from schemalog.formats.documents import read_document
    from schemalog.run.vacuity import vacuity_of
    from schemalog.run.verify import prove
    from schemalog.run.world import World, initial_state
    from schemalog.task.compress import compress, protected_labels
    from schemalog.task.conditions import Simplifier
    from schemalog.task.schema import knowledge_base
    from schemalog.task.tree import Instantiator, declared_tasks

    times: dict[str, float] = {}
    clock = time.process_time()
    kb = knowledge_base()
    read_document(path).to_kb(kb)
    times["load"], clock = time.process_time() - clock, time.process_time()
    tree = Instantiator(kb).instantiate(declared_tasks(kb)[0])
    times["task"], clock = time.process_time() - clock, time.process_time()
    result = compress(tree, "full", protected_labels(kb, tree), Simplifier())
    times["compress"], clock = time.process_time() - clock, time.process_time()
    verdict = None
    if "verify" in stages:
        world = World(tree)
        world.reset(initial_state(kb))
        report = prove(tree, result.tree, world, [world.atoms], None, tree.label)
        vacuity = vacuity_of(tree, World(tree), report.initial_states, 50_000, report.original_completes)
        verdict = (report.sound, report.complete, report.exhaustive, vacuity.vacuous)
        times["verify"] = time.process_time() - clock
    return times, (tree, result.tree, verdict)


def api(path: str, stages: tuple[str, ...]) -> tuple[dict[str, float], tuple]:
    """The same stages through `import schemalog`."""
    import schemalog

    times: dict[str, float] = {}
    clock = time.process_time()
    kb = schemalog.load(path)
    times["load"], clock = time.process_time() - clock, time.process_time()
    task = kb.task()
    times["task"], clock = time.process_time() - clock, time.process_time()
    small = task.compress()
    times["compress"], clock = time.process_time() - clock, time.process_time()
    verdict = None
    if "verify" in stages:
        report = schemalog.verify(task, small)
        verdict = (report.sound, report.complete, report.exhaustive, report.vacuous)
        times["verify"] = time.process_time() - clock
    return times, (task.tree, small.tree, verdict)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--depth", type=int, default=8)
    parser.add_argument("--children", type=int, default=5)
    parser.add_argument("--stages", default=",".join(STAGES))
    args = parser.parse_args()
    stages = tuple(args.stages.split(","))
    from schemalog.cli.main import tune_gc

    tune_gc()
    with tempfile.TemporaryDirectory() as tmp:
        path = str(Path(tmp) / "big.pl")
        subprocess.run([sys.executable, "-m", "schemalog", "generate", "--depth", str(args.depth), "--children",
                        str(args.children), "--rd", "0.5", "--seed", "1", "-o", path], check=True,
                       capture_output=True)
        runs: dict[str, list[dict[str, float]]] = {"internal": [], "api": []}
        for k in range(args.rounds):
            order = [("internal", internal), ("api", api)]
            if k % 2:
                order.reverse()
            outcome = {}
            for name, path_of in order:
                gc.collect()
                times, trees = path_of(path, stages)
                runs[name].append(times)
                outcome[name] = trees
                print(f"round {k + 1} {name:8}: " + ", ".join(f"{s} {times[s]:.2f} s" for s in times),
                      flush=True)
            assert outcome["internal"][0] == outcome["api"][0], "the two paths built different trees"
            assert outcome["internal"][1] == outcome["api"][1], "the two paths compressed differently"
            assert outcome["internal"][2] == outcome["api"][2], "the two paths proved differently"
        behaviours = sum(1 for _ in _walk(outcome["api"][0]))
        print(f"\n{behaviours:,} behaviours, {args.rounds} rounds, CPU seconds (median)\n")
        print("| stage | internal | api | api / internal |\n|---|---:|---:|---:|")
        totals = {"internal": 0.0, "api": 0.0}
        for stage in runs["api"][0]:
            a = statistics.median(r[stage] for r in runs["internal"])
            b = statistics.median(r[stage] for r in runs["api"])
            totals["internal"] += a
            totals["api"] += b
            print(f"| {stage} | {a:.2f} | {b:.2f} | {b / a:.3f} |")
        print(f"| **all** | {totals['internal']:.2f} | {totals['api']:.2f} | "
              f"**{totals['api'] / totals['internal']:.3f}** |")


def _walk(tree):
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node
        stack.extend(node.children)


if __name__ == "__main__":
    main()
