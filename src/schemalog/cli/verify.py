"""`schemalog verify FILE [COMPRESSED]`: prove a compressed task against its original."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.terms import term_to_text
from .options import Parents, budget, positive

if TYPE_CHECKING:  # for annotations only: these load when the command runs
    from ..logic.kb import KnowledgeBase
    from ..logic.terms import Term
    from ..run.vacuity import Vacuity
    from ..run.world import World


INCONCLUSIVE = 3    # verify: no counterexample, but no proof either (state limit, sampling)


def register(sub, parents: Parents) -> None:
    """Add `schemalog verify` and its arguments to the command line."""
    p = sub.add_parser("verify", parents=[parents.limits, parents.resources],
                       help="prove a compressed task against its original, with counterexamples")
    p.add_argument("files", nargs="+", metavar="FILE",
                   help="a task file (compressed here), or an original and a compressed file")
    p.add_argument("--task", help="the task (default: the first task/1)")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES), default="full",
                   help="how to compress a single task file (default full; pre is the paper's rule)")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.add_argument("--states", default="default", metavar="default|all|ATOMS",
                   help="initial states to cover: the file's (default), all assignments of the free atoms "
                        "that satisfy constraint/1, or one state such as 'hand.free, spoon.taken'")
    p.add_argument("--scene", metavar="FILE", help="scene for the selection diagnostic (winner-take-all runs)")
    p.add_argument("--max-states", type=positive, default=defaults.MAX_STATES, metavar="N",
                   help=f"stop exploring after N states per tree, or {defaults.WORK_PER_STATE:,} units of "
                        f"work (condition tests, state atoms) per state; the result then says it is no proof "
                        f"(default {defaults.MAX_STATES:,})")
    p.add_argument("--method", choices=["auto", "symbolic", "explicit"], default="auto",
                   help="explore states as sets (symbolic: decision diagrams, every covered initial state "
                        "at once), one by one (explicit: the reference, which also counts traces), or "
                        "symbolic where it is exact and explicit elsewhere (auto, the default)")
    p.add_argument("--max-bdd-nodes", type=positive, default=5_000_000, metavar="N",
                   help="symbolic: stop past N decision-diagram nodes alive at once, with no proof "
                        "(exit 3; default 5,000,000, about 160 MB)")
    p.add_argument("--no-split", action="store_true",
                   help="explore the whole task even where it splits into independent parts or sequential phases")
    p.add_argument("--sample", type=sample_runs, metavar="RUNS",
                   help=f"check RUNS random runs (at most {defaults.MAX_SAMPLE:,}) instead of every state: "
                        f"finds violations, proves nothing (exit 3 when none is found); within the work "
                        f"budget of --max-states")
    p.add_argument("--seed", type=int, help="random seed of --sample (default 0)")
    p.add_argument("--json", action="store_true", help="print the report as JSON (docs/formats.md)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=run, jitter=None)
    from .verify_each import add_arguments  # verify --each: many files as one sweep (cli/verify_each.py)
    add_arguments(p)


def sample_runs(text: str) -> int:
    """--sample RUNS: a positive count, at most MAX_SAMPLE."""
    runs = positive(text)
    if runs > defaults.MAX_SAMPLE:
        raise argparse.ArgumentTypeError(f"at most {defaults.MAX_SAMPLE:,} runs, not {runs:,}")
    return runs


def _progress(done: int, runs: int) -> None:
    """Sampling progress on a terminal's stderr, rewritten in place."""
    print(f"\rsampled {done:,} of {runs:,} runs", end="", file=sys.stderr, flush=True)


def run(args: argparse.Namespace) -> int:
    """Prove a compressed task against its original: soundness and completion, with diagnostics."""
    if args.each:
        from .verify_each import run_each
        return run_each(args)
    from ..run.verify import Verifier, prove
    from ..run.vacuity import vacuity_of
    from ..run.world import World
    from ..task.tree import count_nodes
    from .common import check_output, emit, inputs_of, scene_of

    check_output(args.output, inputs_of(args))   # before anything is read
    kb, original, compressed, how, inputs = _verify_inputs(args)
    task = original.label
    world = World(original)
    initial = _initial_states(args, kb, world, task)
    scene = scene_of(argparse.Namespace(**{**vars(args), "seed": None}), original)  # --seed samples here
    report = None
    if args.sample:
        tty = sys.stderr.isatty()
        verifier = Verifier(original, compressed, world, max_states=args.max_states)
        report = verifier.sample(initial, args.sample, args.seed or 0, scene, task,
                                 progress=_progress if tty else None)
        if tty:
            print("\r\033[K", end="", file=sys.stderr, flush=True)
    else:
        report = prove(original, compressed, world, initial, scene, task, args.method, args.max_states,
                       args.max_bdd_nodes, split=not args.no_split)
    vacuity = vacuity_of(original, World(original), report.initial_states, args.max_states,
                         report.original_completes)
    if args.json:
        emit(json.dumps(verify_json(report, how, count_nodes(original), count_nodes(compressed), vacuity),
                        indent=2) + "\n", args.output, inputs_of(args, inputs), _verdict_words(report, "JSON", vacuity))
    else:
        lines = verify_lines(report, how, count_nodes(original), count_nodes(compressed), args.states, vacuity)
        emit("\n".join(lines) + "\n", args.output, inputs_of(args, inputs), _verdict_words(report, "text", vacuity))
    return exit_status(report, vacuity)


def exit_status(report, vacuity: "Vacuity | None" = None) -> int:
    """1 on a counterexample or when the task itself never completes (a vacuous proof), 0 for a
    proof, INCONCLUSIVE otherwise."""
    if report.violated or (vacuity is not None and vacuity.vacuous):
        return 1
    return 0 if report.exhaustive and report.sound and report.complete else INCONCLUSIVE


def vacuity_lines(vacuity: "Vacuity | None") -> list[str]:
    """What the report says about the original task's own completion."""
    from ..run.verify import state_text

    if vacuity is None:
        return []
    if vacuity.vacuous:
        n = len(vacuity.states)
        where = "from the covered initial state" if n == 1 else f"from any of the {n} covered initial states"
        lines = [f"the task itself cannot complete: no run of the original accomplishes it {where}, so the "
                 f"properties above hold vacuously"]
        if vacuity.cause is not None:
            lines.append(f"  why (schemalog lint): {vacuity.cause.text()}")
        else:
            lines.append("  (lint finds no single cause: every run of the original gets stuck or loops)")
        return lines
    failing = vacuity.failing
    if not failing:
        return []
    shown = "; ".join(state_text(s) for s in failing[:5]) + ("; ..." if len(failing) > 5 else "")
    return [f"the original task cannot complete from {len(failing)} of {len(vacuity.states)} covered initial "
            f"states (the proof says nothing about those): {shown}"]


def _verify_inputs(args: argparse.Namespace):
    """(kb, original, compressed, how, inputs): one task file compressed here, or an original
    file and a compressed file someone else produced."""
    from ..task import conditions as cond
    from ..formats.documents import load_kb
    from ..task.compress import compress, original_of, protected_labels
    from ..task.conditions import Simplifier
    from ..task.tree import declared_tasks, walk
    from .common import choose_tasks, instantiate_task, load_files

    if len(args.files) == 2:
        first, second = (load_kb([path], args.max_bytes, args.max_steps) for path in args.files)
        task = choose_tasks(first, args.task)[0]
        other_tasks = declared_tasks(second) or [task]
        compressed = instantiate_task(second, other_tasks[0] if args.task is None else task, args)
        for kb in (first, second):
            for warning in kb.warnings:
                print(warning, file=sys.stderr)
        if any(n.origins for n in walk(compressed)):
            original = original_of(instantiate_task(first, task, args))
            if (compressed.label, compressed.post) != (original.label, original.post):
                raise SchemalogError(
                    f"{args.files[1]} compresses {term_to_text(compressed.label)} (post-condition "
                    f"{cond.to_text(compressed.post)}), not {term_to_text(original.label)} of {args.files[0]} "
                    f"({cond.to_text(original.post)}): name the task with --task")
            if original_of(compressed) != original:
                print(f"note: the provenance of {args.files[1]} does not rebuild {args.files[0]}'s "
                      f"{term_to_text(task)} exactly; the world is the original file's", file=sys.stderr)
            return first, original, compressed, f"{args.files[1]}", [*first.files, *second.files]
        raise UsageError(f"{args.files[1]} carries no provenance (origins/2): give one task file to "
                         f"compress and verify, or an original and a file written by schemalog compress")
    if len(args.files) != 1:
        raise UsageError("verify takes one task file, or an original and a compressed file")
    kb, _ = load_files(args)
    tree = instantiate_task(kb, choose_tasks(kb, args.task)[0], args)
    original = original_of(tree)
    if original is not tree:
        return kb, original, tree, "the compressed file", list(kb.files)
    result = compress(original, args.propagate, protected_labels(kb, original),
                      Simplifier(sympy_budget=args.sympy_budget))
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    return kb, original, result.tree, f"propagate {args.propagate}", list(kb.files)


def _initial_states(args: argparse.Namespace, kb: KnowledgeBase, world: World, task: Term) -> list:
    """--states default | all | 'atom, atom': the initial states to cover, settled."""
    from ..run.verify import all_states, constraints, free_atoms
    from ..run.world import initial_state
    from .common import atoms_option

    if args.states == "all":
        atoms = free_atoms(kb, world.original)
        states = all_states(world, atoms, constraints(kb))
        if not states:
            raise SchemalogError("no assignment of the free atoms satisfies the constraints (constraint/1)")
        return states
    if args.states == "default":
        atoms = initial_state(kb)
    else:
        atoms = atoms_option(args.states, "--states")
    for atom in world.unknown(atoms):
        print(f"warning: {term_to_text(atom)} is read or set by no condition of {term_to_text(task)}",
              file=sys.stderr)
    world.reset(atoms)
    return [world.atoms]


def verify_lines(report, how: str, before: int, after: int, states_option: str,
                 vacuity: Vacuity | None = None) -> list[str]:
    """The report as a person reads it: each property, and a counterexample where one fails."""
    from ..run.verify import state_text

    n = len(report.initial_states)
    which = "default: " + state_text(report.initial_states[0]) if states_option == "default" else \
        ("all that satisfy the constraints" if states_option == "all" else state_text(report.initial_states[0]))
    lines = [f"verify {term_to_text(report.task)}: original {before} behaviours, compressed {after} ({how}); "
             f"{n} initial state{'s' if n != 1 else ''} ({which})",
             (f"sampled: visited {report.compressed_states:,} states of the compressed tree in "
              f"{report.seconds:.2f} s (NOT a proof)" if report.sampled else
              (f"explored {report.compressed_states:,} states of the compressed tree as sets (at most "
               f"{report.nodes:,} decision-diagram nodes) in {report.seconds:.2f} s" if report.method == "symbolic" else
               f"explored {report.compressed_states:,} states of the compressed tree and "
               f"{report.original_states:,} of the original in {report.seconds:.2f} s")
              + (f", in {report.parts} parts" if report.parts > 1 else "")
              + ("" if report.exhaustive else f" (stopped at the limit of {report.limit}: NOT a proof)")),
             *([f"note: {report.note}"] if report.note else []), ""]
    titles = {"soundness": "soundness (no perceptual aliasing)", "completion": "completion",
              "flexibility": "flexibility (diagnostic)", "traces": "trace equivalence (diagnostic)",
              "selection": "selection under emphasis (diagnostic)"}
    for name, verdict in report.properties.items():
        sound = report.properties["soundness"].holds is True
        removed = _interleavings_removed(verdict) if name == "traces" and sound else None
        if removed is not None:
            lines.append(f"{titles[name]}: {removed}")
            lines.append("")
            continue
        status = {True: "holds", False: "FAILS", None: "unknown"}[verdict.holds]
        lines.append(f"{titles[name]}: {status}: {verdict.summary}")
        if verdict.counterexample is not None:
            lines.extend(counterexample_lines(verdict.counterexample))
        lines.append("")
    said = vacuity_lines(vacuity)
    if said:
        lines.extend([*said, ""])
    if report.violated:
        verdict = "the compressed tree is " + ("not sound" if report.properties["soundness"].holds is False
                                               else "not complete") + " (exit 1)"
    elif vacuity is not None and vacuity.vacuous:
        verdict = "vacuous: the task itself cannot complete, so nothing is proved about it (exit 1)"
    elif report.exhaustive:
        verdict = "the compressed tree is sound and complete (exit 0)"
    elif report.limit and not report.sampled:
        verdict = f"no proof: stopped at the limit of {report.limit}; no counterexample before it (exit 3)"
    else:
        verdict = "no counterexample found, but this is not a proof (exit 3)"
    lines.append(f"result: {verdict}")
    return lines


def _verdict_words(report, fmt: str, vacuity: "Vacuity | None" = None) -> str:
    """What a verification written to a file says, for `wrote FILE: ...`."""
    verdict = ("not sound" if report.properties["soundness"].holds is False else "not complete") \
        if report.violated else "vacuous (the task itself cannot complete)" if vacuity is not None and vacuity.vacuous \
        else "sound and complete" if report.exhaustive and report.sound and report.complete \
        else "no proof"
    return f"the verification of {term_to_text(report.task)}: {verdict} ({fmt})"


def _interleavings_removed(verdict) -> str | None:
    """Fewer complete traces in a sound compressed tree (each of its runs is one of the
    original's), as what merging does: it runs a merged sequence as one behaviour, so the orders
    its actions could interleave in are gone by design. None when the counts are not that
    (equal, unknown, infinite, or more traces)."""
    rows = verdict.details.get("states") if verdict.holds is False else None
    try:
        original = sum(r["original"] for r in rows)
        compressed = sum(r["compressed"] for r in rows)
    except (TypeError, KeyError):          # not counted, or infinitely many
        return None
    if compressed >= original:
        return None
    text = (f"{original - compressed:,} interleaving{'s' if original - compressed != 1 else ''} removed "
            f"by merging (by design: a merged behaviour runs its actions as one): the original has "
            f"{original:,} complete trace{'s' if original != 1 else ''}, the compressed tree {compressed:,}")
    lost = verdict.details.get("lost_example")
    if lost:
        text += "; e.g. this original trace is no longer produced: " + ", ".join(lost["trace"])
    return text


def counterexample_lines(ce) -> list[str]:
    from ..run.verify import state_text

    lines = [f"  counterexample, from the initial state {state_text(ce.initial)}:"]
    if not ce.path:
        lines.append("    (at the start)")
    for k, step in enumerate(ce.path, 1):
        actions = ", ".join(term_to_text(a) for a in step.actions)
        label = term_to_text(step.behaviour)
        lines.append(f"    {k:3d}  {label}" + (f"   [{actions}]" if actions != label else ""))
    if ce.action is not None:
        done = "".join(f"{term_to_text(a)}, " for a in ce.done_first)
        own = "" if ce.behaviour == ce.action and not done else f": {done}{term_to_text(ce.action)}"
        lines.append(f"    then the compressed tree takes {term_to_text(ce.behaviour)}{own}")
        lines.append(f"      ({ce.where})")
        lines.append(f"    the original would not take {term_to_text(ce.action)} there "
                     f"(state: {state_text(ce.state)}):")
    else:
        lines.append(f"    state: {state_text(ce.state)}")
    lines.extend(f"      {r}" for r in ce.reasons)
    return lines


def verify_json(report, how: str, before: int, after: int, vacuity: Vacuity | None = None) -> dict:
    """The report as data (docs/formats.md)."""
    def ce_json(ce):
        if ce is None:
            return None
        return {"initial": sorted(term_to_text(a) for a in ce.initial),
                "run": [{"behaviour": term_to_text(s.behaviour), "actions": [term_to_text(a) for a in s.actions]}
                        for s in ce.path],
                "state": sorted(term_to_text(a) for a in ce.state),
                "behaviour": None if ce.behaviour is None else term_to_text(ce.behaviour),
                "behaviour_path": ce.where or None,
                "actions_before": [term_to_text(a) for a in ce.done_first],
                "action": None if ce.action is None else term_to_text(ce.action),
                "reasons": list(ce.reasons)}
    return {
        "task": term_to_text(report.task), "compressed": how, "behaviours": {"original": before, "compressed": after},
        "sound": report.properties["soundness"].holds, "complete": report.properties["completion"].holds,
        "exhaustive": report.exhaustive,
        "states": len(report.initial_states),
        "initial_states": [sorted(term_to_text(a) for a in s) for s in report.initial_states],
        "explored": {"compressed": report.compressed_states, "original": report.original_states,
                     "seconds": report.seconds, "parts": report.parts, "sampled": report.sampled,
                     "stopped_at": report.limit or None, "method": report.method,
                     "bdd_nodes": report.nodes if report.method == "symbolic" else None,
                     "note": report.note or None},
        "counterexample": ce_json(report.properties["soundness"].counterexample
                                  or report.properties["completion"].counterexample),
        "properties": {name: {"holds": v.holds, "summary": v.summary, "counterexample": ce_json(v.counterexample),
                              **v.details} for name, v in report.properties.items()},
        **({} if vacuity is None else vacuity_json(vacuity)),
    }


def vacuity_json(vacuity: Vacuity) -> dict:
    """completing_states, not_completing_states, undecided_states, vacuous, and the lint cause."""
    def listed(flag):
        return [sorted(term_to_text(a) for a in s) for s, c in zip(vacuity.states, vacuity.completes) if c is flag]
    return {"completing_states": listed(True), "not_completing_states": listed(False),
            "undecided_states": listed(None), "vacuous": vacuity.vacuous,
            "vacuous_because": None if vacuity.cause is None else vacuity.cause.as_json()}
