"""How a command prints a tree: the format asked for (--json, --format, -o's suffix), and
rich text for the terminal or for a file."""

from __future__ import annotations

import argparse
import io
import json
from pathlib import Path

from ..formats.documents import to_pl, to_yaml
from ..formats.render import carried_clauses, rich_tree, show_json, to_dot, tree_document
from ..logic.kb import KnowledgeBase
from ..logic.terms import Term, term_to_text
from ..task.tree import Behaviour, count_nodes, depth
from .common import emit, inputs_of


SUFFIX_FORMATS = {".json": "json", ".dot": "dot", ".gv": "dot", ".pl": "pl", ".yaml": "yaml", ".yml": "yaml"}


# What `wrote FILE: ...` calls each format.
FORMAT_WORDS = {"json": "JSON", "dot": "Graphviz dot", "pl": "schema text", "yaml": "YAML", "text": "text"}


def output_format(args: argparse.Namespace) -> str:
    """--json, else --format, else the output file's suffix, else text."""
    if args.json:
        return "json"
    if args.format:
        return args.format
    if args.output and args.output != "-":
        return SUFFIX_FORMATS.get(Path(args.output).suffix.lower(), "text")
    return "text"


def rendered(renderable, width: int = 120) -> str:
    from rich.console import Console

    buffer = io.StringIO()
    Console(file=buffer, width=width, no_color=True).print(renderable)
    return buffer.getvalue()


def print_rich(renderable, output: str | None, inputs: list[str], what: str = "") -> None:
    if output and output != "-":
        emit(rendered(renderable), output, inputs, what)
    else:
        from rich.console import Console

        Console(highlight=False).print(renderable)


def output_tree(args: argparse.Namespace, task: Term, tree: Behaviour, header: str,
                 kb: KnowledgeBase | None = None) -> None:
    """Print or write one tree in the requested format (show, decompress)."""
    fmt = output_format(args)
    inputs = inputs_of(args, kb.files if kb is not None else ())
    title = f"{term_to_text(task)}: {count_nodes(tree)} behaviours, depth {depth(tree)}"
    what = f"{title} ({FORMAT_WORDS[fmt]})"
    if fmt == "json":
        emit(json.dumps(show_json(task, tree), indent=2) + "\n", args.output, inputs, what)
    elif fmt == "dot":
        emit(to_dot(tree, term_to_text(task)), args.output, inputs, what)
    elif fmt in ("pl", "yaml"):
        doc = tree_document(tree, carried=carried_clauses(kb) if kb is not None else [])
        emit(to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc), args.output, inputs, what)
    else:
        print_rich(rich_tree(tree, title), args.output, inputs, what)
