"""How a command prints a tree: the format asked for (--json, --format, -o's suffix), rich
text for the terminal or for a file, and pictures (-o fig.png, .svg, .pdf) through Graphviz.

-o's suffix picks the format when neither --json nor --format does: .png, .svg and .pdf
render a picture with Graphviz's `dot` (refused, naming the program, when it is missing);
other picture suffixes (.jpg, .gif, ...) are refused; any other suffix gets text.

Presentation only: what is shown comes from the API (a Task's text, its tree, its initial
state); this module lays it out (formats.render) and draws it (formats.graphviz)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import readable_name
from .common import emit, inputs_of

if TYPE_CHECKING:
    from ..api.task import Task


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


PICTURES = ("png", "svg", "pdf")


def emit_picture(name: str, panels, initial: frozenset | None, fmt: str, output: str, inputs: list[str],
                 what: str | None = "") -> None:
    """Render `panels` as pictures a screen can hold (render.picture_pages) and write them to
    `output` and, when it is split, OUTPUT-1, OUTPUT-2, ... beside it, together and atomically
    (never over an input); a FIFO or a device gets the whole drawing as one picture."""
    from ..api.outputs import check_output, write_together, writes_in_place
    from ..formats.graphviz import render
    from ..formats.render import Page, choose_layout, picture_pages

    check_output(output, inputs)
    path = Path(output)
    if writes_in_place(output):
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


def print_rich(renderable, output: str | None, inputs: list[str], what: str = "") -> None:
    if output and output != "-":
        from ..api.task import rendered

        emit(rendered(renderable), output, inputs, what)
    else:
        from rich.console import Console

        Console(highlight=False).print(renderable)


def output_tree(args: argparse.Namespace, task: Task, header: str) -> None:
    """Print or write one task's tree in the requested format (show, decompress); `header`
    starts what is written as knowledge."""
    fmt = output_format(args)
    inputs = inputs_of(args, task.knowledge.files)
    title = f"{task.name}: {len(task)} behaviours, depth {task.depth}"
    what = f"{title} ({FORMAT_WORDS[fmt]})"
    if fmt in ("json", "dot"):                   # dot: the drawing as one graph
        emit(task.text(fmt), args.output, inputs, what)
    elif fmt in PICTURES:                       # the same drawing, split when a screen cannot hold it
        from ..formats.render import Panel

        emit_picture(task.name, [Panel("tree", "", task.tree)], task.initial_atoms(), fmt, args.output,
                     inputs, what)
    elif fmt in ("pl", "yaml", "seed"):
        emit(task.text(fmt, header=header), args.output, inputs, what)
    else:
        from ..formats.render import rich_tree

        print_rich(rich_tree(task.tree, title, state=task.initial_atoms()), args.output, inputs, what)
