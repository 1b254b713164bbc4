"""Argument types, and the option groups several commands share (`parents=` in argparse).

Nothing here loads the engine: the defaults come from schemalog.defaults, so building the
whole command line (`schemalog --help`) stays cheap.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass

from .. import defaults
from ..api.limits import TIMEOUT_EXIT


# How a command reads its FILE arguments (docs/formats.md): the help of each says it.
TOGETHER = "read together as one knowledge base (schema text, YAML or the authors' SEED format)"


def whole(minimum: int):
    """An argparse type: a whole number at least `minimum`."""
    def read(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}")
        return value
    return read


positive = whole(1)
count = whole(0)


def distance(text: str) -> float:
    """An argparse type: a finite number at least 0 (metres)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (value >= 0 and value < float("inf")):
        raise argparse.ArgumentTypeError("must be a finite distance, at least 0")
    return value


def bounded(low: float, high: float, kind=int):
    """An argparse type: a number of `kind` from `low` to `high`."""
    def read(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a {'whole ' if kind is int else ''}number") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be from {low:g} to {high:,g}")
        return value
    return read


def length(text: str) -> float:
    """An argparse type: a finite positive number."""
    value = distance(text)
    if value <= 0:
        raise argparse.ArgumentTypeError("must be more than 0")
    return value


def seconds(text: str) -> float:
    """An argparse type: a time limit in seconds, from a millisecond to a year."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not defaults.MIN_TIMEOUT <= value <= defaults.MAX_TIMEOUT:     # NaN and inf too
        raise argparse.ArgumentTypeError(f"must be from {defaults.MIN_TIMEOUT:g} to {defaults.MAX_TIMEOUT:,} seconds")
    return value


def fraction(text: str) -> float:
    """An argparse type: a number from 0 to 1."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError("must be between 0 and 1")
    return value


def budget(text: str) -> int:
    """An argparse type: how many variables sympy may simplify."""
    value = positive(text)
    if value > defaults.MAX_SYMPY_BUDGET:
        raise argparse.ArgumentTypeError(f"at most {defaults.MAX_SYMPY_BUDGET} (sympy's cost doubles per variable; "
                                         f"16 ran for over 15 minutes on one condition)")
    return value


@dataclass(frozen=True)
class Parents:
    """The option groups commands take as argparse parents."""

    limits: argparse.ArgumentParser   # --max-bytes, --max-depth, --max-nodes, --max-steps: every command that reads knowledge
    output: argparse.ArgumentParser   # --format, --json, -o: commands that print a tree
    ask: argparse.ArgumentParser      # --task, --compressed, --state, ...: query and repl
    resources: argparse.ArgumentParser   # --timeout, --max-memory: every command but repl (cli/limits.py)


def shared_parents() -> Parents:
    """Build the option groups once, for every command to share."""
    limits = argparse.ArgumentParser(add_help=False)
    limits.add_argument("--max-bytes", type=positive, default=defaults.MAX_BYTES,
                        help=f"refuse input files larger than this (default {defaults.MAX_BYTES:,})")
    limits.add_argument("--max-depth", type=positive, default=defaults.MAX_DEPTH,
                        help=f"deepest task tree to instantiate (default {defaults.MAX_DEPTH})")
    limits.add_argument("--max-nodes", type=positive, default=defaults.MAX_NODES,
                        help=f"largest task tree to instantiate (default {defaults.MAX_NODES:,})")
    limits.add_argument("--max-steps", type=positive, default=defaults.MAX_STEPS, metavar="N",
                        help=f"resolution steps one query, or one directive of a file, may take "
                             f"(default {defaults.MAX_STEPS:,})")

    output = argparse.ArgumentParser(add_help=False)
    output.add_argument("--format", choices=["text", "json", "dot", "yaml", "pl", "seed"],
                        help="output format (default: from -o's suffix, else text)")
    output.add_argument("--json", action="store_true", help="same as --format json")
    output.add_argument("-o", "--output", help="write here (atomically) instead of standard output")

    ask = argparse.ArgumentParser(add_help=False)
    ask.add_argument("--task", help="the task enabled/1, emphasis/2 and next_action/1 look at (default: the first)")
    ask.add_argument("--compressed", action="store_true",
                     help="look at the task's compressed tree instead of the original")
    ask.add_argument("--state", metavar="ATOMS", help="the current state, e.g. 'hand.free, a1.done' "
                     "(default: the files' initial/1)")
    ask.add_argument("--scene", metavar="FILE", help="object positions for emphasis/2 (lambda)")
    ask.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES), default="full",
                     help="how compressed/2 and merged/3 propagate conditions (default full)")
    ask.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                     help=argparse.SUPPRESS)
    ask.set_defaults(seed=None, jitter=None)
    resources = argparse.ArgumentParser(add_help=False)
    resources.add_argument("--timeout", type=seconds, metavar="SECONDS",
                           help=f"stop after this much wall-clock time (exit {TIMEOUT_EXIT}; default: none)")
    resources.add_argument("--max-memory", metavar="SIZE",
                           help=f"memory ceiling, e.g. 512M, 4G or off (default: ${defaults.MEMORY_ENV}, "
                                f"else {defaults.MEMORY_FRACTION * 100:.0f}%% of physical memory)")
    return Parents(limits, output, ask, resources)
