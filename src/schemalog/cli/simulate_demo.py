"""`schemalog simulate-demo --scene FILE`: a synthetic demonstration of a task in a scene."""

from __future__ import annotations

import argparse
import sys

from .. import defaults
from ..errors import UsageError
from .options import Parents, bounded, count, length, positive


def register(sub, parents: Parents) -> None:
    """Add `schemalog simulate-demo` and its arguments to the command line."""
    p = sub.add_parser("simulate-demo", parents=[parents.resources],
                      help="write a synthetic demonstration of a task in a scene")
    p.add_argument("files", nargs="*", metavar="FILE",
                   help="the task knowledge (default: the scene's knowledge: entry)")
    p.add_argument("--scene", required=True, metavar="FILE", help="object positions (YAML)")
    p.add_argument("--task", help="the task to demonstrate (default: the first task/1)")
    p.add_argument("-o", "--output", help="write here (atomically; .json for JSON, else CSV); default: standard output")
    p.add_argument("--seed", type=count, default=0, help="seed of the noise and of --jitter, a whole number "
                   "at least 0 (default 0)")
    p.add_argument("--noise", type=bounded(0, defaults.MAX_NOISE, float), default=defaults.NOISE, metavar="M",
                   help=f"standard deviation of the hand's position noise (default {defaults.NOISE} m, "
                        f"at most {defaults.MAX_NOISE} m)")
    p.add_argument("--jitter", type=bounded(0, defaults.MAX_JITTER, float), default=0.0, metavar="M",
                   help=f"move each object coordinate by up to M metres (with --seed; default 0, at most "
                        f"{defaults.MAX_JITTER:g} m: here --seed also seeds the noise, and the objects "
                        f"stay where the scene puts them unless asked; run's default is {defaults.JITTER})")
    p.add_argument("--rate", type=bounded(1, defaults.MAX_RATE, float), default=defaults.RATE, metavar="HZ",
                   help=f"samples per second (default {defaults.RATE:g}, at most {defaults.MAX_RATE:,g})")
    p.add_argument("--speed", type=bounded(0.01, 2.0, float), default=defaults.SPEED, metavar="M/S",
                   help=f"the speed of the teacher's motions, 0.01 to 2 (default {defaults.SPEED} m/s; each motion "
                        f"also takes 0.3 s to start and stop)")
    p.add_argument("--radius", type=length, default=defaults.RADIUS, metavar="M",
                   help=f"the proximity radius the demonstration is planned for (default {defaults.RADIUS} m)")
    p.add_argument("--max-bytes", type=positive, default=defaults.MAX_BYTES,
                   help=f"refuse input files larger than this (default {defaults.MAX_BYTES:,})")
    p.add_argument("--max-steps", type=positive, default=defaults.MAX_STEPS, metavar="N",
                   help=f"resolution steps one directive of a file, or one look-up of the task's "
                        f"knowledge, may take (default {defaults.MAX_STEPS:,})")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Write a synthetic demonstration of a task in a scene (smooth motions with noise)."""
    import schemalog
    from ..api.learning import read_scene, simulated
    from .common import check_output, emit, inputs_of

    check_output(args.output, inputs_of(args))   # the scene and the files named, before reading them
    scene = read_scene(args.scene, args.max_bytes)
    files = args.files or ([scene.knowledge] if scene.knowledge else [])
    if not files:
        raise UsageError(f"which task knowledge? {args.scene} names none (knowledge: in the scene): "
                         f"give the task file, e.g. kb/tasks/prepare_coffee_and_tea.pl")
    check_output(args.output, inputs_of(args, files))
    knowledge = schemalog.load(*files, max_bytes=args.max_bytes, max_steps=args.max_steps)
    inputs = inputs_of(args, files, knowledge.files)
    check_output(args.output, inputs)            # and every file they consult, before simulating
    json_out = bool(args.output) and args.output.lower().endswith(".json")
    demo = simulated(knowledge, args.task, scene, scene_file=args.scene, output=args.output, seed=args.seed,
                     noise=args.noise, rate=args.rate, speed=args.speed, radius=args.radius, jitter=args.jitter,
                     as_json=json_out)
    if args.output and args.output != "-":
        emit(demo.text, args.output, inputs, f"{demo.summary} ({'JSON' if json_out else 'CSV'})")
    else:
        sys.stdout.write(demo.text)
        print(demo.summary, file=sys.stderr)
    return 0
