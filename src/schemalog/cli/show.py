"""`schemalog show FILE...`: instantiate a task and print its tree."""

from __future__ import annotations

import argparse

from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog show` and its arguments to the command line."""
    p = sub.add_parser("show", parents=[parents.limits, parents.resources, parents.output],
                      help="instantiate a task and print its tree")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task, {TOGETHER}")
    p.add_argument("--task", help="the task to instantiate (default: the first task/1)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Instantiate a task and print its tree."""
    from .common import load_knowledge, task_as_read
    from .output import output_format, output_tree

    output_format(args)                # a picture asked for without Graphviz: say so before any work
    task = task_as_read(load_knowledge(args), args)   # as instantiated: --task 'add(X)' shows the schema it found
    output_tree(args, task, f"The task tree of {task.name}, written by schemalog show.")
    return 0
