"""Compress generated task trees from 1k to 100k behaviours.

    python benchmarks/bench_compress.py [--sizes 1000 10000 100000] [--repeat 3] [--chain 0.67]

Each tree is balanced, four sub-tasks per behaviour; siblings act on one object with
one agent, and each sibling after the first is released by its predecessor's `done`
with probability --chain (else by `true`), so about that share of the behaviours is
sequential. Measured in one run, for each size and both propagation modes that keep
the task correct (pre, full): the compression time (Algorithm 1 with Definition 1 by
hashing), behaviours per second, the reduction degree reached, how many conditions
were simplified and how many needed sympy. A chain probability of 0.67 gives RD about 0.5.

A second table puts Definition 1 by hashing (compress.sequential_pairs) beside the same
rule as a nested loop over sibling pairs, on one parent with n children: the case where
the loop is quadratic and the index is not.
"""

from __future__ import annotations

import argparse
import random
import sys
import time

from schemalog.task import conditions as cond
from schemalog.cli.main import tune_gc
from schemalog.task.compress import compress, sequential_pairs
from schemalog.logic.terms import Atom, Struct
from schemalog.task.tree import Behaviour

BRANCHING = 4
OBJECTS = ("cup", "spoon", "water", "coffee", "tea")


def done(name: str) -> cond.Lit:
    return cond.Lit(Struct(".", (Atom(name), Atom("done"))))


def generated_tree(size: int, chain: float, seed: int = 1) -> Behaviour:
    """A balanced tree of `size` behaviours with chained releasers (built bottom-up)."""
    rnd = random.Random(seed)
    # Parent index of node i in a complete BRANCHING-ary tree laid out level by level.
    children: list[list[int]] = [[] for _ in range(size)]
    for i in range(1, size):
        children[(i - 1) // BRANCHING].append(i)
    built: dict[int, Behaviour] = {}
    for i in range(size - 1, -1, -1):
        kids = []
        obj = Atom(OBJECTS[i % len(OBJECTS)])
        for n, c in enumerate(children[i]):
            releaser = cond.TRUE if n == 0 or rnd.random() >= chain else done(f"b{children[i][n - 1]}")
            child = built.pop(c)
            kids.append(Behaviour(label=Struct(f"b{c}", (obj,)), objects=(obj,), releaser=releaser,
                                  post=done(f"b{c}"), children=child.children))
        built[i] = Behaviour(label=Struct(f"b{i}", (obj,)), objects=(obj,), post=done(f"b{i}"),
                             children=tuple(kids))
    return built[0]


def naive_pairs(kids: tuple[Behaviour, ...]) -> list[tuple[int, int]]:
    """Definition 1 by comparing every ordered pair of siblings (the nested loop)."""
    posts = [cond.canonical(k.post) for k in kids]
    entries = [cond.canonical(k.entry) for k in kids]
    return [(i, j) for i, a in enumerate(kids) for j, b in enumerate(kids)
            if i != j and a.agent == b.agent and a.objects == b.objects and posts[i] == entries[j]
            and not isinstance(posts[i], cond.Const)]


def wide_group(n: int, chain: float, seed: int = 2) -> tuple[Behaviour, ...]:
    rnd = random.Random(seed)
    obj = Atom("cup")
    return tuple(Behaviour(label=Struct(f"w{i}", (obj,)), objects=(obj,), post=done(f"w{i}"),
                           releaser=cond.TRUE if i == 0 or rnd.random() >= chain else done(f"w{i - 1}"))
                 for i in range(n))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--chain", type=float, default=0.67)
    parser.add_argument("--wide", type=int, nargs="+", default=[500, 1000, 2000, 4000])
    args = parser.parse_args(argv)
    tune_gc()  # what the schemalog command does

    rows = []
    for size in args.sizes:
        tree = generated_tree(size, args.chain)
        for mode in ("pre", "full"):
            best, result = float("inf"), None
            for _ in range(args.repeat):
                start = time.perf_counter()
                result = compress(tree, mode)
                best = min(best, time.perf_counter() - start)
            rows.append((size, mode, best, result))
            print(f"  {size:>7} {mode}: {best:.2f}s", file=sys.stderr)

    print("| behaviours | propagate | compress s | behaviours/s | Bm | RD | conditions | needed sympy |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|")
    for size, mode, best, r in rows:
        share = r.simplifier.sympy_calls / r.simplifier.calls if r.simplifier.calls else 0.0
        print(f"| {size:,} | {mode} | {best:.3f} | {size / best:,.0f} | {r.nodes_after:,} "
              f"| {r.reduction_degree:.2f} | {r.simplifier.calls:,} | {r.simplifier.sympy_calls} ({share:.1%}) |")
    print()
    print("Growth of compression time per 10x behaviours (target: under 12x):")
    for mode in ("pre", "full"):
        series = [(s, b) for s, m, b, _ in rows if m == mode]
        for (s0, b0), (s1, b1) in zip(series, series[1:]):
            print(f"- {mode}: {s0:,} -> {s1:,}: x{b1 / b0:.1f} (size x{s1 / s0:.0f})")

    print()
    print("Definition 1 on one parent with n children: hashing vs nested loop (same pairs):")
    print()
    print("| siblings | hashed s | nested loop s | loop / hashed |")
    print("|---:|---:|---:|---:|")
    for n in args.wide:
        kids = wide_group(n, args.chain)
        start = time.perf_counter()
        hashed = sequential_pairs(kids)
        t_hash = time.perf_counter() - start
        start = time.perf_counter()
        looped = naive_pairs(kids)
        t_loop = time.perf_counter() - start
        assert sorted(hashed) == sorted(looped), "the index and the loop disagree"
        print(f"| {n:,} | {t_hash:.4f} | {t_loop:.3f} | {t_loop / t_hash:,.0f}x |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
