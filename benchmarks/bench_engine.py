"""The Prolog engine beside SWI-Prolog, in one run: four classic programs, and a join over a task tree.

    python benchmarks/bench_engine.py [--repeat 3] [--sizes 2000 8000 32000 100000]

1. Naive reverse of a 30-element list (496 logical inferences each), repeated; logical
   inferences per second (LIPS) for schemalog's engine and for `swipl -O` on the same program,
   and the ratio. swipl (Debian: swi-prolog-nox) must be on PATH.
   Then queens (all 92 solutions of 8 queens), tak(18, 12, 6) and a zebra puzzle (its whole
   search), the same text in both systems: seconds per run and the ratio (target: within 75x
   of `swipl -O`, issue 19).
2. `sequential(X, Y)` (kb/compression.pl, Definition 1 as a rule) over the facts of a
   generated tree (RD 0.5), answered by both engines from the same facts: how the cost of a
   join grows with the tree. The rule joins `parent(B1, P), parent(B2, P)` on the second
   argument, which both engines index just in time.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from schemalog.cli.main import tune_gc
from schemalog.formats.documents import document_from_text
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.engine import Engine
from schemalog.task.facts import tree_facts
from schemalog.evaluate.generate import generate
from schemalog.logic.parse import parse_term
from schemalog.shipped import shipped_text
from schemalog.logic.terms import Struct, term_to_text

NREV = """
app([], L, L).
app([H|T], L, [H|R]) :- app(T, L, R).
nrev([], []).
nrev([H|T], R) :- nrev(T, RT), app(RT, [H], R).
range(N, N, [N]) :- !.
range(I, N, [I|T]) :- I < N, I1 is I + 1, range(I1, N, T).
bench(0, _) :- !.
bench(K, L) :- nrev(L, _), K1 is K - 1, bench(K1, L).
"""
INFERENCES = 496   # per naive reverse of 30 elements: 31 nrev calls + 465 app calls

QUEENS = """
queens(N, Qs) :- range(1, N, Ns), queens(Ns, [], Qs).
queens([], Qs, Qs).
queens(Unplaced, Safe, Qs) :- sel(Q, Unplaced, Rest), \\+ attack(Q, Safe), queens(Rest, [Q|Safe], Qs).
attack(X, Xs) :- attack(X, 1, Xs).
attack(X, N, [Y|_]) :- X is Y + N ; X is Y - N.
attack(X, N, [_|Ys]) :- N1 is N + 1, attack(X, N1, Ys).
sel(X, [X|Xs], Xs).
sel(X, [Y|Ys], [Y|Zs]) :- sel(X, Ys, Zs).
range(N, N, [N]) :- !.
range(I, N, [I|T]) :- I < N, I1 is I + 1, range(I1, N, T).
"""
TAK = """
tak(X, Y, Z, A) :- X =< Y, !, Z = A.
tak(X, Y, Z, A) :-
    X1 is X - 1, Y1 is Y - 1, Z1 is Z - 1,
    tak(X1, Y, Z, A1), tak(Y1, Z, X, A2), tak(Z1, X, Y, A3), tak(A1, A2, A3, A).
"""
ZEBRA = """
houses([house(_, _, _, _, _), house(_, _, _, _, _), house(_, _, _, _, _),
        house(_, _, _, _, _), house(_, _, _, _, _)]).
right_of(A, B, [B, A|_]).
right_of(A, B, [_|Y]) :- right_of(A, B, Y).
next_to(A, B, [A, B|_]).
next_to(A, B, [B, A|_]).
next_to(A, B, [_|Y]) :- next_to(A, B, Y).
member_(X, [X|_]).
member_(X, [_|Y]) :- member_(X, Y).
zebra(Houses) :-
    houses(Houses),
    member_(house(red, english, _, _, _), Houses),
    member_(house(_, spanish, dog, _, _), Houses),
    member_(house(green, _, _, coffee, _), Houses),
    member_(house(_, ukrainian, _, tea, _), Houses),
    right_of(house(green, _, _, _, _), house(ivory, _, _, _, _), Houses),
    member_(house(_, _, snails, _, winstons), Houses),
    member_(house(yellow, _, _, _, kools), Houses),
    Houses = [_, _, house(_, _, _, milk, _), _, _],
    Houses = [house(_, norwegian, _, _, _)|_],
    next_to(house(_, _, _, _, chesterfields), house(_, _, fox, _, _), Houses),
    next_to(house(_, _, _, _, kools), house(_, _, horse, _, _), Houses),
    member_(house(_, _, _, orange_juice, luckies), Houses),
    member_(house(_, japanese, _, _, parliaments), Houses),
    next_to(house(_, norwegian, _, _, _), house(blue, _, _, _, _), Houses),
    member_(house(_, _, zebra, _, _), Houses),
    member_(house(_, _, _, water, _), Houses).
"""

# (name, program, goal run once per timing, swipl runs per timing); each goal fails if its
# answer is wrong, so a fast wrong engine is not timed.
PROGRAMS = [("queens 8, all solutions", QUEENS, "findall(Q, queens(8, Q), L), length(L, 92)", 100),
            ("tak(18, 12, 6)", TAK, "tak(18, 12, 6, A), A == 7", 100),
            ("zebra, whole search", ZEBRA, "findall(H, zebra(H), [_])", 300)]
TARGET = 75   # times slower than swipl -O, at most (issue 19)


def ours_program(program: str, goal: str, repeat: int) -> float:
    kb = document_from_text(program, "program.pl").to_kb()
    best = float("inf")
    for _ in range(repeat):
        engine = Engine(kb, max_steps=10**10)
        started = time.perf_counter()
        if engine.first(parse_term(goal)) is None:
            raise SystemExit(f"schemalog's answer to {goal} is wrong")
        best = min(best, time.perf_counter() - started)
    return best


def swipl_program(swipl: str, program: str, goal: str, repeat: int, times: int) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "program.pl"
        path.write_text(program)
        timing = (f"findall(T, (between(1, {repeat}, _), statistics(cputime, T0), "
                  f"forall(between(1, {times}, _), ({goal})), statistics(cputime, T1), "
                  f"T is (T1 - T0) / {times}), Ts), min_list(Ts, B), format('~w~n', [B]), halt")
        check = f"(\\+ ({goal}) -> halt(1) ; true)"
        out = subprocess.run([swipl, "-q", "-O", "-g", check, "-g", timing, str(path)], capture_output=True,
                             text=True, check=True, timeout=600)
    return max(float(out.stdout.strip()), 1e-9)


def ours_nrev(repeat: int, times: int) -> float:
    return times * INFERENCES / ours_program(NREV, f"range(1, 30, L), bench({times}, L)", repeat)


def swipl_nrev(swipl: str, repeat: int, times: int) -> float:
    return times * INFERENCES / swipl_program(swipl, NREV, f"range(1, 30, L), bench({times}, L)", repeat, 1)


def join_program(size: int) -> tuple[list, str, int]:
    """The facts of a generated tree of about `size` behaviours, and kb/compression.pl
    with those facts as one program text (for swipl)."""
    depth, branching = 4, 2
    while sum(branching ** level for level in range(depth)) < size:
        depth += 1
    tree = generate(depth, branching, 0.5, seed=1)
    # `b3.done` is '.'(b3, done), which SWI-Prolog 7 reads as a dict access: both engines get
    # the same facts with at(b3, done) instead.
    facts = [_no_dots(f) for f in tree_facts(tree)]
    text = shipped_text("kb/compression.pl") + "\n" + "\n".join(term_to_text(f, quoted=True) + "." for f in facts)
    return facts, text, sum(1 for f in facts if f.name == "node")


def _no_dots(t):
    if isinstance(t, Struct):
        return Struct("at" if t.name == "." and len(t.args) == 2 else t.name, tuple(_no_dots(a) for a in t.args))
    return t


def ours_join(facts: list) -> tuple[int, float]:
    kb = KnowledgeBase()
    kb.consult_text(shipped_text("kb/compression.pl"), "kb/compression.pl")
    kb.add_facts(facts)  # the same clauses as the text, without a million-clause parse
    started = time.perf_counter()
    answers = len(Engine(kb, max_steps=10**11).answers(parse_term("sequential(X, Y)")))
    return answers, time.perf_counter() - started


def swipl_join(swipl: str, text: str) -> tuple[int, float]:
    with tempfile.TemporaryDirectory() as tmp:
        program = Path(tmp) / "join.pl"
        program.write_text(text)
        goal = ("statistics(cputime, T0), findall(X-Y, sequential(X, Y), L), statistics(cputime, T1), "
                "length(L, N), T is T1 - T0, format('~w ~w~n', [N, T]), halt")
        out = subprocess.run([swipl, "-q", "-g", goal, str(program)], capture_output=True, text=True,
                             check=True, timeout=600)
    n, seconds = out.stdout.split()
    return int(n), float(seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--times", type=int, default=300, help="naive reverses per timing (ours)")
    parser.add_argument("--sizes", type=int, nargs="+", default=[2000, 8000, 32000, 100000])
    parser.add_argument("--programs-only", action="store_true", help="skip the join over task trees")
    args = parser.parse_args()
    swipl = shutil.which("swipl")
    if swipl is None:
        raise SystemExit("swipl is not on PATH (Debian: apt-get install swi-prolog-nox)")
    version = subprocess.run([swipl, "--version"], capture_output=True, text=True).stdout.strip()
    tune_gc()
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    print(f"python {sys.version.split()[0]}; {version}\n")
    ours = ours_nrev(args.repeat, args.times)
    theirs = swipl_nrev(swipl, args.repeat, args.times * 200)
    print("## Naive reverse, 30 elements (496 inferences each), best of", args.repeat, "\n")
    print("| engine | LIPS | ratio |\n|---|---:|---:|")
    print(f"| schemalog | {ours:,.0f} | {theirs / ours:,.0f}x slower |")
    print(f"| swipl -O | {theirs:,.0f} | 1 |\n")
    print(f"## Classic programs, seconds per run, best of {args.repeat} (target: within {TARGET}x of swipl -O)\n")
    print("| program | schemalog s | swipl -O s | ratio | target |\n|---|---:|---:|---:|---|")
    ratios = [("naive reverse", theirs / ours)]
    for name, program, goal, times in PROGRAMS:
        t_ours = ours_program(program, goal, args.repeat)
        t_swipl = swipl_program(swipl, program, goal, args.repeat, times)
        ratios.append((name, t_ours / t_swipl))
        print(f"| {name} | {t_ours:.4f} | {t_swipl:.5f} | {t_ours / t_swipl:,.0f}x | "
              f"{'met' if t_ours / t_swipl <= TARGET else 'MISSED'} |")
        sys.stdout.flush()
    missed = [name for name, ratio in ratios if ratio > TARGET]
    print(f"\nWithin {TARGET}x of swipl -O: {len(ratios) - len(missed)} of {len(ratios)} programs"
          + (f" (missed: {', '.join(missed)})" if missed else "") + "\n")
    if args.programs_only:
        return
    print("## sequential(X, Y) over a generated tree's facts (kb/compression.pl)\n")
    print("| behaviours | answers | schemalog s | swipl s | ratio | schemalog growth |")
    print("|---:|---:|---:|---:|---:|---:|")
    previous = None
    for size in args.sizes:
        facts, text, nodes = join_program(size)
        n_ours, t_ours = ours_join(facts)
        n_swipl, t_swipl = swipl_join(swipl, text)
        if n_ours != n_swipl:
            raise SystemExit(f"answers differ at {nodes} behaviours: schemalog {n_ours}, swipl {n_swipl}")
        growth = f"x{t_ours / previous[1]:.1f} for x{nodes / previous[0]:.1f} behaviours" if previous else ""
        print(f"| {nodes:,} | {n_ours:,} | {t_ours:.3f} | {t_swipl:.4f} | {t_ours / max(t_swipl, 1e-6):,.0f}x "
              f"| {growth} |")
        sys.stdout.flush()
        previous = (nodes, t_ours)


if __name__ == "__main__":
    main()
