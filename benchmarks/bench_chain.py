"""The schema prover's two weak spots (issue 48, item 5), side by side in one run:

    python benchmarks/bench_chain.py [--chains 1000 3000 10000] [--generated 4 5 6]
                                     [--before SRC] [--timeout 600]

- chain N: one schema with N sub-tasks in sequence, step i released by step i-1's
  post-condition (`c{i}` by `c{i-1}.done`; the `wide` shape of bench_scale.py). Compression
  merges it into one leaf of N actions, so `auto` explores it one state at a time.
- generated D: `schemalog generate --depth D --children 10 --rd 0.5 --seed 1`, 1,111 /
  11,111 / 111,111 behaviours for D = 4, 5, 6 (1,111,111 at D = 7: run it alone).

Each `schemalog verify FILE` (default limits) runs in a fresh process; the table gives its wall
time, its peak RSS (ru_maxrss of a probe whose only child is the command), the states its first
line reports, its result, and the growth of time and memory to the next size. With --before
SRC (the src/ of another checkout, grammar/ and kb/ beside it) each runs with that code too.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_scale import wide  # noqa: E402

PROBE = ("import resource, subprocess, sys, time; t = time.perf_counter(); "
         "p = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
         "print(time.perf_counter() - t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, p.returncode); "
         "print(p.stdout)")
RESULT = {0: "proved", 1: "counterexample", 3: "no proof"}


def measure(path: str, src: Path | None, timeout: float) -> dict:
    env = {**os.environ, "PYTHONPATH": str(src)} if src else None
    try:
        out = subprocess.run([sys.executable, "-c", PROBE, sys.executable, "-m", "schemalog", "verify", path],
                             capture_output=True, text=True, timeout=timeout, env=env).stdout
    except subprocess.TimeoutExpired:
        return {"s": timeout, "mb": 0.0, "states": "", "result": f"timed out after {timeout:.0f} s"}
    head, _, text = out.partition("\n")
    seconds, peak_kb, code = head.split()
    found = re.search(r"explored ([\d,]+) states of the compressed tree(?: and ([\d,]+) of the original)?", text)
    states = "" if not found else found.group(1) + (f" + {found.group(2)}" if found.group(2) else "")
    limit = re.search(r"stopped at the limit of ([^(\n]+)", text)
    result = RESULT.get(int(code), f"exit {code}") + (f" ({limit.group(1).strip()})" if limit else "")
    return {"s": float(seconds), "mb": int(peak_kb) / 1024, "states": states, "result": result}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chains", type=int, nargs="*", default=[1000, 3000, 10000])
    parser.add_argument("--generated", type=int, nargs="*", default=[4, 5, 6], help="depths, 10 children each")
    parser.add_argument("--before", type=Path, help="the src/ of the code to compare with")
    parser.add_argument("--timeout", type=float, default=600)
    args = parser.parse_args()
    here = Path(__file__).resolve().parents[1] / "src"
    versions = [("before", args.before), ("after", here)] if args.before else [("", here)]
    print("| task | behaviours | code | wall s | peak MB | KiB per behaviour | states (compressed + original) "
          "| result | time growth | memory growth |")
    print("|---|---:|---|---:|---:|---:|---|---|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        cases = []
        for n in args.chains:
            path = os.path.join(tmp, f"chain{n}.pl")
            Path(path).write_text(wide(n))
            cases.append((f"chain {n:,}", n + 1, path))
        for depth in args.generated:
            path = os.path.join(tmp, f"gen{depth}.pl")
            subprocess.run([sys.executable, "-m", "schemalog", "generate", "--depth", str(depth), "--children", "10",
                            "--rd", "0.5", "--seed", "1", "-o", path], check=True, capture_output=True,
                           env={**os.environ, "PYTHONPATH": str(here)})
            cases.append((f"generated D={depth}", sum(10 ** k for k in range(depth)), path))
        last: dict = {}
        for task, size, path in cases:
            kind = task.split()[0]
            for name, src in versions:
                r = measure(path, src, args.timeout)
                prev = last.get((kind, name))
                grow_t = f"x{r['s'] / prev[1]['s']:.1f} for x{size / prev[0]:.1f}" if prev else ""
                grow_m = f"x{r['mb'] / prev[1]['mb']:.1f}" if prev and prev[1]["mb"] else ""
                last[(kind, name)] = (size, r)
                print(f"| {task} | {size:,} | {name} | {r['s']:.2f} | {r['mb']:.0f} | {r['mb'] * 1024 / size:.1f} "
                      f"| {r['states']} | {r['result']} | {grow_t} | {grow_m} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
