"""`schemalog learn DEMO --structure FILE`: segment a demonstration and teach it (Sec. II-C, II-D)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from .. import defaults
from ..errors import READABLE, UsageError, readable_name
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
    from ..api.learning import learned, structure_files
    from ..api.outputs import Staging
    from .common import check_output, inputs_of

    named = [(o, option) for o, option in ((args.output, "-o"), (args.plot, "--plot"), (args.motions, "--motions"))
             if o and o != "-"]
    outputs = [o for o, _ in named]
    for out, option in named:                        # the demonstration and the structure, before reading
        check_output(out, inputs_of(args), option)
    if len(set(map(os.path.abspath, outputs))) < len(outputs):
        raise UsageError("-o, --plot and --motions must name different files")
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UsageError(f"--plot {args.plot}: name a .png, .svg or .pdf file")
    consulted = structure_files(args.structure)      # the files the structure consults
    for out, option in named:
        check_output(out, inputs_of(args, consulted), option)
    lesson = learned(args.demo, args.structure, args.task, radius=args.radius, hysteresis=args.hysteresis,
                     min_motion=args.min_motion, max_bytes=args.max_bytes, bases=args.bases,
                     motions=bool(args.motions))
    to_stdout = args.output is None or args.output == "-"
    # Everything is computed before anything is written, and the files are written side by side
    # under temporary names, then renamed together: bad input or a failed write leaves none behind.
    staging = Staging()
    try:
        if args.plot:
            lesson.plot(staging.stage(args.plot))
        if lesson.motions is not None:
            Path(staging.stage(args.motions)).write_text(lesson.motions, encoding="utf-8", errors=READABLE)
        if not to_stdout:
            Path(staging.stage(args.output)).write_text(lesson.text, encoding="utf-8", errors=READABLE)
        staging.commit()
    except OSError as err:
        raise staging.failed(err) from None
    finally:
        staging.clean()
    print("\n".join(lesson.report), file=sys.stderr if to_stdout else sys.stdout)
    said = {args.output: f"{lesson.task}, {lesson.behaviours} behaviours learned from {args.demo} (schema text)",
            args.plot: "the demonstration and its segments (a picture)",
            args.motions: "the motion primitives (JSON)"}
    for _, target in staging.staged:                 # what was written, as every writer says it
        print(f"wrote {readable_name(target)}: {said.get(target, '')}", file=sys.stderr)
    if to_stdout:
        sys.stdout.write(lesson.text)
    return 0
