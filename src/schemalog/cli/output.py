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


def emit_picture(name: str, panels, initial: frozenset | None, fmt: str, output: str, inputs: list[str],
                 what: str | None = "") -> None:
    """Render `panels` as pictures a screen can hold (render.picture_pages) and write them to
    `output` and, when it is split, OUTPUT-1, OUTPUT-2, ... beside it, together and atomically
    (never over an input); a FIFO or a device gets the whole drawing as one picture."""
    from ..formats.documents import output_target, write_together
    from ..formats.graphviz import render
    from ..formats.render import Page, choose_layout, picture_pages
    from .common import check_output

    check_output(output, inputs)
    path = Path(output)
    if output_target(output).in_place:
        pages = [Page(choose_layout(name, panels, initial)[0], "")]
    else:
        # the overview names the other pictures in its labels: readably (a control character or
        # a byte that is not UTF-8 in the file's name would break Graphviz's label)
        pages = picture_pages(name, panels, initial, lambda k: readable_name(f"{path.stem}-{k}{path.suffix}"))
    names = [output] + [str(path.with_name(f"{path.stem}-{k}{path.suffix}")) for k in range(1, len(pages))]
    for extra in names[1:]:
        check_output(extra, inputs)
    write_together([(file, render(page.dot, fmt)) for file, page in zip(names, pages)])
    if what is None:
        return
    if len(pages) == 1:
        print(f"wrote {readable_name(output)}" + (f": {what}" if what else ""), file=sys.stderr)
        return
    print(f"wrote {readable_name(output)} (overview) and {readable_name(names[1])}"
          + (f" ... {readable_name(names[-1])}" if len(names) > 2 else "")
          + f" (one per panel or sub-task), {len(pages)} pictures a screen can hold"
          + (f": {what}" if what else ""), file=sys.stderr)
    for file, page in zip(names[1:], pages[1:]):
        print(f"  {readable_name(file)}: {page.what}", file=sys.stderr)


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
    elif fmt == "dot":                          # the drawing as one graph
        emit(to_dot(tree, term_to_text(task), initial_atoms(kb, tree)), args.output, inputs, what)
    elif fmt in PICTURES:                       # the same drawing, split when a screen cannot hold it
        from ..formats.render import Panel

        emit_picture(term_to_text(task), [Panel("tree", "", tree)], initial_atoms(kb, tree), fmt, args.output,
                     inputs, what)
    elif fmt in ("pl", "yaml", "seed"):
        doc = tree_document(tree, carried=carried_clauses(kb) if kb is not None else [])
        emit(written(doc, fmt, header), args.output, inputs, what)
    else:
        print_rich(rich_tree(tree, title), args.output, inputs, what)


def initial_atoms(kb: KnowledgeBase | None, tree: Behaviour) -> frozenset:
    """The settled initial state of the files' initial/1 (the state a picture is coloured in)."""
    from ..run.world import World, initial_state

    return World(tree, initial_state(kb) if kb is not None else ()).atoms
