"""How the learning path's cost grows with the length of a demonstration.

    python benchmarks/bench_learn.py [--rates 50,100,200,400,800]

One run: the simulated prepareboth demonstration in the kitchen (coffee, then tea: 55 actions)
written at several sampling rates, so the same task has more and more samples. For each, the
seconds spent reading the CSV, segmenting, teaching, and fitting the motion primitives (a DMP per
action, one per merged action), with the cost per thousand samples, and beside it the growth
factor against the previous row (x2 samples each row: x2 time is linear growth). The baseline of
the primitive columns is fitting the same segments one by one: `merged / per-action` says what
merging the primitives costs on top.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

from schemalog.cli.main import tune_gc
from schemalog.learn.demo import read_demonstration, write_demonstration
from schemalog.formats.documents import load_kb
from schemalog.learn.learn import Lesson, fit_motions
from schemalog.logic.parse import parse_term
from schemalog.task.compress import compress
from schemalog.run.scene import read_scene
from schemalog.learn.segment import segment
from schemalog.learn.simulate import simulate
from schemalog.learn.teach import teach
from schemalog.task.tree import instantiate

ROOT = __file__.rsplit("/benchmarks/", 1)[0]


def best_of(runs: int, fn):
    """The fastest of `runs` calls (seconds) and the last result."""
    best, result = float("inf"), None
    for _ in range(runs):
        started = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - started)
    return best, result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rates", default="50,100,200,400,800")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    tune_gc()
    knowledge = load_kb([f"{ROOT}/kb/tasks/prepare_coffee_and_tea.pl"])
    structure = load_kb([f"{ROOT}/kb/tasks/coffee_structure.pl"])
    scene = read_scene(f"{ROOT}/kb/scenes/kitchen.yaml")
    task = parse_term("prepareboth")
    print(f"python {sys.version.split()[0]}; prepareboth in the kitchen; best of {args.runs} runs\n")
    print("| rate Hz | samples | read s | segment s | teach s | DMP per action s | DMP merged s | merged / per-action "
          "| total ms per 1k samples | growth |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    previous = None
    with tempfile.TemporaryDirectory() as where:
        for rate in (float(r) for r in args.rates.split(",")):
            demo = simulate(knowledge, task, scene, rate=rate)
            path = os.path.join(where, f"demo{int(rate)}.csv")
            write_demonstration(demo, path)
            t_read, demo = best_of(args.runs, lambda: read_demonstration(path))
            t_seg, segments = best_of(args.runs, lambda: segment(demo))
            t_teach, teaching = best_of(args.runs, lambda: teach(structure, task, demo, segments))
            # The learned tree, as learn() builds it, for the merged primitives.
            from schemalog.formats.documents import document_from_text
            from schemalog.logic.kb import KnowledgeBase
            from schemalog.learn.teach import learned_text
            text = learned_text(teaching, structure, "", demo_file="d", structure_files=["s"], rows={}, settings="")
            learned = document_from_text(text + open(f"{ROOT}/kb/tasks/coffee_structure.pl").read(),
                                         "<l>").to_kb(KnowledgeBase())
            tree = instantiate(learned, task)
            lesson = Lesson(demo, segments, teaching, text, learned, tree, compress(tree).tree, 0.1)
            t_all, motions = best_of(args.runs, lambda: fit_motions(lesson))
            single = Lesson(demo, segments, teaching, text, learned, tree, tree, 0.1)   # no merged actions
            t_each, _ = best_of(args.runs, lambda: fit_motions(single))
            t_merged = max(t_all - t_each, 0.0)
            total = t_read + t_seg + t_teach + t_all
            growth = f"x{total / previous:.2f}" if previous else "-"
            previous = total
            print(f"| {rate:g} | {len(demo):,} | {t_read:.3f} | {t_seg:.3f} | {t_teach:.3f} | {t_each:.3f} | "
                  f"{t_merged:.3f} | {t_merged / t_each:.2f} | {1000 * total / len(demo) * 1000:.1f} | {growth} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
