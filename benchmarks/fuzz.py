"""The long fuzz profile: the generators of tests/fuzz/ for N minutes, every distinct failure once.

    python benchmarks/fuzz.py --minutes 10                     # every probe, round robin
    python benchmarks/fuzz.py --minutes 3 --probes queries knowledge --findings /tmp/fuzz-findings.md

Runs the probes of tests/fuzz/test_fuzz_cli.py and test_fuzz_api.py (PROBES: mutated knowledge, scenes,
demonstrations, queries, odd command lines, hostile file names, the REPL on standard input, signals,
exports, includes, mutated BT.CPP trees with their models and semantics files beside a secret only an
include reaches, sweep grids, and the Python API under odd arguments) with the long generators
(SCHEMALOG_FUZZ=long: deep nesting, wide tasks, unlowered limits) and random seeds, in chunks of
--chunk examples per probe, until the time is up. It never stops at a failure: each broken promise
is reduced to a signature (its kind, numbers and names taken out) and kept once, with the
smallest case that showed it. It prints the inputs tried per probe, the exit statuses seen, the
distinct failures with a reproducer each, and the time; --findings appends each new failure to a
Markdown file as it is found, and the report at the end. Exit status 0 when nothing failed, 1 otherwise.
"""

from __future__ import annotations

import argparse
import collections
import os
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SUBPROCESS_PROBES = {"repl", "signals"}


def load_probes(fast: bool):
    """The probes of the fuzz suite, with the long generators unless `fast`."""
    if not fast:
        os.environ["SCHEMALOG_FUZZ"] = "long"
    sys.path[:0] = [str(ROOT / "src"), str(ROOT / "tests" / "fuzz")]
    import test_fuzz_api
    import test_fuzz_cli
    return {**test_fuzz_cli.PROBES, **test_fuzz_api.PROBES}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=5.0, help="how long to run (default 5)")
    parser.add_argument("--probes", nargs="+", metavar="NAME", help="only these probes (default: all)")
    parser.add_argument("--chunk", type=int, default=100,
                        help="examples per in-process probe before moving on, a tenth of it for the "
                             "subprocess probes (default 100)")
    parser.add_argument("--seed", type=int, help="seed of the first chunk (default: random); chunk i uses seed + i")
    parser.add_argument("--fast", action="store_true", help="the fast profile's generators (what CI draws from)")
    parser.add_argument("--findings", metavar="FILE", help="append the distinct failures to this Markdown file")
    parser.add_argument("--log", metavar="FILE", help="keep the case running now in this file")
    parser.add_argument("--repro-dir", metavar="DIR",
                        help="write each distinct failure's whole reproducer here (reproducers in the report are cut)")
    args = parser.parse_args()
    # Names that are not UTF-8 (the file-names probe) reach reproducers and messages as surrogates.
    sys.stdout.reconfigure(errors="backslashreplace")

    from hypothesis import HealthCheck, Phase, given, seed, settings

    probes = load_probes(args.fast)
    from harness import signature

    names = args.probes or list(probes)
    unknown = [n for n in names if n not in probes]
    if unknown:
        parser.error(f"unknown probes {unknown}; there are {list(probes)}")
    tried = collections.Counter()
    statuses = collections.defaultdict(collections.Counter)
    spent = collections.Counter()
    failures: dict[str, dict] = {}
    first_seed = args.seed if args.seed is not None else random.randrange(1 << 30)
    start = time.monotonic()
    stop_at = start + args.minutes * 60
    chunk = 0

    def run_chunk(name: str, chunk_seed: int) -> None:
        strategies, probe, check = probes[name]

        # the probes that start a process per case take ten times as long per case
        examples = max(2, args.chunk // 10) if name in SUBPROCESS_PROBES else args.chunk

        @settings(max_examples=examples, database=None, deadline=None, phases=[Phase.generate],
                  suppress_health_check=list(HealthCheck))
        @seed(chunk_seed)
        @given(**strategies)
        def body(**drawn):
            if time.monotonic() > stop_at:
                return
            began = time.monotonic()
            if args.log:   # what is running now, in case the run dies on it (a case beyond every guard)
                Path(args.log).write_text(f"{name} {drawn!r}\n", encoding="utf-8", errors="backslashreplace")
            case, outcome = probe(**drawn)
            spent[name] += time.monotonic() - began
            tried[name] += 1
            statuses[name]["hang" if outcome.hung else outcome.status] += 1
            for problem in check(case, outcome, **drawn):
                key = f"{name}: {signature(problem)}"
                size = len(case.reproducer())
                seen = failures.get(key)
                if seen is None or size < seen["size"]:
                    failures[key] = {"problem": problem, "case": case, "outcome": outcome, "size": size,
                                     "count": (seen or {}).get("count", 0), "probe": name,
                                     "drawn": {k: v for k, v in drawn.items() if k in ("signum", "delay", "wait")}}
                failures[key]["count"] += 1
                if seen is None:
                    line = f"[{time.monotonic() - start:6.0f} s] new failure in {name}: {problem}"
                    print(line, flush=True)
                    if args.findings:   # as it goes, for whoever reads the file while this runs
                        with open(args.findings, "a", encoding="utf-8", errors="backslashreplace") as out:
                            out.write(f"\n- long run (seed {first_seed}) {line}\n\n  ```sh\n  "
                                      + case.reproducer(600).replace("\n", "\n  ") + "\n  ```\n")

        body()

    while time.monotonic() < stop_at:
        for name in names:
            if time.monotonic() >= stop_at:
                break
            run_chunk(name, first_seed + chunk)
            chunk += 1
    elapsed = time.monotonic() - start

    report = [f"## Long fuzz run: {args.minutes:g} min, seed {first_seed}, {sum(tried.values()):,} inputs, "
              f"{len(failures)} distinct failures ({elapsed:.0f} s)", "",
              "| probe | inputs | time s | inputs/s | exit statuses |", "|---|---:|---:|---:|---|"]
    for name in names:
        seen = ", ".join(f"{k}: {v}" for k, v in sorted(statuses[name].items(), key=lambda kv: str(kv[0])))
        rate = tried[name] / spent[name] if spent[name] else 0
        report.append(f"| {name} | {tried[name]:,} | {spent[name]:.0f} | {rate:.1f} | {seen} |")
    for key, failure in sorted(failures.items()):
        case, outcome = failure["case"], failure["outcome"]
        report += ["", f"### {failure['problem'][:200]}", "",
                   f"probe {failure['probe']}, seen {failure['count']} times; exit status {outcome.status}"
                   + (f"; {failure['drawn']}" if failure["drawn"] else ""), "", "```sh", case.reproducer(1200), "```",
                   "", "```", (outcome.stderr.strip() or "(no stderr)")[-1200:], "```"]
    if args.repro_dir:
        Path(args.repro_dir).mkdir(parents=True, exist_ok=True)
        for number, failure in enumerate(sorted(failures.values(), key=lambda f: f["problem"]), 1):
            path = Path(args.repro_dir) / f"failure-{number:02d}.sh"
            # a file name that is not UTF-8 comes back as its own bytes (surrogateescape): the
            # reproducer makes the very file the case had
            path.write_text(f"# {failure['problem']}\n" + failure["case"].reproducer(limit=10**9) + "\n",
                            encoding="utf-8", errors="surrogateescape")
        report.append(f"\nWhole reproducers: {args.repro_dir}/failure-NN.sh")
    text = "\n".join(report) + "\n"
    print(text)
    if args.findings:
        with open(args.findings, "a", encoding="utf-8", errors="backslashreplace") as out:
            out.write("\n" + text)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
