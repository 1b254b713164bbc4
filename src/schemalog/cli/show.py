"""`schemalog show FILE...`: instantiate a task and print its tree."""

from __future__ import annotations

import argparse

from ..logic.terms import term_to_text
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
    from .common import choose_tasks, instantiate_task, load_files
    from .output import output_format, output_tree

    output_format(args)                # a picture asked for without Graphviz: say so before any work
    kb, _ = load_files(args)
    tree = instantiate_task(kb, choose_tasks(kb, args.task)[0], args)
    task = tree.label  # as instantiated: --task 'add(X)' shows the schema it found
    output_tree(args, task, tree, f"The task tree of {term_to_text(task)}, written by schemalog show.", kb)
    return 0
