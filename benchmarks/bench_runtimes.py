"""The paper's claim in real runtimes: exported trees ticked in BehaviorTree.CPP and py_trees.

    python benchmarks/bench_runtimes.py [--shapes 4x2,6x4] [--out runtimes.md]

One run over the paper's grid (depth 4-6 x 2-4 children x RD 0, 0.3, 0.5, 0.7, as
`schemalog bench --runtimes`): each generated task, original and compressed, exported to BT.CPP
v4 XML and to a py_trees module and run to completion in each, its actions performed in the
emulated world of the original task. Prints the Markdown table benchmarks/README.md shows
(evaluate/runtimes.py says what each column measures).
"""

from __future__ import annotations

import argparse
import sys
import time

from schemalog.cli.main import tune_gc
from schemalog.evaluate.runtimes import PAPER_REDUCTIONS, PAPER_SHAPES, measure_runtimes, runtimes_markdown


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shapes", help="DEPTHxCHILDREN,... (default: the paper's nine)")
    parser.add_argument("--out", help="also write the table here")
    args = parser.parse_args()
    shapes = PAPER_SHAPES if not args.shapes else tuple(
        tuple(int(x) for x in s.split("x")) for s in args.shapes.split(","))
    tune_gc()
    sys.setrecursionlimit(20_000)
    started = time.perf_counter()
    rows = measure_runtimes(shapes, PAPER_REDUCTIONS, progress=lambda d: print(d, file=sys.stderr))
    command = "python benchmarks/bench_runtimes.py" + (f" --shapes {args.shapes}" if args.shapes else "")
    table = runtimes_markdown(rows, command)
    print(table)
    print(f"{len(rows)} trees in {time.perf_counter() - started:,.0f} s", file=sys.stderr)
    if args.out:
        with open(args.out, "w") as handle:
            handle.write(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
