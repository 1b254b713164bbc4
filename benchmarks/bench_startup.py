"""How long schemalog takes to start, beside the interpreter's own floor and SWI-Prolog, in one run.

    python benchmarks/bench_startup.py [--runs 15] [--baseline REV]

Each command is run `--runs` times, the commands taking turns so that a slow moment of the
machine falls on all of them; the table gives the median wall time and the 10th-90th
percentile spread. Rows:

- `python -c pass`: what any Python command costs here before it does anything;
- `swipl -g true -t halt`: SWI-Prolog answering `true` (Debian: swi-prolog-nox);
- `schemalog --help`, and `schemalog query kb/tasks/mix_with_spoon.pl true` with the start-up
  cache warm and with it turned off (SCHEMALOG_CACHE_DIR=off);
- with `--baseline REV`, the same two schemalog commands from a checkout of REV (a temporary
  git worktree, run with PYTHONPATH pointing at it), e.g. the commit before the layout change.

It also lists, per schemalog command, the third-party libraries it loads (`-X importtime`).
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
QUERY = ["query", "kb/tasks/mix_with_spoon.pl", "true"]
HEAVY = ("lark", "yaml", "rich", "sympy", "numpy", "matplotlib", "py_trees", "prompt_toolkit")


def _wall(argv: list[str], env: dict) -> float:
    started = time.perf_counter()
    subprocess.run(argv, cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - started


def _libraries(argv: list[str], env: dict) -> list[str]:
    """The third-party libraries `python -X importtime` shows a command importing."""
    out = subprocess.run([sys.executable, "-X", "importtime", *argv[1:]], cwd=ROOT, env=env,
                         capture_output=True, text=True, check=True)
    names = {line.split("|")[-1].strip().split(".")[0] for line in out.stderr.splitlines() if "|" in line}
    return sorted(names & set(HEAVY))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument("--baseline", metavar="REV", help="also time these commands at this git revision")
    args = parser.parse_args()

    env = dict(os.environ)
    cold = {**env, "SCHEMALOG_CACHE_DIR": "off"}
    me = [sys.executable, "-m", "schemalog"]
    rows: list[tuple[str, list[str], dict]] = [("python -c pass", [sys.executable, "-c", "pass"], env)]
    swipl = shutil.which("swipl")
    if swipl:
        rows.append(("swipl -g true -t halt", [swipl, "-g", "true", "-t", "halt"], env))
    rows += [("schemalog --help", [*me, "--help"], env),
             ("schemalog query mix_with_spoon.pl true", [*me, *QUERY], env),
             ("  the same, cache off", [*me, *QUERY], cold)]
    worktree = None
    if args.baseline:
        worktree = Path(tempfile.mkdtemp(prefix="schemalog-baseline-"))
        subprocess.run(["git", "worktree", "add", "--detach", str(worktree), args.baseline], cwd=ROOT,
                       check=True, capture_output=True)
        old = {**env, "PYTHONPATH": str(worktree / "src")}
        rows += [(f"baseline {args.baseline}: --help", [*me, "--help"], old),
                 (f"baseline {args.baseline}: query", [*me, *QUERY], old)]
    try:
        for _, argv, row_env in rows:       # warm the file cache and schemalog's own cache
            _wall(argv, row_env)
        times: list[list[float]] = [[] for _ in rows]
        for _ in range(args.runs):
            for i, (_, argv, row_env) in enumerate(rows):
                times[i].append(_wall(argv, row_env))
        libraries = {label: _libraries(argv, row_env) for label, argv, row_env in rows
                     if argv[:3] == me}
    finally:
        if worktree is not None:
            subprocess.run(["git", "worktree", "remove", "--force", str(worktree)], cwd=ROOT, capture_output=True)

    floor = statistics.median(times[0])
    print(f"{args.runs} runs each, taking turns; median wall time, 10th-90th percentile\n")
    print("| command | median s | spread s | over `python -c pass` | libraries loaded |")
    print("|---|---:|---:|---:|---|")
    for (label, argv, _), samples in zip(rows, times):
        deciles = statistics.quantiles(samples, n=10) if len(samples) > 1 else [samples[0]] * 9
        median = statistics.median(samples)
        libs = ", ".join(libraries.get(label, [])) or ("-" if label in libraries else "")
        print(f"| {label} | {median:.3f} | {deciles[0]:.3f}-{deciles[-1]:.3f} | {median - floor:+.3f} | {libs} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
