"""What the commands share: loading knowledge files, choosing a task, reading terms and
scenes from options, and writing outputs that never replace a file that was read.

The commands import this module when they run, not when the command line is built.
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from .. import defaults
from ..errors import CannotWrite, SchemalogError, UsageError, readable_name
from ..formats.documents import Document, output_target, read_document, write_atomically
from ..logic.kb import KnowledgeBase
from ..logic.parse import parse_term
from ..logic.terms import Struct, Term, Var, term_to_text
from ..logic.unify import Bindings
from ..run.scene import NO_SCENE, Scene, object_name, read_scene
from ..run.world import state_atoms
from ..task.schema import check_schemas, knowledge_base
from ..task.tree import Behaviour, Instantiator, declared_tasks, walk

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


def load_files(args: argparse.Namespace) -> tuple[KnowledgeBase, list[Document]]:
    """The files of the command line in one knowledge base; -o is checked against them before
    they are read and against every file they consulted once they are."""
    output = getattr(args, "output", None)
    check_output(output, inputs_of(args))
    kb = knowledge_base()
    kb.max_bytes = args.max_bytes
    kb.max_steps = args.max_steps    # each directive's budget
    docs = []
    for path in args.files:
        with uncollected():
            doc = read_document(path, args.max_bytes)
        doc.to_kb(kb)       # directives run here, with the collector on
        docs.append(doc)
    gc.freeze()             # the knowledge base lives as long as the command: never scanned again
    for warning in kb.warnings:
        print(warning, file=sys.stderr)
    check_output(output, inputs_of(args, kb.files))
    return kb, docs


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


def task_term(text: str) -> Term:
    try:
        return parse_term(text, "--task")
    except SchemalogError as err:
        raise UsageError(f"--task {text!r} is not a term: {err.message}") from None


def root_candidates(kb: KnowledgeBase) -> list[str]:
    """Schemas never used as a sub-task: likely tasks, for a helpful message."""
    schemas = check_schemas(kb)
    used = {term_to_text(e.behaviour) for s in schemas for e in s.entries}
    return [term_to_text(s.task) for s in schemas if s.entries and term_to_text(s.task) not in used]


def choose_tasks(kb: KnowledgeBase, task: str | None, every: bool = False) -> list[Term]:
    if task is not None:
        term = task_term(task)
        if not defines(kb, term):
            known = [term_to_text(t) for t in declared_tasks(kb)] or root_candidates(kb)
            hint = f"; tasks here: {', '.join(known[:8])}" if known else ""
            raise SchemalogError(f"unknown task {term_to_text(term)}: no schema({term_to_text(term)}, "
                                 f"Subtasks, Post) in {', '.join(kb.files)}{hint}")
        return [term]
    declared = declared_tasks(kb)
    if declared:
        return declared if every else declared[:1]
    if every:
        return []
    roots = root_candidates(kb)
    hint = f" (candidates: {', '.join(roots[:8])})" if roots else ""
    raise UsageError(f"no task declared with task/1: name one with --task{hint}")


def defines(kb: KnowledgeBase, task: Term) -> bool:
    """Whether some schema/3 head unifies with `task`."""
    goal = Struct("schema", (task, Var("_"), Var("_")))
    return any(Bindings().unify(c.head, goal) for c in kb.candidates("schema", 3, task) or [])


def instantiate_task(kb: KnowledgeBase, task: Term, args: argparse.Namespace,
                     read: dict | None = None) -> Behaviour:
    """The task's tree (`read`: schemas already read, by id of their clause); the sub-tasks
    SEED knowledge leaves out are said on stderr."""
    instantiator = Instantiator(kb, max_depth=args.max_depth, max_nodes=args.max_nodes, read=read)
    tree = instantiator.instantiate(task)
    for warning in instantiator.warnings:
        print(warning, file=sys.stderr)
    return tree


def trees_to_use(kb: KnowledgeBase, args: argparse.Namespace) -> tuple[Behaviour, Behaviour, str]:
    """The task's original tree, the tree to use and what kind it is (run, export): the file's
    own (a compressed file's, or the original), or with --compressed the original compressed
    (--propagate, its notes on stderr)."""
    from ..task.compress import compress, original_of, protected_labels
    from ..task.conditions import Simplifier

    tree = instantiate_task(kb, choose_tasks(kb, args.task)[0], args)
    original = original_of(tree)
    kind = "compressed" if original is not tree else "original"
    if args.compressed:
        result = compress(original, args.propagate, protected_labels(kb, original),
                          Simplifier(sympy_budget=args.sympy_budget))
        for note in result.notes:
            print(f"note: {note}", file=sys.stderr)
        tree, kind = result.tree, f"compressed (propagate {args.propagate})"
    return original, tree, kind


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


def check_output(output: str | None, inputs: Iterable[str], option: str = "-o") -> None:
    """Refuse, before any work is written, an output that is one of the `inputs` (inputs_of)
    or that names no file (output_target: a directory, `name/`, no such directory), exit 2,
    or that the system would refuse (a name too long, a directory not writable), exit 1.
    Standard output (None, `-`) is always fine."""
    if output is None or output == "-":
        return
    refuse_overwriting(output, inputs, option)
    try:
        output_target(output)
    except CannotWrite:
        raise
    except SchemalogError as err:
        raise UsageError(err.message) from None


def refuse_overwriting(output: str, inputs: Iterable[str], option: str = "-o") -> None:
    """Refuse an output file that is one of the files read (through links and hard links too)."""
    out = Path(output).resolve()
    for name in inputs:
        if name.startswith("<"):
            continue
        if Path(name).resolve() == out or _same_file(name, output):
            raise UsageError(f"{option} {output} would overwrite an input file; choose another name")


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def term_option(text: str, option: str) -> Term:
    try:
        return parse_term(text, option)
    except SchemalogError as err:
        raise UsageError(f"{option} {text!r} is not a term: {err.message}") from None


def atoms_option(text: str, option: str) -> list[Term]:
    """A state given on the command line, 'hand.free, a1.done': its atoms, or a usage error."""
    try:
        return state_atoms(term_option(text, option), option)
    except UsageError:
        raise
    except SchemalogError as err:
        raise UsageError(err.message) from None


def scene_of(args: argparse.Namespace, original: Behaviour) -> Scene:
    """The scene of --scene, jittered by --seed/--jitter, checked against the task's objects."""
    if args.scene is None:
        if args.seed is not None or args.jitter is not None:
            raise UsageError("--seed and --jitter move the objects of a scene: give --scene too")
        return NO_SCENE
    scene = read_scene(args.scene, args.max_bytes)
    for node in walk(original):
        for obj in node.objects[:1]:    # lambda reads the distance to a behaviour's first object
            if object_name(obj) not in scene.objects:
                known = ", ".join(sorted(scene.objects)) or "none"
                raise SchemalogError(f"the scene {args.scene} has no position for {object_name(obj)}, which "
                                     f"{node.name} acts on (objects in the scene: {known})", node.source)
    if args.seed is not None or args.jitter is not None:
        scene = scene.jittered(args.seed if args.seed is not None else 0,
                               args.jitter if args.jitter is not None else defaults.JITTER)
    return scene


def workspace_of(args: argparse.Namespace, files: list[str]):
    """The files as a query workspace (api/workspace.py), focused as --task/--compressed/--state ask."""
    from ..api.workspace import COMPRESSED, Options, Workspace

    options = Options(propagate=args.propagate, max_bytes=args.max_bytes, max_depth=args.max_depth,
                      max_nodes=args.max_nodes, max_steps=args.max_steps, sympy_budget=args.sympy_budget,
                      scene=NO_SCENE)
    workspace = Workspace(files, options)
    if args.scene is not None:
        if workspace.focus is None:
            raise UsageError("--scene positions the objects of a task, and these files have none")
        options = Options(**{**vars(options), "scene": scene_of(args, workspace.focus.original)})
        workspace.options = options
    if args.task is not None:
        workspace.set_focus(*workspace.find_tree(task_term(args.task)))
    if args.compressed:
        if workspace.focus is None:
            raise UsageError("--compressed needs a task: these files have none")
        workspace.set_focus(workspace.focus, COMPRESSED)
    if args.state is not None:
        workspace.set_state(atoms_option(args.state, "--state"))
    return workspace
