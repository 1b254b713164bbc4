"""`schemalog check FILE...`: parse and validate knowledge files, and instantiate their tasks."""

from __future__ import annotations

import argparse
import gc

from ..errors import readable_name
from ..logic.terms import term_to_text
from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog check` and its arguments to the command line."""
    p = sub.add_parser("check", parents=[parents.limits, parents.resources], help="parse and validate knowledge files")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files to check, {TOGETHER}")
    p.add_argument("--task", help="instantiate this task (default: every task/1)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Parse, read every schema, and instantiate the tasks."""
    from ..task.compress import original_of
    from ..task.schema import check_schemas, schema_clauses
    from ..task.tree import count_nodes, depth
    from .common import choose_tasks, instantiate_task, load_files, uncollected

    kb = load_files(args)[0]   # not the documents too: their clauses would stay in memory
    clauses = schema_clauses(kb)
    # read once: instantiating takes a ground fact's schema from here instead of reading it again
    with uncollected():                  # reading schemas runs no Prolog and makes no cycles
        read = {id(c): schema for c, schema in zip(clauses, check_schemas(kb))}
    schemas = len(read)
    tasks = choose_tasks(kb, args.task, every=True)
    files = ", ".join(map(readable_name, args.files))
    report = []
    trees = []
    for task in tasks:
        tree = instantiate_task(kb, task, args, read)
        trees.append(original_of(tree))      # a compressed file: lint its original
        report.append(f"{term_to_text(task)} ({count_nodes(tree)} behaviours, depth {depth(tree)})")
    del read                             # the trees hold what they need of it
    gc.freeze()                          # the trees live to the end: lint's collections skip them
    _warn(kb, trees, unused=args.task is None)
    summary = f"ok: {files}: {schemas} schemas"
    summary += f"; tasks: {', '.join(report)}" if report else "; no task/1 declared (nothing instantiated)"
    print(summary)
    return 0


def _warn(kb, trees, unused: bool) -> None:
    """Print lint's findings as warnings, as SWI-Prolog warns while it consults (exit unchanged)."""
    import sys

    from ..errors import SchemalogError
    from ..run.lint import error_finding, facts_of, lint_knowledge
    from .common import uncollected

    try:
        facts = facts_of(kb)             # may run Prolog: with the collector on
        with uncollected():              # lint's passes over the tree make no cycles
            findings = lint_knowledge(kb, trees, facts, unused)
    except SchemalogError as err:
        findings = (error_finding(err),)
    for finding in findings:
        print(finding.text("warning"), file=sys.stderr)
    if findings:
        print(f"({len(findings)} warning{'s' if len(findings) != 1 else ''}: schemalog lint explains them, "
              f"and fails on its errors)", file=sys.stderr)
