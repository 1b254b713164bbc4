"""`schemalog query FILE... QUERY`: answer one Prolog query over knowledge files (docs/queries.md)."""

from __future__ import annotations

import argparse
import sys

from ..errors import SchemalogError
from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog query` and its arguments to the command line."""
    p = sub.add_parser("query", parents=[parents.limits, parents.resources, parents.ask],
                       help="answer a Prolog query over knowledge files (docs/queries.md)")
    p.add_argument("files", nargs="*", metavar="FILE", help=f"knowledge files to query (none: the built-ins alone), {TOGETHER}")
    p.add_argument("query", metavar="QUERY", help="a goal, e.g. 'sequential(X, Y)' (the final '.' is optional)")
    p.add_argument("--first", action="store_true", help="stop after the first answer")
    p.add_argument("--json", action="store_true", help="print a JSON list of bindings")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Answer one query over knowledge files: every answer (or the first), as text or JSON."""
    from .common import workspace_of
    from .toplevel import run_query

    try:
        workspace = workspace_of(args, args.files)
    except SchemalogError as err:
        print(str(err), file=sys.stderr)
        return 2
    for note in workspace.notes:
        print(note, file=sys.stderr)
    return run_query(workspace, args.query, first=args.first, as_json=args.json)
