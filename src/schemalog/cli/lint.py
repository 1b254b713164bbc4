"""`schemalog lint FILE...`: diagnostics for task knowledge that loads but cannot work."""

from __future__ import annotations

import argparse
import json
import sys

from ..errors import readable_name
from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog lint` and its arguments to the command line."""
    p = sub.add_parser("lint", parents=[parents.limits, parents.resources],
                       help="find knowledge that loads but cannot work (file:line:col, what to do)")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files to lint, {TOGETHER}")
    p.add_argument("--task", help="lint this task (default: every task/1)")
    p.add_argument("--strict", action="store_true", help="fail (exit 1) on warnings too")
    p.add_argument("--json", action="store_true", help="print the findings as JSON (docs/formats.md)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load the files, instantiate their tasks, print every finding; 1 with errors (--strict: any)."""
    from ..api.knowledge import task_term
    from ..errors import SchemalogError, UsageError
    from ..api.check import errors as count_errors, finding_of
    from .common import load_knowledge

    if args.task is not None:
        task_term(args.task)            # a --task that is no term is a usage error, before any reading
    try:
        knowledge = load_knowledge(args)
    except UsageError:
        raise
    except SchemalogError as err:        # what the loader refuses is the first finding, and the last
        findings, loaded, names = [finding_of(err)], False, [] if args.task is None else [args.task]
    else:
        loaded = True
        findings = knowledge.lint(args.task, max_depth=args.max_depth, max_nodes=args.max_nodes)
        names = knowledge.declared() if args.task is None else [args.task]
    errors = count_errors(findings)
    warnings = len(findings) - errors
    if args.json:
        print(json.dumps({"files": list(args.files), "tasks": names, "errors": errors, "warnings": warnings,
                          "findings": [f.as_json() for f in findings]}, indent=2))
    else:
        for f in findings:
            print(f.text())
        files = ", ".join(map(readable_name, args.files))
        if findings:
            print(f"lint: {files}: {_count(errors, 'error')}, {_count(warnings, 'warning')}", file=sys.stderr)
        else:
            print(f"lint: {files}: clean", file=sys.stderr)
        if loaded and not names:
            print("note: no task/1 declared: the clauses were linted, no task tree (name one with --task)",
                  file=sys.stderr)
    return 1 if errors or (args.strict and warnings) else 0


def _count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"
