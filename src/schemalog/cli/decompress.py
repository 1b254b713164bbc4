"""`schemalog decompress FILE...`: restore the original tree of a compressed task from its provenance."""

from __future__ import annotations

import argparse

from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog decompress` and its arguments to the command line."""
    p = sub.add_parser("decompress", parents=[parents.limits, parents.resources, parents.output],
                       help="restore the original tree of a compressed task file")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"a compressed task file (compress -o: its origins/2 give the original), {TOGETHER}")
    p.add_argument("--task", help="the task (default: the first task/1)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Restore the original tree of a compressed task from its provenance."""
    from .common import load_knowledge, said, task_as_read
    from .output import output_tree

    task = task_as_read(load_knowledge(args), args)
    original = task.decompress()
    said(original.notes)
    output_tree(args, original, f"The original tree of {task.name}, restored by schemalog decompress.")
    return 0
