"""`schemalog export FILE --to btcpp|py_trees`: a task tree for a behaviour-tree runtime."""

from __future__ import annotations

import argparse

from .. import defaults
from ..errors import readable_name
from .options import TOGETHER, Parents, budget

TARGETS = ("btcpp", "py_trees")


def register(sub, parents: Parents) -> None:
    """Add `schemalog export` and its arguments to the command line."""
    p = sub.add_parser("export", parents=[parents.limits, parents.resources],
                       help="write a task tree for BehaviorTree.CPP v4 (XML) or py_trees (a Python module)")
    p.add_argument("files", nargs="+", metavar="FILE", help=f"knowledge files holding the task, {TOGETHER}")
    p.add_argument("--to", choices=TARGETS, help="the runtime (default: from -o's suffix, .xml or .py)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.add_argument("--task", help="the task to export (default: the first task/1)")
    p.add_argument("--compressed", action="store_true", help="compress first (Algorithm 1), then export")
    p.add_argument("--propagate", choices=list(defaults.PROPAGATE_MODES), default="full",
                   help="with --compressed: what merged behaviours pass to their children (default full)")
    p.add_argument("--state", metavar="ATOMS", help="the initial state the tree starts from "
                                                    "(default: the files' initial/1)")
    p.add_argument("--sympy-budget", type=budget, default=defaults.SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Export a task tree, original or compressed, for BT.CPP or py_trees."""
    from ..errors import UsageError
    from .common import emit, inputs_of, load_knowledge, task_to_use

    target = args.to
    if target is None:
        suffix = (args.output or "").rsplit(".", 1)[-1].lower() if args.output and "." in args.output else ""
        target = {"xml": "btcpp", "py": "py_trees"}.get(suffix)
        if target is None:
            raise UsageError("name the runtime with --to btcpp or --to py_trees (or give -o a .xml or .py name)")
    knowledge = load_knowledge(args)
    task = task_to_use(knowledge, args)
    text = task.text(target, args.state)
    what = "BehaviorTree.CPP v4 XML" if target == "btcpp" else "a py_trees module"
    emit(text, args.output, inputs_of(args, knowledge.files),
         f"{task.name}, {task.kind} tree of {len(task)} behaviours ({what})")
    return 0


def convert_xml(args: argparse.Namespace) -> int:
    """`convert tree.xml`: a BT.CPP v4 document as schema knowledge (or YAML)."""
    from ..api.knowledge import task_term, xml_document
    from ..errors import SchemalogError, UsageError
    from ..formats.documents import YAML_SUFFIXES, to_pl, to_yaml
    from ..logic.terms import term_to_text
    from .common import emit, inputs_of

    if getattr(args, "to", None) not in (None, "pl", "yaml"):
        raise UsageError(f"--to {args.to}: a BT.CPP document converts to pl or yaml")
    doc, imported = xml_document(args.input, args.max_bytes)
    if args.task and task_term(args.task) != imported.tree.label:
        raise SchemalogError(f"--task {args.task}: the task of {args.input} is {term_to_text(imported.tree.label)}")
    yaml = args.to == "yaml" or (args.to is None and args.output and args.output.endswith(YAML_SUFFIXES))
    out = to_yaml(doc) if yaml else to_pl(doc, header=f"Converted by schemalog from the BehaviorTree.CPP "
                                                      f"document {readable_name(args.input)}.")
    from ..task.tree import count_nodes
    emit(out, args.output, inputs_of(args, imported.includes),
         f"{term_to_text(imported.tree.label)}: {count_nodes(imported.tree)} behaviours as "
         f"{'YAML' if yaml else 'schema text'}")
    return 0
