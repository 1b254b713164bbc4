"""The `schemalog` command: check, show and convert task knowledge.

Exit status: 0 success, 1 bad input (a message with file:line:column), 2 bad usage.
No command prints a traceback; SCHEMALOG_DEBUG=1 shows one for internal errors.
"""

from __future__ import annotations

import argparse
import gc
import io
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
from .compress import PROPAGATE_MODES, compress, decompress, protected_labels
from .conditions import DEFAULT_SYMPY_BUDGET, MAX_SYMPY_BUDGET, Simplifier
from .render import carried_clauses, compare_dot, rich_tree, show_json, to_dot, tree_document, tree_json
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
    """Print, or write atomically to `output`, which must not be any file read."""
    if output is None or output == "-":
        sys.stdout.write(text)
        return
    out = Path(output).resolve()
    if any(not i.startswith("<") and Path(i).resolve() == out for i in inputs):
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


_SUFFIX_FORMATS = {".json": "json", ".dot": "dot", ".gv": "dot", ".pl": "pl", ".yaml": "yaml", ".yml": "yaml"}


def _format(args: argparse.Namespace) -> str:
    """--json, else --format, else the output file's suffix, else text."""
    if args.json:
        return "json"
    if args.format:
        return args.format
    if args.output and args.output != "-":
        return _SUFFIX_FORMATS.get(Path(args.output).suffix.lower(), "text")
    return "text"


def _rendered(renderable, width: int = 120) -> str:
    from rich.console import Console

    buffer = io.StringIO()
    Console(file=buffer, width=width, no_color=True).print(renderable)
    return buffer.getvalue()


def _print_rich(renderable, output: str | None, inputs: list[str]) -> None:
    if output and output != "-":
        _emit(_rendered(renderable), output, inputs)
    else:
        from rich.console import Console

        Console(highlight=False).print(renderable)


def _output_tree(args: argparse.Namespace, task: Term, tree: Behaviour, header: str,
                 kb: KnowledgeBase | None = None) -> None:
    """Print or write one tree in the requested format (show, decompress)."""
    fmt = _format(args)
    inputs = kb.files if kb is not None else args.files
    if fmt == "json":
        _emit(json.dumps(show_json(task, tree), indent=2) + "\n", args.output, inputs)
    elif fmt == "dot":
        _emit(to_dot(tree, term_to_text(task)), args.output, inputs)
    elif fmt in ("pl", "yaml"):
        doc = tree_document(tree, carried=carried_clauses(kb) if kb is not None else [])
        _emit(to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc), args.output, inputs)
    else:
        title = f"{term_to_text(task)}: {count_nodes(tree)} behaviours, depth {depth(tree)}"
        _print_rich(rich_tree(tree, title), args.output, inputs)


def cmd_show(args: argparse.Namespace) -> int:
    """Instantiate a task and print its tree."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label  # as instantiated: --task 'add(X)' shows the schema it found
    _output_tree(args, task, tree, f"The task tree of {term_to_text(task)}, written by schemalog show.", kb)
    return 0


def cmd_compress(args: argparse.Namespace) -> int:
    """Merge sequential behaviours (Algorithm 1) and report the paper's figures."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label
    result = compress(tree, args.propagate, protected_labels(kb, tree),
                      Simplifier(sympy_budget=args.sympy_budget))
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    figures = (f"Bi = {result.nodes_before}, Bm = {result.nodes_after}, D = {result.depth_before}, "
               f"RD = (Bi - Bm) / (Bi - D) = {result.reduction_degree:.2f}")
    fmt = _format(args)
    if fmt == "json":
        data = {"task": term_to_text(task), "propagate": result.propagate,
                "nodes_before": result.nodes_before, "nodes_after": result.nodes_after,
                "depth_before": result.depth_before, "depth_after": result.depth_after,
                "reduction_degree": round(result.reduction_degree, 4),
                "conditions": {"simplified": result.simplifier.calls,
                               "needed_sympy": result.simplifier.sympy_calls},
                "notes": result.notes, "tree": tree_json(result.tree)}
        _emit(json.dumps(data, indent=2) + "\n", args.output, kb.files)
    elif fmt == "dot":
        _emit(compare_dot(result.original, result.tree, term_to_text(task), result.propagate),
              args.output, kb.files)
    elif fmt in ("pl", "yaml"):
        doc = tree_document(result.tree, carried=carried_clauses(kb))
        header = (f"Compressed by schemalog (Algorithm 1, propagate {result.propagate}) from "
                  f"{', '.join(args.files)}, task {term_to_text(task)}.\n{figures}.\n"
                  f"`schemalog decompress` restores the original tree from the origins/2 facts.")
        _emit(to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc), args.output, kb.files)
    else:
        from rich.console import Console, Group
        from rich.table import Table

        before = f"Original: {result.nodes_before} behaviours, depth {result.depth_before}"
        after = (f"Compressed (propagate {result.propagate}): {result.nodes_after} behaviours, "
                 f"depth {result.depth_after}")
        to_file = bool(args.output and args.output != "-")
        if to_file or Console().width >= 140:  # side by side where there is room
            table = Table(show_header=True, header_style="bold", box=None, pad_edge=False)
            table.add_column(before)
            table.add_column(after)
            table.add_row(rich_tree(result.original), rich_tree(result.tree))
            view = Group(table, "", figures)
        else:
            view = Group(rich_tree(result.original, before), "", rich_tree(result.tree, after), "", figures)
        _print_rich(view, args.output, kb.files)
    return 0


def cmd_decompress(args: argparse.Namespace) -> int:
    """Restore the original tree of a compressed task from its provenance."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label
    if not tree.origins:
        print(f"note: {term_to_text(task)} carries no provenance (origins/2): it is shown as it is",
              file=sys.stderr)
    original = decompress(tree)
    _output_tree(args, original.label, original,
                 f"The original tree of {term_to_text(task)}, restored by schemalog decompress.", kb)
    return 0


def cmd_convert(args: argparse.Namespace) -> int:
    """Convert knowledge between SEED, schema text and YAML."""
    doc = read_document(args.input, args.max_bytes)
    for note in doc.notes:
        print(note, file=sys.stderr)
    if args.task:
        declaration = Clause(Struct("task", (_task_term(args.task),)), TRUE, None)
        doc = Document((declaration, *doc.items), doc.file, doc.notes, doc.seed)
    loaded = doc.to_kb()
    check_schemas(loaded)  # what is written must load again: check before writing
    target = args.to or ("yaml" if args.output and args.output.endswith(YAML_SUFFIXES) else "pl")
    if target == "yaml":
        text = to_yaml(doc)
    else:
        origin = "the SEED long-term memory" if doc.seed else ""
        header = f"Converted by schemalog from {origin + ' ' if origin else ''}{doc.file}."
        text = to_pl(doc, header=header)
    _emit(text, args.output, [args.input, *loaded.files])
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


def _budget(text: str) -> int:
    value = _positive(text)
    if value > MAX_SYMPY_BUDGET:
        raise argparse.ArgumentTypeError(f"at most {MAX_SYMPY_BUDGET} (sympy's cost doubles per variable; "
                                         f"16 ran for over 15 minutes on one condition)")
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

    output = argparse.ArgumentParser(add_help=False)
    output.add_argument("--format", choices=["text", "json", "dot", "yaml", "pl"],
                        help="output format (default: from -o's suffix, else text)")
    output.add_argument("--json", action="store_true", help="same as --format json")
    output.add_argument("-o", "--output", help="write here (atomically) instead of standard output")

    p = sub.add_parser("show", parents=[limits, output], help="instantiate a task and print its tree")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task to instantiate (default: the first task/1)")
    p.set_defaults(run=cmd_show)

    p = sub.add_parser("compress", parents=[limits, output],
                       help="merge sequential behaviours (Definition 1, Algorithm 1)")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task to compress (default: the first task/1)")
    p.add_argument("--propagate", choices=list(PROPAGATE_MODES), default="full",
                   help="what the children of a merged behaviour inherit: its pre AND not post "
                        "(full, default), its pre (pre: the paper's rule), or nothing (none)")
    p.add_argument("--sympy-budget", type=_budget, default=DEFAULT_SYMPY_BUDGET, metavar="N",
                   help=f"simplify with sympy up to N variables (default {DEFAULT_SYMPY_BUDGET}, "
                        f"at most {MAX_SYMPY_BUDGET}: its cost doubles per variable)")
    p.set_defaults(run=cmd_compress)

    p = sub.add_parser("decompress", parents=[limits, output],
                       help="restore the original tree of a compressed task file")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task (default: the first task/1)")
    p.set_defaults(run=cmd_decompress)

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
