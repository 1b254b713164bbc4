"""What a user hands the API besides knowledge: a state as text, a scene file, an output path.

    state  = 'hand.free, spoon.taken' | ['hand.free', 'spoon.taken']   (positive atoms)
    scene  = a YAML file of object positions (docs/semantics.md), jittered by seed/jitter
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Iterable

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.terms import Term

if TYPE_CHECKING:
    from ..run.scene import Scene
    from .task import Task


def state_atoms(state: str | Iterable[str], option: str = "state") -> list[Term]:
    """A state as text, 'hand.free, a1.done' (or an iterable of atoms' texts): its atoms."""
    from ..logic.opread import parse_term
    from ..run.world import state_atoms as atoms_of

    text = state if isinstance(state, str) else ", ".join(state) or "true"
    try:
        return atoms_of(parse_term(text, option), option)
    except UsageError:
        raise
    except SchemalogError as err:
        raise UsageError(f"{option} {text!r}: {err.message}") from None


def refuse_overwriting(output: str, inputs: Iterable[str], option: str = "-o") -> None:
    """Refuse an output file that is one of the files read (through links and hard links too)."""
    from pathlib import Path as FilePath

    out = FilePath(output).resolve()
    for name in inputs:
        if name.startswith("<"):
            continue
        if FilePath(name).resolve() == out or _same_file(name, output):
            raise UsageError(f"{option} {output} would overwrite an input file; choose another name")


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def read_scene_for(task: Task, scene: str | os.PathLike | None, seed: int | None, jitter: float | None,
                   max_bytes: int = defaults.MAX_BYTES) -> Scene:
    """The scene file, jittered by seed/jitter, checked against the task's objects."""
    from ..run.scene import NO_SCENE

    if scene is None:
        if seed is not None or jitter is not None:
            raise UsageError("--seed and --jitter move the objects of a scene: give --scene too")
        return NO_SCENE
    return scene_for_tree(task.original.tree, scene, seed, jitter, max_bytes)


def scene_for_tree(tree, scene: str | os.PathLike, seed: int | None, jitter: float | None,
                   max_bytes: int = defaults.MAX_BYTES) -> Scene:
    """The scene file, checked against the objects of an original tree, jittered by seed/jitter."""
    from ..run.scene import object_name, read_scene
    from ..task.tree import walk

    name = os.fspath(scene)
    found = read_scene(name, max_bytes)
    for node in walk(tree):
        for obj in node.objects[:1]:    # lambda reads the distance to a behaviour's first object
            if object_name(obj) not in found.objects:
                known = ", ".join(sorted(found.objects)) or "none"
                raise SchemalogError(f"the scene {name} has no position for {object_name(obj)}, which "
                                     f"{node.name} acts on (objects in the scene: {known})", node.source)
    if seed is not None or jitter is not None:
        found = found.jittered(seed if seed is not None else 0, jitter if jitter is not None else defaults.JITTER)
    return found


def term_option(text: str, option: str) -> Term:
    """A term given as an option's text, or a usage error naming the option."""
    from ..logic.opread import parse_term

    try:
        return parse_term(text, option)
    except SchemalogError as err:
        raise UsageError(f"{option} {text!r} is not a term: {err.message}") from None


def atoms_option(text: str, option: str) -> list[Term]:
    """A state given as an option's text, 'hand.free, a1.done' (query and repl's --state):
    its atoms, or a usage error (`is not a term` when it does not parse)."""
    from ..run.world import state_atoms as atoms_of

    try:
        return atoms_of(term_option(text, option), option)
    except UsageError:
        raise
    except SchemalogError as err:
        raise UsageError(err.message) from None
