"""`schemalog lint FILE...`: diagnostics for task knowledge that loads but cannot work, and for
BT.CPP trees (files or folders: the blackboard rules of bt/lint.py, decided on the tree's runs)."""

from __future__ import annotations

import argparse
import json
import sys

from ..errors import readable_name
from .options import TOGETHER, Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog lint` and its arguments to the command line."""
    from .trees import add_nodes_option

    p = sub.add_parser("lint", parents=[parents.limits, parents.resources],
                       help="find knowledge or BT.CPP trees that load but cannot work (file:line:col, what to do)")
    p.add_argument("files", nargs="+", metavar="FILE",
                   help=f"knowledge files to lint, {TOGETHER}; or BT.CPP tree files and folders, read as one program")
    p.add_argument("--task", help="lint this task (default: every task/1); BT.CPP trees: the tree to run "
                                  "(createTree's ID; default the main_tree_to_execute)")
    p.add_argument("--strict", action="store_true", help="fail (exit 1) on warnings too")
    p.add_argument("--json", action="store_true", help="print the findings as JSON (docs/formats.md)")
    p.add_argument("--format", choices=("text", "json", "sarif"), default=None,
                   help="text (default), json (as --json) or sarif: SARIF 2.1.0, which GitHub code scanning "
                        "shows on the lines of a pull request (docs/lint.md)")
    p.add_argument("-o", "--output", metavar="FILE", help="write the findings there (atomically), not to stdout")
    p.add_argument("--provided", action="append", default=[], metavar="FILE",
                   help="BT.CPP trees: a YAML file of the blackboard entries the program sets before the tree runs "
                        "(`provides:`) and reads after it (`reads:`), each `name: where` (docs/lint.md); "
                        "repeatable; --profile nav2 gives Nav2's")
    p.add_argument("--each", action="store_true",
                   help="BT.CPP trees: lint each FILE as a program of its own (a pre-commit hook's changed files: "
                        "Nav2's trees each define MainTree); XML that is no BT.CPP tree (package.xml) or a nodes "
                        "file is said to be skipped")
    add_nodes_option(p, max_states=True, drop_names=False)
    p.set_defaults(run=run, drop_names=False)


def run(args: argparse.Namespace) -> int:
    """Load the files, instantiate their tasks, print every finding; 1 with errors (--strict: any)."""
    from ..api.knowledge import task_term
    from ..errors import SchemalogError, UsageError
    from ..api.check import errors as count_errors, finding_of
    from .common import load_knowledge
    from .trees import schema_route, tree_route

    fmt = "json" if args.json else args.format or "text"
    if args.json and args.format not in (None, "json"):
        raise UsageError(f"--json and --format {args.format} ask for two formats: give one")
    if tree_route(args):                 # BT.CPP trees: the blackboard rules (bt/lint.py)
        return run_trees(args, fmt)
    schema_route(args)
    if args.each:
        raise UsageError("--each applies to BT.CPP trees (XML files and folders); "
                         f"{', '.join(map(readable_name, args.files))} is read as task knowledge")
    if args.provided:
        raise UsageError("--provided applies to BT.CPP trees; "
                         f"{', '.join(map(readable_name, args.files))} is read as task knowledge")
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
    if fmt != "text":
        _print(args, fmt, findings, {"tasks": names, "errors": errors, "warnings": warnings})
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


def _print(args: argparse.Namespace, fmt: str, findings, more: dict) -> None:
    """The findings as JSON (lint's own) or SARIF, printed or written to -o."""
    from .. import __version__
    from ..api.tree_lint import sarif
    from .common import emit

    if fmt == "sarif":
        text = json.dumps(sarif(findings, __version__), indent=2)
    else:
        text = json.dumps({"files": list(args.files), **more, "findings": [f.as_json() for f in findings]}, indent=2)
    emit(text + "\n", args.output, [*args.files, *args.nodes, *args.semantics, *args.provided], fmt.upper())


def run_trees(args: argparse.Namespace, fmt: str) -> int:
    """Lint one BT.CPP program (files and folders read as one): bt/lint.py's CHECKS."""
    from ..api.tree_lint import lint_document, read_provided
    from .trees import _profiles, _read, _rules, _shown, _versions

    rules = _rules(args)
    provided = read_provided(args.provided, args.max_bytes, profiles=_profiles(args))
    if args.each:
        return _run_each(args, fmt, rules, provided)
    document = _read(args, args.files, _versions(args, 1)[0])
    findings = lint_document(document, rules, provided, max_states=args.max_states, once=args.run_once)
    errors = sum(1 for f in findings if f.severity == "error")
    warnings = sum(1 for f in findings if f.severity == "warning")
    infos = sum(1 for f in findings if f.severity == "info")
    _write(args, fmt, findings, {"tree": document.main, "errors": errors, "warnings": warnings, "infos": infos})
    if fmt == "text":
        for f in findings:
            if f.severity == "note":
                print(f"note: {f.message}", file=sys.stderr)
        verdict = (f"{_count(errors, 'error')}, {_count(warnings, 'warning')}, {_count(infos, 'info')}"
                   if errors or warnings or infos else "no finding")
        print(f"lint: {_shown(args.files)} (tree {document.main}): {verdict}", file=sys.stderr)
    return 1 if errors or (args.strict and warnings) else 0


def _write(args: argparse.Namespace, fmt: str, findings, more: dict) -> None:
    """A BT.CPP lint's findings: JSON or SARIF (_print), else each finding but the notes as text,
    printed or written to -o."""
    if fmt != "text":
        _print(args, fmt, findings, more)
        return
    text = "".join(f.text() + "\n" for f in findings if f.severity != "note")
    if args.output:
        from .common import emit
        emit(text, args.output, [*args.files, *args.nodes, *args.semantics, *args.provided], "text")
    else:
        sys.stdout.write(text)


def _count(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _run_each(args: argparse.Namespace, fmt: str, rules, provided) -> int:
    """Lint each FILE as its own program; a file that cannot be read is its one finding (as a
    knowledge file's is), one that is no BT.CPP tree is skipped and said; 1 with any error."""
    import os

    from ..api.check import finding_of
    from ..api.tree_lint import lint_document
    from ..errors import SchemalogError
    from .diff_rev import not_a_tree
    from .trees import _read, _versions

    findings, lines = [], []
    version = _versions(args, 1)[0]
    for path in args.files:
        skip = None if os.path.isdir(path) else not_a_tree((path,), args.max_bytes)
        if skip:
            lines.append(f"lint: {readable_name(path)}: {skip}")
            continue
        try:
            document = _read(args, path, version)
        except SchemalogError as err:
            found = [finding_of(err)]
            main = "not read"
        else:
            found = lint_document(document, rules, provided, max_states=args.max_states, once=args.run_once)
            main = f"tree {document.main}"
        findings.extend(found)
        counts = [f"{_count(sum(f.severity == k for f in found), k)}" for k in ("error", "warning", "info")]
        real = [f for f in found if f.severity != "note"]
        lines.append(f"lint: {readable_name(path)} ({main}): {', '.join(counts) if real else 'no finding'}")
        lines.extend(f"note: {f.message}" for f in found if f.severity == "note")     # what it covered
    errors = sum(f.severity == "error" for f in findings)
    warnings = sum(f.severity == "warning" for f in findings)
    _write(args, fmt, findings, {"errors": errors, "warnings": warnings,
                                 "infos": sum(f.severity == "info" for f in findings)})
    for line in lines:
        print(line, file=sys.stderr)
    return 1 if errors or (args.strict and warnings) else 0
