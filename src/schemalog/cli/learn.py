"""`schemalog learn DEMO --structure FILE`: segment a demonstration and teach it (Sec. II-C, II-D)."""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

from .. import defaults
from ..errors import READABLE, SchemalogError, UsageError, readable_name
from .options import Parents, bounded, distance, length, positive


def register(sub, parents: Parents) -> None:
    """Add `schemalog learn` and its arguments to the command line."""
    p = sub.add_parser("learn", parents=[parents.resources],
                      help="learn task knowledge from a demonstration (Sec. II-C, II-D; docs/learning.md)")
    p.add_argument("demo", metavar="DEMO", help="the demonstration, CSV or JSON (docs/learning.md)")
    p.add_argument("--structure", required=True, metavar="FILE",
                   help="the partially specified task structure: schema knowledge whose sub-tasks have no actions")
    p.add_argument("--task", help="the demonstrated task (default: the structure's first task/1)")
    p.add_argument("-o", "--output", help="write the learned knowledge here (atomically); default: standard output")
    p.add_argument("--radius", type=length, default=defaults.RADIUS, metavar="M",
                   help=f"the proximity sphere around each object (default {defaults.RADIUS} m)")
    p.add_argument("--hysteresis", type=distance, default=defaults.HYSTERESIS, metavar="M",
                   help=f"how far beyond the radius leaving counts (default {defaults.HYSTERESIS} m)")
    p.add_argument("--min-motion", type=distance, default=defaults.MIN_MOTION, metavar="M",
                   help=f"a stretch moving the hand less than this is a pause, not an action (default {defaults.MIN_MOTION} m)")
    p.add_argument("--max-bytes", type=positive, default=defaults.MAX_DEMO_BYTES,
                   help=f"refuse a demonstration larger than this (default {defaults.MAX_DEMO_BYTES:,})")
    p.add_argument("--plot", metavar="FILE", help="draw the trajectory, its segments and objects, and the merged "
                   "primitives (PNG, SVG or PDF by suffix)")
    p.add_argument("--motions", metavar="FILE", help="write the motion primitives (DMPs) and their reproduction "
                   "errors as JSON")
    p.add_argument("--bases", type=bounded(0, defaults.MAX_BASES), default=defaults.BASES, metavar="N",
                   help=f"basis functions of a primitive per segment (default {defaults.BASES}, at most "
                        f"{defaults.MAX_BASES}; 0: no primitives)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Segment a demonstration, teach it to a task structure, and write the learned knowledge."""
    from ..formats.documents import read_document
    from ..logic.terms import term_to_text
    from ..task.tree import count_nodes
    from .common import check_output, inputs_of, task_term

    from ..learn.learn import learn, lesson_lines, motions_json

    named = [(o, option) for o, option in ((args.output, "-o"), (args.plot, "--plot"), (args.motions, "--motions"))
             if o and o != "-"]
    outputs = [o for o, _ in named]
    for out, option in named:                        # the demonstration and the structure, before reading
        check_output(out, inputs_of(args), option)
    if len(set(map(os.path.abspath, outputs))) < len(outputs):
        raise UsageError("-o, --plot and --motions must name different files")
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UsageError(f"--plot {args.plot}: name a .png, .svg or .pdf file")
    consulted = read_document(args.structure).to_kb().files  # the files the structure consults
    for out, option in named:
        check_output(out, inputs_of(args, consulted), option)
    task = task_term(args.task) if args.task else None
    lesson = learn(args.demo, args.structure, task, radius=args.radius, hysteresis=args.hysteresis,
                   min_motion=args.min_motion, max_bytes=args.max_bytes, bases=args.bases)
    report = lesson_lines(lesson)
    to_stdout = args.output is None or args.output == "-"
    motions_text = None
    if args.motions:
        if lesson.motions is None:
            raise UsageError("--motions needs primitives: --bases 0 turns them off")
        motions_text = json.dumps(motions_json(lesson, lesson.motions), indent=1) + "\n"
    # Everything is computed before anything is written, and the files are written side by side
    # under temporary names, then renamed together: bad input or a failed write leaves none behind.
    staged: list[tuple[str, str]] = []
    try:
        if args.plot:
            from ..evaluate.figures import demonstration_figure
            demonstration_figure(lesson, Path(_stage(args.plot, staged)))
        if motions_text is not None:
            Path(_stage(args.motions, staged)).write_text(motions_text, encoding="utf-8", errors=READABLE)
        if not to_stdout:
            Path(_stage(args.output, staged)).write_text(lesson.text, encoding="utf-8", errors=READABLE)
        _commit(staged)
    except OSError as err:
        temporaries = {t: target for t, target in staged}
        name = temporaries.get(err.filename, err.filename) if err.filename else (staged[-1][1] if staged else "")
        raise SchemalogError(f"cannot write {name or 'the output'}: {err.strerror or err}; nothing was written") from None
    finally:
        for temporary, _ in staged:
            if os.path.exists(temporary):
                os.unlink(temporary)
    print("\n".join(report), file=sys.stderr if to_stdout else sys.stdout)
    said = {args.output: f"{term_to_text(lesson.tree.label)}, {count_nodes(lesson.tree)} behaviours learned "
                         f"from {args.demo} (schema text)",
            args.plot: "the demonstration and its segments (a picture)",
            args.motions: "the motion primitives (JSON)"}
    for _, target in staged:                          # what was written, as every writer says it
        print(f"wrote {readable_name(target)}: {said.get(target, '')}", file=sys.stderr)
    if to_stdout:
        sys.stdout.write(lesson.text)
    return 0


def _stage(target: str, staged: list[tuple[str, str]]) -> str:
    """A temporary file beside `target`, with its suffix, to be renamed onto it (see run); for a
    FIFO or a device, one in the temporary directory, to be copied into it."""
    from ..formats.documents import output_target

    path = output_target(target)
    try:
        fd, temporary = tempfile.mkstemp(prefix=f".{path.path.name}.", suffix=Path(target).suffix,
                                         dir=None if path.in_place else path.path.parent)
    except OSError as err:
        raise OSError(err.errno, err.strerror, target) from None
    os.close(fd)
    staged.append((temporary, target))
    return temporary


def _commit(staged: list[tuple[str, str]]) -> None:
    """Write the special ones (FIFO, device) in place, then rename the staged files onto their
    targets (through links), together: a device that refuses (/dev/full) is found before any
    file is replaced, since it cannot be checked beforehand."""
    from ..formats.documents import file_mode, output_target, write_in_place

    targets = [(temporary, output_target(target)) for temporary, target in staged]
    for temporary, target in targets:
        if target.in_place:
            write_in_place(target.path, Path(temporary).read_bytes())
    for temporary, target in targets:
        if not target.in_place:
            os.chmod(temporary, file_mode(target.path))
    for temporary, target in targets:
        if not target.in_place:
            os.replace(temporary, target.path)
