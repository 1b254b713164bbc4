"""`schemalog convert FILE`: knowledge between SEED, schema text and YAML, and BT.CPP XML in."""

from __future__ import annotations

import argparse

from .options import Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog convert` and its arguments to the command line."""
    p = sub.add_parser("convert", parents=[parents.limits, parents.resources],
                       help="convert knowledge: SEED, schema text, YAML or BT.CPP XML -> schema text, YAML "
                            "or SEED")
    p.add_argument("input", metavar="FILE", help="the knowledge to convert: the authors' SEED format (.prolog), schema text (.pl), YAML (.yaml) or a BehaviorTree.CPP v4 tree (.xml)")
    p.add_argument("-o", "--output", help="output file; its suffix (.pl, .yaml, .prolog) picks the format")
    p.add_argument("--to", choices=["pl", "yaml", "seed"],
                   help="output format (default: from -o, else pl); seed writes the tasks' trees as "
                        "SEED long-term memory")
    p.add_argument("--task", help="declare this task (task/1) in the output; with --to seed, the task "
                                  "to write (default: every task/1)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Convert knowledge between SEED, schema text and YAML (a BT.CPP document: to schema text or YAML)."""
    from ..api.convert import Conversion, convert_xml
    from ..inputs import is_xml
    from .common import check_output, emit, inputs_of, said

    check_output(args.output, inputs_of(args))
    if is_xml(args.input):                           # BehaviorTree.CPP v4 (formats/btcpp.py), by content
        converted = convert_xml(args.input, getattr(args, "to", None), args.task, args.output, args.max_bytes)
    else:
        conversion = Conversion(args.input, args.max_bytes)
        said(conversion.notes)
        try:
            converted = conversion.convert(args.to, args.task, args.output, max_steps=args.max_steps,
                                           max_depth=args.max_depth, max_nodes=args.max_nodes)
        finally:
            said(conversion.warnings)
    emit(converted.text, args.output, inputs_of(args, converted.files), converted.what)
    return 0
