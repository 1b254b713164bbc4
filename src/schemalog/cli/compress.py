"""`schemalog compress FILE...`: merge sequential behaviours (Definition 1, Algorithm 1)."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING

from .. import defaults
from ..errors import readable_name
from ..logic.terms import term_to_text
from .options import TOGETHER, Parents, budget

if TYPE_CHECKING:  # for annotations only: these load when the command runs
    from ..logic.kb import KnowledgeBase


def register(sub, parents: Parents) -> None:
    """Add `schemalog compress` and its arguments to the command line."""
    p = sub.add_parser("compress", parents=[parents.limits, parents.resources, parents.output],
                       help="merge sequential behaviours (Definition 1, Algorithm 1)")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task to compress, {TOGETHER}")
    p.add_argument("--task", help="the task to compress (default: the first task/1)")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES), default="full",
                   help="what the children of a merged behaviour inherit: its pre AND not post "
                        "(full, default), its pre (pre: the paper's rule), or nothing (none)")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=f"simplify with sympy up to N variables (default {defaults.SYMPY_BUDGET}, "
                        f"at most {defaults.MAX_SYMPY_BUDGET}: its cost doubles per variable)")
    p.add_argument("--verify", action="store_true",
                   help="then prove the compressed task against the original from the initial state "
                        "(as schemalog verify; exit 1 on a counterexample, 3 without a proof)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Merge sequential behaviours (Algorithm 1) and report the paper's figures."""
    from ..formats.render import carried_clauses, rich_tree, tree_document, tree_json
    from ..task.compress import compress, protected_labels
    from ..task.conditions import Simplifier
    from .common import choose_tasks, emit, inputs_of, instantiate_task, load_files
    from ..run.world import World
    from .output import PICTURES, emit_picture, output_format, print_rich, written, FORMAT_WORDS
    from ..run.vacuity import vacuity_of
    from .verify import exit_status, verify_json, verify_lines

    fmt = output_format(args)          # a picture asked for without Graphviz: say so before any work
    kb, _ = load_files(args)
    inputs = inputs_of(args, kb.files)
    tree = instantiate_task(kb, choose_tasks(kb, args.task)[0], args)
    task = tree.label
    result = compress(tree, args.propagate, protected_labels(kb, tree),
                      Simplifier(sympy_budget=args.sympy_budget))
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    figures = (f"Bi = {result.nodes_before}, Bm = {result.nodes_after}, D = {result.depth_before}, "
               f"RD = (Bi - Bm) / (Bi - D) = {result.reduction_degree:.2f}")
    report = _verify_compression(kb, result, args) if args.verify else None
    vacuity = None if report is None else vacuity_of(result.original, World(result.original),
                                                     report.initial_states, defaults.MAX_STATES,
                                                     report.original_completes)
    code = 0 if report is None else exit_status(report, vacuity)
    how = f"propagate {result.propagate}"
    what = (f"{term_to_text(task)} compressed ({how}): {result.nodes_after} behaviours from "
            f"{result.nodes_before}, RD {result.reduction_degree:.2f} ({FORMAT_WORDS.get(fmt, fmt)})")
    if fmt == "json":
        data = {"task": term_to_text(task), "propagate": result.propagate,
                "nodes_before": result.nodes_before, "nodes_after": result.nodes_after,
                "depth_before": result.depth_before, "depth_after": result.depth_after,
                "reduction_degree": round(result.reduction_degree, 4),
                "conditions": {"simplified": result.simplifier.calls,
                               "needed_sympy": result.simplifier.sympy_calls},
                "notes": result.notes, "tree": tree_json(result.tree)}
        if report is not None:
            data["verification"] = verify_json(report, how, result.nodes_before, result.nodes_after, vacuity)
        emit(json.dumps(data, indent=2) + "\n", args.output, inputs, what)
        return code
    elif fmt == "dot" or fmt in PICTURES:    # the paper's Figure 2; the picture and its DOT text alike
        from ..formats.render import panels_dot

        panels, initial = _figure2(kb, result, args)
        name = term_to_text(result.original.label)
        if fmt == "dot":
            emit(panels_dot(name, panels, initial), args.output, inputs, what)
        else:
            emit_picture(name, panels, initial, fmt, args.output, inputs, what)
    elif fmt in ("pl", "yaml", "seed"):
        doc = tree_document(result.tree, carried=carried_clauses(kb))
        header = (f"Compressed by schemalog (Algorithm 1, propagate {result.propagate}) from "
                  f"{', '.join(map(readable_name, args.files))}, task {term_to_text(task)}.\n{figures}.\n"
                  f"`schemalog decompress` restores the original tree from the origins/2 facts.")
        emit(written(doc, fmt, header), args.output, inputs, what)
    else:
        from rich.console import Console, Group
        from rich.table import Table

        before = f"Original: {result.nodes_before} behaviours, depth {result.depth_before}"
        after = (f"Compressed (propagate {result.propagate}): {result.nodes_after} behaviours, "
                 f"depth {result.depth_after}")
        to_file = bool(args.output and args.output != "-")
        if to_file or Console().width >= 140:  # side by side where there is room
            table = Table(show_header=True, header_style="bold", box=None, pad_edge=False)
            table.add_column(before)
            table.add_column(after)
            table.add_row(rich_tree(result.original), rich_tree(result.tree))
            view = Group(table, "", figures)
        else:
            view = Group(rich_tree(result.original, before), "", rich_tree(result.tree, after), "", figures)
        print_rich(view, args.output, inputs, what)
    if report is not None:
        # After the compressed task (or alone, when that went to a file): what verify would print.
        print("\n" + "\n".join(verify_lines(report, how, result.nodes_before, result.nodes_after, "default",
                                                vacuity)))
    return code


def _figure2(kb: KnowledgeBase, result, args: argparse.Namespace) -> tuple[list, frozenset]:
    """The paper's Figure 2's panels: the learned tree, the merge with perceptual aliasing
    (--propagate none, its aliased behaviours marked), and the merge with --propagate; and
    the initial state they are coloured in."""
    from ..formats.render import aliased_behaviours, figure2_panels
    from ..task.compress import compress, protected_labels
    from ..task.conditions import Simplifier
    from .output import initial_atoms

    initial = initial_atoms(kb, result.original)
    merged, complete = aliased_behaviours(result.original, result.tree, initial)
    searched = "" if complete else "in the first 2,000 reachable states"
    if result.propagate == "none":
        return figure2_panels(result.original, result.tree, result.propagate, initial,
                              merged_aliased=merged, searched=searched), initial
    aliasing = compress(result.original, "none", protected_labels(kb, result.original),
                        Simplifier(sympy_budget=args.sympy_budget)).tree
    return figure2_panels(result.original, result.tree, result.propagate, initial, aliasing,
                          aliased_behaviours(result.original, aliasing, initial)[0], merged, searched), initial


def _verify_compression(kb: KnowledgeBase, result, args: argparse.Namespace):
    """`compress --verify`: prove the compressed tree against its original from the initial state."""
    from ..run.verify import prove
    from ..run.world import World, initial_state

    world = World(result.original)
    world.reset(initial_state(kb))
    initial = [world.atoms]
    task = result.original.label
    return prove(result.original, result.tree, world, initial, None, task)
