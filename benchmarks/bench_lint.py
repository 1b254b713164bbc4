"""`schemalog lint` on BT.CPP trees, the blackboard rules (bt/lint.py): issue 43's speed targets.

    PYTHONPATH=src python benchmarks/bench_lint.py [--rounds 3]

Times, in process through the API (api/tree_lint.lint_document, what `schemalog lint` runs after
reading), the best of --rounds: every Nav2 tree of the corpus with Nav2's node models
(tests/bt/lint_fixtures/bb_nav2_tree_nodes.xml) and the nav2 profile, and the combat robot's
folder (tests/bt/corpus/combat/behavior_trees, 11 files, main tree rmuc_2026). Targets: the
largest corpus tree under 2 s, the combat folder under 10 s. Prints one Markdown row per program:
nodes, findings, explored states (the note), seconds.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

from schemalog import defaults  # noqa: E402
from schemalog.api.behaviour_trees import read_semantics, read_tree  # noqa: E402
from schemalog.api.tree_lint import lint_document, read_provided  # noqa: E402
from schemalog.bt.model import size  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    corpus = ROOT / "tests" / "bt" / "corpus"
    nodes = ROOT / "tests" / "bt" / "lint_fixtures" / "bb_nav2_tree_nodes.xml"
    rules, provided = read_semantics(profiles=["nav2"]), read_provided(profiles=["nav2"])
    programs = [(p.name, read_tree(str(p), [nodes]), rules, provided)
                for p in sorted((corpus / "nav2").glob("*.xml")) if p.name != "nav2_tree_nodes.xml"]
    programs.append(("combat/behavior_trees (rmuc_2026)",
                     read_tree(str(corpus / "combat" / "behavior_trees"), main="rmuc_2026"), None, None))
    print("| program | nodes | errors | warnings | s (best of %d) |" % args.rounds)
    print("|---|---:|---:|---:|---:|")
    for name, document, r, given in programs:
        best = float("inf")
        for _ in range(args.rounds):
            t = time.perf_counter()
            found = lint_document(document, r, given, max_states=defaults.MAX_STATES)
            best = min(best, time.perf_counter() - t)
        errors = sum(f.severity == "error" for f in found)
        warnings = sum(f.severity == "warning" for f in found)
        print(f"| {name} | {size(document)} | {errors} | {warnings} | {best:.2f} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
