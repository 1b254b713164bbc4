"""The classic benchmark suite (benchmarks/classic/*.pl) beside `swipl -O`, in one run.

    python benchmarks/bench_classic.py [--rounds 5] [--target 0.3] [--out table.md] [PROGRAM ...]
    python benchmarks/bench_classic.py --smoke [PROGRAM ...]       answers only, no timing

Each program defines `bench(Answer)`: one run of the benchmark, with a ground answer. For
every program and round, two child processes take turns: schemalog's engine (this script
with `--child`) and `swipl -O`. Each loads the program, runs `bench(A)` once (the answer,
written in canonical form and compared between the two; a program whose answers differ is
not timed), then times `(between(1, N, _), bench(_), fail ; true)` inside itself: CPU time
(`time.process_time` around the engine's query, `statistics(cputime)` in swipl), so start-up
and loading are excluded. N is calibrated once per system before the rounds, doubling until a
timing takes `--target` seconds. A program's ratio is the median of its rounds' ratios of
seconds per run (schemalog / swipl); the table gives the geometric mean over the programs
timed and each system's peak resident memory per program (the child's maximum RSS, the
interpreter's own included; `os.wait4`). With `--baseline CHECKOUT`, schemalog from that
checkout's src/ runs in the same rounds too (the same N), for a before/after in one run.

A program our reader cannot load (none now) is listed as not loadable
with the error, and counts in no mean. `--smoke` only checks the answers (tests/logic/
test_classic.py runs it).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
CLASSIC = HERE / "classic"

# Programs our reader cannot load yet, and why (checked by --smoke: a program listed here
# that loads and answers as swipl does is reported, so the list stays true).
NOT_LOADABLE: dict[str, str] = {}   # chat_parser was, until the reader translated DCG rules

_DRIVER = """
'$bc_calibrate'(N0, Target, N) :-
    '$bc_time'(N0, T),
    ( T >= Target -> N = N0 ; N1 is N0 * 2, '$bc_calibrate'(N1, Target, N) ).
'$bc_time'(N, T) :-
    garbage_collect,
    statistics(cputime, T0),
    ( between(1, N, _), '$bc_run', fail ; true ),
    statistics(cputime, T1),
    T is T1 - T0.
'$bc_run' :- {goal}.
'$bc_main'(Given, Target) :-
    ( catch(bench(A), E, (print_message(error, E), fail)) -> true ; A = '$failed' ),
    write_term(A, [quoted(true), ignore_ops(true)]), nl,
    ( Given =:= 0 -> '$bc_calibrate'(1, Target, N) ; N = Given ),
    '$bc_time'(N, T),
    format("~w ~15f~n", [N, T]).
"""


def canonical(term) -> str:
    """A term as swipl's `write_term(T, [quoted(true), ignore_ops(true)])` writes it."""
    from schemalog.logic.terms import CONS, NIL, Atom, Float, Int, Str, Struct, Var, quote_atom
    out: list[str] = []
    stack: list = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, str):
            out.append(t)
        elif isinstance(t, Int):
            out.append(str(t.value))
        elif isinstance(t, Float):
            out.append(repr(t.value))
        elif isinstance(t, Atom):
            out.append(_atom(t, NIL, quote_atom))
        elif isinstance(t, Str):
            out.append('"' + t.value.replace("\\", "\\\\").replace('"', '\\"') + '"')
        elif isinstance(t, Var):
            out.append("_")
        elif isinstance(t, Struct) and t.name == CONS and len(t.args) == 2:
            items, tail = [], t
            while isinstance(tail, Struct) and tail.name == CONS and len(tail.args) == 2:
                items.append(tail.args[0])
                tail = tail.args[1]
            parts: list = ["["]
            for k, item in enumerate(items):
                parts += [item] if k == 0 else [",", item]
            if tail != NIL:
                parts += ["|", tail]
            parts.append("]")
            stack.extend(reversed(parts))
        else:
            parts = [_atom(Atom(t.name), NIL, quote_atom) + "("]
            for k, arg in enumerate(t.args):
                parts += [arg] if k == 0 else [",", arg]
            parts.append(")")
            stack.extend(reversed(parts))
    return "".join(out)


def _atom(atom, nil, quote_atom) -> str:
    """An atom as swipl writes it quoted: a plain name bare, even one that is an operator
    of our reader (`not`, `and`), which ignore_ops writes bare too."""
    if re.fullmatch(r"[a-z][A-Za-z0-9_]*", atom.name):
        return atom.name
    return quote_atom(atom.name)     # `[]` bare: our reader has no '[]' apart from []


def ours_answer(path: Path) -> str:
    """Load `path` into a fresh knowledge base and answer bench(A) once: the canonical text
    of A, or raise (a load error, an exception, a failure)."""
    from schemalog.logic.engine import Engine
    from schemalog.logic.kb import KnowledgeBase
    from schemalog.logic.parse import parse_term
    kb = KnowledgeBase()
    kb.consult(path)
    goal = parse_term("bench(A)")
    b = Engine(kb, max_steps=10**13).first(goal)
    if b is None:
        raise RuntimeError(f"bench(A) failed ({'; '.join(kb.warnings) or 'no warnings'})")
    return canonical(b.resolve(goal.args[0]))


def child(path: Path, iterations: int, target: float, timed_goal: str = "bench(_)",
          src: Path = HERE.parent / "src") -> None:
    """Run in a child process: the answer, then N and the CPU seconds of N runs (JSON)."""
    import schemalog
    if Path(schemalog.__file__).resolve().parents[1] != src.resolve():
        raise SystemExit(f"the child imported {schemalog.__file__}, not {src}'s")
    from schemalog.cli.main import tune_gc
    from schemalog.logic.engine import Engine
    from schemalog.logic.kb import KnowledgeBase
    from schemalog.logic.parse import parse_term
    tune_gc()                         # what `schemalog` itself runs with
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    try:
        answer = ours_answer(path)
    except Exception as err:          # reported, not timed
        print(json.dumps({"error": f"{type(err).__name__}: {err}"}))
        return
    kb = KnowledgeBase()
    kb.consult(path)

    def timed(n: int) -> float:
        goal = parse_term(f"(between(1, {n}, _), {timed_goal}, fail ; true)")
        engine = Engine(kb, max_steps=10**13)
        started = time.process_time()
        engine.first(goal)
        return time.process_time() - started

    n = iterations or 1
    seconds = timed(n)
    while not iterations and seconds < target:
        n *= 2
        seconds = timed(n)
    print(json.dumps({"answer": answer, "n": n, "seconds": seconds}))


def _run(argv: list[str], timeout: float, env: dict | None = None) -> tuple[str, str, float]:
    """stdout, stderr and the peak RSS (MiB) of a child process."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(argv, stdout=out, stderr=err, text=True, env=env)
        started = time.monotonic()
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - started > timeout:
                proc.kill()
                pid, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.01)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return out.read(), err.read(), usage.ru_maxrss / 1024


def run_ours(path: Path, iterations: int, target: float, goal: str = "bench(_)",
             src: Path = HERE.parent / "src") -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(src)
    out, err, rss = _run([sys.executable, str(Path(__file__).resolve()), "--child", str(path), "--src", str(src),
                          "--iterations", str(iterations), "--target", str(target), "--goal", goal], 3600, env)
    try:
        result = json.loads(out.strip().splitlines()[-1])
    except (ValueError, IndexError):
        result = {"error": (err.strip().splitlines() or ["no output"])[-1]}
    result["rss"] = rss
    return result


def run_swipl(swipl: str, path: Path, iterations: int, target: float, goal: str = "bench(_)") -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        driver = Path(tmp) / "driver.pl"
        driver.write_text(_DRIVER.replace("{goal}", goal))
        goal = f"'$bc_main'({iterations}, {target})"
        out, err, rss = _run([swipl, "-O", "-q", "-g", goal, "-t", "halt", str(driver), str(path)], 3600)
    lines = out.strip().splitlines()
    if len(lines) < 2:
        return {"error": err.strip()[-300:] or "no output", "rss": rss}
    n, seconds = lines[-1].split()
    return {"answer": lines[-2], "n": int(n), "seconds": float(seconds), "rss": rss}


def programs(names: list[str]) -> list[Path]:
    paths = sorted(CLASSIC.glob("*.pl"))
    if names:
        wanted = {n.removesuffix(".pl") for n in names}
        paths = [p for p in paths if p.stem in wanted]
        missing = wanted - {p.stem for p in paths}
        if missing:
            raise SystemExit(f"no such program in {CLASSIC}: {', '.join(sorted(missing))}")
    return paths


def swipl_answer(swipl: str, path: Path) -> str:
    result = run_swipl(swipl, path, 1, 0.0)
    if "error" in result:
        raise RuntimeError(f"swipl on {path.name}: {result['error']}")
    return result["answer"]


def smoke(swipl: str, paths: list[Path]) -> list[str]:
    """The problems found: each program gives swipl's answer, or is listed as not loadable
    and still fails to load. An empty list means all is well."""
    problems = []
    for path in paths:
        theirs = swipl_answer(swipl, path)
        try:
            ours = ours_answer(path)
        except Exception as err:
            if path.stem not in NOT_LOADABLE:
                problems.append(f"{path.stem}: {type(err).__name__}: {err}")
            continue
        if path.stem in NOT_LOADABLE:
            problems.append(f"{path.stem}: listed as not loadable, but it loads"
                            + ("" if ours == theirs else " (with an answer other than swipl's)"))
        elif ours != theirs:
            problems.append(f"{path.stem}: answer {ours[:200]} where swipl gives {theirs[:200]}")
    return problems


def sieve(swipl: str, sizes: list[int], rounds: int, target: float) -> None:
    """sieve.pl's primes(MAX, _) for each MAX, ours and swipl taking turns: the growth of a
    predicate's assert/retract cost with its size (MAX clauses asserted, all retracted)."""
    path = CLASSIC / "sieve.pl"
    print("| primes to | schemalog s | swipl -O s | ratio | schemalog growth | swipl growth |")
    print("|---:|---:|---:|---:|---:|---:|")
    previous = None
    for size in sizes:
        goal = f"primes({size}, _)"
        t_ours, t_swipl = [], []
        for _ in range(rounds):
            ours = run_ours(path, 1, target, goal)
            theirs = run_swipl(swipl, path, 0, target, goal)
            t_ours.append(ours["seconds"])
            t_swipl.append(theirs["seconds"] / theirs["n"])
        a, b = statistics.median(t_ours), statistics.median(t_swipl)
        growth = (f"x{a / previous[0]:.2f} | x{b / previous[1]:.2f}" if previous else " | ")
        print(f"| {size:,} | {a:.4f} | {b:.6f} | {a / b:.0f}x | {growth} |", flush=True)
        previous = (a, b)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("programs", nargs="*", help="names of programs in benchmarks/classic (default: all)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--target", type=float, default=0.3, help="seconds per timing, calibrated")
    parser.add_argument("--out", type=Path, help="also write the table (markdown) here")
    parser.add_argument("--smoke", action="store_true", help="check the answers only")
    parser.add_argument("--sieve", type=int, nargs="+", metavar="MAX",
                        help="time sieve.pl's primes(MAX, _) for each MAX (assert/retract growth)")
    parser.add_argument("--goal", default="bench(_)", help=argparse.SUPPRESS)
    parser.add_argument("--src", type=Path, default=HERE.parent / "src", help=argparse.SUPPRESS)
    parser.add_argument("--baseline", type=Path, metavar="CHECKOUT",
                        help="also time schemalog from another checkout (its src/), in the same rounds")
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    parser.add_argument("--iterations", type=int, default=0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.child, args.iterations, args.target, args.goal, args.src)
        return
    swipl = shutil.which("swipl")
    if swipl is None:
        raise SystemExit("swipl is not on PATH (Debian: apt-get install swi-prolog-nox)")
    if args.sieve:
        sieve(swipl, args.sieve, args.rounds, args.target)
        return
    paths = programs(args.programs)
    if args.smoke:
        sys.path.insert(0, str(HERE.parent / "src"))
        problems = smoke(swipl, paths)
        for p in problems:
            print(p)
        print(f"{len(paths) - len(problems)} of {len(paths)} programs as expected")
        raise SystemExit(1 if problems else 0)
    version = subprocess.run([swipl, "--version"], capture_output=True, text=True).stdout.strip()
    commit = subprocess.run(["git", "-C", str(HERE), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    print(f"python {sys.version.split()[0]}; {version}; commit {commit}; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}", flush=True)
    # calibration: each system its own N, then rounds taking turns
    plan: dict[Path, dict] = {}
    for path in paths:
        ours = run_ours(path, 0, args.target)
        theirs = run_swipl(swipl, path, 0, args.target)
        entry = plan[path] = {"ours": ours, "swipl": theirs, "ratios": [], "t_ours": [], "t_swipl": [],
                              "rss_ours": ours["rss"], "rss_swipl": theirs["rss"], "t_base": [], "base_ratios": []}
        if "error" in ours or "error" in theirs:
            entry["skip"] = ours.get("error") or "swipl: " + theirs["error"]
        elif ours["answer"] != theirs["answer"]:
            entry["skip"] = f"answers differ: {ours['answer'][:80]} / swipl {theirs['answer'][:80]}"
        print(f"  {path.stem}: calibrated, ours N={ours.get('n')}, swipl N={theirs.get('n')}"
              + (f" (not timed: {entry['skip']})" if "skip" in entry else ""), flush=True)
    for round_ in range(args.rounds):
        for path, entry in plan.items():
            if "skip" in entry:
                continue
            ours = run_ours(path, entry["ours"]["n"], args.target)
            theirs = run_swipl(swipl, path, entry["swipl"]["n"], args.target)
            t_ours = ours["seconds"] / ours["n"]
            t_swipl = max(theirs["seconds"], 1e-9) / theirs["n"]
            entry["t_ours"].append(t_ours)
            entry["t_swipl"].append(t_swipl)
            entry["ratios"].append(t_ours / t_swipl)
            if args.baseline:
                base = run_ours(path, entry["ours"]["n"], args.target, src=args.baseline / "src")
                if "seconds" in base:
                    entry["t_base"].append(base["seconds"] / base["n"])
                    entry["base_ratios"].append(entry["t_base"][-1] / t_swipl)
            entry["rss_ours"] = max(entry["rss_ours"], ours["rss"])
            entry["rss_swipl"] = max(entry["rss_swipl"], theirs["rss"])
        print(f"  round {round_ + 1} of {args.rounds} done", flush=True)
    based = bool(args.baseline)
    lines = [f"| program | schemalog ms/run | swipl -O ms/run | ratio (median) | ratios, {args.rounds} rounds "
             f"| peak RSS MiB ours / swipl |" + (" baseline ms/run | baseline ratio |" if based else ""),
             "|---|---:|---:|---:|---|---:|" + ("---:|---:|" if based else "")]
    ratios, base_ratios = [], []
    for path, entry in plan.items():
        if "skip" in entry:
            lines.append(f"| {path.stem} | not timed: {entry['skip']} | | | | |" + (" | |" if based else ""))
            continue
        ratio = statistics.median(entry["ratios"])
        ratios.append((ratio, path.stem))
        extra = ""
        if based and entry["base_ratios"]:
            base_ratios.append(statistics.median(entry["base_ratios"]))
            extra = f" {statistics.median(entry['t_base']) * 1e3:.3f} | {base_ratios[-1]:.0f}x |"
        elif based:
            extra = " failed | |"
        lines.append(f"| {path.stem} | {statistics.median(entry['t_ours']) * 1e3:.3f} | "
                     f"{statistics.median(entry['t_swipl']) * 1e3:.4f} | {ratio:.0f}x | "
                     f"{min(entry['ratios']):.0f}-{max(entry['ratios']):.0f}x | "
                     f"{entry['rss_ours']:.0f} / {entry['rss_swipl']:.0f} |" + extra)
    if ratios:
        geo = math.exp(sum(math.log(r) for r, _ in ratios) / len(ratios))
        worst = max(ratios)
        over = [f"{n} {r:.0f}x" for r, n in sorted(ratios, reverse=True) if r > 60]
        lines.append("")
        lines.append(f"Geometric mean over {len(ratios)} programs: **{geo:.1f}x** (target 35x); worst: "
                     f"{worst[1]} {worst[0]:.0f}x; beyond 60x: {', '.join(over) if over else 'none'}.")
        if base_ratios:
            lines.append(f"The baseline ({args.baseline}), same rounds: geometric mean "
                         f"{math.exp(sum(math.log(r) for r in base_ratios) / len(base_ratios)):.1f}x over "
                         f"{len(base_ratios)} programs.")
    table = "\n".join(lines)
    print()
    print(table)
    if args.out:
        args.out.write_text(table + "\n")


if __name__ == "__main__":
    main()
