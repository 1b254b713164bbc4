"""`schemalog run FILE...`: execute a task with the attentional executive against an emulated robot."""

from __future__ import annotations

import argparse
import json
import sys

from .. import defaults
from .options import TOGETHER, Parents, budget, count, distance, positive


def register(sub, parents: Parents) -> None:
    """Add `schemalog run` and its arguments to the command line."""
    p = sub.add_parser("run", parents=[parents.limits, parents.resources],
                       help="execute a task with the attentional executive against an emulated robot")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task to run, {TOGETHER}")
    p.add_argument("--task", help="the task to run (default: the first task/1)")
    p.add_argument("--scene", metavar="FILE", help="object positions (YAML, docs/semantics.md); "
                                                   "without it every lambda is neutral")
    p.add_argument("--compressed", action="store_true", help="compress first, then run in the same world")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES),
                   help="with --compressed: what merged behaviours pass to their children (default full)")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.add_argument("--state", metavar="ATOMS", help="the initial state, e.g. 'hand.free, spoon.taken' "
                                                    "(default: the file's initial/1 facts)")
    p.add_argument("--seed", type=int, help="move the scene's objects randomly with this seed")
    p.add_argument("--jitter", type=distance, metavar="M",
                   help=f"how far (metres, per coordinate) --seed moves objects (default {defaults.JITTER}: "
                        f"here --seed only moves objects, so it moves them unless told 0; simulate-demo's "
                        f"default is 0, its --seed also seeding the noise)")
    p.add_argument("--selector", choices=list(defaults.SELECTORS), default="incremental",
                   help="incremental (default): re-evaluate what an action touched; "
                        "scan: visit every behaviour at every decision, the paper's cost model")
    p.add_argument("--fail", action="append", metavar="LABEL",
                   help="make the robot fail this action's command (repeatable), e.g. 'a5(cup)'")
    p.add_argument("--fail-times", type=positive, metavar="N",
                   help="each --fail action fails only its first N commands (default: every one)")
    p.add_argument("--retries", type=count, default=defaults.RETRIES, metavar="N",
                   help=f"retry a failed behaviour N times before inhibiting it (default {defaults.RETRIES})")
    p.add_argument("--recovery", choices=list(defaults.RECOVERIES), default=defaults.RECOVERIES[0],
                   help="when the robot fails an action inside a merged behaviour: decompress (default) "
                        "splits just that behaviour into its actions, so only the failed one is retried "
                        "and inhibited; resume retries the merged behaviour from the failed action")
    p.add_argument("--max-decisions", type=positive, metavar="N",
                   help="stop after N decisions (default: 4 per action of the original task, at least 100)")
    p.add_argument("--json", action="store_true", help="print the run as JSON (docs/formats.md)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Execute a task with the attentional executive against an emulated robot."""
    from ..api.execution import decision_lines, decision_width, summary_lines
    from .common import check_output, emit, inputs_of, load_knowledge, said, task_to_use

    knowledge = load_knowledge(args)
    if args.propagate is not None and not args.compressed:
        print("note: --propagate applies with --compressed; this run compresses nothing", file=sys.stderr)
    args.propagate = args.propagate or "full"
    task = task_to_use(knowledge, args)
    run = task.start(args.scene, seed=args.seed, jitter=args.jitter, state=args.state, selector=args.selector,
                     fail=args.fail or (), fail_times=args.fail_times, retries=args.retries,
                     recovery=args.recovery, max_decisions=args.max_decisions)
    said(run.notes)
    inputs = inputs_of(args, knowledge.files)
    check_output(args.output, inputs)   # refuse before running, not after
    if args.json:
        emit(json.dumps(run.finish().as_json(), indent=2) + "\n", args.output, inputs, run.words("JSON"))
        return 0 if run.completed else 1
    lines = run.header()
    out = sys.stdout if not args.output or args.output == "-" else None
    width = decision_width(task.tree)
    if out:
        print("\n".join(lines), flush=True)
        lines = []
    for decision in run:                # each decision printed as it is taken
        text = decision_lines(decision, width)
        if out:
            print("\n".join(text))
        else:
            lines.extend(text)
    lines.extend(summary_lines(run.executive))
    if out:
        print("\n".join(lines))
    else:
        emit("\n".join(lines) + "\n", args.output, inputs, run.words("text"))
    return 0 if run.completed else 1
