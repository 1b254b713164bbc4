"""Kinesthetic demonstrations: what the robot recorded while a teacher moved it (Sec. II-C).

    Demonstration = (times, positions, orientations, gripper, objects, rows)
      times         (n,)    seconds, strictly increasing
      positions     (n, 3)  end-effector position, metres, in the robot's base frame
      orientations  (n, 4)  end-effector quaternion (qx, qy, qz, qw), or None when not recorded
      gripper       tuple[GripperEvent]: the teacher's open/close commands, at a sample each
      objects       {name: (n, 3)} where each object is at each sample
      rows          (n,)    where each sample was written: a CSV line, a JSON sample number

Two file formats carry the same data (docs/learning.md). CSV, one sample per line:

    t,x,y,z,qx,qy,qz,qw,gripper,water_x,water_y,water_z,cup_x,cup_y,cup_z
    0.00,0.400,0.000,0.450,0,0,0,1,,0.55,-0.30,0.10,0.60,0.10,0.05
    1.52,0.551,-0.298,0.121,0,0,0,1,close,0.55,-0.30,0.10,0.60,0.10,0.05

and JSON, with gripper events at their own times:

    {"time": [...], "position": [[x, y, z], ...], "orientation": [[qx, qy, qz, qw], ...],
     "gripper": [{"time": 1.52, "command": "close"}],
     "objects": {"water": [x, y, z], "cup": [[x, y, z], ...]}}

Reading checks everything a later step relies on and names the row of the first problem;
writing is atomic.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import defaults
from ..formats.documents import write_atomically
from ..errors import SchemalogError, SourcePos, shown_number
from ..inputs import read_limited
from ..logic.terms import int_of_digits, int_text

COMMANDS = ("open", "close")
POSITION = ("x", "y", "z")
ORIENTATION = ("qx", "qy", "qz", "qw")
MAX_BYTES = defaults.MAX_DEMO_BYTES
MAX_COORDINATE = 1000.0   # metres: farther from the base is a unit or recording error, not a pose
MAX_SPEED = 10.0          # metres per second: faster is a tracking glitch
BASELINE = 0.01           # seconds: speeds are measured over at least this long (see plausible)
_OBJECT_COLUMN = re.compile(r"^([a-z][A-Za-z0-9_]*)_([xyz])$")
_UNIT = 0.1          # a quaternion whose norm is off by more than this is a recording error


@dataclass(frozen=True)
class GripperEvent:
    """The teacher commanded the gripper at sample `index` (written at `row`)."""

    index: int
    command: str
    row: int


@dataclass(frozen=True, eq=False)
class Demonstration:
    """One recorded demonstration, checked: finite, time increasing, at least two samples."""

    times: np.ndarray
    positions: np.ndarray
    orientations: np.ndarray | None
    gripper: tuple[GripperEvent, ...]
    objects: dict[str, np.ndarray]
    rows: np.ndarray
    file: str = "<demonstration>"
    row_name: str = "line"          # CSV rows are lines of the file; JSON rows are sample numbers

    def __len__(self) -> int:
        return len(self.times)

    def where(self, index: int) -> str:
        """How a message names sample `index`: `line 57` or `sample 57`."""
        return f"{self.row_name} {int(self.rows[index])}"

    def pos(self, index: int) -> SourcePos | None:
        """The file position of sample `index` (CSV only: JSON samples have no line of their own)."""
        return SourcePos(self.file, int(self.rows[index]), 1) if self.row_name == "line" else None

    def error(self, message: str, index: int | None = None) -> SchemalogError:
        """A message about sample `index`: at its line (CSV), or naming the file (JSON)."""
        pos = self.pos(index) if index is not None else None
        return SchemalogError(message if pos else f"{self.file}: {message}", pos)

    @property
    def poses(self) -> np.ndarray:
        """Position and orientation side by side: (n, 7), or (n, 3) without orientation."""
        if self.orientations is None:
            return self.positions
        return np.hstack([self.positions, self.orientations])


# ---------------------------------------------------------------------------
# Reading

def read_demonstration(path: str | Path, max_bytes: int = MAX_BYTES) -> Demonstration:
    """Read a CSV or JSON demonstration (by suffix; JSON if the text starts with `{`)."""
    file = str(path)
    data = read_limited(path, max_bytes)
    try:
        text = data.decode("utf-8-sig")     # spreadsheets write a byte-order mark
    except UnicodeDecodeError as err:
        raise SchemalogError(f"{file} is not UTF-8 text (byte {err.start})") from None
    if file.lower().endswith(".json") or text.lstrip().startswith("{"):
        return demonstration_from_json(text, file)
    return demonstration_from_csv(text, file)


def demonstration_from_csv(text: str, file: str = "<csv>") -> Demonstration:
    """Read CSV text: a header line, then one sample per line; `#` lines are comments."""
    lines = text.split("\n")

    def fail(message: str, line: int, column: int = 1) -> SchemalogError:
        return SchemalogError(message, SourcePos(file, line, column),
                              lines[line - 1] if 0 < line <= len(lines) else None)

    header: list[str] | None = None
    header_line = 0
    records: list[tuple[int, list[str], list[int]]] = []
    for number, line in enumerate(lines, start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields, columns = _split(line)
        if header is None:
            header, header_line = [f.strip() for f in fields], number
            continue
        records.append((number, fields, columns))
    if header is None:
        raise SchemalogError(f"{file} is empty: a demonstration starts with a header line "
                             f"(t,x,y,z,...)", SourcePos(file, 1, 1))
    _, header_columns = _split(lines[header_line - 1])
    layout = _layout(header, lambda message, k: fail(message, header_line, header_columns[k]))
    if len(records) < 2:
        raise fail(f"a demonstration needs at least two samples, {file} has {len(records)}",
                   records[0][0] if records else header_line)
    n = len(records)
    values = np.empty((n, len(header)))
    gripper: list[GripperEvent] = []
    g = layout.get("gripper")
    numeric = [k for k in range(len(header)) if k != g]
    if g is not None:
        values[:, g] = 0.0
    for i, (number, fields, columns) in enumerate(records):
        if len(fields) != len(header):
            raise fail(f"this row has {len(fields)} fields, the header {len(header)}", number)
        if g is not None:
            raw = fields[g].strip()
            if raw and raw not in COMMANDS:
                raise fail(f"gripper must be empty, open or close, not {raw!r}", number, columns[g])
            if raw:
                gripper.append(GripperEvent(i, raw, number))
        # The common case in one conversion per row; a field that is not a finite number is then
        # found and named field by field (a sum is finite when every term is, overflow aside).
        try:
            row = [float(fields[k]) for k in numeric]
            total = sum(row)
        except ValueError:
            row, total = None, math.nan
        if not total - total == 0:
            for k in numeric:
                _number(fields[k].strip(), header[k], lambda message: fail(message, number, columns[k]))
        values[i, numeric] = row
    rows = np.array([r[0] for r in records])
    times = values[:, layout["t"]]
    for i in range(1, n):
        if not times[i] > times[i - 1]:
            number, _, columns = records[i]
            raise fail(f"time {fields_text(times[i])} s is not after the previous row's "
                       f"{fields_text(times[i - 1])} s (time must increase)", number, columns[layout["t"]])
    positions = values[:, list(layout["position"])]
    orientations = None
    if "orientation" in layout:
        orientations = values[:, list(layout["orientation"])]
        _unit_quaternions(orientations, lambda i, message: fail(message, int(rows[i]),
                                                                records[i][2][layout["orientation"][0]]))
    objects = {name: values[:, list(cols)] for name, cols in layout["objects"].items()}

    def at_row(i: int, what: str, message: str) -> SchemalogError:
        number, _, columns = records[i]
        k = {"hand": layout["position"][0]}.get(what, layout["objects"].get(what, (0,))[0])
        return fail(message, number, columns[k])
    plausible(times, positions, objects, at_row)
    return Demonstration(times, positions, orientations, tuple(gripper), objects, rows, file, "line")


def fields_text(value: float) -> str:
    """A number as a message shows it: short, exact enough to find in the file."""
    return f"{value:.6g}"


def _split(line: str) -> tuple[list[str], list[int]]:
    """The fields of one CSV line and the 1-based column where each starts."""
    if '"' not in line:                      # the common case, without csv's quoting rules
        fields = line.split(",")
        columns, at = [], 1
        for field in fields:
            columns.append(at)
            at += len(field) + 1
        return fields, columns
    fields = next(csv.reader([line]), [])
    columns, quoted = [1], False
    for k, ch in enumerate(line):
        if ch == '"':
            quoted = not quoted
        elif ch == "," and not quoted:
            columns.append(k + 2)
    return fields, (columns + [len(line) + 1] * len(fields))[:len(fields)]


def _layout(header: list[str], fail) -> dict:
    """Where each quantity is in the header; every column known, none twice, none missing."""
    index: dict[str, int] = {}
    for k, name in enumerate(header):
        if name in index:
            raise fail(f"column {name!r} appears twice", k)
        index[name] = k
    missing = [c for c in ("t", *POSITION) if c not in index]
    if missing:
        raise fail(f"missing column{'s' if len(missing) > 1 else ''} {', '.join(missing)}: a demonstration "
                   f"needs t, x, y, z, optionally qx, qy, qz, qw and gripper, and <object>_x, <object>_y, "
                   f"<object>_z for each object", 0)
    layout: dict = {"t": index["t"], "position": tuple(index[c] for c in POSITION), "objects": {}}
    present = [c for c in ORIENTATION if c in index]
    if present and len(present) < 4:
        lacking = [c for c in ORIENTATION if c not in index]
        raise fail(f"orientation columns are qx, qy, qz, qw together: {', '.join(lacking)} missing",
                   index[present[0]])
    if present:
        layout["orientation"] = tuple(index[c] for c in ORIENTATION)
    if "gripper" in index:
        layout["gripper"] = index["gripper"]
    axes: dict[str, dict[str, int]] = {}
    for k, name in enumerate(header):
        if name in ("t", "gripper", *POSITION, *ORIENTATION):
            continue
        match = _OBJECT_COLUMN.match(name)
        if not match:
            raise fail(f"unknown column {name!r} (objects are <name>_x, <name>_y, <name>_z with a "
                       f"lower-case name)", k)
        axes.setdefault(match.group(1), {})[match.group(2)] = k
    if not axes:
        raise fail("no object columns: give each object's position as <name>_x, <name>_y, <name>_z "
                   "(e.g. cup_x, cup_y, cup_z)", 0)
    for name, found in axes.items():
        lacking = [f"{name}_{a}" for a in POSITION if a not in found]
        if lacking:
            raise fail(f"missing column{'s' if len(lacking) > 1 else ''} {', '.join(lacking)} of object "
                       f"{name}", min(found.values()))
        layout["objects"][name] = tuple(found[a] for a in POSITION)
    return layout


def _number(raw: str, what: str, fail) -> float:
    """A finite number, or a message naming the column."""
    if not raw:
        raise fail(f"{what} is empty (every sample needs a value)")
    try:
        value = float(raw)
    except ValueError:
        raise fail(f"{what} is not a number: {raw!r}") from None
    if math.isnan(value):
        raise fail(f"{what} is NaN (positions and times must be finite numbers)")
    if not math.isfinite(value):
        raise fail(f"{what} is infinite (positions and times must be finite numbers)")
    return value


def _unit_quaternions(q: np.ndarray, fail) -> None:
    """Normalise recorded quaternions in place; refuse ones that are not near unit length."""
    norms = np.linalg.norm(q, axis=1)
    bad = np.flatnonzero(np.abs(norms - 1.0) > _UNIT)
    if bad.size:
        i = int(bad[0])
        raise fail(i, f"the orientation (qx, qy, qz, qw) has norm {norms[i]:.3g}, not a unit quaternion")
    q /= norms[:, None]


def demonstration_from_json(text: str, file: str = "<json>") -> Demonstration:
    """Read JSON text (the layout in the module docstring)."""
    try:
        # Integers of any length, read as the knowledge reader does (int_of_digits): json's own
        # int() stops at Python's 4,300 digits with a ValueError; a number too large is refused
        # below, at its sample, as an infinite one is.
        data = json.loads(text, parse_int=int_of_digits)
    except json.JSONDecodeError as err:
        raise SchemalogError(f"JSON syntax error: {err.msg}", SourcePos(file, err.lineno, err.colno),
                             text.split("\n")[err.lineno - 1]) from None

    def fail(message: str) -> SchemalogError:
        return SchemalogError(f"{file}: {message}")

    if not isinstance(data, dict):
        raise fail("a JSON demonstration is an object with time, position, gripper and objects")
    known = ("time", "position", "orientation", "gripper", "objects")
    for key in data:
        if key not in known:
            raise fail(f"unknown key {key!r} (known: {', '.join(known)})")
    missing = [k for k in ("time", "position", "objects") if k not in data]
    if missing:
        raise fail(f"missing {', '.join(missing)}: a demonstration needs time, position and objects")
    times = _json_column(data["time"], "time", 1, fail)
    n = len(times)
    if n < 2:
        raise fail(f"a demonstration needs at least two samples, it has {n}")
    positions = _json_column(data["position"], "position", 3, fail, n)
    for i in range(1, n):
        if not times[i] > times[i - 1]:
            raise fail(f"sample {i + 1}: time {fields_text(times[i])} s is not after the previous sample's "
                       f"{fields_text(times[i - 1])} s (time must increase)")
    orientations = None
    if data.get("orientation") is not None:
        orientations = _json_column(data["orientation"], "orientation", 4, fail, n)
        _unit_quaternions(orientations, lambda i, message: fail(f"sample {i + 1}: {message}"))
    objects_data = data["objects"]
    if not isinstance(objects_data, dict) or not objects_data:
        raise fail("objects maps each object's name to its position [x, y, z] (static) or one "
                   "position per sample")
    objects: dict[str, np.ndarray] = {}
    for name, value in objects_data.items():
        if not isinstance(name, str) or not re.match(r"^[a-z][A-Za-z0-9_]*$", name):
            raise fail(f"object name {name!r} is not a lower-case word like cup or water_bottle")
        if isinstance(value, list) and len(value) == 3 and all(not isinstance(v, list) for v in value):
            fixed = _json_column([value], f"objects.{name}", 3, fail)
            objects[name] = np.repeat(fixed, n, axis=0)
        else:
            objects[name] = _json_column(value, f"objects.{name}", 3, fail, n)
    events: list[GripperEvent] = []
    raw_events = data.get("gripper") or []
    if not isinstance(raw_events, list):
        raise fail("gripper is a list of events {\"time\": t, \"command\": \"open\" | \"close\"}")
    for k, event in enumerate(raw_events, start=1):
        if not isinstance(event, dict) or set(event) != {"time", "command"}:
            raise fail(f"gripper event {k}: an event is {{\"time\": t, \"command\": \"open\" | \"close\"}}")
        if event["command"] not in COMMANDS:
            raise fail(f"gripper event {k}: the command must be open or close, not {event['command']!r}")
        t = event["time"]
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not _finite(t):
            raise fail(f"gripper event {k}: time must be a finite number{_too_large(t)}")
        if t < times[0] or t > times[-1]:
            raise fail(f"gripper event {k} ({event['command']} at t = {fields_text(t)} s) is outside any "
                       f"segment: the recording runs from {fields_text(times[0])} to {fields_text(times[-1])} s")
        index = int(np.searchsorted(times, t, side="left"))
        events.append(GripperEvent(index, event["command"], k))
    events.sort(key=lambda e: e.index)
    plausible(times, positions, objects, lambda i, what, message: fail(f"sample {i + 1}: {message}"))
    rows = np.arange(1, n + 1)
    return Demonstration(times, positions, orientations, tuple(events), objects, rows, file, "sample")


def plausible(times: np.ndarray, positions: np.ndarray, objects: dict[str, np.ndarray], fail) -> None:
    """Refuse positions no robot records: kilometres away, or jumping faster than MAX_SPEED.

    The speed is measured against the latest sample at least BASELINE (10 ms) earlier, and a
    distance covered in less counts as if it took BASELINE: a sensor's white noise (sigma per
    sample) makes the apparent speed between neighbouring samples grow with the rate (about
    2.4 sigma / dt, 24 m/s for 1 mm at 10 kHz), while over 10 ms it stays 0.24 m/s for 1 mm at
    any rate. A glitch (a sample centimetres or metres off) is as far off its predecessor 10 ms
    back. At 100 Hz and below this is the speed between neighbouring samples.
    """
    n = len(times)
    index = np.arange(1, n)
    back = np.searchsorted(times, times[1:] - BASELINE, side="right") - 1
    back = np.clip(np.minimum(back, index - 1), 0, None)
    span = times[1:] - times[back]
    for what, track in (("hand", positions), *sorted(objects.items())):
        name = "the end-effector" if what == "hand" else what
        far = np.flatnonzero(np.abs(track).max(axis=1) > MAX_COORDINATE)
        if far.size:
            i = int(far[0])
            raise fail(i, what, f"{name} is {np.abs(track[i]).max():.3g} m from the base: positions are in "
                                f"metres, within {MAX_COORDINATE:g} m")
        speed = np.linalg.norm(track[1:] - track[back], axis=1) / np.maximum(span, BASELINE)
        fast = np.flatnonzero(speed > MAX_SPEED)
        if fast.size:
            k = int(fast[0])
            i, j = k + 1, int(back[k])
            jump = float(np.linalg.norm(track[i] - track[j]))
            within = f"in {span[k]:.3g} s" + (f" (counted as {BASELINE * 1000:g} ms: speeds are measured over at least "
                                               f"{BASELINE * 1000:g} ms)" if span[k] < BASELINE else "")
            raise fail(i, what, f"{name} jumps {jump:.3g} m {within} ({speed[k]:.3g} m/s, more than "
                                f"{MAX_SPEED:g} m/s): a tracking glitch? Remove or repair the sample")


def _json_column(value, what: str, width: int, fail, n: int | None = None) -> np.ndarray:
    """A list of numbers (width 1) or of `width`-number lists, all finite, as an array."""
    if not isinstance(value, list):
        raise fail(f"{what} must be a list")
    if n is not None and len(value) != n:
        if width == 3 and len(value) in (2, 4) and all(not isinstance(v, list) for v in value):
            raise fail(f"{what} must be a position [x, y, z], or one per sample")
        raise fail(f"{what} has {len(value)} sample{'s' if len(value) != 1 else ''}, time has {n}")
    out = np.empty((len(value), width))
    for i, item in enumerate(value):
        items = [item] if width == 1 else item
        if not isinstance(items, list) or len(items) != width:
            raise fail(f"sample {i + 1}: {what} must be {width} numbers")
        for j, v in enumerate(items):
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise fail(f"sample {i + 1}: {what} is not a number: {v!r}")
            if not _finite(v):
                size = "NaN" if v != v else "infinite" if isinstance(v, float) else \
                    f"{shown_number(int_text(v))}, too large"
                raise fail(f"sample {i + 1}: {what} is {size} (positions and times must be finite numbers)")
            out[i, j] = v
    return out[:, 0] if width == 1 else out


def _finite(value: int | float) -> bool:
    """Whether `value` is a number a float holds: compared, never converted, so that an integer
    of 5,000 digits is refused rather than raising OverflowError (math.isfinite converts)."""
    return -sys.float_info.max <= value <= sys.float_info.max


def _too_large(value) -> str:
    """`, not 1234...5678 (5,000 digits): too large` for an integer no float holds, else ``."""
    if isinstance(value, int) and not isinstance(value, bool) and not _finite(value):
        return f", not {shown_number(int_text(value))}: too large"
    return ""


# ---------------------------------------------------------------------------
# Writing

def demonstration_csv(demo: Demonstration, comment: str = "") -> str:
    """The demonstration as CSV text (millimetre-and-better precision, one sample per line)."""
    out = io.StringIO()
    for line in comment.splitlines():
        out.write(f"# {line}\n" if line else "#\n")
    names = sorted(demo.objects)
    header = ["t", *POSITION, *(ORIENTATION if demo.orientations is not None else ()), "gripper",
              *(f"{name}_{a}" for name in names for a in POSITION)]
    out.write(",".join(header) + "\n")
    commands = {e.index: e.command for e in demo.gripper}
    for i in range(len(demo)):
        fields = [f"{demo.times[i]:.6f}", *(f"{v:.6f}" for v in demo.positions[i])]
        if demo.orientations is not None:
            fields += [f"{v:.6f}" for v in demo.orientations[i]]
        fields.append(commands.get(i, ""))
        fields += [f"{v:.6f}" for name in names for v in demo.objects[name][i]]
        out.write(",".join(fields) + "\n")
    return out.getvalue()


def demonstration_json(demo: Demonstration) -> str:
    """The demonstration as JSON text; objects that never move are written once."""
    objects = {}
    for name in sorted(demo.objects):
        track = demo.objects[name]
        objects[name] = (np.round(track[0], 6).tolist() if np.all(track == track[0])
                         else np.round(track, 6).tolist())
    data = {"time": np.round(demo.times, 6).tolist(),
            "position": np.round(demo.positions, 6).tolist()}
    if demo.orientations is not None:
        data["orientation"] = np.round(demo.orientations, 6).tolist()
    data["gripper"] = [{"time": round(float(demo.times[e.index]), 6), "command": e.command}
                       for e in demo.gripper]
    data["objects"] = objects
    return json.dumps(data, separators=(",", ":")) + "\n"


def write_demonstration(demo: Demonstration, path: str | Path, comment: str = "") -> None:
    """Write CSV or JSON by suffix, atomically."""
    text = demonstration_json(demo) if str(path).lower().endswith(".json") else demonstration_csv(demo, comment)
    write_atomically(path, text)


__all__ = ["Demonstration", "GripperEvent", "read_demonstration", "demonstration_from_csv",
           "demonstration_from_json", "demonstration_csv", "demonstration_json", "write_demonstration",
           "COMMANDS"]
