"""`schemalog repl FILE...`: the interactive top level over knowledge files (session.py)."""

from __future__ import annotations

import argparse
import sys

from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog repl` and its arguments to the command line."""
    p = sub.add_parser("repl", parents=[parents.limits, parents.ask], help="the interactive query top level")
    p.add_argument("files", nargs="*", metavar="FILE", help=f"knowledge files to start with (:load adds more), {TOGETHER}")
    p.add_argument("--plain", action="store_true",
                   help="read queries line by line without prompt_toolkit (as when piped)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """The interactive top level (prompt_toolkit) over knowledge files."""
    from .common import workspace_of
    from .session import Repl

    workspace = workspace_of(args, args.files)
    interactive = sys.stdin.isatty() and sys.stdout.isatty() and not args.plain
    return Repl(workspace).loop(interactive)
