"""Learning from demonstration (Sec. II-C, II-D; docs/learning.md), as `schemalog learn` and
`schemalog simulate-demo` do it: a demonstration segmented and taught to a partially
specified task structure, and a synthetic demonstration of a task in a scene.

    learned(demo, structure, task, ...)     -> Learned(lesson, text, report, motions)
    simulated(knowledge, task, scene, ...)  -> Simulated(text, summary)
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .. import defaults
from ..errors import UsageError

if TYPE_CHECKING:
    from ..run.scene import Scene
    from .knowledge import Knowledge


@dataclass(frozen=True)
class Learned:
    """What one lesson produced: the learned knowledge's text, the report, the primitives."""

    lesson: object             # learn.learn.Lesson: the demonstration, segments, teaching, tree
    task: str                  # the learned task's label as text
    behaviours: int            # how many its tree has
    text: str                  # the learned knowledge (schema text)
    report: tuple[str, ...]    # the demonstration, each segment and where it went, the task
    motions: str | None        # the primitives as JSON text, when asked for

    def plot(self, path: str | os.PathLike) -> None:
        """Draw the trajectory, its segments and objects, and the merged primitives (by suffix:
        PNG, SVG or PDF)."""
        from pathlib import Path

        from ..evaluate.figures import demonstration_figure

        demonstration_figure(self.lesson, Path(path))


def structure_files(structure: str) -> tuple[str, ...]:
    """The files a task structure consults (and itself): what learn reads besides the demo."""
    from ..formats.documents import read_document

    return tuple(read_document(structure).to_kb().files)


def learned(demo: str, structure: str, task: str | None = None, *, radius: float = defaults.RADIUS,
            hysteresis: float = defaults.HYSTERESIS, min_motion: float = defaults.MIN_MOTION,
            max_bytes: int = defaults.MAX_DEMO_BYTES, bases: int = defaults.BASES,
            motions: bool = False) -> Learned:
    """Segment the demonstration, teach the structure's task (default: its first task/1), and
    check what was learned; with `motions`, the motion primitives as JSON too."""
    import json

    from ..learn.learn import learn, lesson_lines, motions_json
    from ..logic.terms import term_to_text
    from ..task.tree import count_nodes

    from .choosing import task_term

    term = task_term(task) if task else None
    lesson = learn(demo, structure, term, radius=radius, hysteresis=hysteresis, min_motion=min_motion,
                   max_bytes=max_bytes, bases=bases)
    report = tuple(lesson_lines(lesson))
    motions_text = None
    if motions:
        if lesson.motions is None:
            raise UsageError("--motions needs primitives: --bases 0 turns them off")
        motions_text = json.dumps(motions_json(lesson, lesson.motions), indent=1) + "\n"
    return Learned(lesson, term_to_text(lesson.tree.label), count_nodes(lesson.tree), lesson.text, report,
                   motions_text)


def read_scene(path: str, max_bytes: int = defaults.MAX_BYTES) -> Scene:
    """A scene file (object positions, docs/semantics.md): .name, .objects, .knowledge."""
    from ..run.scene import read_scene as read

    return read(path, max_bytes)


@dataclass(frozen=True)
class Simulated:
    """A synthetic demonstration as text (CSV or JSON) and a line that sums it up."""

    text: str
    summary: str


def simulated(knowledge: Knowledge, task: str | None, scene: Scene, *, scene_file: str, output: str | None = None,
              seed: int = 0, noise: float = defaults.NOISE, rate: float = defaults.RATE,
              speed: float = defaults.SPEED, radius: float = defaults.RADIUS, jitter: float = 0.0,
              as_json: bool = False) -> Simulated:
    """A demonstration of the task (default: the first task/1) in the scene (its objects moved
    by up to `jitter` with `seed`): smooth motions with noise, as CSV (or JSON)."""
    from ..learn.demo import demonstration_csv, demonstration_json
    from ..learn.simulate import simulate
    from ..logic.terms import term_to_text

    from .choosing import choose_task

    term = choose_task(knowledge._kb, task)
    if jitter:
        scene = scene.jittered(seed, jitter)
    name = output if output and output != "-" else "<stdout>"
    demo = simulate(knowledge._kb, term, scene, seed=seed, noise=noise, rate=rate, speed=speed,
                    radius=radius, file=name)
    comment = (f"A simulated demonstration of {term_to_text(term)} in {scene.name} ({scene_file}), written by "
               f"schemalog simulate-demo:\nminimum-jerk point-to-point motions at {speed:g} m/s, {rate:g} Hz, "
               f"position noise {noise:g} m (seed {seed}).")
    text = demonstration_json(demo) if as_json else demonstration_csv(demo, comment)
    commands = len(demo.gripper)
    summary = (f"simulated {term_to_text(term)} in {scene.name}: {len(demo):,} samples over {demo.times[-1]:.1f} s, "
               f"{commands} gripper commands")
    return Simulated(text, summary)
