"""Synthetic demonstrations: a teacher's motions for a known task in a scene, so the learning
path is testable without a robot.

    Leaf     = an action of the task tree, in the order the executive performs it
    Waypoint = (position, orientation quaternion): where a point-to-point motion stops
    Track    = the samples of one motion: minimum-jerk in position, slerp in orientation

The executive runs the task in the scene; each gripper command becomes a gripper event, and
each arm action a motion that produces exactly one segment (Sec. II-C) on its object: it ends
entering the object's proximity sphere, leaving it, at the grasp or release before a gripper
command, or at the end. Motions from one object to another lift to a safe height first.
Carried objects move with the hand. White noise is added to the hand's positions. The result
is segmented before it is returned: a scene where this plan would cut differently (objects
too close together for their spheres) is refused with the first difference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import defaults
from .demo import Demonstration, GripperEvent, plausible
from ..errors import SchemalogError
from ..run.execute import Executive
from ..logic.kb import KnowledgeBase
from ..run.scene import Scene
from .segment import DEFAULT_HYSTERESIS, DEFAULT_RADIUS, segment
from ..logic.terms import Struct, Term, term_to_text
from ..task.tree import instantiate
from ..run.world import World, initial_state

DEFAULT_RATE = defaults.RATE
DEFAULT_NOISE = defaults.NOISE
DEFAULT_SPEED = defaults.SPEED
DWELL = 0.3               # seconds the hand rests at a gripper command
DOWN = np.array([1.0, 0.0, 0.0, 0.0])      # (qx, qy, qz, qw): the gripper pointing down


@dataclass(frozen=True)
class Leaf:
    """One action to demonstrate."""

    label: Term
    command: str | None      # "open" / "close" for a gripper command
    obj: str | None


def demonstrated_leaves(kb: KnowledgeBase, task: Term, scene: Scene) -> list[Leaf]:
    """The actions of `task` in the order the executive performs them in `scene`."""
    tree = instantiate(kb, task)
    executive = Executive(tree, World(tree, initial_state(kb)), scene)
    outcome = executive.run()
    if not outcome.completed:
        raise SchemalogError(f"{term_to_text(task)} does not complete in {scene.name} ({outcome.reason}): "
                             f"there is nothing to demonstrate")
    plan = executive.plan
    by_label = {plan.nodes[i].label: i for i in plan.leaves}
    leaves = []
    for label in executive.trace:
        if isinstance(label, Struct) and label.name == "gripper" and len(label.args) == 1 \
                and term_to_text(label.args[0]) in ("open", "close"):
            leaves.append(Leaf(label, term_to_text(label.args[0]), None))
            continue
        obj = plan.obj[by_label[label]]
        if obj is None or obj not in scene.objects:
            raise SchemalogError(f"cannot demonstrate {term_to_text(label)}: it acts on no object of the scene "
                                 f"{scene.name} ({', '.join(scene.objects)})")
        leaves.append(Leaf(label, None, obj))
    return leaves


class _Teacher:
    """Moves the hand through the leaves, a motion at a time (each one array of samples)."""

    def __init__(self, scene: Scene, radius: float, rate: float, speed: float,
                 max_samples: int = defaults.MAX_SIMULATED) -> None:
        if any(len(p) != 3 for p in (scene.end_effector, *scene.objects.values())):
            raise SchemalogError(f"scene {scene.name} is 2-D: a demonstration needs 3-D positions")
        self.r = radius
        self.rate, self.speed = rate, speed
        self.max_samples = max_samples
        self.objects = {name: np.array(p, dtype=float) for name, p in scene.objects.items()}
        self.safe = max(p[2] for p in self.objects.values()) + 2.5 * radius
        self.hand = np.array(scene.end_effector, dtype=float)
        self.orientation = DOWN.copy()
        self.held: tuple[str, np.ndarray] | None = None
        self.count = 1
        self.positions: list[np.ndarray] = [self.hand[None, :].copy()]
        self.orientations: list[np.ndarray] = [self.orientation[None, :].copy()]
        self.tracks: dict[str, list[np.ndarray]] = {n: [p[None, :].copy()] for n, p in self.objects.items()}
        self.events: list[GripperEvent] = []

    # -- geometry -------------------------------------------------------------
    def inside(self, name: str) -> bool:
        return float(np.linalg.norm(self.hand - self.objects[name])) < self.r

    def facing(self, target: np.ndarray) -> np.ndarray:
        """The gripper pointing down, turned to face away from the robot's base at `target`."""
        yaw = math.atan2(target[1], target[0])
        return np.array([math.cos(yaw / 2), math.sin(yaw / 2), 0.0, 0.0])   # down, then yaw about z

    def aside(self, name: str, distance: float) -> np.ndarray:
        """A point beside `name` at `distance`, on the side farthest from every other object."""
        centre = self.objects[name]
        best, best_gap = None, -1.0
        for k in range(16):
            angle = 2 * math.pi * k / 16
            p = centre + distance * np.array([math.cos(angle), math.sin(angle), 0.0])
            others = [np.linalg.norm(p - q) for n, q in self.objects.items()
                      if n != name and (self.held is None or n != self.held[0])]
            gap = min(others, default=math.inf)
            if gap > best_gap:
                best, best_gap = p, gap
        return best

    # -- motion ---------------------------------------------------------------
    def move(self, target: np.ndarray, orientation: np.ndarray | None = None) -> None:
        """One minimum-jerk point-to-point motion to `target`."""
        start, q0 = self.hand.copy(), self.orientation.copy()
        q1 = q0 if orientation is None else orientation
        distance = float(np.linalg.norm(target - start))
        duration = 0.3 + distance / self.speed
        steps = self._budget(duration * self.rate, minimum=2)
        s = np.arange(1, steps + 1) / steps
        blend = 10 * s ** 3 - 15 * s ** 4 + 6 * s ** 5
        self._samples(start + blend[:, None] * (target - start), _slerp(q0, q1, blend))

    def rest(self, seconds: float) -> None:
        steps = self._budget(seconds * self.rate)
        self._samples(np.tile(self.hand, (steps, 1)), np.tile(self.orientation, (steps, 1)))

    def transfer(self, target: np.ndarray, orientation: np.ndarray) -> None:
        """Lift to the safe height, travel above the target, then descend onto it."""
        if np.linalg.norm(self.hand[:2] - target[:2]) > 1e-9:
            if self.hand[2] < self.safe - 1e-9:
                self.move(np.array([*self.hand[:2], self.safe]))
            self.move(np.array([*target[:2], max(self.safe, target[2])]), orientation)
        self.move(target, orientation)

    def _budget(self, planned: float, minimum: int = 1) -> int:
        """The samples of the next motion (at least `minimum`), within max_samples in all."""
        steps = max(minimum, int(round(planned))) if planned < self.max_samples else self.max_samples + 1
        if self.count + steps > self.max_samples:
            raise SchemalogError(f"the demonstration would have more than {self.max_samples:,} samples at "
                                 f"{self.rate:g} Hz and {self.speed:g} m/s: lower --rate or raise --speed "
                                 f"(or bring the scene's objects closer)")
        return steps

    def _samples(self, hands: np.ndarray, orientations: np.ndarray) -> None:
        """Append samples; the held object moves with the hand, the others stay."""
        self.positions.append(hands)
        self.orientations.append(orientations)
        for name, track in self.tracks.items():
            if self.held is not None and self.held[0] == name:
                track.append(hands + self.held[1])
            else:
                track.append(np.broadcast_to(self.objects[name], hands.shape))
        self.hand, self.orientation = hands[-1].copy(), orientations[-1].copy()
        if self.held is not None:
            self.objects[self.held[0]] = self.hand + self.held[1]
        self.count += len(hands)

    # -- actions --------------------------------------------------------------
    def demonstrate(self, leaf: Leaf, following: Leaf | None) -> None:
        if leaf.command is not None:
            self.command(leaf.command)
            return
        name = leaf.obj
        centre = self.objects[name]
        turn = self.facing(centre)
        if following is not None and following.command == "close":
            if not self.inside(name):
                raise SchemalogError(f"cannot demonstrate {term_to_text(leaf.label)} before a grasp from outside "
                                     f"{name}'s sphere: the approach would be two segments")
            self.move(centre + np.array([0.0, 0.0, 0.2 * self.r]), turn)
        elif following is not None and following.command == "open":
            if self.inside(name):
                self.move(centre + np.array([0.5 * self.r, 0.0, 0.3 * self.r]), turn)
            else:
                spot = self.aside(name, 1.6 * self.r)
                self.move(np.array([*spot[:2], max(self.hand[2], centre[2] + 1.4 * self.r)]), turn)
                self.move(spot + np.array([0.0, 0.0, 0.01]), turn)
        elif self.inside(name):
            self.move(centre + np.array([0.0, 0.0, 1.4 * self.r]), turn)           # leave, upwards
        else:
            self.transfer(centre + np.array([0.0, 0.0, 0.8 * self.r]), turn)     # enter, from above

    def command(self, command: str) -> None:
        self.events.append(GripperEvent(self.count - 1, command, 0))
        if command == "close":
            near = [n for n in self.objects if self.inside(n) and (self.held is None or n != self.held[0])]
            if near and self.held is None:
                name = min(near, key=lambda n: np.linalg.norm(self.hand - self.objects[n]))
                self.held = (name, self.objects[name] - self.hand)
        else:
            self.held = None
        self.rest(DWELL)

    def demonstration(self, noise: float, seed: int, file: str) -> Demonstration:
        rng = np.random.default_rng(seed)
        positions = np.concatenate(self.positions)
        if noise > 0:
            positions = positions + rng.normal(0.0, noise, positions.shape)
        n = len(positions)
        times = np.round(np.arange(n) / self.rate, 6)
        events = tuple(GripperEvent(e.index, e.command, e.index + 2) for e in self.events)
        return Demonstration(times, positions, np.concatenate(self.orientations), events,
                             {name: np.concatenate(track) for name, track in self.tracks.items()},
                             np.arange(2, n + 2), file, "line")


def _slerp(q0: np.ndarray, q1: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Spherical interpolation between unit quaternions, the short way round, at each fraction in s."""
    s = np.asarray(s, dtype=float)[:, None]
    dot = float(np.dot(q0, q1))
    if dot < 0:
        q1, dot = -q1, -dot
    if dot > 0.9995:
        q = q0 + s * (q1 - q0)
        return q / np.linalg.norm(q, axis=1, keepdims=True)
    theta = math.acos(dot)
    return (np.sin((1 - s) * theta) * q0 + np.sin(s * theta) * q1) / math.sin(theta)


def simulate(kb: KnowledgeBase, task: Term, scene: Scene, *, seed: int = 0, noise: float = DEFAULT_NOISE,
             rate: float = DEFAULT_RATE, speed: float = DEFAULT_SPEED, radius: float = DEFAULT_RADIUS,
             file: str = "<simulated>", max_samples: int = defaults.MAX_SIMULATED) -> Demonstration:
    """A demonstration of `task` in `scene` that segments back into the task's actions, and that
    `learn` reads back: within max_samples, and with no jump read as a tracking glitch."""
    leaves = demonstrated_leaves(kb, task, scene)
    teacher = _Teacher(scene, radius, rate, speed, max_samples)
    for k, leaf in enumerate(leaves):
        teacher.demonstrate(leaf, leaves[k + 1] if k + 1 < len(leaves) else None)
    demo = teacher.demonstration(noise, seed, file)
    # What learn would refuse is refused here, before anything is written (--noise is bounded so
    # that this does not happen by chance: 1 cm of noise is 0.24 m/s over 10 ms).
    plausible(demo.times, demo.positions, demo.objects,
              lambda i, what, message: SchemalogError(f"the simulated demonstration would be refused by learn: "
                                                      f"{message} (sample {i + 1}; lower --noise?)"))
    segments = segment(demo, radius, DEFAULT_HYSTERESIS)
    wanted = [(leaf.command or "motion", leaf.obj) for leaf in leaves]
    got = [(s.label.args[0].name if s.kind == "gripper" else "motion", s.obj if s.kind == "motion" else None)
           for s in segments]
    for k, (w, g) in enumerate(zip(wanted, got)):
        if w != g:
            raise SchemalogError(f"the simulated demonstration of {term_to_text(task)} in {scene.name} would segment "
                                 f"as {_name(g)} where the task does {term_to_text(leaves[k].label)} (action {k + 1}): "
                                 f"are the objects closer than twice the radius ({radius:g} m)?")
    if len(wanted) != len(got):
        raise SchemalogError(f"the simulated demonstration of {term_to_text(task)} in {scene.name} segments into "
                             f"{len(got)} actions, the task has {len(wanted)}")
    return demo


def _name(item: tuple[str, str | None]) -> str:
    kind, obj = item
    return f"a motion on {obj}" if kind == "motion" else f"gripper({kind})"


__all__ = ["simulate", "demonstrated_leaves", "Leaf", "DEFAULT_RATE", "DEFAULT_NOISE", "DEFAULT_SPEED"]
