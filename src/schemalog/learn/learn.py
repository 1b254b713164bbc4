"""Learning from demonstration, end to end: a recording in, schema knowledge out (Sec. II-C, II-D).

    demonstration --segment--> segments --teach(structure)--> learned knowledge (text)
                                    \\--fit--> a motion primitive per action, and per merged
                                               behaviour of the compressed learned task

`learn` does the work and returns a `Lesson`; `lesson_lines` is the report a person reads.
Nothing is written here: the command line writes the outputs, atomically, once all succeeded.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..task import conditions as cond
from .. import defaults
from . import primitives
from ..task.compress import compress, protected_labels
from .demo import Demonstration, read_demonstration
from ..formats.documents import YAML_SUFFIXES, document_from_text, read_document, read_source, to_pl
from ..errors import SchemalogError
from ..logic.kb import KnowledgeBase
from .segment import DEFAULT_HYSTERESIS, DEFAULT_MIN_MOTION, DEFAULT_RADIUS, Segment, segment
from .teach import Attachment, Teaching, learned_text, teach
from ..logic.terms import Term, term_to_text
from ..task.tree import Behaviour, count_nodes, instantiate, walk


@dataclass
class Lesson:
    """Everything one `schemalog learn` produced."""

    demo: Demonstration
    segments: list[Segment]
    teaching: Teaching
    text: str
    learned_kb: KnowledgeBase
    tree: Behaviour
    compressed: Behaviour
    radius: float
    motions: "Motions | None" = None

    def actions_of(self) -> dict[Term, Segment]:
        """Each action of the learned task and the segment that demonstrated it."""
        out: dict[Term, Segment] = {}
        for step in self.teaching.steps:
            label = step.label if isinstance(step, Attachment) else step.action
            out.setdefault(label, step.segment)
        return out


def where_demonstrated(demo: Demonstration, seg: Segment) -> str:
    """`coffee.csv lines 2-245 (0.00-2.43 s), enters water`."""
    first, last = int(demo.rows[seg.start]), int(demo.rows[seg.end])
    span = f"{demo.row_name}s {first}-{last}" if last != first else f"{demo.row_name} {first}"
    return (f"{Path(demo.file).name} {span} ({demo.times[seg.start]:.2f}-{demo.times[seg.end]:.2f} s), "
            f"{seg.cause}")


def learn(demo_path: str, structure_path: str, task: Term | None, *, radius: float = DEFAULT_RADIUS,
          hysteresis: float = DEFAULT_HYSTERESIS, min_motion: float = DEFAULT_MIN_MOTION,
          max_bytes: int | None = None, bases: int | None = defaults.BASES) -> Lesson:
    """Segment the demonstration, teach the structure's task, and check what was learned."""
    demo = read_demonstration(demo_path, **({"max_bytes": max_bytes} if max_bytes else {}))
    structure = read_document(structure_path)
    kb = structure.to_kb()
    # The structure is copied into the output: as written, or as Prolog when it is YAML or SEED.
    plain = not structure.seed and not structure_path.endswith(YAML_SUFFIXES)
    structure_text = read_source(structure_path) if plain else to_pl(structure)
    if task is None:
        from ..task.tree import declared_tasks
        declared = declared_tasks(kb)
        if not declared:
            raise SchemalogError(f"{structure_path} declares no task/1: name the demonstrated task with --task")
        task = declared[0]
    notes: list[str] = []
    segments = segment(demo, radius, hysteresis, min_motion=min_motion, notes=notes)
    teaching = teach(kb, task, demo, segments)
    teaching.notes[:0] = notes
    if not teaching.attachments:
        raise SchemalogError(f"{demo_path} teaches nothing new: each of its {len(teaching.steps)} actions is one "
                             f"{structure_path} already knows")
    rows = {a.label: where_demonstrated(demo, a.segment) for a in teaching.attachments}
    settings = (f"Segmentation: proximity radius {radius:g} m, hysteresis {hysteresis:g} m, "
                f"pauses under {min_motion:g} m dropped.")
    text = learned_text(teaching, kb, structure_text, demo_file=Path(demo_path).name,
                        structure_files=[structure_path], rows=rows, settings=settings)
    # What was learned must read back: the same checks `schemalog check` makes.
    learned_kb = document_from_text(text, "<learned>").to_kb()
    tree = instantiate(learned_kb, task)
    compressed = compress(tree, "full", protected_labels(learned_kb, tree)).tree
    lesson = Lesson(demo, segments, teaching, text, learned_kb, tree, compressed, radius)
    if bases:
        lesson.motions = fit_motions(lesson, bases)
    return lesson


@dataclass(frozen=True)
class Primitive:
    """A motion primitive: what it stands for, the primitive, and how well it reproduces the demonstration."""

    label: Term
    parts: tuple[Term, ...]             # the learned actions it covers, in order (one unless merged)
    dmp: primitives.DMP
    error: primitives.Error
    times: np.ndarray                   # the demonstrated samples it was fitted to (merged: concatenated)
    poses: np.ndarray
    single: primitives.Error | None = None   # merged: a primitive with one segment's bases, for comparison


@dataclass(frozen=True)
class Motions:
    """A primitive per learned action, and a merged one per merged behaviour of the compressed task."""

    bases: int
    actions: tuple[Primitive, ...]
    merged: tuple[Primitive, ...]


def fit_motions(lesson: Lesson, bases: int = defaults.BASES) -> Motions:
    """Encode each demonstrated action as a DMP, and each merged action as one DMP of its parts."""
    demo = lesson.demo
    poses = demo.poses
    by_label = lesson.actions_of()

    def span(seg: Segment) -> tuple[np.ndarray, np.ndarray]:
        return demo.times[seg.start:seg.end + 1], poses[seg.start:seg.end + 1]

    actions = []
    for label, seg in by_label.items():
        if seg.kind != "motion":
            continue
        t, p = span(seg)
        dmp = primitives.fit(t, p, n_basis=bases)
        actions.append(Primitive(label, (label,), dmp, primitives.reproduction_error(dmp, t, p), t, p))
    merged = []
    for b in walk(lesson.compressed):
        if b.children or not b.merged_from:
            continue
        segs = [by_label.get(label) for label in b.merged_from]
        if any(s is None or s.kind != "motion" for s in segs):
            continue        # a part this demonstration did not show, or a gripper command
        parts = [span(s) for s in segs]
        dmp = primitives.merge(parts, n_basis_per_part=bases)
        t, p = _concatenated(parts)
        single = primitives.fit(t, p, n_basis=bases)
        merged.append(Primitive(b.label, b.merged_from, dmp, primitives.reproduction_error(dmp, t, p), t, p,
                                primitives.reproduction_error(single, t, p)))
    return Motions(bases, tuple(actions), tuple(merged))


def _concatenated(parts: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Consecutive segments as one trajectory (they share their junction sample: kept once)."""
    times, poses = [parts[0][0]], [parts[0][1]]
    for t, p in parts[1:]:
        if t[0] == times[-1][-1]:
            t, p = t[1:], p[1:]
        times.append(t)
        poses.append(p)
    return np.concatenate(times), np.concatenate(poses)


def motions_json(lesson: Lesson, motions: Motions) -> dict:
    """The primitives as JSON (docs/learning.md): each with its segment(s) and reproduction error."""
    by_label = lesson.actions_of()
    demo = lesson.demo

    def error(e: primitives.Error) -> dict:
        return {"rms": e.rms, "max": e.max, "final": e.final, "angle_rms": e.angle_rms}

    def segment_json(label: Term) -> dict:
        seg = by_label[label]
        return {"action": term_to_text(label), "first_row": int(demo.rows[seg.start]),
                "last_row": int(demo.rows[seg.end]), "start_time": float(demo.times[seg.start]),
                "end_time": float(demo.times[seg.end]), "object": seg.obj, "ends": seg.cause}

    return {"demonstration": demo.file, "task": term_to_text(lesson.teaching.task),
            "dimensions": ["x", "y", "z"] + (["qx", "qy", "qz", "qw"] if demo.orientations is not None else []),
            "bases_per_segment": motions.bases,
            "actions": [{"label": term_to_text(m.label), "segment": segment_json(m.label),
                         "dmp": primitives.to_json(m.dmp), "error": error(m.error)} for m in motions.actions],
            "merged": [{"label": term_to_text(m.label), "parts": [segment_json(p) for p in m.parts],
                        "dmp": primitives.to_json(m.dmp), "error": error(m.error),
                        "error_with_one_segments_bases": error(m.single)} for m in motions.merged]}


def motions_lines(motions: Motions) -> list[str]:
    """The primitives' reproduction errors, as the report prints them."""
    def mm(v: float) -> str:
        return f"{v * 1000:.1f} mm"
    lines = []
    if motions.actions:
        worst = max(motions.actions, key=lambda m: m.error.rms)
        mean = float(np.mean([m.error.rms for m in motions.actions]))
        final = max(m.error.final for m in motions.actions)
        lines.append(f"motion primitives (DMP, {motions.bases} bases per segment): {len(motions.actions)} actions; "
                     f"reproduction error RMS {mm(mean)} on average, worst {mm(worst.error.rms)} "
                     f"({term_to_text(worst.label)}); end point within {mm(final)}")
    if motions.merged:
        lines.append(f"merged primitives, one per merged action of the compressed task ({motions.bases} bases per part):")
        width = max(len(term_to_text(m.label)) for m in motions.merged)
        for m in motions.merged:
            lines.append(f"  {term_to_text(m.label):<{width}}  {len(m.parts)} segments, {m.times[-1] - m.times[0]:4.1f} s: "
                         f"RMS {mm(m.error.rms)}, max {mm(m.error.max)}, end {mm(m.error.final)}  "
                         f"(one segment's {motions.bases} bases: RMS {mm(m.single.rms)})")
    return lines


def lesson_lines(lesson: Lesson) -> list[str]:
    """The report: the demonstration, each segment and where it went, and the learned task."""
    demo, teaching = lesson.demo, lesson.teaching
    motions = sum(1 for s in lesson.segments if s.kind == "motion")
    lines = [f"{demo.file}: {len(demo):,} samples over {demo.times[-1] - demo.times[0]:.1f} s, "
             f"{len(demo.objects)} objects ({', '.join(sorted(demo.objects))}); "
             f"{len(lesson.segments)} segments: {motions} motions, {len(lesson.segments) - motions} gripper commands "
             f"(radius {lesson.radius:g} m)", ""]
    rows = []
    for k, step in enumerate(teaching.steps, start=1):
        seg = step.segment
        first, last = int(demo.rows[seg.start]), int(demo.rows[seg.end])
        span = f"{first}-{last}" if last != first else f"{first}"
        if isinstance(step, Attachment):
            what = term_to_text(step.label)
            where = f"-> {term_to_text(step.subtask)}"
            release = cond.to_text(step.releaser)
            second = f"{term_to_text(step.runner_up[0])} {step.runner_up[1]:.3g}" if step.runner_up else "-"
        else:
            what = term_to_text(step.action)
            where = "recognised (known action)"
            release = second = ""
        rows.append((str(k), what, span, f"{demo.times[seg.end]:.2f}", seg.cause, where, release,
                     f"{step.emphasis:.3g}", second))
    header = ("#", "action", demo.row_name + "s", "t end", "ends", "attached to", "releaser", "e", "runner-up")
    widths = [max(len(r[c]) for r in [header, *rows]) for c in range(len(header))]
    for r in [header, *rows]:
        lines.append("  ".join(v.rjust(w) if c in (0, 3, 7) else v.ljust(w)
                               for c, (v, w) in enumerate(zip(r, widths))).rstrip())
    lines.append("")
    lines += [f"note: {note}" for note in teaching.notes]
    taught = ", ".join(term_to_text(s.task) for s in teaching.schemas) or "none"
    lines.append(f"taught {len(teaching.schemas)} sub-tasks of {term_to_text(teaching.task)}: {taught}")
    if teaching.untaught:
        lines.append(f"warning: not demonstrated, still without actions: "
                     f"{', '.join(term_to_text(t) for t in teaching.untaught)}")
    state = "accomplished" if teaching.accomplished else "NOT accomplished"
    lines.append(f"{term_to_text(teaching.task)} is {state} at the end of the demonstration "
                 f"({cond.to_text(teaching.post)})")
    before, after = count_nodes(lesson.tree), count_nodes(lesson.compressed)
    merged = sum(1 for b in walk(lesson.compressed) if b.merged_from)
    lines.append(f"learned task: {before} behaviours; compressed: {after} behaviours ({merged} merged)")
    if lesson.motions is not None:
        lines += motions_lines(lesson.motions)
    return lines


__all__ = ["learn", "Lesson", "lesson_lines", "where_demonstrated", "Motions", "Primitive", "fit_motions",
           "motions_json", "motions_lines"]
