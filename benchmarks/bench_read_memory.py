"""Peak memory to read a file holding one big quoted atom, against the file's size.

    python benchmarks/bench_read_memory.py [--before SRC] [--sizes 1 2 5 10] [--timeout 300]

For each size (MB) it writes `p('aaaa...').` and runs `schemalog check FILE` and
`schemalog query FILE 'p(X), atom_length(X, N)'` in a fresh process, with no memory ceiling,
and prints a Markdown table of each process's peak resident set (ru_maxrss of a wrapper's only
child) and CPU seconds. With `--before SRC` (a `src/` directory of another checkout, with
its grammar/ and kb/ beside it, e.g. from `git archive 9719e15 src grammar kb | tar -x -C
/tmp/old`) the same commands run with that code too, alternating, in the same run.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[1] / "src"

# The command runs as the wrapper's only child, so RUSAGE_CHILDREN's peak is that command's.
WRAPPER = """
import json, resource, subprocess, sys
try:
    code = subprocess.run(sys.argv[2:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                          timeout=float(sys.argv[1])).returncode
except subprocess.TimeoutExpired:
    code = -1
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(json.dumps([code, r.ru_maxrss, r.ru_utime + r.ru_stime]))
"""

COMMANDS = {"check": ["check"], "query atom_length": ["query", "{file}", "p(X), atom_length(X, N)"]}


def measure(src: Path, argv: list[str], timeout: float) -> tuple[int, float, float]:
    """Exit status, peak RSS in MiB and CPU seconds of `python -m schemalog ARGV` with `src`."""
    env = {**os.environ, "PYTHONPATH": str(src), "SCHEMALOG_MAX_MEMORY": "off"}
    out = subprocess.run([sys.executable, "-c", WRAPPER, str(timeout), sys.executable, "-m", "schemalog",
                          *argv], capture_output=True, text=True, env=env, check=True).stdout
    code, rss_kib, cpu = json.loads(out)
    return code, rss_kib / 1024, cpu


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, help="the src/ directory of the code to compare with")
    parser.add_argument("--sizes", type=float, nargs="+", default=[1, 2, 5, 10], help="atom sizes in MB")
    parser.add_argument("--timeout", type=float, default=300, help="seconds per command (default 300)")
    args = parser.parse_args()
    versions = [("before", args.before)] if args.before else []
    versions.append(("after", HERE))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for mb in args.sizes:
            path = Path(tmp, f"big{mb:g}.pl")
            path.write_text(f"p('{'a' * int(mb * 1_000_000)}').\n")
            size = path.stat().st_size / 2**20
            for name, argv in COMMANDS.items():
                argv = [a.format(file=path) for a in argv] if "{file}" in argv else [*argv, str(path)]
                for version, src in versions:
                    code, rss, cpu = measure(src, argv, args.timeout)
                    rows.append((f"{mb:g}", name, version, f"{rss:,.0f}", f"{rss / size:,.1f}", f"{cpu:.2f}",
                                 str(code)))
                    print(" | ".join(rows[-1]), file=sys.stderr, flush=True)
    print("| atom MB | command | version | peak RSS MiB | RSS / file size | CPU s | exit |")
    print("|---:|---|---|---:|---:|---:|---:|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
