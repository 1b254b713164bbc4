"""How a command prints a tree: the format asked for (--json, --format, -o's suffix), rich
text for the terminal or for a file, and pictures (-o fig.png, .svg, .pdf) through Graphviz.

-o's suffix picks the format when neither --json nor --format does: .png, .svg and .pdf
render a picture with Graphviz's `dot` (refused, naming the program, when it is missing);
other picture suffixes (.jpg, .gif, ...) are refused; any other suffix gets text."""

from __future__ import annotations

import argparse
import io
import json
import sys
from pathlib import Path

from ..errors import readable_name
from ..formats.documents import to_pl, to_yaml, write_atomically
from ..formats.render import carried_clauses, rich_tree, show_json, to_dot, tree_document
from ..logic.kb import KnowledgeBase
from ..logic.terms import Term, term_to_text
from ..task.tree import Behaviour, count_nodes, depth
from .common import emit, inputs_of


SUFFIX_FORMATS = {".json": "json", ".dot": "dot", ".gv": "dot", ".pl": "pl", ".yaml": "yaml", ".yml": "yaml",
                  ".prolog": "seed"}


# What `wrote FILE: ...` calls each format.
FORMAT_WORDS = {"json": "JSON", "dot": "Graphviz dot", "pl": "schema text", "yaml": "YAML", "text": "text",
                "seed": "SEED long-term memory", "png": "PNG picture", "svg": "SVG picture", "pdf": "PDF picture"}


def output_format(args: argparse.Namespace) -> str:
    """--json, else --format, else the output file's suffix (png, svg, pdf: a picture, `dot`
    checked for now, before any work), else text."""
    from ..formats.graphviz import dot_program, image_format, refuse_unknown_picture

    if args.json:
        return "json"
    if args.format:
        return args.format
    if args.output and args.output != "-":
        picture = image_format(args.output)
        if picture is not None:
            dot_program()
            return picture
        refuse_unknown_picture(args.output)
        return SUFFIX_FORMATS.get(Path(args.output).suffix.lower(), "text")
    return "text"


def written(doc, fmt: str, header: str) -> str:
    """A tree's knowledge as text: schema text (pl), YAML, or SEED long-term memory."""
    if fmt == "seed":
        from ..formats.seed import seed_text
        return seed_text(list(doc.items), header=header)
    return to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc)


PICTURES = ("png", "svg", "pdf")


def emit_picture(dot: str, fmt: str, output: str, inputs: list[str], what: str | None = "") -> None:
    """Render `dot` as a picture and write it to `output` atomically (never over an input)."""
    from ..formats.graphviz import render
    from .common import check_output

    check_output(output, inputs)
    data = render(dot, fmt)
    write_atomically(output, data)
    if what is not None:
        print(f"wrote {readable_name(output)}" + (f": {what}" if what else ""), file=sys.stderr)


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
    elif fmt in PICTURES or fmt == "dot":      # the picture and its DOT text are one drawing
        dot = to_dot(tree, term_to_text(task), initial_atoms(kb, tree))
        if fmt == "dot":
            emit(dot, args.output, inputs, what)
        else:
            emit_picture(dot, fmt, args.output, inputs, what)
    elif fmt in ("pl", "yaml", "seed"):
        doc = tree_document(tree, carried=carried_clauses(kb) if kb is not None else [])
        emit(written(doc, fmt, header), args.output, inputs, what)
    else:
        print_rich(rich_tree(tree, title), args.output, inputs, what)


def initial_atoms(kb: KnowledgeBase | None, tree: Behaviour) -> frozenset:
    """The settled initial state of the files' initial/1 (the state a picture is coloured in)."""
    from ..run.world import World, initial_state

    return World(tree, initial_state(kb) if kb is not None else ()).atoms
