"""What skipping the interpreter's teardown saves at the end of a large command, in one run.

    python benchmarks/bench_exit.py [--depth 17] [--children 2] [--runs 3]

Generates a task (`schemalog generate`, RD 0.5; depth 17 x 2 children = 131,071 behaviours)
and runs `schemalog compress FILE --json` on it, output to /dev/null, two ways taking turns:

- `run()`: the console script's entry point, which flushes and leaves with `os._exit`;
- `sys.exit(main())`: the same command line, then Python's normal shutdown, which frees the
  workspace, the trees and the knowledge base object by object.

Each child notes the moment `main()` returns; the table gives the median wall time of the whole
process and of what comes after `main()` (the exit), and their ratio.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = """
import sys, time
import schemalog.cli.main as m
main = m.main
def timed(argv=None):
    code = main(argv)
    sys.stderr.write(f"RETURNED {time.time()!r}\\n"); sys.stderr.flush()
    return code
m.main = timed
sys.argv[0] = "schemalog"
if WAY == "run":
    m.run()
m.tune_gc(); sys.setrecursionlimit(20_000)
sys.exit(m.main())
"""


def _one(way: str, task: Path) -> tuple[float, float]:
    """(whole process, after main() returned) in seconds."""
    started = time.time()
    r = subprocess.run([sys.executable, "-c", CHILD.replace("WAY", repr(way)), "compress", str(task), "--json"],
                       cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=True,
                       env={**os.environ, "PYTHONPATH": str(ROOT / "src")})
    ended = time.time()
    returned = float(next(l for l in r.stderr.splitlines() if l.startswith("RETURNED")).split()[1])
    return ended - started, ended - returned


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--depth", type=int, default=17)
    parser.add_argument("--children", type=int, default=2)
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        task = Path(tmp) / "task.pl"
        subprocess.run([sys.executable, "-m", "schemalog", "generate", "--depth", str(args.depth),
                        "--children", str(args.children), "--rd", "0.5", "--seed", "1", "-o", str(task)],
                       check=True, env={**os.environ, "PYTHONPATH": str(ROOT / "src")})
        times: dict[str, list[tuple[float, float]]] = {"run()": [], "sys.exit(main())": []}
        for _ in range(args.runs):
            for way, key in (("run", "run()"), ("exit", "sys.exit(main())")):
                times[key].append(_one(way, task))
    print("| exit | whole s | after main() s |\n|---|---:|---:|")
    for key, rows in times.items():
        print(f"| `{key}` | {statistics.median(w for w, _ in rows):.2f} | "
              f"{statistics.median(a for _, a in rows):.3f} |")
    fast, slow = (statistics.median(a for _, a in times[k]) for k in times)
    whole_fast, whole_slow = (statistics.median(w for w, _ in times[k]) for k in times)
    print(f"\nthe exit: x{slow / max(fast, 1e-6):.0f} faster with os._exit; "
          f"the whole command x{whole_slow / whole_fast:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
