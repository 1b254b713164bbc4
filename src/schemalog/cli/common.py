"""What the commands share: the API called with the command line's options (the files, -o
checked against every file read, --task, --compressed), the notes it collects said on
stderr, and outputs written (api/outputs.py) with a `wrote FILE: ...` line.

The commands import this module when they run, not when the command line is built.
"""

from __future__ import annotations

import argparse
import gc
import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from ..api.outputs import check_output, write_atomically
from ..errors import readable_name

if TYPE_CHECKING:
    from ..api.knowledge import Knowledge
    from ..api.task import Task


def load_knowledge(args: argparse.Namespace) -> Knowledge:
    """The files of the command line as one program (schemalog.load), its warnings on stderr;
    -o is checked against them before they are read and against every file they consulted once
    they are."""
    from ..api.knowledge import _load

    output = getattr(args, "output", None)
    check_output(output, inputs_of(args))
    knowledge = _load(args.files, args.max_bytes, args.max_steps, uncollected)
    gc.freeze()             # the knowledge base lives as long as the command: never scanned again
    for warning in knowledge.warnings:
        print(warning, file=sys.stderr)
    check_output(output, inputs_of(args, knowledge.files))
    return knowledge


def task_of(knowledge: Knowledge, args: argparse.Namespace) -> Task:
    """--task's tree (default: the first task/1), what the instantiation noted on stderr."""
    task = knowledge.task(args.task, max_depth=args.max_depth, max_nodes=args.max_nodes)
    said(task.notes)
    return task


def task_as_read(knowledge: Knowledge, args: argparse.Namespace) -> Task:
    """--task's tree exactly as the files give it, provenance not followed (show, decompress),
    what the instantiation noted on stderr."""
    from ..api.knowledge import task_as_read

    task = task_as_read(knowledge, args.task, args.max_depth, args.max_nodes)
    said(task.notes)
    return task


def said(notes) -> None:
    """The notes and warnings an API call collected, on stderr."""
    for note in notes:
        print(note, file=sys.stderr)


def task_to_use(knowledge: Knowledge, args: argparse.Namespace) -> Task:
    """The file's own task (a compressed file's, or the original), or with --compressed the
    original compressed (--propagate, its notes on stderr): run, export."""
    task = task_of(knowledge, args)
    if args.compressed:
        task = task.original.compress(args.propagate, sympy_budget=args.sympy_budget)
        said(task.notes)
    return task


@contextmanager
def uncollected() -> Iterator[None]:
    """No garbage collection in the block, and everything alive frozen after it (gc.freeze).

    For work that runs no Prolog and makes no reference cycles: reading a file (millions of
    small immutable terms), reading its schemas, lint's passes over a tree. The collector would
    scan what they build in each young collection it survives and again in the older generation
    (0.7-0.9 s of `schemalog check` of 97,656 behaviours); frozen, it is never scanned again,
    and reference counting still frees it. Directives (to_kb) and instantiation, which may run
    Prolog, run with the collector on. What is frozen is never collected as a cycle: right for
    a command that ends after its work, as the command line's do (main ends with os._exit)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        if enabled:
            gc.enable()


# The options that name a file a command reads. (generate's --scene is written, not read:
# generate reads nothing and passes no inputs.)
INPUT_OPTIONS = ("files", "input", "demo", "structure", "scene")


def inputs_of(args: argparse.Namespace, *more: Iterable[str]) -> list[str]:
    """Every file the command reads, as far as known: its file arguments, --scene, learn's
    demonstration and --structure, and `more` (a knowledge base's `files`: the consulted ones)."""
    found: list[str] = []
    for key in INPUT_OPTIONS:
        value = getattr(args, key, None)
        for name in [value] if isinstance(value, str) else value or []:
            found.append(str(name))
    for names in more:
        found.extend(str(n) for n in names)
    return found


def emit(text: str, output: str | None, inputs: Iterable[str], what: str | None = "") -> None:
    """Print, or write atomically to `output`, which must not be any file read, and say on
    stderr what was written there (`what`; None: the command says it itself)."""
    if output is None or output == "-":
        sys.stdout.write(text)
        return
    check_output(output, inputs)
    write_atomically(output, text)
    if what is not None:
        print(f"wrote {readable_name(output)}" + (f": {what}" if what else ""), file=sys.stderr)


def workspace_of(args: argparse.Namespace, files: list[str]):
    """The files as a query workspace, focused as --task/--compressed/--state/--scene ask."""
    from ..api.repl import open_workspace

    return open_workspace(files, propagate=args.propagate, max_bytes=args.max_bytes, max_depth=args.max_depth,
                          max_nodes=args.max_nodes, max_steps=args.max_steps, sympy_budget=args.sympy_budget,
                          scene=args.scene, seed=args.seed, jitter=args.jitter, task=args.task,
                          compressed=args.compressed, state=args.state)
