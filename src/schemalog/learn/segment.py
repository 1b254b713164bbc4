"""Segmentation of a demonstration into symbolic actions (Sec. II-C).

    Segment = (label, kind, obj, start, end, cause)
      label   a1(water) for a motion, gripper(close) for a command
      kind    "motion" | "gripper"
      obj     the closest object when the segment ends (the object the motion was about)
      start, end   sample indices; a motion spans start..end, a command sits at start == end
      cause   why the segment ended: "enters water", "leaves cup", "gripper close", "end"

A motion segment ends when the end-effector enters or leaves an object's proximity sphere
(radius 0.1 m) or the teacher commands the gripper; each motion gets the next label a1, a2,
... and the closest object; each command becomes gripper(open) or gripper(close).

Where the paper is silent (docs/learning.md):
- Events are detected on the hand's position averaged over `smoothing` seconds (50 ms), so
  noise at 1 kHz does not flicker across a border; the hysteresis handles what remains.
- A stretch where the (averaged) hand moves less than `min_motion` from where it started (1 cm)
  is a pause, not a motion: resting after the last command makes no action.
- The gripper starts open; a command that does not change its state (open when open) is
  ignored with a note, so a column that records the gripper's state on every row works too.
- Leaving needs the hand `hysteresis` beyond the radius (default 5 mm), so sensor noise at the
  border does not cut a motion into slivers.
- The object in the hand does not segment: closing the gripper engages the nearest object
  inside its sphere, and it stays engaged (no events, never the closest object) while held
  and, after the gripper opens, until the hand has left its sphere. Otherwise carrying the
  water to the cup would be "near water" all the way, and letting go would cut a motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import defaults
from .demo import Demonstration
from ..errors import SchemalogError
from ..logic.terms import Atom, Struct, Term

DEFAULT_RADIUS = defaults.RADIUS
DEFAULT_HYSTERESIS = defaults.HYSTERESIS
DEFAULT_MIN_MOTION = defaults.MIN_MOTION
DEFAULT_SMOOTHING = defaults.SMOOTHING


@dataclass(frozen=True)
class Segment:
    """One symbolic action of a demonstration."""

    label: Term
    kind: str
    obj: str
    start: int
    end: int
    cause: str

    @property
    def action(self) -> str:
        """The action's name: a3, or gripper."""
        return self.label.name if isinstance(self.label, Struct) else str(self.label)


def motion_label(number: int, obj: str) -> Term:
    """a<number>(obj)."""
    return Struct(f"a{number}", (Atom(obj),))


def gripper_label(command: str) -> Term:
    """gripper(open) or gripper(close)."""
    return Struct("gripper", (Atom(command),))


def smoothed(times: np.ndarray, values: np.ndarray, window: float) -> np.ndarray:
    """A centred moving average over `window` seconds (fewer samples at the ends)."""
    if window <= 0 or len(times) < 3:
        return values
    half = int(round(window / 2 / float(np.median(np.diff(times)))))
    if half < 1:
        return values
    n = len(values)
    sums = np.vstack([np.zeros((1, values.shape[1])), np.cumsum(values, axis=0)])
    lo = np.maximum(np.arange(n) - half, 0)
    hi = np.minimum(np.arange(n) + half + 1, n)
    return (sums[hi] - sums[lo]) / (hi - lo)[:, None]


def segment(demo: Demonstration, radius: float = DEFAULT_RADIUS, hysteresis: float = DEFAULT_HYSTERESIS,
            first_label: int = 1, min_motion: float = DEFAULT_MIN_MOTION, smoothing: float = DEFAULT_SMOOTHING,
            notes: list[str] | None = None) -> list[Segment]:
    """Cut `demo` into motions and gripper commands, in the order they happened; what was
    ignored (repeated gripper commands, pauses) is told in `notes`."""
    if radius <= 0 or hysteresis < 0:
        raise SchemalogError("the proximity radius must be positive and the hysteresis not negative")
    notes = notes if notes is not None else []
    names = sorted(demo.objects)
    n = len(demo)
    hand = smoothed(demo.times, demo.positions, smoothing)
    # distance[i, k]: end-effector to object k at sample i
    distance = np.stack([np.linalg.norm(hand - demo.objects[name], axis=1) for name in names], axis=1)
    raw = np.stack([np.linalg.norm(demo.positions - demo.objects[name], axis=1) for name in names], axis=1)
    nearest_k = int(np.argmin(raw.min(axis=0)))
    if raw[:, nearest_k].min() >= radius:
        i = int(np.argmin(raw[:, nearest_k]))
        raise demo.error(
            f"the end-effector never comes within {radius:g} m of an object (nearest: "
            f"{names[nearest_k]}, {raw[i, nearest_k]:.3f} m at {demo.where(i)}): no action to learn; "
            f"is the radius right (--radius) and are positions in metres?", i)
    inside = distance[0] < radius
    engaged: dict[int, str] = {}             # object -> "held" | "released"
    commands: dict[int, list[str]] = {}
    for event in demo.gripper:
        commands.setdefault(event.index, []).append(event.command)

    segments: list[Segment] = []
    counter = first_label
    start = 0

    def closest(i: int) -> int:
        free = [k for k in range(len(names)) if k not in engaged]
        pool = free or list(range(len(names)))
        return min(pool, key=lambda k: distance[i, k])

    pauses = 0

    def cut(i: int, cause: str) -> None:
        nonlocal counter, start, pauses
        if i <= start:
            return
        moved = np.linalg.norm(hand[start:i + 1] - hand[start], axis=1).max()
        if moved >= min_motion:
            segments.append(Segment(motion_label(counter, names[closest(i)]), "motion",
                                    names[closest(i)], start, i, cause))
            counter += 1
        else:
            pauses += 1
        start = i

    closed = False        # the gripper is taken to start open, holding nothing
    repeated: list[str] = []

    for i in range(n):
        events: list[str] = []
        for k in range(len(names)):
            d = distance[i, k]
            state = engaged.get(k)
            if state == "held":
                continue
            if state == "released":
                if d > radius + hysteresis:
                    del engaged[k]
                    inside[k] = False
                continue
            if not inside[k] and d < radius:
                inside[k] = True
                events.append(f"enters {names[k]}")
            elif inside[k] and d > radius + hysteresis:
                inside[k] = False
                events.append(f"leaves {names[k]}")
        if events and i > 0:
            cut(i, ", ".join(events))
        for command in commands.get(i, ()):
            if closed == (command == "close"):
                repeated.append(f"{demo.where(i)} ({command})")
                continue
            closed = command == "close"
            cut(i, f"gripper {command}")
            if command == "close":
                near = [k for k in range(len(names)) if k not in engaged and distance[i, k] < radius]
                if near:
                    engaged[min(near, key=lambda k: distance[i, k])] = "held"
                at = names[closest(i)] if not near else names[min(near, key=lambda k: distance[i, k])]
            else:
                held = [k for k, s in engaged.items() if s == "held"]
                for k in held:
                    engaged[k] = "released"
                at = names[held[0]] if held else names[closest(i)]
            segments.append(Segment(gripper_label(command), "gripper", at, i, i, f"gripper {command}"))
    cut(n - 1, "end")
    if repeated:
        shown = ", ".join(repeated[:3]) + (f" and {len(repeated) - 3} more" if len(repeated) > 3 else "")
        notes.append(f"{len(repeated)} gripper command{'s' if len(repeated) > 1 else ''} that did not change its "
                     f"state ignored: {shown}")
    if pauses:
        notes.append(f"{pauses} stretch{'es' if pauses > 1 else ''} moving the hand less than {min_motion:g} m "
                     f"dropped as pauses")
    if not any(s.kind == "motion" for s in segments):
        raise demo.error("the demonstration has no motion: the hand never moves more than "
                         f"{min_motion:g} m between events (--min-motion)")
    return segments


__all__ = ["Segment", "segment", "smoothed", "motion_label", "gripper_label", "DEFAULT_RADIUS", "DEFAULT_HYSTERESIS"]
