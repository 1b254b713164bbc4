"""How the learning path's cost grows with the length of a recording, beside the old primitives.

    python benchmarks/bench_learn.py [--rows 10000,100000,1000000] [--old-rev 1f951c6] [--old-up-to 100000]

One recording: the simulated preparecoffee demonstration in the kitchen (21 motions, 6 gripper
commands, 40 s), simulated without noise at 100 Hz, then resampled (linear interpolation of the
hand, its orientation and the objects) to each number of rows over the same 40 s, with 1 mm of
fresh white noise on the hand: a valid recording at 250 Hz to 25 kHz that segments into the same
27 actions. For each size, the seconds spent reading the CSV, segmenting, teaching, and fitting
the motion primitives (a DMP per action, one per merged action: `learn`'s default 30 bases), and
beside the last the same primitives fitted by src/schemalog/learn/primitives.py as it was at
--old-rev (read from git; only up to --old-up-to rows: its smoothing window grows with the
samples per basis, so its cost is quadratic in the rows). Growth is against the previous row
(x10 rows each row: x10 time is linear growth).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
import types

import numpy as np

from schemalog.cli.main import tune_gc
from schemalog.formats.documents import document_from_text, load_kb
from schemalog.learn import learn as learn_module
from schemalog.learn.demo import Demonstration, GripperEvent, read_demonstration, write_demonstration
from schemalog.learn.learn import Lesson, fit_motions
from schemalog.learn.segment import segment
from schemalog.learn.simulate import simulate
from schemalog.learn.teach import learned_text, teach
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.run.scene import read_scene
from schemalog.task.compress import compress
from schemalog.task.tree import instantiate

ROOT = __file__.rsplit("/benchmarks/", 1)[0]


def resampled(demo: Demonstration, rows: int, seed: int = 0) -> Demonstration:
    """The demonstration at `rows` evenly spaced samples over its duration, 1 mm of noise on the hand."""
    times = np.linspace(demo.times[0], demo.times[-1], rows)

    def at(track: np.ndarray) -> np.ndarray:
        return np.stack([np.interp(times, demo.times, track[:, k]) for k in range(track.shape[1])], axis=1)

    q = at(demo.orientations)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    hand = at(demo.positions) + np.random.default_rng(seed).normal(0.0, 0.001, (rows, 3))
    events = []
    for e in demo.gripper:
        index = int(np.searchsorted(times, demo.times[e.index]))
        events.append(GripperEvent(index, e.command, index + 2))
    return Demonstration(np.round(times, 7), hand, q, tuple(events),
                         {name: at(track) for name, track in demo.objects.items()}, np.arange(2, rows + 2),
                         "resampled", "line")


def old_primitives(rev: str):
    """src/schemalog/learn/primitives.py as it was at `rev`, as a module, or None without git."""
    try:
        source = subprocess.run(["git", "-C", ROOT, "show", f"{rev}:src/schemalog/learn/primitives.py"],
                                capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    module = types.ModuleType("old_primitives")
    sys.modules[module.__name__] = module           # dataclasses look their module up
    exec(compile(source, f"{rev}:primitives.py", "exec"), module.__dict__)
    return module


def timed(fn):
    started = time.perf_counter()
    result = fn()
    return time.perf_counter() - started, result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rows", default="10000,100000,1000000")
    parser.add_argument("--old-rev", default="1f951c6")
    parser.add_argument("--old-up-to", type=int, default=100_000)
    args = parser.parse_args()
    tune_gc()
    knowledge = load_kb([f"{ROOT}/kb/tasks/prepare_coffee_and_tea.pl"])
    structure_text = open(f"{ROOT}/kb/tasks/coffee_structure.pl").read()
    structure = load_kb([f"{ROOT}/kb/tasks/coffee_structure.pl"])
    task = parse_term("preparecoffee")
    base = simulate(knowledge, task, read_scene(f"{ROOT}/kb/scenes/kitchen.yaml"), noise=0.0)
    old = old_primitives(args.old_rev)
    print(f"python {sys.version.split()[0]}; preparecoffee in the kitchen ({base.times[-1]:.1f} s), resampled; "
          f"one run each; old primitives: {args.old_rev if old else 'not available (no git)'}\n")
    print("| rows | rate Hz | read s | segment s | teach s | primitives s | old primitives s | old / new "
          "| growth (read, segment, primitives) | old growth |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    previous = previous_old = None
    with tempfile.TemporaryDirectory() as where:
        for rows in (int(r) for r in args.rows.split(",")):
            path = os.path.join(where, f"demo{rows}.csv")
            write_demonstration(resampled(base, rows), path)
            t_read, demo = timed(lambda: read_demonstration(path))
            t_seg, segments = timed(lambda: segment(demo))
            t_teach, teaching = timed(lambda: teach(structure, task, demo, segments))
            text = learned_text(teaching, structure, "", demo_file="d", structure_files=["s"], rows={}, settings="")
            learned = document_from_text(text + structure_text, "<l>").to_kb(KnowledgeBase())
            tree = instantiate(learned, task)
            lesson = Lesson(demo, segments, teaching, text, learned, tree, compress(tree).tree, 0.1)
            t_fit, motions = timed(lambda: fit_motions(lesson))
            t_old = None
            if old is not None and rows <= args.old_up_to:
                saved = learn_module.primitives
                learn_module.primitives = old
                try:
                    t_old, _ = timed(lambda: fit_motions(lesson))
                finally:
                    learn_module.primitives = saved
            now = (t_read, t_seg, t_fit)
            growth = ", ".join(f"x{a / b:.1f}" for a, b in zip(now, previous)) if previous else "-"
            old_growth = f"x{t_old / previous_old:.1f}" if t_old is not None and previous_old else "-"
            previous, previous_old = now, t_old
            print(f"| {rows:,} | {rows / base.times[-1]:,.0f} | {t_read:.2f} | {t_seg:.2f} | {t_teach:.3f} | "
                  f"{t_fit:.2f} | {'-' if t_old is None else f'{t_old:.2f}'} | "
                  f"{'-' if t_old is None else f'{t_old / t_fit:.1f}'} | {growth} | {old_growth} |", flush=True)
            assert len(motions.actions) == 21, "the resampled recording segments as the original"
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
