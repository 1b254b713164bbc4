"""Learning from demonstration, end to end: a recording in, schema knowledge out (Sec. II-C, II-D).

    demonstration --segment--> segments --teach(structure)--> learned knowledge (text)
                                    \\--fit--> a motion primitive per action, and per merged
                                               behaviour of the compressed learned task

`learn` does the work and returns a `Lesson`; `lesson_lines` is the report a person reads.
Nothing is written here: the command line writes the outputs, atomically, once all succeeded.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from . import conditions as cond
from .compress import compress, protected_labels
from .demo import Demonstration, read_demonstration
from .documents import YAML_SUFFIXES, document_from_text, read_document, read_source, to_pl
from .errors import SchemalogError
from .kb import KnowledgeBase
from .segment import DEFAULT_HYSTERESIS, DEFAULT_MIN_MOTION, DEFAULT_RADIUS, Segment, segment
from .teach import Attachment, Teaching, learned_text, teach
from .terms import Term, term_to_text
from .tree import Behaviour, count_nodes, instantiate, walk


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
    primitives: dict = field(default_factory=dict)       # filled by primitives_of (motions.py)

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
          max_bytes: int | None = None) -> Lesson:
    """Segment the demonstration, teach the structure's task, and check what was learned."""
    demo = read_demonstration(demo_path, **({"max_bytes": max_bytes} if max_bytes else {}))
    limit = {"max_bytes": max_bytes} if max_bytes else {}
    structure = read_document(structure_path, **limit)
    kb = structure.to_kb(KnowledgeBase())
    # The structure is copied into the output: as written, or as Prolog when it is YAML or SEED.
    plain = not structure.seed and not structure_path.endswith(YAML_SUFFIXES)
    structure_text = read_source(structure_path, **limit) if plain else to_pl(structure)
    if task is None:
        from .tree import declared_tasks
        declared = declared_tasks(kb)
        if not declared:
            raise SchemalogError(f"{structure_path} declares no task/1: name the demonstrated task with --task")
        task = declared[0]
    segments = segment(demo, radius, hysteresis, min_motion=min_motion)
    teaching = teach(kb, task, demo, segments)
    rows = {a.label: where_demonstrated(demo, a.segment) for a in teaching.attachments}
    settings = (f"Segmentation: proximity radius {radius:g} m, hysteresis {hysteresis:g} m, "
                f"pauses under {min_motion:g} m dropped.")
    text = learned_text(teaching, kb, structure_text, demo_file=Path(demo_path).name,
                        structure_files=[structure_path], rows=rows, settings=settings)
    # What was learned must read back: the same checks `schemalog check` makes.
    learned_kb = document_from_text(text, "<learned>").to_kb(KnowledgeBase())
    tree = instantiate(learned_kb, task)
    compressed = compress(tree, "full", protected_labels(learned_kb, tree)).tree
    return Lesson(demo, segments, teaching, text, learned_kb, tree, compressed, radius)


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
        else:
            what = term_to_text(step.action)
            where = "recognised (known action)"
            release = ""
        rows.append((str(k), what, span, f"{demo.times[seg.end]:.2f}", seg.cause, where, release,
                     f"{step.emphasis:.3g}"))
    header = ("#", "action", demo.row_name + "s", "t end", "ends", "attached to", "releaser", "e")
    widths = [max(len(r[c]) for r in [header, *rows]) for c in range(len(header))]
    for r in [header, *rows]:
        lines.append("  ".join(v.rjust(w) if c in (0, 3, 7) else v.ljust(w)
                               for c, (v, w) in enumerate(zip(r, widths))).rstrip())
    lines.append("")
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
    return lines


__all__ = ["learn", "Lesson", "lesson_lines", "where_demonstrated"]
