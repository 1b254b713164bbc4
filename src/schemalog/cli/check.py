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
    p.add_argument("--no-lint", action="store_true",
                   help="only parse, validate and instantiate: skip lint's findings (which fail check on an error)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Parse, read every schema, instantiate the tasks and lint them; 1 when lint finds an error."""
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
    errors = 0 if args.no_lint else _lint(kb, trees, unused=args.task is None)
    summary = f"{files}: {schemas} schemas"
    summary += f"; tasks: {', '.join(report)}" if report else "; no task/1 declared (nothing instantiated)"
    if errors:
        print(f"failed: {summary}; lint found {errors} error{'s' if errors != 1 else ''} above "
              f"(`schemalog check --no-lint` checks without lint)")
        return 1
    print(f"ok: {summary}" + ("; not linted (--no-lint)" if args.no_lint else ""))
    return 0


def _lint(kb, trees, unused: bool) -> int:
    """Print lint's findings with the severity lint gives them, as SWI-Prolog prints what it
    finds while it consults; the number of errors."""
    import sys

    from ..errors import SchemalogError
    from ..run.lint import ERROR, error_finding, facts_of, lint_knowledge
    from .common import uncollected

    try:
        facts = facts_of(kb)             # may run Prolog: with the collector on
        with uncollected():              # lint's passes over the tree make no cycles
            findings = lint_knowledge(kb, trees, facts, unused)
    except SchemalogError as err:
        findings = (error_finding(err),)
    for finding in findings:
        print(finding.text(), file=sys.stderr)
    return sum(1 for f in findings if f.severity == ERROR)
