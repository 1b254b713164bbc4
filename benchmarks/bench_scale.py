"""Big and wide inputs: check, compress, run, show and verify in time linear in their size.

    python benchmarks/bench_scale.py [--quick] [--timeout 300] [--shapes wide chain binary cond ...]
                                     [--sizes N ...] [--commands CMD ...] [--before SRC]

It writes, in a temporary directory, task files of four shapes at growing sizes, runs each
command on each as a user would (`python -m schemalog ...`, a fresh process), and prints a
Markdown table: the CPU seconds of each run (the machine may be shared: CPU time, not wall
time), its exit status, and the growth to the next size (time(10x size) / time(size): about 10
means linear, 1 means the size does not matter, 100 quadratic; from 10k to 50k it is
scaled to a 10x step).

- wide N:   one schema with N sub-tasks in sequence (`c{i}` released by `c{i-1}.done`)
- flat N:   one schema with N sub-tasks all released at once (`true`): each completion changes
            every sibling's mu
- chain N:  t0 has sub-task t1, t1 has t2, ... N deep: refused at --max-depth (256)
- binary L: t0 has two sub-tasks t1, t1 two t2, ... L levels (2^L behaviours): refused at
            --max-nodes without building it
- cond N:   a releaser that is an N-literal `and` (`p0 and p1 and ...`), true in the initial state
- ychain N: YAML, a releaser `a0.done and a1.done and ...` of N literals that nothing makes true
            (N findings on one line)
- yor N:    YAML, a releaser `a0.done ; a1.done ; ...` of N literals, all true initially
- gen N:    `generate --depth 2 --children N`: a task of N + 1 behaviours written as knowledge
            (a command holding {n} and {path} gets them in place, and no file appended)

With `--before SRC` (the src/ directory of another checkout, its grammar/ and kb/ beside it,
e.g. `git archive 9719e15 src grammar kb | tar -x -C /tmp/old`), each command also runs with
that code, just before this tree's, so the two are measured side by side in one run.

Reading the files (lark's LALR parser, logic/parse.py) is part of every command; `check`
shows what reading and instantiating alone cost.
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def wide(n: int) -> str:
    entries = ", ".join(f"(c{i}, {'go' if i == 0 else f'c{i - 1}.done'})" for i in range(n))
    leaves = "\n".join(f"schema(c{i}, [], c{i}.done)." for i in range(n))
    return f"task(t0).\ninitial(go).\nschema(t0, [{entries}], t0.done).\n{leaves}\n"


def flat(n: int) -> str:
    entries = ", ".join(f"(c{i}, true)" for i in range(n))
    leaves = "\n".join(f"schema(c{i}, [], c{i}.done)." for i in range(n))
    return f"task(t0).\nschema(t0, [{entries}], t0.done).\n{leaves}\n"


def chain(n: int) -> str:
    lines = ["task(t0)."] + [f"schema(t{i}, [(t{i + 1}, true)], t{i}.done)." for i in range(n)]
    return "\n".join(lines + [f"schema(t{n}, [], t{n}.done)."]) + "\n"


def binary(levels: int) -> str:
    lines = ["task(t0)."] + [f"schema(t{i}, [(t{i + 1}, true), (t{i + 1}, true)], t{i}.done)."
                             for i in range(levels)]
    return "\n".join(lines + [f"schema(t{levels}, [], t{levels}.done)."]) + "\n"


def cond(n: int) -> str:
    literals = " and ".join(f"p{i}" for i in range(n))
    initial = ", ".join(f"p{i}" for i in range(n))
    return (f"task(t0).\ninitial(({initial})).\nschema(t0, [(a, {literals}), (b, a.done)], t0.done).\n"
            f"schema(a, [], a.done).\nschema(b, [], b.done).\n")


def _yaml(n: int, op: str, initial: bool) -> str:
    atoms = [f"a{i}.done" for i in range(n)]
    init = f"- initial: ({','.join(atoms)})\n" if initial else ""
    return (f"schemalog: 1\nitems:\n- task: t0\n{init}- schema: t0\n  subtasks:\n  - behaviour: b\n"
            f"    releaser: {f' {op} '.join(atoms)}\n  post: t0.done\n- schema: b\n  subtasks: []\n  post: b.done\n")


def ychain(n: int) -> str:
    return _yaml(n, "and", False)


def yor(n: int) -> str:
    return _yaml(n, ";", True)


def gen(n: int) -> str:
    return ""                 # generate makes its own task: the file is only where it writes


SHAPES = {
    "wide": (wide, (1_000, 10_000, 50_000), ("check", "compress", "run", "verify --max-states 3000")),
    "flat": (flat, (1_000, 2_000, 5_000, 10_000), ("run", "verify --max-states 3000", "verify --states all")),
    "chain": (chain, (1_000, 10_000, 100_000), ("check",)),
    "binary": (binary, (20, 40), ("check",)),
    "cond": (cond, (1_000, 10_000, 100_000), ("check", "show --json", "compress", "run",
                                              "verify --max-states 3000")),
    "ychain": (ychain, (10_000, 20_000, 50_000, 100_000), ("check",)),
    "yor": (yor, (10_000, 20_000, 50_000, 100_000), ("check", "verify --max-states 3000")),
    "gen": (gen, (10_000, 30_000, 100_000), ("generate --depth 2 --children {n} -o {path}",)),
}
SUFFIX = {"ychain": ".yaml", "yor": ".yaml"}
QUICK = {"wide": (1_000, 10_000), "flat": (1_000, 10_000), "chain": (1_000, 10_000), "binary": (20, 40), "cond": (1_000, 10_000),
         "ychain": (10_000, 20_000), "yor": (10_000, 20_000), "gen": (10_000, 30_000)}


def timed(argv: list[str], timeout: float, src: Path | None = None) -> tuple[float, int, str]:
    """CPU seconds of one command in a fresh process (with the code in `src`, else as
    installed), its exit status, its last stderr line."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = None if src is None else {**os.environ, "PYTHONPATH": str(src)}
    try:
        done = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, env=env)
        code, err = done.returncode, (done.stderr.strip().splitlines() or [""])[-1]
    except subprocess.TimeoutExpired:
        code, err = -1, f"timed out after {timeout:.0f} s"
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, code, err


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the two smaller sizes of each shape only")
    parser.add_argument("--timeout", type=float, default=300, help="seconds per command (default 300)")
    parser.add_argument("--shapes", nargs="+", choices=list(SHAPES), default=list(SHAPES),
                        help="the shapes to measure (default all)")
    parser.add_argument("--sizes", type=int, nargs="+", help="these sizes instead of the shapes' own")
    parser.add_argument("--commands", nargs="+", help="these commands instead of the shapes' own, e.g. 'run --selector scan'")
    parser.add_argument("--before", type=Path, help="the src/ directory of the code to compare with, side by side")
    args = parser.parse_args()
    here = Path(__file__).resolve().parents[1] / "src"
    versions = [("before", args.before), ("after", here)] if args.before else [("", None)]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for shape in args.shapes:
            make, sizes, commands = SHAPES[shape]
            sizes = args.sizes or (QUICK[shape] if args.quick else sizes)
            commands = args.commands or commands
            paths = {}
            for n in sizes:
                paths[n] = Path(tmp, f"{shape}{n}{SUFFIX.get(shape, '.pl')}")
                paths[n].write_text(make(n))
            for command in commands:
                for version, src in versions:
                    times = []
                    for n in sizes:
                        words = [w.format(n=n, path=paths[n]) for w in command.split()]
                        argv = [sys.executable, "-m", "schemalog", *words, *([] if "{" in command else [str(paths[n])])]
                        started = time.perf_counter()
                        cpu, code, err = timed(argv, args.timeout, src)
                        wall = time.perf_counter() - started
                        times.append(cpu)
                        # per 10x of size, so 10k -> 50k compares with 1k -> 10k (binary: per 10x levels)
                        growth = "" if len(times) < 2 else \
                            f"x{(times[-1] / max(times[-2], 1e-9)) ** (1 / math.log10(n / sizes[len(times) - 2])):.1f}"
                        note = err if code not in (0,) else ""
                        rows.append((shape, f"{n:,}", command, version, f"{cpu:.2f}", f"{wall:.2f}", str(code),
                                     growth, note[:110]))
                        print(" | ".join(rows[-1]), file=sys.stderr, flush=True)
    print("| shape | size | command | code | CPU s | wall s | exit | growth per 10x | message |")
    print("|---|---:|---|---|---:|---:|---:|---:|---|")
    for row in rows:
        print("| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
