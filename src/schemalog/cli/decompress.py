"""`schemalog decompress FILE...`: restore the original tree of a compressed task from its provenance."""

from __future__ import annotations

import argparse
import sys

from ..logic.terms import term_to_text
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
    from ..task.compress import decompress
    from .common import choose_tasks, instantiate_task, load_files
    from .output import output_tree

    kb, _ = load_files(args)
    tree = instantiate_task(kb, choose_tasks(kb, args.task)[0], args)
    task = tree.label
    if not tree.origins:
        print(f"note: {term_to_text(task)} carries no provenance (origins/2): it is shown as it is",
              file=sys.stderr)
    original = decompress(tree)
    output_tree(args, original.label, original,
                 f"The original tree of {term_to_text(task)}, restored by schemalog decompress.", kb)
    return 0
