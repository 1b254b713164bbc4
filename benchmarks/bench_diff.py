"""`schemalog diff` beside `schemalog verify` on the same pairs: Nav2 trees and edits of them.

    PYTHONPATH=src python benchmarks/bench_diff.py [--edits 8] [--rounds 3] [--max-states 50000]

For every Nav2 tree of the corpus (tests/bt/corpus/nav2, read with nav2_tree_nodes.xml; not the
BT.CPP 3 one), --edits edits of it made by the project's own edit generator, the one the proofs
are checked against BT.CPP with (tests/bt/test_proofs_against_btcpp.py's `edit`, seeds 0, 1, ...
until --edits edits that change the tree: a single-child composite wrapped or unwrapped,
siblings nested or flattened, two swapped, a node dropped, a count changed, a RunOnce, attributes
reordered, a type changed for a near relative, a pre-condition added or removed). Each pair
(tree, edited tree) is timed in one run, in process, through the API, verify and diff taking
turns round after round: api.behaviour_trees.prove_trees (what `schemalog verify A B` runs)
and api.tree_diff.diff_trees (what `schemalog diff A B` runs: the same proof of the whole pair,
then every place decided, then the direction), each the best of --rounds. Issue 47's target:
diff within 2x of verify. One row per tree (the worst pair's ratio and edit, the median
ratio, the verdicts), then every pair over 2x with the prover calls of each (cProfile): where
diff's time went.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import platform
import pstats
import random
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "bt"))         # the edit generator lives with the tests
sys.path.insert(0, str(ROOT / "tests"))

from schemalog import defaults  # noqa: E402
from schemalog.api.behaviour_trees import prove_trees, read_tree  # noqa: E402
from schemalog.api.tree_diff import diff_trees  # noqa: E402
from schemalog.bt.model import walk  # noqa: E402

from test_proofs_against_btcpp import edit  # noqa: E402

NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
BTCPP3 = "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml"


def trees() -> list[Path]:
    return sorted(p for p in NAV2.glob("*.xml") if p != NODES and p.name != BTCPP3)


def edits(document, count: int) -> list[tuple[str, object]]:
    """`count` edits of the document's main tree that change it, by seeds 0, 1, ... (as generated)."""
    out, seed = [], 0
    while len(out) < count and seed < 50 * count:
        kind, root = edit(random.Random(seed), document.root)
        seed += 1
        if kind != "none" and root != document.root:
            out.append((f"{kind}#{seed - 1}", document.with_trees(tuple(
                (i, root if i == document.main else r) for i, r in document.trees))))
    return out


def best(rounds: int, fn) -> tuple[object, float]:
    times, result = [], None
    for _ in range(rounds):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return result, min(times) * 1000


def verdict(v) -> str:
    return "proved" if v.equal and v.complete else "refuted" if not v.equal else "undecided"


PROVERS = ("prove_by_parts", "_congruent", "prove_equal")


def provers(fn) -> str:
    """The prover calls fn makes (bt/prove.py): how many of each, their cumulative ms (cProfile)."""
    prof = cProfile.Profile()
    prof.runcall(fn)
    stats = pstats.Stats(prof).stats
    calls = {name: (n, cum) for (file, _, name), (n, _, _, cum, _) in stats.items()
             if name in PROVERS and file.endswith(os.path.join("bt", "prove.py"))}
    return ", ".join(f"{name} x{calls[name][0]} {calls[name][1] * 1000:,.1f} ms" for name in PROVERS if name in calls)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edits", type=int, default=8, help="edits per tree")
    ap.add_argument("--rounds", type=int, default=3, help="timed runs of each (best)")
    ap.add_argument("--max-states", type=int, default=defaults.MAX_STATES)
    ap.add_argument("--no-profile", action="store_true", help="skip profiling the pairs over 2x")
    args = ap.parse_args()
    print(f"python {platform.python_version()}, {os.cpu_count()} CPUs ({platform.machine()}), --edits {args.edits}, "
          f"--rounds {args.rounds} (best), max_states {args.max_states}\n")
    print("| tree | nodes | pairs | verify: proved/refuted/undecided | verify ms (sum) | diff ms (sum) "
          "| diff/verify median | worst pair | its verify ms | its diff ms | worst ratio |")
    print("| --- | ---: | ---: | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: |")
    over, ratios, agree = [], [], 0
    warm = read_tree(trees()[0], (NODES,))              # imports and first-call costs out of the figures
    prove_trees(warm, warm, args.max_states), diff_trees(warm, warm, args.max_states)
    for path in trees():
        a = read_tree(path, (NODES,))
        rows = []
        for kind, b in edits(a, args.edits):
            verify_ms = diff_ms = 0.0
            v = d = None
            for _ in range(args.rounds):        # turns, so a slow spell of the machine falls on both
                v, t1 = best(1, lambda: prove_trees(a, b, args.max_states))
                d, t2 = best(1, lambda: diff_trees(a, b, args.max_states))
                verify_ms = t1 if not verify_ms else min(verify_ms, t1)
                diff_ms = t2 if not diff_ms else min(diff_ms, t2)
            agree += verdict(v) == verdict(d.diff.verdict)
            rows.append((kind, b, v, d, verify_ms, diff_ms, diff_ms / verify_ms))
        counts = [sum(verdict(r[2]) == w for r in rows) for w in ("proved", "refuted", "undecided")]
        worst = max(rows, key=lambda r: r[6])
        ratios += [r[6] for r in rows]
        over += [(path.name, r) for r in rows if r[6] > 2]
        nodes = sum(1 for _, r in a.trees for _ in walk(r))
        print(f"| {path.stem} | {nodes} | {len(rows)} | {'/'.join(map(str, counts))} "
              f"| {sum(r[4] for r in rows):,.1f} | {sum(r[5] for r in rows):,.1f} "
              f"| {statistics.median(r[6] for r in rows):.2f}x | {worst[0]} | {worst[4]:,.1f} | {worst[5]:,.1f} "
              f"| {worst[6]:.2f}x |", flush=True)
    print(f"\n{len(ratios)} pairs; diff/verify: median {statistics.median(ratios):.2f}x, worst {max(ratios):.2f}x; "
          f"{len(over)} over 2x; diff's whole-pair verdict the same as verify's on {agree} of {len(ratios)}")
    for name, (kind, b, v, d, tv, td, ratio) in over:
        places = d.diff.places
        print(f"\n{name} {kind}: verify {verdict(v)} {tv:,.1f} ms ({v.states:,} states), diff {td:,.1f} ms "
              f"({ratio:.2f}x), {len(places)} place(s): "
              + "; ".join(f"{p.effect}" for p in places))
        if not args.no_profile:
            a = read_tree(NAV2 / name, (NODES,))
            print(f"  verify: {provers(lambda: prove_trees(a, b, args.max_states))}")
            print(f"  diff:   {provers(lambda: diff_trees(a, b, args.max_states))}")


if __name__ == "__main__":
    main()
