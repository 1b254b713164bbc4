"""What a user hands the API: each public call's arguments checked against its annotations
(checked), and the values besides knowledge: a state as text, a scene file, an output path.

    state  = 'hand.free, spoon.taken' | ['hand.free', 'spoon.taken']   (positive atoms)
    scene  = a YAML file of object positions (docs/semantics.md), jittered by seed/jitter

Every function and method `import schemalog` exports is @checked: a value of a type its
annotation does not name, or a value that type cannot hold (a NUL in a file name, 0 states),
is a UsageError saying what to pass, raised before the call does anything, never Python's
TypeError, AttributeError or ValueError from somewhere inside. The kinds of value are declared
once, in KINDS, by the names the annotations use (Path, Count, Task, ...), so one kind reads
the same in every call.
"""

from __future__ import annotations

import functools
import inspect
import numbers
import os
import reprlib
import sys
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.terms import Term

if TYPE_CHECKING:
    from ..run.scene import Scene
    from .task import Task

# What the annotations of public calls name, for type checkers; KINDS says what each takes.
Path = str | os.PathLike[str]             # a file name
Paths = Path | Iterable[Path]             # a file name, or several: given as a tuple
Name = str                                # a name that may be shown as a file's: no NUL
Count = int                               # a limit on how many: 1 or more
Times = int                               # how often: 0 or more
Size = int | str                          # bytes, or '2G'; a memory ceiling
Seconds = float                           # a time limit


class _Refused(Exception):
    """A value a kind does not take; `why` says what is wrong with it when its type is right."""

    def __init__(self, why: str | None = None) -> None:
        super().__init__(why)
        self.why = why


@dataclass(frozen=True)
class Kind:
    """What a parameter takes: how a message names it, and `take`, which returns the value to
    pass on (an int for a numpy integer, a tuple for an iterator) or raises _Refused."""

    says: str
    take: Callable[[Any], Any]


def _typed(*types: type) -> Callable[[Any], Any]:
    def take(value):
        if isinstance(value, types):
            return value
        raise _Refused
    return take


def _int(value) -> int:
    # a bool is an int to Python, never to a limit (max_states=True); numpy's integers are ints
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return int(value)
    raise _Refused


def _at_least(least: int) -> Callable[[Any], int]:
    def take(value) -> int:
        number = _int(value)
        if number < least:
            raise _Refused(f"is {number}; pass an int of {least} or more")
        return number
    return take


def _size(value):
    return value if isinstance(value, str) else _int(value)


def _number(value):
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return value if type(value) in (int, float) else float(value)
    raise _Refused


def _no_nul(name: str) -> None:
    if "\0" in name:
        raise _Refused(f"{_shown(name)} holds a NUL character, which no file name can")


def _name(value) -> str:
    if not isinstance(value, str):
        raise _Refused
    _no_nul(value)
    return value


def _path(value):
    if isinstance(value, os.PathLike):
        name = os.fspath(value)
        if not isinstance(name, str):
            raise _Refused(f"is a path of bytes ({_shown(name)}); pass it as a str (os.fsdecode(path))")
    elif isinstance(value, str):
        name = value
    else:
        raise _Refused
    _no_nul(name)
    return value


def _strings(value) -> tuple:
    # read once, into a tuple: a generator checked here is still whole for the call
    if isinstance(value, (str, bytes)):
        raise _Refused
    try:
        items = tuple(value)
    except TypeError:
        raise _Refused from None
    for item in items:
        if not isinstance(item, str):
            raise _Refused(f"holds {_a(item)}{_value_shown(item)}; each of its items must be a str")
    return items


def _paths(value) -> tuple:
    # one name stands for itself; a list is read once, into a tuple, each item a file name
    if isinstance(value, (str, os.PathLike)):
        return (_path(value),)
    if isinstance(value, (bytes, bytearray)):
        raise _Refused
    try:
        items = tuple(value)
    except TypeError:
        raise _Refused from None
    for item in items:
        try:
            _path(item)
        except _Refused as refused:
            raise _Refused(refused.why or f"holds {_a(item)}{_value_shown(item)}; each of its items must be a "
                                          f"file name (a str or a pathlib.Path)") from None
    return items


def _callable(value):
    if callable(value):
        return value
    raise _Refused


def _api_class(module: str, name: str) -> Callable[[Any], Any]:
    """isinstance against a class of the API, without importing its module (which imports this
    one): while that module is not loaded, no instance of the class can exist."""
    def take(value):
        loaded = sys.modules.get(module)
        if loaded is not None and isinstance(value, getattr(loaded, name)):
            return value
        raise _Refused
    return take


KINDS: dict[str, Kind] = {
    "None": Kind("None", _typed(type(None))),
    "bool": Kind("True or False", _typed(bool)),
    "int": Kind("an int", _int),
    "Count": Kind("an int of 1 or more", _at_least(1)),
    "Times": Kind("an int of 0 or more", _at_least(0)),
    "float": Kind("a number", _number),
    "Seconds": Kind("a number of seconds", _number),
    "str": Kind("a str", _typed(str)),
    "Size": Kind("a size (bytes as an int, or a str such as '2G')", _size),
    "Name": Kind("a str", _name),
    "Path": Kind("a file name (a str or a pathlib.Path)", _path),
    "Iterable[str]": Kind("a list of str", _strings),
    "Paths": Kind("a file name or a list of them", _paths),
    "Callable": Kind("a function", _callable),
    "dict": Kind("a dict", _typed(dict)),
    "Task": Kind("a Task", _api_class("schemalog.api.task", "Task")),
    "TreeDocument": Kind("a TreeDocument (schemalog.read_tree)", _api_class("schemalog.api.trees", "TreeDocument")),
}


def _hint(value, key: str) -> str:
    """What to do instead, for a value of the kind `key` names or one it is made from."""
    if key == "Task":
        if isinstance(value, (str, os.PathLike)):      # `schemalog verify` takes file names
            name = os.fspath(value)
            shown = repr(name) if len(name) <= 160 else "path"     # whole: a call to copy
            return f" (load the file first: schemalog.load({shown}).task())"
        if type(value).__name__ == "Knowledge":
            return " (a Knowledge's task is knowledge.task())"
        return " (schemalog.load(path).task() makes one)"
    if key in ("str", "Name") and isinstance(value, (bytes, bytearray)):
        return " (decode it first: data.decode())"
    return ""


def _kinds_of(annotation: str, where: str) -> tuple[tuple[str, Kind], ...]:
    """The kinds an annotation names, `X | Y | None` (Callable[[...], ...] read as Callable)."""
    parts, depth, start = [], 0, 0
    for i, char in enumerate(annotation):
        depth += {"[": 1, "]": -1}.get(char, 0)
        if char == "|" and depth == 0:
            parts.append(annotation[start:i])
            start = i + 1
    parts.append(annotation[start:])
    found = []
    for part in (p.strip() for p in parts):
        key = part if part in KINDS else part.split("[")[0]
        if key not in KINDS:
            raise TypeError(f"{where}: no argument kind for the annotation {part!r} (arguments.KINDS)")
        found.append((key, KINDS[key]))
    return tuple(found)


def checked(function):
    """Check a public call's arguments against its annotations: what it cannot take is a
    UsageError naming the argument and what to pass (KINDS). Arguments left to their defaults
    are not checked; `**options` are checked by the call they are passed on to."""
    signature = inspect.signature(function)
    where = f"{function.__qualname__}()"
    kinds = {}
    for name, parameter in signature.parameters.items():
        if name in ("self", "cls") or parameter.kind is parameter.VAR_KEYWORD:
            continue
        if parameter.annotation is parameter.empty:
            raise TypeError(f"{where}: the public parameter {name} has no annotation to check it by")
        kinds[name] = _kinds_of(parameter.annotation, where)
    several = {name for name, p in signature.parameters.items() if p.kind is p.VAR_POSITIONAL}

    @functools.wraps(function)
    def call(*args, **kwargs):
        try:
            bound = signature.bind(*args, **kwargs)
        except TypeError as err:
            takes = ", ".join(n for n in signature.parameters if n not in ("self", "cls"))
            raise UsageError(f"{where}: {err} (it takes {takes})") from None
        for name, value in bound.arguments.items():
            if name in several:
                bound.arguments[name] = tuple(_taken(kinds[name], item, f"{name}[{i}]", where)
                                              for i, item in enumerate(value))
            elif name in kinds:
                bound.arguments[name] = _taken(kinds[name], value, name, where)
        return function(*bound.args, **bound.kwargs)
    return call


def _taken(kinds: tuple[tuple[str, Kind], ...], value, name: str, where: str):
    """The value as the first of `kinds` that takes it gives it, else a UsageError."""
    why = None
    for _, kind in kinds:
        try:
            return kind.take(value)
        except _Refused as refused:
            why = why or refused.why
    if why is not None:      # its type is one the call takes, its value is not
        raise UsageError(f"{where}: {name} {why}")
    says = [kind.says for _, kind in kinds]
    wanted = says[0] if len(says) == 1 else f"{', '.join(says[:-1])} or {says[-1]}"
    hint = next(filter(None, (_hint(value, key) for key, _ in kinds)), "")
    raise UsageError(f"{where}: {name} is {_a(value)}{_value_shown(value)}; pass {wanted}{hint}")


def _a(value) -> str:
    """`an int`, `a Knowledge`: the value's type, as a message names it."""
    name = type(value).__name__
    if name in ("bytes", "bytearray"):
        return name
    return f"{'an' if name[0].lower() in 'aeiou' else 'a'} {name}"


_SHORT = reprlib.Repr()
_SHORT.maxstring = _SHORT.maxother = 40


def _shown(value) -> str:
    return _SHORT.repr(value)


def _value_shown(value) -> str:
    """The value itself, short, when it is a plain one whose text says more than its type."""
    if type(value) in (str, bytes, int, float, bool, bytearray):
        return f" ({_shown(value)})"
    return ""


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
