"""`schemalog generate`: write a task in the shape of the paper's evaluation (Sec. IV-B)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .. import defaults
from ..errors import UsageError
from .options import Parents, fraction, positive


def register(sub, parents: Parents) -> None:
    """Add `schemalog generate` and its arguments to the command line."""
    p = sub.add_parser("generate", parents=[parents.resources],
                      help="write a task in the shape of the paper's evaluation (Sec. IV-B)")
    p.add_argument("--depth", type=positive, required=True,
                   help=f"levels of the tree (the paper: 4, 5, 6; at most {defaults.MAX_DEPTH})")
    p.add_argument("--children", type=positive, required=True,
                   help="children per behaviour (the paper: 2, 3, 4)")
    p.add_argument("--rd", type=fraction, default=0.0, metavar="RD",
                   help="the reduction degree to aim at, 0 to 1 (default 0); the one achieved is reported")
    p.add_argument("--seed", type=int, default=0, help="which chains are drawn (default 0)")
    p.add_argument("--siblings-only", action="store_true",
                   help="release behaviours only by a sibling's done (caps RD lower, e.g. 0.55 for binary trees)")
    p.add_argument("--format", choices=["pl", "yaml"], help="output format (default: from -o's suffix, else pl)")
    p.add_argument("--scene", metavar="FILE", help="also write a scene with the objects (for schemalog run)")
    p.add_argument("--max-nodes", type=positive, default=defaults.MAX_NODES,
                   help=f"refuse shapes with more behaviours (default {defaults.MAX_NODES:,})")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Write a task in the shape of the paper's evaluation and report the RD it achieves."""
    from ..api.generate import check_shape, generated
    from .common import check_output, emit

    check_shape(args.depth, args.children, args.max_nodes)
    outputs = [o for o in (args.output, args.scene) if o not in (None, "-")]
    if args.scene == "-":
        raise UsageError("--scene needs a file name (the task itself goes to standard output without -o)")
    if len(outputs) == 2 and Path(outputs[0]).resolve() == Path(outputs[1]).resolve():
        raise UsageError(f"-o and --scene name the same file, {args.output}")
    for output, option in ((args.output, "-o"), (args.scene, "--scene")):  # every destination before any
        check_output(output, [], option)          # generate reads no file
    task = generated(args.depth, args.children, args.rd, args.seed, cousins=not args.siblings_only, fmt=args.format,
                     file=args.output, max_nodes=args.max_nodes)
    said = f"task {task.task}, {task.figures}"
    emit(task.text, args.output, [], said)
    if args.output in (None, "-"):          # the task went to standard output: its figures beside it
        print(said, file=sys.stderr)
    if args.scene:
        emit(task.scene, args.scene, [], f"the scene of {task.task}: {args.children} objects")
    if task.shortfall:
        print(f"note: RD {task.reduction_degree:.2f} is more than {defaults.RD_TOLERANCE} from the "
              f"{args.rd:.2f} asked: {task.shortfall}", file=sys.stderr)
    return 0
