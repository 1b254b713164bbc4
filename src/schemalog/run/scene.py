"""Scenes: where the objects are, so the bottom-up regulation can be computed (Sec. II-B).

    Position = tuple[float, ...]            2-D or 3-D, metres
    Scene    = (objects: name -> Position, end_effector: Position, scale, min_lambda, neutral)

A scene file is YAML:

    end_effector: [0.0, 0.0, 0.40]     # where the hand starts
    scale: 1.0                         # the distance at which lambda reaches 1
    min_lambda: 0.05                   # lambda is clamped into [min_lambda, 1]
    neutral_lambda: 1.0                # lambda of a behaviour with no object
    knowledge: ../tasks/mix.pl         # optional: the task file this scene stages
    objects:
      spoon: [0.30, -0.20, 0.05]
      cup:   [0.45,  0.10, 0.05]

`lambda_at(obj, where) = clamp(distance(where, obj) / scale, min_lambda, 1)`: proportional to
the robot-object distance (Sec. II-B), so the nearer the object, the higher the emphasis.
"""

from __future__ import annotations

import json
import math
import random
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

from .. import defaults
from ..errors import SchemalogError, SourcePos, shown_name
from ..inputs import compose_yaml, read_limited
from ..logic.terms import Atom, Term, term_to_text

Position = tuple[float, ...]

DEFAULT_SCALE = 1.0
DEFAULT_MIN_LAMBDA = 0.05
DEFAULT_NEUTRAL_LAMBDA = 1.0
MAX_COORDINATE = 1000.0   # metres from the base, as in a demonstration (learn/demo.py): farther is a unit error
_KEYS = ("name", "end_effector", "scale", "min_lambda", "neutral_lambda", "objects", "knowledge")


def object_name(obj: Term) -> str:
    """The name a scene file uses for an object term: `spoon`, `'Cup 1'` as `Cup 1`."""
    return obj.name if isinstance(obj, Atom) else term_to_text(obj)


@dataclass(frozen=True)
class Scene:
    """Object positions and the parameters of the bottom-up regulation lambda."""

    objects: dict[str, Position] = field(default_factory=dict, hash=False)
    end_effector: Position = (0.0, 0.0, 0.0)
    scale: float = DEFAULT_SCALE
    min_lambda: float = DEFAULT_MIN_LAMBDA
    neutral_lambda: float = DEFAULT_NEUTRAL_LAMBDA
    name: str = "no scene"
    file: str | None = None
    knowledge: str | None = None          # the task file this scene stages (simulate-demo's default)
    marks: dict[str, SourcePos] = field(default_factory=dict, hash=False, compare=False)

    def lambda_at(self, obj: str | None, where: Position) -> float:
        """Bottom-up regulation of a behaviour on `obj` with the hand at `where`."""
        if obj is None or obj not in self.objects:
            return self.neutral_lambda
        d = math.dist(where, self.objects[obj]) / self.scale
        return min(1.0, max(self.min_lambda, d))

    def jittered(self, seed: int, jitter: float) -> "Scene":
        """Another object configuration: each coordinate moved by up to +-jitter metres."""
        rng = random.Random(seed)
        moved = {name: tuple(round(c + rng.uniform(-jitter, jitter), 6) for c in pos)
                 for name, pos in sorted(self.objects.items())}
        return replace(self, objects=moved, name=f"{self.name} (seed {seed}, jitter {jitter:g})")


NO_SCENE = Scene()          # compared with ==, not `is`: a run unpickled holds a copy of it


def scene_text(scene: Scene, comment: str = "") -> str:
    """The scene as a scene file that read_scene accepts again."""
    def xyz(p: Position) -> str:
        return "[" + ", ".join(f"{c:g}" for c in p) + "]"
    lines = [f"# {line}" for line in comment.splitlines()]
    lines += [f"name: {json.dumps(scene.name)}", f"end_effector: {xyz(scene.end_effector)}"]
    if scene.scale != DEFAULT_SCALE:
        lines.append(f"scale: {scene.scale:g}")
    lines.append("objects:" if scene.objects else "objects: {}")
    lines += [f"  {name if re.fullmatch(r'[a-z][A-Za-z0-9_]*', name) else json.dumps(name)}: {xyz(pos)}"
              for name, pos in scene.objects.items()]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------
# Reading scene files

def read_scene(path: str | Path, max_bytes: int | None = None) -> Scene:
    """Read and check a scene file; every error names file:line:column."""
    file = str(path)
    data = read_limited(path, defaults.MAX_BYTES if max_bytes is None else max_bytes, f"scene {shown_name(file)}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SchemalogError(f"scene {file} is not UTF-8 text (byte {err.start})") from None
    return scene_from_yaml(text, file)


def scene_from_yaml(text: str, file: str = "<scene>") -> Scene:
    """Read a scene from YAML text (composed, not constructed, so every value keeps its place)."""
    import yaml  # loaded only when YAML is read or written

    lines = text.split("\n")
    root, fail = compose_yaml(text, file)
    if not isinstance(root, yaml.MappingNode):
        raise SchemalogError("a scene is a mapping with `objects` and `end_effector`", SourcePos(file, 1, 1))

    def number(node, what: str, positive: bool = False) -> float:
        # A plain scalar that reads as a number: YAML 1.1 leaves `1e-1` a string, users don't.
        if not isinstance(node, yaml.ScalarNode):
            raise fail(f"{what} must be a number", node)
        numeric = node.tag in ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float") or (
            node.tag == "tag:yaml.org,2002:str" and node.style is None)
        text = node.value.replace("_", "").lower()
        text = {".nan": "nan", ".inf": "inf", "+.inf": "inf", "-.inf": "-inf"}.get(text, text)
        try:
            value = float(text) if numeric else None
        except ValueError:
            value = None
        if value is None:
            raise fail(f"{what} must be a number, not {node.value!r}", node)
        if not math.isfinite(value) or (positive and value <= 0):
            raise fail(f"{what} must be a finite{' positive' if positive else ''} number", node)
        return value

    def position(node, what: str) -> Position:
        if not isinstance(node, yaml.SequenceNode) or len(node.value) not in (2, 3):
            raise fail(f"{what} must be a position: a list of 2 or 3 numbers, like [0.3, -0.2, 0.05]", node)
        coordinates = []
        for c in node.value:
            value = number(c, f"a coordinate of {what}")
            if abs(value) > MAX_COORDINATE:
                raise fail(f"a coordinate of {what} is {value:.3g} m: positions are in metres from the robot's base, "
                           f"within {MAX_COORDINATE:g} m", c)
            coordinates.append(value)
        return tuple(coordinates)

    values: dict = {}
    marks: dict[str, SourcePos] = {}
    seen: set[str] = set()
    for key_node, value in root.value:
        key = key_node.value
        if key not in _KEYS:
            raise fail(f"unknown key {key!r} in a scene (known: {', '.join(_KEYS)})", key_node)
        if key in seen:
            raise fail(f"{key!r} appears twice", key_node)
        seen.add(key)
        if key == "name":
            if not isinstance(value, yaml.ScalarNode) or not str(value.value).strip():
                raise fail("`name` is a line of text", value)
            values["name"] = str(value.value)
        elif key == "end_effector":
            values["end_effector"] = position(value, "end_effector")
        elif key == "objects":
            if not isinstance(value, yaml.MappingNode):
                raise fail("`objects` maps each object name to its position", value)
            objects: dict[str, Position] = {}
            for name_node, pos_node in value.value:
                if not isinstance(name_node, yaml.ScalarNode) or not str(name_node.value).strip():
                    raise fail("an object's name is a word, like spoon", name_node)
                name = str(name_node.value)
                if name in objects:
                    raise fail(f"object {name!r} appears twice", name_node)
                objects[name] = position(pos_node, f"the position of {name}")
                marks[name] = SourcePos(file, name_node.start_mark.line + 1, name_node.start_mark.column + 1)
            values["objects"] = objects
        elif key == "knowledge":
            # A path relative to the scene file, like an include.
            if not isinstance(value, yaml.ScalarNode) or not str(value.value).strip():
                raise fail("`knowledge` is the path of a task file, relative to the scene", value)
            base = Path(file).parent if not file.startswith("<") else Path(".")
            values["knowledge"] = str(base / str(value.value))
        elif key == "min_lambda":
            values[key] = number(value, key, positive=True)
            if values[key] > 1:
                raise fail("min_lambda must be in (0, 1]", value)
        elif key == "neutral_lambda":
            values[key] = number(value, key, positive=True)
            if values[key] > 1:
                raise fail("neutral_lambda must be in (0, 1]", value)
        else:
            values[key] = number(value, key, positive=True)
    if "end_effector" not in values:
        raise SchemalogError("the scene has no `end_effector` (where the hand starts)", SourcePos(file, 1, 1))
    dims = len(values["end_effector"])
    for name, pos in values.get("objects", {}).items():
        if len(pos) != dims:
            mark = marks[name]
            raise SchemalogError(f"{name} has {len(pos)} coordinates but end_effector has {dims}: "
                                 f"positions mix 2-D and 3-D", mark,
                                 lines[mark.line - 1] if mark.line <= len(lines) else None)
    values.setdefault("name", Path(file).stem)
    return Scene(file=file, marks=marks, **values)


__all__ = ["Scene", "NO_SCENE", "Position", "read_scene", "scene_from_yaml", "scene_text", "object_name"]
