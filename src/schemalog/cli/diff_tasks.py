"""`schemalog diff A.pl B.pl`: two versions of a task (schema knowledge), or a task and the
compressed form `schemalog compress` wrote, compared on runs (api/task_diff.py)."""

from __future__ import annotations

import argparse


def run_tasks(args: argparse.Namespace, fmt: str) -> int:
    """Compare two versions of a task on the verifier's runs; print the report in `fmt`."""
    import json

    import schemalog
    from ..api.task_diff import diff_tasks
    from ..errors import UsageError, readable_name
    from .common import check_output, emit, inputs_of, said
    from .trees import schema_route

    schema_route(args)                      # --nodes, --profile, ... apply to BT.CPP trees only
    if fmt not in ("text", "json", "markdown"):
        raise UsageError(f"diff of task knowledge prints text, JSON or Markdown, not {fmt}")
    check_output(args.output, inputs_of(args))
    first, second = (schemalog.load(path, max_bytes=args.max_bytes, max_steps=args.max_steps)
                     for path in args.files)
    for knowledge in (first, second):
        said(knowledge.warnings)
    a = first.task(args.task, max_depth=args.max_depth, max_nodes=args.max_nodes)
    declared = second.tasks()
    name = args.task if args.task is not None else (declared[0] if declared else a.name)
    b = second.task(name, max_depth=args.max_depth, max_nodes=args.max_nodes)
    said([*a.notes, *b.notes])
    report = diff_tasks(a, b, readable_name(args.files[0]), readable_name(args.files[1]),
                        max_states=args.max_states)
    inputs = inputs_of(args, [*first.files, *second.files])
    if fmt == "json":
        emit(json.dumps(report.as_json(), indent=2) + "\n", args.output, inputs, "JSON")
    elif fmt == "markdown":
        emit(report.markdown(), args.output, inputs, "Markdown")
    else:
        emit(report.text(), args.output, inputs, "text")
    return report.exit_status
