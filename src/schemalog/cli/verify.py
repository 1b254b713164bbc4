"""`schemalog verify FILE [COMPRESSED]`: prove a compressed task against its original."""

from __future__ import annotations

import argparse
import json
import sys

from .. import defaults
from ..errors import UsageError
from .options import Parents, budget, positive

INCONCLUSIVE = 3    # verify: no counterexample, but no proof either (state limit, sampling)


def register(sub, parents: Parents) -> None:
    """Add `schemalog verify` and its arguments to the command line."""
    p = sub.add_parser("verify", parents=[parents.limits, parents.resources],
                       help="prove a compressed task against its original, with counterexamples")
    p.add_argument("files", nargs="+", metavar="FILE",
                   help="a task file (compressed here), or an original and a compressed file; for BT.CPP trees, "
                        "each may be a folder whose *.xml files are read as one program")
    p.add_argument("--task", help="the task (default: the first task/1); for BT.CPP trees, the BehaviorTree "
                        "ID to run (default: main_tree_to_execute)")
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
                        f"(default {defaults.MAX_STATES:,}); for BT.CPP trees, pairs of states in all, one budget for "
                        f"the whole proof")
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
    from .trees import add_nodes_option
    add_nodes_option(p)
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
    import schemalog
    from .common import check_output, emit, inputs_of, said
    from .trees import run_verify, schema_route, tree_route

    if tree_route(args):               # BT.CPP trees: BT.CPP's semantics (cli/trees.py)
        return run_verify(args)
    schema_route(args)
    check_output(args.output, inputs_of(args))   # before anything is read
    original, compressed, inputs = _verify_inputs(args)
    tty = bool(args.sample) and sys.stderr.isatty()
    states = args.states if args.states in ("default", "all") else args.states
    report = schemalog.verify(original, compressed, states=states, method=args.method, max_states=args.max_states,
                              max_bdd_nodes=args.max_bdd_nodes, split=not args.no_split, scene=args.scene,
                              sample=args.sample, seed=args.seed or 0, progress=_progress if tty else None)
    if tty:
        print("\r\033[K", end="", file=sys.stderr, flush=True)
    said(report.notes)
    if args.json:
        emit(json.dumps(report.as_json(), indent=2) + "\n", args.output, inputs_of(args, inputs),
             report.words("JSON"))
    else:
        emit(report.text(), args.output, inputs_of(args, inputs), report.words("text"))
    return report.exit_status


def _verify_inputs(args: argparse.Namespace):
    """(original, compressed, files read): one task file compressed here, or an original file
    and a compressed file someone else produced."""
    import schemalog
    from .common import load_knowledge, said, task_of

    if len(args.files) == 2:
        first, second = (schemalog.load(path, max_bytes=args.max_bytes, max_steps=args.max_steps)
                         for path in args.files)
        for knowledge in (first, second):
            said(knowledge.warnings)
        original = task_of(first, args).original
        declared = second.tasks()
        name = args.task if args.task is not None else (declared[0] if declared else original.name)
        compressed = second.task(name, max_depth=args.max_depth, max_nodes=args.max_nodes)
        said(compressed.notes)
        if not compressed.provenance:
            raise UsageError(f"{args.files[1]} carries no provenance (origins/2): give one task file to "
                             f"compress and verify, or an original and a file written by schemalog compress")
        return original, compressed, [*first.files, *second.files]
    if len(args.files) != 1:
        raise UsageError("verify takes one task file, or an original and a compressed file")
    knowledge = load_knowledge(args)
    task = task_of(knowledge, args)
    if task.compressed:
        return task.original, task, list(knowledge.files)
    compressed = task.compress(args.propagate, sympy_budget=args.sympy_budget)
    said(compressed.notes)
    return task, compressed, list(knowledge.files)


