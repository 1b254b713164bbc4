"""`schemalog check FILE...`: parse and validate knowledge files, and instantiate their tasks."""

from __future__ import annotations

import argparse
import gc

from ..errors import readable_name
from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog check` and its arguments to the command line."""
    p = sub.add_parser("check", parents=[parents.limits, parents.resources], help="parse and validate knowledge files")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files to check, {TOGETHER}")
    p.add_argument("--task", help="instantiate this task (default: every task/1)")
    p.add_argument("--no-lint", action="store_true",
                   help="only parse, validate and instantiate: skip lint's findings (which fail check on an error)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Parse, read every schema, instantiate the tasks and lint them; 1 when lint finds an error."""
    from ..api.check import Checking, errors as count_errors
    from .common import load_knowledge, said, uncollected

    knowledge = load_knowledge(args)
    checking = Checking(knowledge, args.task, max_depth=args.max_depth, max_nodes=args.max_nodes,
                        quiet=uncollected)   # reading schemas runs no Prolog and makes no cycles
    files = ", ".join(map(readable_name, args.files))
    report = []
    for name, task in checking.tasks():
        said(task.notes)
        report.append(f"{name} ({len(task)} behaviours, depth {task.depth})")
    gc.freeze()                          # the trees live to the end: lint's collections skip them
    errors = 0
    if not args.no_lint:
        # lint's findings with the severity lint gives them, as SWI-Prolog prints what it finds
        # while it consults
        findings = checking.lint(unused=args.task is None)
        said(f.text() for f in findings)
        errors = count_errors(findings)
    summary = f"{files}: {checking.schemas} schemas"
    summary += f"; tasks: {', '.join(report)}" if report else "; no task/1 declared (nothing instantiated)"
    if errors:
        print(f"failed: {summary}; lint found {errors} error{'s' if errors != 1 else ''} above "
              f"(`schemalog check --no-lint` checks without lint)")
        return 1
    print(f"ok: {summary}" + ("; not linted (--no-lint)" if args.no_lint else ""))
    return 0
