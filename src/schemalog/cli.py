"""The `schemalog` command: check, show and convert task knowledge.

Exit status: 0 success, 1 bad input (a message with file:line:column), 2 bad usage.
No command prints a traceback; SCHEMALOG_DEBUG=1 shows one for internal errors.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import sys
from pathlib import Path

from . import __version__
from .documents import YAML_SUFFIXES, Document, read_document, to_pl, to_yaml, write_atomically
from .engine import PrologError
from .errors import SchemalogError, UsageError
from .kb import KnowledgeBase
from .parse import MAX_BYTES, Clause, parse_term
from .render import rich_tree, show_json, to_dot, tree_document
from .schema import check_schemas
from .terms import TRUE, Struct, Term, Var, term_to_text
from .unify import Bindings
from .tree import DEFAULT_MAX_DEPTH, DEFAULT_MAX_NODES, Behaviour, count_nodes, declared_tasks, depth, instantiate


# ---------------------------------------------------------------------------
# Shared steps

def _load(args: argparse.Namespace) -> tuple[KnowledgeBase, list[Document]]:
    kb = KnowledgeBase()
    docs = []
    for path in args.files:
        doc = read_document(path, args.max_bytes)
        doc.to_kb(kb)
        docs.append(doc)
    for warning in kb.warnings:
        print(warning, file=sys.stderr)
    return kb, docs


def _task_term(text: str) -> Term:
    try:
        return parse_term(text, "--task")
    except SchemalogError as err:
        raise UsageError(f"--task {text!r} is not a term: {err.message}") from None


def _root_candidates(kb: KnowledgeBase) -> list[str]:
    """Schemas never used as a sub-task: likely tasks, for a helpful message."""
    schemas = check_schemas(kb)
    used = {term_to_text(e.behaviour) for s in schemas for e in s.entries}
    return [term_to_text(s.task) for s in schemas if s.entries and term_to_text(s.task) not in used]


def _choose_tasks(kb: KnowledgeBase, task: str | None, every: bool = False) -> list[Term]:
    if task is not None:
        term = _task_term(task)
        if not _defines(kb, term):
            known = [term_to_text(t) for t in declared_tasks(kb)] or _root_candidates(kb)
            hint = f"; tasks here: {', '.join(known[:8])}" if known else ""
            raise SchemalogError(f"unknown task {term_to_text(term)}: no schema({term_to_text(term)}, "
                                 f"Subtasks, Post) in {', '.join(kb.files)}{hint}")
        return [term]
    declared = declared_tasks(kb)
    if declared:
        return declared if every else declared[:1]
    if every:
        return []
    roots = _root_candidates(kb)
    hint = f" (candidates: {', '.join(roots[:8])})" if roots else ""
    raise UsageError(f"no task declared with task/1: name one with --task{hint}")


def _defines(kb: KnowledgeBase, task: Term) -> bool:
    """Whether some schema/3 head unifies with `task`."""
    goal = Struct("schema", (task, Var("_"), Var("_")))
    return any(Bindings().unify(c.head, goal) for c in kb.candidates("schema", 3, task) or [])


def _instantiate(kb: KnowledgeBase, task: Term, args: argparse.Namespace) -> Behaviour:
    return instantiate(kb, task, max_depth=args.max_depth, max_nodes=args.max_nodes)


def _emit(text: str, output: str | None, inputs: list[str]) -> None:
    if output is None or output == "-":
        sys.stdout.write(text)
        return
    out = Path(output).resolve()
    if any(Path(i).resolve() == out for i in inputs):
        raise UsageError(f"-o {output} would overwrite an input file; choose another name")
    write_atomically(output, text)


# ---------------------------------------------------------------------------
# Commands

def cmd_check(args: argparse.Namespace) -> int:
    """Parse, read every schema, and instantiate the tasks."""
    kb, _ = _load(args)
    schemas = check_schemas(kb)
    tasks = _choose_tasks(kb, args.task, every=True)
    files = ", ".join(args.files)
    report = []
    for task in tasks:
        tree = _instantiate(kb, task, args)
        report.append(f"{term_to_text(task)} ({count_nodes(tree)} behaviours, depth {depth(tree)})")
    summary = f"ok: {files}: {len(schemas)} schemas"
    summary += f"; tasks: {', '.join(report)}" if report else "; no task/1 declared (nothing instantiated)"
    print(summary)
    return 0


def cmd_show(args: argparse.Namespace) -> int:
    """Instantiate a task and print its tree."""
    kb, _ = _load(args)
    task = _choose_tasks(kb, args.task)[0]
    tree = _instantiate(kb, task, args)
    fmt = "json" if args.json else args.format
    if fmt == "json":
        _emit(json.dumps(show_json(task, tree), indent=2) + "\n", args.output, args.files)
    elif fmt == "dot":
        _emit(to_dot(tree, term_to_text(task)), args.output, args.files)
    elif fmt in ("pl", "yaml"):
        doc = tree_document(task, tree)
        text = to_pl(doc, header=f"The task tree of {term_to_text(task)}, written by schemalog show.") \
            if fmt == "pl" else to_yaml(doc)
        _emit(text, args.output, args.files)
    else:
        from rich.console import Console

        title = f"{term_to_text(task)}: {count_nodes(tree)} behaviours, depth {depth(tree)}"
        if args.output and args.output != "-":
            from io import StringIO

            buffer = StringIO()
            Console(file=buffer, width=120, no_color=True).print(rich_tree(tree, title))
            _emit(buffer.getvalue(), args.output, args.files)
        else:
            Console(highlight=False).print(rich_tree(tree, title))
    return 0


def cmd_convert(args: argparse.Namespace) -> int:
    """Convert knowledge between SEED, schema text and YAML."""
    doc = read_document(args.input, args.max_bytes)
    for note in doc.notes:
        print(note, file=sys.stderr)
    if args.task:
        declaration = Clause(Struct("task", (_task_term(args.task),)), TRUE, None)
        doc = Document((declaration, *doc.items), doc.file, doc.notes, doc.seed)
    check_schemas(doc.to_kb())  # what is written must load again: check before writing
    target = args.to or ("yaml" if args.output and args.output.endswith(YAML_SUFFIXES) else "pl")
    if target == "yaml":
        text = to_yaml(doc)
    else:
        origin = "the SEED long-term memory" if doc.seed else ""
        header = f"Converted by schemalog from {origin + ' ' if origin else ''}{doc.file}."
        text = to_pl(doc, header=header)
    _emit(text, args.output, [args.input])
    return 0


# ---------------------------------------------------------------------------
# Argument parsing

def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError("must be at least 1")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="schemalog",
        description="Compress and check robot task structures (schema(m, l, p) knowledge).")
    parser.add_argument("--version", action="version", version=f"schemalog {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    limits = argparse.ArgumentParser(add_help=False)
    limits.add_argument("--max-bytes", type=_positive, default=MAX_BYTES,
                        help=f"refuse input files larger than this (default {MAX_BYTES:,})")
    limits.add_argument("--max-depth", type=_positive, default=DEFAULT_MAX_DEPTH,
                        help=f"deepest task tree to instantiate (default {DEFAULT_MAX_DEPTH})")
    limits.add_argument("--max-nodes", type=_positive, default=DEFAULT_MAX_NODES,
                        help=f"largest task tree to instantiate (default {DEFAULT_MAX_NODES:,})")

    p = sub.add_parser("check", parents=[limits], help="parse and validate knowledge files")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="instantiate this task (default: every task/1)")
    p.set_defaults(run=cmd_check)

    p = sub.add_parser("show", parents=[limits], help="instantiate a task and print its tree")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task to instantiate (default: the first task/1)")
    p.add_argument("--format", choices=["text", "json", "dot", "yaml", "pl"], default="text")
    p.add_argument("--json", action="store_true", help="same as --format json")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=cmd_show)

    p = sub.add_parser("convert", parents=[limits],
                       help="convert knowledge: SEED or schema text or YAML -> schema text or YAML")
    p.add_argument("input", metavar="FILE")
    p.add_argument("-o", "--output", help="output file; its suffix (.pl, .yaml) picks the format")
    p.add_argument("--to", choices=["pl", "yaml"], help="output format (default: from -o, else pl)")
    p.add_argument("--task", help="declare this task (task/1) in the output")
    p.set_defaults(run=cmd_convert)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "run", None):
        parser.print_help(sys.stderr)
        return 2
    try:
        return args.run(args)
    except SchemalogError as err:
        print(str(err), file=sys.stderr)
        if err.exit_code == 2:
            print(f"(see: schemalog {args.command} --help)", file=sys.stderr)
        return err.exit_code
    except PrologError as err:
        print(f"error: uncaught Prolog exception: {err}", file=sys.stderr)
        return 1
    except RecursionError:
        print("error: the input nests too deeply to process", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as err:  # an internal error must still not dump a traceback on users
        if os.environ.get("SCHEMALOG_DEBUG"):
            raise
        print(f"internal error: {type(err).__name__}: {err} (please report it; "
              f"SCHEMALOG_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 70


def tune_gc() -> None:
    """Collect garbage less often: loading builds millions of small immutable objects and
    almost no cycles, and the default thresholds make it superlinear (x25 per 10x size
    instead of x10, benchmarks/bench_foundation.py)."""
    gc.set_threshold(50_000, 20, 100)


def run() -> None:
    """Console-script entry point."""
    tune_gc()
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    code = main()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        pass
    raise SystemExit(code)


__all__ = ["main", "run"]
