"""`schemalog compress FILE...`: merge sequential behaviours (Definition 1, Algorithm 1)."""

from __future__ import annotations

import argparse
import json

from .. import defaults
from .options import TOGETHER, Parents, budget


def register(sub, parents: Parents) -> None:
    """Add `schemalog compress` and its arguments to the command line."""
    p = sub.add_parser("compress", parents=[parents.limits, parents.resources, parents.output],
                       help="merge sequential behaviours (Definition 1, Algorithm 1)")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task to compress, {TOGETHER}; "
                        "or BT.CPP tree files and folders of them (each folder's *.xml files), read as one program")
    p.add_argument("--task", help="the task to compress (default: the first task/1); for a BT.CPP tree, the "
                        "BehaviorTree ID to run (default: main_tree_to_execute)")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES), default="full",
                   help="what the children of a merged behaviour inherit: its pre AND not post "
                        "(full, default), its pre (pre: the paper's rule), or nothing (none)")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=f"simplify with sympy up to N variables (default {defaults.SYMPY_BUDGET}, "
                        f"at most {defaults.MAX_SYMPY_BUDGET}: its cost doubles per variable)")
    p.add_argument("--verify", action="store_true",
                   help="then prove the compressed task against the original from the initial state "
                        "(as schemalog verify; exit 1 on a counterexample, 3 without a proof)")
    from .trees import add_nodes_option
    add_nodes_option(p, max_states=True)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Merge sequential behaviours (Algorithm 1) and report the paper's figures."""
    import schemalog
    from ..api.figures import compression_json, figure2
    from ..formats.render import rich_tree
    from .common import emit, inputs_of, load_knowledge, said, task_of
    from .output import PICTURES, emit_picture, output_format, print_rich, FORMAT_WORDS

    from .trees import run_compress, schema_route, tree_route

    if tree_route(args):               # a BT.CPP tree: BT.CPP's semantics (cli/trees.py)
        return run_compress(args)
    schema_route(args)
    fmt = output_format(args)          # a picture asked for without Graphviz: say so before any work
    knowledge = load_knowledge(args)
    inputs = inputs_of(args, knowledge.files)
    task = task_of(knowledge, args)
    small = task.compress(args.propagate, sympy_budget=args.sympy_budget)
    said(small.notes)
    result = small.compression
    report = schemalog.verify(small.original, small) if args.verify else None
    code = 0 if report is None else report.exit_status
    how = f"propagate {result.propagate}"
    what = (f"{task.name} compressed ({how}): {result.nodes_after} behaviours from "
            f"{result.nodes_before}, RD {result.reduction_degree:.2f} ({FORMAT_WORDS.get(fmt, fmt)})")
    if fmt == "json":
        emit(json.dumps(compression_json(small, report), indent=2) + "\n", args.output, inputs, what)
        return code
    elif fmt == "dot" or fmt in PICTURES:    # the paper's Figure 2; the picture and its DOT text alike
        from ..formats.render import panels_dot

        panels, initial = figure2(small, args.sympy_budget)
        if fmt == "dot":
            emit(panels_dot(small.original.name, panels, initial), args.output, inputs, what)
        else:
            emit_picture(small.original.name, panels, initial, fmt, args.output, inputs, what)
    elif fmt in ("pl", "yaml", "seed"):
        emit(small.text(fmt), args.output, inputs, what)
    else:
        from rich.console import Console, Group
        from rich.table import Table

        before = f"Original: {result.nodes_before} behaviours, depth {result.depth_before}"
        after = (f"Compressed (propagate {result.propagate}): {result.nodes_after} behaviours, "
                 f"depth {result.depth_after}")
        to_file = bool(args.output and args.output != "-")
        initial = small.original.initial_atoms()    # both trees coloured in the original's initial state
        if to_file or Console().width >= 140:  # side by side where there is room
            table = Table(show_header=True, header_style="bold", box=None, pad_edge=False)
            table.add_column(before)
            table.add_column(after)
            table.add_row(rich_tree(small.original.tree, state=initial), rich_tree(small.tree, state=initial))
            view = Group(table, "", result.figures())
        else:
            view = Group(rich_tree(small.original.tree, before, state=initial), "",
                         rich_tree(small.tree, after, state=initial), "",
                         result.figures())
        print_rich(view, args.output, inputs, what)
    if report is not None:
        # After the compressed task (or alone, when that went to a file): what verify would print.
        said(report.notes)
        print("\n" + report.text(), end="")
    return code
