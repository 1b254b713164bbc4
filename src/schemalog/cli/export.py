"""`schemalog export FILE --to btcpp|py_trees`: a task tree for a behaviour-tree runtime."""

from __future__ import annotations

import argparse

from .. import defaults
from .options import TOGETHER, Parents, budget, count

TARGETS = ("btcpp", "py_trees")


def register(sub, parents: Parents) -> None:
    """Add `schemalog export` and its arguments to the command line."""
    p = sub.add_parser("export", parents=[parents.limits, parents.resources],
                       help="write a task tree for BehaviorTree.CPP v4 (XML) or py_trees (a Python module)")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task, {TOGETHER}")
    p.add_argument("--to", choices=TARGETS, help="the runtime (default: from -o's suffix, .xml or .py)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.add_argument("--task", help="the task to export (default: the first task/1)")
    p.add_argument("--compressed", action="store_true", help="compress first (Algorithm 1), then export")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES), default="full",
                   help="with --compressed: what merged behaviours pass to their children (default full)")
    state = p.add_mutually_exclusive_group()
    state.add_argument("--state", metavar="ATOMS", help="write this initial state into the tree, for its first "
                                                        "tick to set (default: the robot writes the state)")
    state.add_argument("--initial", action="store_true",
                       help="write the files' initial/1 into the tree, for its first tick to set")
    p.add_argument("--node-types", metavar="YAML",
                   help="BT.CPP node types and port names for the actions: `a1: PickUp(object)` per line "
                        "(default: the functor, ports arg1, arg2 ...)")
    p.add_argument("--retries", type=count, default=defaults.RETRIES, metavar="N",
                   help=f"a failed action is retried N times, then inhibited, as `run` does (default {defaults.RETRIES})")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Export a task tree, original or compressed, for BT.CPP or py_trees."""
    from ..errors import UsageError
    from .common import emit, inputs_of, load_knowledge, task_to_use

    target = args.to
    if target is None:
        suffix = (args.output or "").rsplit(".", 1)[-1].lower() if args.output and "." in args.output else ""
        target = {"xml": "btcpp", "py": "py_trees"}.get(suffix)
        if target is None:
            raise UsageError("name the runtime with --to btcpp or --to py_trees (or give -o a .xml or .py name)")
    knowledge = load_knowledge(args)
    task = task_to_use(knowledge, args)
    text = task.text(target, True if args.initial else args.state, retries=args.retries, node_types=args.node_types)
    what = "BehaviorTree.CPP v4 XML" if target == "btcpp" else "a py_trees module"
    emit(text, args.output, inputs_of(args, knowledge.files),
         f"{task.name}, {task.kind} tree of {len(task)} behaviours ({what})")
    return 0
