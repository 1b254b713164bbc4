"""Issue 48's reach targets for behaviour-tree proofs, in one run: ours beside the reference.

    PYTHONPATH=src python benchmarks/bench_reach.py [--max-states 50000] [--quick]

Ours is `prove_by_parts` (what `schemalog verify A.xml B.xml` runs: parts in every context,
identical subtrees taken whole, bt/congruence.py); the reference is `prove_equal` on the two
whole documents (the product exploration, no parts, no congruence). Both run with the same
max_states, the default registrations (every Action either way) and the default executor (the
tree may be halted by haltTree between any two ticks and ticked anew). Each proof runs in a
forked child, so its peak memory (ru_maxrss) is its own. Rows:

- nest N: a flat Sequence of N Action leaves against the same with two middle children nested
  in a Sequence of their own, N = 50 .. 800 (cost should grow linearly with N);
- loop -1: a rewrite (a nested Sequence flattened) under `RetryUntilSuccessful num_attempts="-1"`
  and under `Repeat num_cycles="-1"`;
- retry 5->4: ROSCon-style `RetryUntilSuccessful num_attempts` changed from 5 to 4 around
  FollowPath; the shortest counterexample's length in events, beside the states spent;
- composed k: a Sequence calling Nav2's navigate_to_pose_w_replanning_and_recovery k times as a
  SubTree, against the same wrapped whole in a single-child Sequence (k=36: about 800 nodes
  expanded; k=91: about 2,000).
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import platform
import resource
import time
from pathlib import Path

from schemalog import defaults
from schemalog.api.behaviour_trees import EVENTS_PER_TICK, read_tree
from schemalog.bt.model import Document, Node
from schemalog.bt.prove import prove_by_parts, prove_equal

NAV2 = Path(__file__).resolve().parents[1] / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"


def act(name: str) -> Node:
    return Node(name, (), (), "Action")


def doc(root: Node) -> Document:
    return Document((("Main", root),), "Main")


def nest(n: int) -> tuple[Document, Document]:
    leaves = tuple(act(f"L{i}") for i in range(n))
    k = n // 2
    nested = leaves[:k] + (Node("Sequence", (), leaves[k:k + 2]),) + leaves[k + 2:]
    return doc(Node("Sequence", (), leaves)), doc(Node("Sequence", (), nested))


def forever(loop: str, port: str) -> tuple[Document, Document]:
    arm, take_off, hover = act("Arm"), act("TakeOff"), act("Hover")
    nested = Node(loop, ((port, "-1"),), (Node("Sequence", (), (arm, Node("Sequence", (), (take_off, hover)))),))
    flat = Node(loop, ((port, "-1"),), (Node("Sequence", (), (arm, take_off, hover)),))
    return doc(nested), doc(flat)


def retries(a: int, b: int) -> tuple[Document, Document]:
    def tree(n: int) -> Node:
        return Node("Sequence", (), (act("ComputePathToPose"),
                                     Node("RetryUntilSuccessful", (("num_attempts", str(n)),), (act("FollowPath"),))))
    return doc(tree(a)), doc(tree(b))


def composed(k: int) -> tuple[Document, Document]:
    d = read_tree(NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml", [NODES])
    main = Node("Sequence", (), tuple(Node("SubTree", (("ID", d.main),)) for _ in range(k)))
    a = Document(d.trees + (("Composed", main),), "Composed", d.models)
    b = Document(d.trees + (("Composed", Node("Sequence", (), (main,))),), "Composed", d.models)
    return a, b


def expanded_nodes(document: Document) -> int:
    from schemalog.bt.semantics import program

    stack, count = [program(document).root], 0
    while stack:
        n = stack.pop()
        count += 1
        stack.extend(n.kids)
    return count


def _child(conn, build, arg, prover, max_states) -> None:
    a, b = build(*arg)
    t = time.process_time()
    if prover == "ours":
        v = prove_by_parts(a, b, max_states=max_states, max_events_per_tick=EVENTS_PER_TICK)
    else:
        v = prove_equal(a, b, max_states=max_states, max_events_per_tick=EVENTS_PER_TICK, halts=True)
    seconds = time.process_time() - t
    cex = v.counterexample
    events = sum(len(t.events) for t in cex.ticks_a) if cex else 0
    conn.send((v.equal, v.complete, v.states, seconds, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024,
               events))


def measured(build, arg, prover: str, max_states: int):
    """(equal, complete, states, CPU seconds, peak MB, counterexample events) in a forked child."""
    ctx = multiprocessing.get_context("fork")
    here, there = ctx.Pipe()
    p = ctx.Process(target=_child, args=(there, build, arg, prover, max_states))
    p.start()
    out = here.recv()
    p.join()
    return out


def word(r) -> str:
    equal, complete = r[0], r[1]
    return "proved" if equal and complete else "refuted" if not equal else "NOT proved"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-states", type=int, default=defaults.MAX_STATES)
    ap.add_argument("--quick", action="store_true", help="small sizes only (N up to 200, k up to 4)")
    args = ap.parse_args()
    print(f"python {platform.python_version()}, {os.cpu_count()} CPUs ({platform.machine()}), "
          f"max_states {args.max_states}; CPU seconds, peak RSS of the proving process\n")
    rows = [(f"nest N={n}", nest, (n,)) for n in ((50, 100, 200) if args.quick else (50, 100, 200, 400, 800))]
    rows += [("loop -1 (Retry)", forever, ("RetryUntilSuccessful", "num_attempts")),
             ("loop -1 (Repeat)", forever, ("Repeat", "num_cycles")),
             ("retry 5->4", retries, (5, 4))]
    rows += [(f"composed k={k} ({expanded_nodes(composed(k)[0]):,} nodes)", composed, (k,))
             for k in ((1, 4) if args.quick else (1, 36, 91))]
    print("| case | ours: verdict | states | s | MB | reference: verdict | states | s | MB | reference/ours s |")
    print("| --- | --- | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |")
    for name, build, arg in rows:
        o = measured(build, arg, "ours", args.max_states)
        r = measured(build, arg, "reference", args.max_states)
        extra = f" (counterexample: {o[5]} events)" if not o[0] else ""
        ratio = f"{r[3] / o[3]:.1f}x" if o[3] > 0.0005 else "-"
        print(f"| {name}{extra} | {word(o)} | {o[2]:,} | {o[3]:.2f} | {o[4]} | {word(r)} | {r[2]:,} | {r[3]:.2f} "
              f"| {r[4]} | {ratio} |", flush=True)


if __name__ == "__main__":
    main()
