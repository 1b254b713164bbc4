"""Behaviour trees from the corpus (tests/bt/corpus/): import, compression, ticks, proof.

    PYTHONPATH=src python benchmarks/bench_bt.py [--rounds 3] [--max-states 50000]

For every corpus .xml file (Nav2 trees read with nav2_tree_nodes.xml as their TreeNodesModel;
BT.CPP trees with the main tree named where the file names none, as tests/bt/test_btxml.py
does), one row: whether it imported (else the refusal's first 60 characters), the nodes before
and after compression (bt/compress.py), the rewrites made, the node ticks per root tick before
and after (mean over `simulate(document, seed, root_ticks=50)` for seeds 0..9; internal nodes
count, which is what compression saves), and the verdict of the proof of the compressed tree
against the original (`prove_by_parts`, as `schemalog compress` runs it) with its time in ms,
the median of --rounds runs.

Real Nav2 trees are mostly tight already, so three SYNTHETIC variants are added, built in code
from real Nav2 trees the way generated or hand-merged trees often look: a Sequence inside a
Sequence, a single-child Fallback around a subtree, a double Inverter around a condition.

A second table puts, for every file where a rewrite was made, the proof by parts beside the
whole-tree proof (`prove_equal` on the two documents, the same max_states): states and time.

A third (issue 48, reach) wraps every corpus tree whole in a single-child Sequence and proves the
wrap against the tree: ours (`prove_by_parts`, which takes the identical subtree whole, bt/
congruence.py) beside the reference explorer (`prove_equal` on the two documents, no congruence,
the same executor's moves: halts=True), the same max_states, in one run: verdict, states, ms and
the ratio of the times.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time
from pathlib import Path

from schemalog import defaults
from schemalog.api.behaviour_trees import EVENTS_PER_TICK, compress_tree, read_tree
from schemalog.bt.model import Node, walk
from schemalog.bt.prove import prove_by_parts, prove_equal, simulate
from schemalog.errors import SchemalogError

CORPUS = Path(__file__).resolve().parents[1] / "tests" / "bt" / "corpus"
NAV2 = CORPUS / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
MAIN_OF = {"log_test.xml": "Main", "subtree_test.xml": "BehaviorTree"}   # as test_btxml.py
SEEDS, ROOT_TICKS = range(10), 50


def read(path: Path):
    nodes = (NODES,) if NAV2 in path.parents else ()
    return read_tree(path, nodes=nodes, main=MAIN_OF.get(path.name))


def ticks_per_root_tick(document) -> float:
    runs = [simulate(document, seed, ROOT_TICKS) for seed in SEEDS]
    return sum(n for _, n, _ in runs) / sum(len(s) for _, _, s in runs)


def timed(rounds: int, fn):
    """fn()'s result and its median time in ms over `rounds` runs."""
    times, result = [], None
    for _ in range(rounds):
        t = time.perf_counter()
        result = fn()
        times.append((time.perf_counter() - t) * 1000)
    return result, statistics.median(times)


def verdict_word(v) -> str:
    return "proved" if v.equal and v.complete else "refuted" if not v.equal else "not proved"


# ---------------------------------------------------------------------------------------------
# Synthetic variants: one node of a real Nav2 tree wrapped

def wrap_first(document, match, wrap):
    """`document` with the first node (pre-order, main tree) that `match` accepts replaced by `wrap(node)`."""
    target = next(n for n in walk(document.root) if match(n))

    def rebuild(node: Node) -> Node:
        if node is target:
            return wrap(node)
        return node.with_children(tuple(rebuild(c) for c in node.children))

    trees = tuple((i, rebuild(r) if i == document.main else r) for i, r in document.trees)
    return document.with_trees(trees)


def synthetic():
    seq = read(NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml")
    fall = read(NAV2 / "navigate_w_replanning_and_round_robin_recovery.xml")
    inv = read(NAV2 / "navigate_through_poses_w_replanning_and_recovery.xml")
    return [
        ("SYNTHETIC nested Sequence (navigate_to_pose_w_replanning_and_recovery)",
         wrap_first(seq, lambda n: n.type == "Sequence" and len(n.children) >= 2,
                    lambda n: n.with_children((Node("Sequence", children=n.children[:2]),) + n.children[2:]))),
        ("SYNTHETIC single-child Fallback (navigate_w_replanning_and_round_robin_recovery)",
         wrap_first(fall, lambda n: n.type == "RoundRobin", lambda n: Node("Fallback", children=(n,)))),
        ("SYNTHETIC double Inverter (navigate_through_poses_w_replanning_and_recovery)",
         wrap_first(inv, lambda n: n.type == "GoalUpdated",
                    lambda n: Node("Inverter", children=(Node("Inverter", children=(n,)),)))),
    ]


# ---------------------------------------------------------------------------------------------

def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3, help="timed runs per proof (median)")
    ap.add_argument("--max-states", type=int, default=defaults.MAX_STATES)
    ap.add_argument("--wrap-only", action="store_true", help="only the table of whole trees wrapped")
    args = ap.parse_args()
    print(f"python {platform.python_version()}, {os.cpu_count()} CPUs ({platform.machine()}), "
          f"--rounds {args.rounds}, max_states {args.max_states}, seeds 0..9 x {ROOT_TICKS} root ticks\n")

    cases = []
    for path in sorted(CORPUS.rglob("*.xml")):
        if path == NODES:
            continue
        try:
            cases.append((str(path.relative_to(CORPUS)), read(path), "yes"))
        except SchemalogError as err:
            cases.append((str(path.relative_to(CORPUS)), None, err.message[:60].replace("|", "\\|")))
    cases += [(name, doc, "yes (built)") for name, doc in synthetic()]
    if args.wrap_only:
        wrap_tables(cases, args)
        return

    print("| file | imported | nodes before | nodes after | rewrites | ticks/root tick before | after "
          "| proof | proof ms |")
    print("| --- | --- | ---: | ---: | --- | ---: | ---: | --- | ---: |")
    rewritten = []
    for name, doc, imported in cases:
        if doc is None:
            print(f"| {name} | {imported} | | | | | | | |")
            continue
        c = compress_tree(doc, args.max_states)
        rules = ", ".join(f"{r.rule} {r.type}" for r in c.rewrites) or "none"
        before, after = ticks_per_root_tick(c.original), ticks_per_root_tick(c.compressed)
        proof, ms = "-", ""
        if c.rewrites:
            v, t = timed(args.rounds, lambda: prove_by_parts(c.original, c.compressed, max_states=args.max_states,
                                                               max_events_per_tick=EVENTS_PER_TICK))
            proof, ms = verdict_word(v), f"{t:.1f}"
            rewritten.append((name, c))
        print(f"| {name} | {imported} | {c.nodes_before} | {c.nodes_after} | {rules} | {before:.2f} "
              f"| {after:.2f} | {proof} | {ms} |")

    print("\nProof by parts beside the whole-tree proof (same max_states), files with a rewrite:\n")
    print("| file | by parts: verdict | states | ms | whole: verdict | states | ms | whole/parts ms |")
    print("| --- | --- | ---: | ---: | --- | ---: | ---: | ---: |")
    for name, c in rewritten:
        opts = dict(max_states=args.max_states, max_events_per_tick=EVENTS_PER_TICK)
        vp, tp = timed(args.rounds, lambda: prove_by_parts(c.original, c.compressed, **opts))
        vw, tw = timed(args.rounds, lambda: prove_equal(c.original, c.compressed, halts=True, **opts))
        print(f"| {name} | {verdict_word(vp)} | {vp.states} | {tp:.1f} | {verdict_word(vw)} | {vw.states} "
              f"| {tw:.1f} | {tw / tp:.1f}x |")
    wrap_tables(cases, args)


def wrap_tables(cases, args) -> None:
    print("\nA whole tree wrapped in a single-child Sequence, against the tree: ours (congruence) beside the "
          "reference explorer (same max_states):\n")
    print("| file | nodes | ours: verdict | states | ms | reference: verdict | states | ms | reference/ours ms |")
    print("| --- | ---: | --- | ---: | ---: | --- | ---: | ---: | ---: |")
    opts = dict(max_states=args.max_states, max_events_per_tick=EVENTS_PER_TICK)
    for name, doc, _ in cases:
        if doc is None or name.startswith("SYNTHETIC"):
            continue
        wrapped = doc.with_trees(tuple((i, Node("Sequence", children=(r,)) if i == doc.main else r)
                                       for i, r in doc.trees))
        vo, to = timed(args.rounds, lambda: prove_by_parts(doc, wrapped, **opts))
        vr, tr = timed(1, lambda: prove_equal(doc, wrapped, halts=True, **opts))
        nodes = sum(1 for _, r in doc.trees for _ in walk(r))
        print(f"| {name} | {nodes} | {verdict_word(vo)} | {vo.states} | {to:.1f} | {verdict_word(vr)} | {vr.states} "
              f"| {tr:.1f} | {tr / to:.1f}x |", flush=True)


if __name__ == "__main__":
    main()
