"""Big and wide inputs: check, compress, run, show and verify in time linear in their size.

    python benchmarks/bench_scale.py [--quick] [--timeout 300] [--shapes wide chain binary cond]

It writes, in a temporary directory, task files of four shapes at growing sizes, runs each
command on each as a user would (`python -m schemalog ...`, a fresh process), and prints a
Markdown table: the CPU seconds of each run (the machine may be shared: CPU time, not wall
time), its exit status, and the growth to the next size (time(10x size) / time(size): about 10
means linear, 1 means the size does not matter, 100 quadratic; from 10k to 50k it is
scaled to a 10x step).

- wide N:   one schema with N sub-tasks in sequence (`c{i}` released by `c{i-1}.done`)
- chain N:  t0 has sub-task t1, t1 has t2, ... N deep: refused at --max-depth (256)
- binary L: t0 has two sub-tasks t1, t1 two t2, ... L levels (2^L behaviours): refused at
            --max-nodes without building it
- cond N:   a releaser that is an N-literal `and` (`p0 and p1 and ...`), true in the initial state

Reading the files (lark's LALR parser, logic/parse.py) is part of every command; `check`
shows what reading and instantiating alone cost.
"""

from __future__ import annotations

import argparse
import math
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


SHAPES = {
    "wide": (wide, (1_000, 10_000, 50_000), ("check", "compress", "run", "verify --max-states 3000")),
    "chain": (chain, (1_000, 10_000, 100_000), ("check",)),
    "binary": (binary, (20, 40), ("check",)),
    "cond": (cond, (1_000, 10_000, 100_000), ("check", "show --json", "compress", "run",
                                              "verify --max-states 3000")),
}
QUICK = {"wide": (1_000, 10_000), "chain": (1_000, 10_000), "binary": (20, 40), "cond": (1_000, 10_000)}


def timed(argv: list[str], timeout: float) -> tuple[float, int, str]:
    """CPU seconds of one command in a fresh process, its exit status, its last stderr line."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        done = subprocess.run(argv, capture_output=True, text=True, timeout=timeout)
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
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for shape in args.shapes:
            make, sizes, commands = SHAPES[shape]
            sizes = QUICK[shape] if args.quick else sizes
            paths = {}
            for n in sizes:
                paths[n] = Path(tmp, f"{shape}{n}.pl")
                paths[n].write_text(make(n))
            for command in commands:
                times = []
                for n in sizes:
                    argv = [sys.executable, "-m", "schemalog", *command.split(), str(paths[n])]
                    started = time.perf_counter()
                    cpu, code, err = timed(argv, args.timeout)
                    wall = time.perf_counter() - started
                    times.append(cpu)
                    # per 10x of size, so 10k -> 50k compares with 1k -> 10k (binary: per 10x levels)
                    growth = "" if len(times) < 2 else \
                        f"x{(times[-1] / max(times[-2], 1e-9)) ** (1 / math.log10(n / sizes[len(times) - 2])):.1f}"
                    note = err if code not in (0,) else ""
                    rows.append((shape, f"{n:,}", command, f"{cpu:.2f}", f"{wall:.2f}", str(code), growth,
                                 note[:110]))
                    print(" | ".join(rows[-1]), file=sys.stderr, flush=True)
    print("| shape | size | command | CPU s | wall s | exit | growth | message |")
    print("|---|---:|---|---:|---:|---:|---:|---|")
    for row in rows:
        print("| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
