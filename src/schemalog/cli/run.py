"""`schemalog run FILE...`: execute a task with the attentional executive against an emulated robot."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING

from .. import defaults
from ..logic.terms import term_to_text
from .options import TOGETHER, Parents, budget, count, distance, positive

if TYPE_CHECKING:  # for annotations only: these load when the command runs
    from ..logic.terms import Term
    from ..run.execute import Decision, Executive
    from ..task.tree import Behaviour


def register(sub, parents: Parents) -> None:
    """Add `schemalog run` and its arguments to the command line."""
    p = sub.add_parser("run", parents=[parents.limits, parents.resources],
                       help="execute a task with the attentional executive against an emulated robot")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task to run, {TOGETHER}")
    p.add_argument("--task", help="the task to run (default: the first task/1)")
    p.add_argument("--scene", metavar="FILE", help="object positions (YAML, docs/semantics.md); "
                                                   "without it every lambda is neutral")
    p.add_argument("--compressed", action="store_true", help="compress first, then run in the same world")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES),
                   help="with --compressed: what merged behaviours pass to their children (default full)")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.add_argument("--state", metavar="ATOMS", help="the initial state, e.g. 'hand.free, spoon.taken' "
                                                    "(default: the file's initial/1 facts)")
    p.add_argument("--seed", type=int, help="move the scene's objects randomly with this seed")
    p.add_argument("--jitter", type=distance, metavar="M",
                   help=f"how far (metres, per coordinate) --seed moves objects (default {defaults.JITTER}: "
                        f"here --seed only moves objects, so it moves them unless told 0; simulate-demo's "
                        f"default is 0, its --seed also seeding the noise)")
    p.add_argument("--selector", choices=list(defaults.SELECTORS), default="incremental",
                   help="incremental (default): re-evaluate what an action touched; "
                        "scan: visit every behaviour at every decision, the paper's cost model")
    p.add_argument("--fail", action="append", metavar="LABEL",
                   help="make the robot fail this action's command (repeatable), e.g. 'a5(cup)'")
    p.add_argument("--fail-times", type=positive, metavar="N",
                   help="each --fail action fails only its first N commands (default: every one)")
    p.add_argument("--retries", type=count, default=defaults.RETRIES, metavar="N",
                   help=f"retry a failed behaviour N times before inhibiting it (default {defaults.RETRIES})")
    p.add_argument("--recovery", choices=list(defaults.RECOVERIES), default=defaults.RECOVERIES[0],
                   help="when the robot fails an action inside a merged behaviour: decompress (default) "
                        "splits just that behaviour into its actions, so only the failed one is retried "
                        "and inhibited; resume retries the merged behaviour from the failed action")
    p.add_argument("--max-decisions", type=positive, metavar="N",
                   help="stop after N decisions (default: 4 per action of the original task, at least 100)")
    p.add_argument("--json", action="store_true", help="print the run as JSON (docs/formats.md)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Execute a task with the attentional executive against an emulated robot."""
    from ..run.execute import Executive, RobotManager
    from ..run.scene import NO_SCENE
    from ..run.world import World, initial_state
    from ..task.tree import count_nodes, walk
    from .common import atoms_option, check_output, emit, inputs_of, load_files, scene_of, trees_to_use

    kb, _ = load_files(args)
    if args.propagate is not None and not args.compressed:
        print("note: --propagate applies with --compressed; this run compresses nothing", file=sys.stderr)
    args.propagate = args.propagate or "full"
    original, tree, kind = trees_to_use(kb, args)
    task = tree.label
    scene = scene_of(args, original)
    world = World(original)
    if args.state is not None:
        initial = atoms_option(args.state, "--state")
    else:
        initial = initial_state(kb)
        if not kb.clauses("initial", 1):
            print(f"note: {', '.join(args.files)} declares no initial state (initial/1): every atom "
                  f"starts false; give one with --state", file=sys.stderr)
    for atom in world.unknown(initial):
        print(f"warning: {'--state' if args.state is not None else 'initial/1'} names "
              f"{term_to_text(atom)}, which no condition of {term_to_text(task)} reads or sets",
              file=sys.stderr)
    world.reset(initial)
    failures = _failures(args, original, tree)
    executive = Executive(tree, world, scene, robot=RobotManager(scene, failures),
                          selector=args.selector, retries=args.retries, max_decisions=args.max_decisions,
                          recovery=args.recovery)
    if scene is NO_SCENE:
        print("note: no --scene: every behaviour gets the neutral lambda, so emphasis follows "
              "progress alone", file=sys.stderr)
    header = (f"run {term_to_text(task)}: {kind} tree of {count_nodes(tree)} behaviours; "
              f"selector {args.selector}; {_scene_words(scene)}")
    fmt = "json" if args.json else "text"
    inputs = inputs_of(args, kb.files)
    check_output(args.output, inputs)   # refuse before running, not after
    if fmt == "json":
        outcome = executive.run()
        data = run_json(executive, task, kind, initial, args)
        emit(json.dumps(data, indent=2) + "\n", args.output, inputs, _run_words(executive, "JSON"))
    else:
        lines = [header, f"initial state: {', '.join(term_to_text(a) for a in initial) or '(nothing true)'}"]
        out = sys.stdout if not args.output or args.output == "-" else None
        width = min(40, max(len(n.name) for n in walk(tree)))
        if out:
            print("\n".join(lines), flush=True)
            lines = []
        for decision in executive:
            text = decision_lines(decision, width)
            if out:
                print("\n".join(text))
            else:
                lines.extend(text)
        outcome = executive.outcome
        lines.extend(summary_lines(executive))
        if out:
            print("\n".join(lines))
        else:
            emit("\n".join(lines) + "\n", args.output, inputs, _run_words(executive, "text"))
    return 0 if outcome.completed else 1


def _run_words(ex: Executive, fmt: str) -> str:
    """What a run written to a file holds, for `wrote FILE: ...`."""
    return (f"the run of {term_to_text(ex.given_tree.label)}, {len(ex.decisions)} decisions, "
            f"{ex.outcome.status.value} ({fmt})")


def _scene_words(scene) -> str:
    """The scene as the header names it; without one every lambda is neutral."""
    from ..run.scene import NO_SCENE

    return "no scene (neutral distances)" if scene is NO_SCENE else f"scene {scene.name}"


def _failures(args: argparse.Namespace, original: Behaviour, tree: Behaviour) -> dict:
    """--fail LABEL (repeatable): the robot fails these commands (--fail-times, default always)."""
    from ..task.tree import walk
    from .common import term_option

    actions = {n.label for n in walk(original) if not n.children} | \
        {n.label for n in walk(tree) if not n.children}
    failures = {}
    for text in args.fail or []:
        label = term_option(text, "--fail")
        if label not in actions:
            print(f"warning: --fail {text}: no action (leaf behaviour) of the task is labelled "
                  f"{term_to_text(label)}, so no command will fail", file=sys.stderr)
        failures[label] = args.fail_times
    return failures


def decision_lines(d: Decision, width: int) -> list[str]:
    """One decision as text: the winner, its emphasis, the runner-up, merged actions beneath."""
    runner = f"{term_to_text(d.runner_up[0])} {d.runner_up[1]:.4g}" if d.runner_up else "-"
    status = f"  FAILED: the robot did not complete {term_to_text(d.failed)}" if d.failed is not None else ""
    lines = [f"{d.index:4d}  {term_to_text(d.behaviour):<{width}}  e {d.emphasis:<9.4g} "
             f"runner-up {runner:<{width + 8}} {d.enabled:3d} enabled{status}"]
    if d.apart:     # one behaviour used twice (add(water) in coffee and in tea): which is which
        lines.append(f"{'':6}(winner: {d.apart[0]}; runner-up: {d.apart[1]})")
    steps = [*d.skipped, *d.executed, *([d.failed] if d.failed is not None else [])]
    if len(steps) > 1 or (steps and steps[0] != d.behaviour):  # a merged behaviour: its actions
        lines.extend(f"{'':6}- {term_to_text(a)} (skipped: accomplished)" for a in d.skipped)
        lines.extend(f"{'':6}- {term_to_text(a)}" for a in d.executed)
        if d.failed is not None:
            lines.append(f"{'':6}- {term_to_text(d.failed)} (failed)")
    if d.decompressed:
        merged, *parts = (term_to_text(x) for x in d.decompressed)
        then = f"{term_to_text(d.failed)} is retried on its own" if d.inhibited is None else \
            f"{term_to_text(d.failed)} alone is inhibited"
        lines.append(f"{'':6}decompressed {merged} into {', '.join(parts)}: {then}")
    return lines


def _micro(seconds: float) -> str:
    return f"{seconds * 1e6:.0f} us" if seconds < 0.01 else f"{seconds * 1e3:.1f} ms"


def summary_lines(ex: Executive) -> list[str]:
    """The end of a run: status, reasons, decisions and time per decision."""
    from ..task.tree import count_nodes

    o = ex.outcome
    lines = [f"{o.status.value}: {o.reason}"]
    lines.extend(f"  {b}" for b in o.blocked)
    split = [d.decompressed[0] for d in ex.decisions if d.decompressed]
    if split:
        lines.append(f"decompressed {len(split)} merged behaviour{'s' if len(split) > 1 else ''} after failures "
                     f"({', '.join(term_to_text(x) for x in split)}): the tree went from "
                     f"{count_nodes(ex.given_tree)} to {count_nodes(ex.tree)} behaviours")
    times = sorted(d.seconds for d in ex.decisions)
    if times:
        mean = sum(times) / len(times)
        lines.append(f"{len(ex.decisions)} decisions, {len(ex.trace)} actions; time per decision "
                     f"({ex.selector_name}): mean {_micro(mean)}, median {_micro(times[len(times) // 2])}, "
                     f"max {_micro(times[-1])}")
    else:
        lines.append("no decision taken")
    return lines


def run_json(ex: Executive, task: Term, kind: str, initial: list[Term], args: argparse.Namespace) -> dict:
    """The run as data (docs/formats.md)."""
    from ..task.tree import count_nodes

    times = [d.seconds for d in ex.decisions]
    return {
        "task": term_to_text(task), "tree": kind, "behaviours": count_nodes(ex.given_tree),
        "final_behaviours": count_nodes(ex.tree), "recovery": ex.recovery,
        "selector": ex.selector_name, "scene": ex.scene.name,
        "initial_state": [term_to_text(a) for a in initial],
        "completed": ex.outcome.completed, "status": ex.outcome.status.value,
        "reason": ex.outcome.reason, "blocked": list(ex.outcome.blocked),
        "trace": [term_to_text(a) for a in ex.trace],
        "decisions": [{
            "index": d.index, "behaviour": term_to_text(d.behaviour), "emphasis": d.emphasis,
            "runner_up": None if d.runner_up is None else {
                "behaviour": term_to_text(d.runner_up[0]), "emphasis": d.runner_up[1],
                "where": d.apart[1] if d.apart else None},
            "where": d.apart[0] if d.apart else None,
            "enabled": d.enabled, "executed": [term_to_text(a) for a in d.executed],
            "skipped": [term_to_text(a) for a in d.skipped],
            "failed": None if d.failed is None else term_to_text(d.failed),
            "decompressed": None if not d.decompressed else {
                "behaviour": term_to_text(d.decompressed[0]),
                "into": [term_to_text(x) for x in d.decompressed[1:]]},
            "inhibited": None if d.inhibited is None else term_to_text(d.inhibited),
            "seconds": d.seconds, "hand": list(d.hand)} for d in ex.decisions],
        "decision_times": times,
        "final_state": sorted(term_to_text(a) for a in ex.world.atoms),
        "setup_seconds": ex.setup_seconds,
    }
