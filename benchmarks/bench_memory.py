"""Memory and speed of long programs, beside `swipl -O`, in one run: does cost grow with iterations?

    python benchmarks/bench_memory.py [--reversals 30 300 3000 30000] [--queries 100 1000]

Three loops that must run in memory that does not grow with their iteration count (issue 37):

1. a tail-recursive loop, `loop(K, L) :- nrev(L, _), K1 is K - 1, loop(K1, L).`, naive
   reverse of a 30-element list K times: peak RSS and logical inferences per second (LIPS,
   496 a reversal) for schemalog, for schemalog with the collection of unreachable bindings
   switched off (what every version before it did; only up to 3,000 reversals, as it grows
   by about 120 KB a reversal), and for `swipl -O`;
2. the same reversals in a failure-driven loop, `(between(1, K, _), nrev(L, _), fail ; true)`;
3. a REPL session: N queries piped into `schemalog repl`, each 30 reversals.

Each figure is the median of --rounds processes (3; peak RSS is the largest of the processes' own,
read from wait4), start-up included
in the RSS and excluded from the LIPS (each system times its own query, after running it once
with K = 1, which compiles the clauses). swipl (Debian:
swi-prolog-nox) must be on PATH.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_engine import INFERENCES, NREV as BENCH   # app/3, nrev/2, range/3 and bench/2

NREV = BENCH + """
loop(0, _) :- !.
loop(K, L) :- nrev(L, _), K1 is K - 1, loop(K1, L).
run(K) :- range(1, 30, L), loop(K, L).
fdl(K) :- range(1, 30, L), ( between(1, K, _), nrev(L, _), fail ; true ).
"""

# Ours, in a child process: the query's CPU seconds on stdout (start-up excluded).
OURS = """
import sys, time
from schemalog.logic.engine import Engine
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.cli.main import tune_gc
tune_gc()   # as the command line does
kb = KnowledgeBase()
kb.consult(sys.argv[1])
engine = Engine(kb, max_steps=10**13)
if sys.argv[3] == "off":
    engine.collect_growth = 10**15
engine.first(parse_term(sys.argv[4]))   # warm-up: each clause is compiled at its first call
start = time.process_time()
assert engine.first(parse_term(sys.argv[2])) is not None
print(time.process_time() - start)
"""

SWIPL = """
:- initialization(main, main).
main :- current_prolog_flag(argv, [File, Goal, Warm]), consult(File), term_to_atom(G, Goal),
        term_to_atom(W, Warm), once(W),
        statistics(cputime, T0), once(G), statistics(cputime, T1), T is T1 - T0, writeln(T).
"""


def measured(command: list[str], stdin: str | None = None) -> tuple[str, float]:
    """Run `command`; its stdout and its peak RSS in MB."""
    proc = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    if stdin is not None:
        proc.stdin.write(stdin)
    proc.stdin.close()
    out = proc.stdout.read()
    err = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"{Path(command[0]).name} {command[-1]} exited {proc.returncode}: {err.strip()[-400:]}")
    return out, usage.ru_maxrss / 1024


def warm_up(goal: str) -> str:
    """The same goal once: run(3000) -> run(1)."""
    return goal.split("(")[0] + "(1)"


ROUNDS = 3


def median_of(command: list[str]) -> tuple[float, float]:
    """The median CPU seconds `command` prints over ROUNDS processes, and the largest peak RSS."""
    runs = []
    for _ in range(ROUNDS):
        out, mb = measured(command)
        runs.append((float(out.strip().splitlines()[-1]), mb))
    return statistics.median(s for s, _ in runs), max(mb for _, mb in runs)


def ours(program: Path, goal: str, collect: str = "on") -> tuple[float, float]:
    return median_of([sys.executable, "-c", OURS, str(program), goal, collect, warm_up(goal)])


def theirs(swipl: str, runner: Path, program: Path, goal: str) -> tuple[float, float]:
    return median_of([swipl, "-O", str(runner), "--", str(program), goal, warm_up(goal)])


def lips(k: int, seconds: float) -> str:
    return f"{k * INFERENCES / seconds:,.0f}" if seconds > 0 else "-"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reversals", type=int, nargs="+", default=[30, 300, 3_000, 30_000])
    parser.add_argument("--off-up-to", type=int, default=3_000,
                        help="largest K run with the collection switched off (it grows ~120 KB a reversal)")
    parser.add_argument("--queries", type=int, nargs="+", default=[100, 1_000])
    parser.add_argument("--rounds", type=int, default=3, help="processes per figure (the median is shown)")
    args = parser.parse_args()
    global ROUNDS
    ROUNDS = args.rounds
    swipl = shutil.which("swipl")
    if swipl is None:
        raise SystemExit("swipl not found: apt-get install swi-prolog-nox")
    with tempfile.TemporaryDirectory() as tmp:
        program = Path(tmp, "nrev.pl")
        program.write_text(NREV)
        runner = Path(tmp, "run.pl")
        runner.write_text(SWIPL)

        print("1. Tail-recursive loop, run(K): K naive reverses of 30 elements\n")
        print("| reversals | schemalog LIPS | schemalog peak MB | collection off: LIPS | peak MB "
              "| swipl -O LIPS | swipl peak MB | slower than swipl |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|")
        for k in args.reversals:
            goal = f"run({k})"
            s, mb = ours(program, goal)
            if k <= args.off_up_to:
                s_off, mb_off = ours(program, goal, "off")
                off = f"{lips(k, s_off)} | {mb_off:.0f}"
            else:
                off = "- | -"
            t, tmb = theirs(swipl, runner, program, goal)
            ratio = f"{t and s / t:.0f}x" if t > 0 else "-"
            print(f"| {k:,} | {lips(k, s)} | {mb:.0f} | {off} | {lips(k, t)} | {tmb:.0f} | {ratio} |", flush=True)

        print("\n2. Failure-driven loop, fdl(K)\n")
        print("| reversals | schemalog LIPS | schemalog peak MB | swipl -O LIPS | swipl peak MB |")
        print("|---:|---:|---:|---:|---:|")
        for k in args.reversals:
            s, mb = ours(program, f"fdl({k})")
            t, tmb = theirs(swipl, runner, program, f"fdl({k})")
            print(f"| {k:,} | {lips(k, s)} | {mb:.0f} | {lips(k, t)} | {tmb:.0f} |", flush=True)

        print("\n3. A REPL session: N queries `run(30).` piped into `schemalog repl nrev.pl`\n")
        print("| queries | peak MB |")
        print("|---:|---:|")
        for n in args.queries:
            _, mb = measured([sys.executable, "-m", "schemalog", "repl", str(program)], "run(30).\n" * n)
            print(f"| {n:,} | {mb:.0f} |", flush=True)


if __name__ == "__main__":
    main()
