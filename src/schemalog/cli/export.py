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
    from ..logic.terms import term_to_text
    from ..run.world import World, initial_state
    from ..task.tree import count_nodes
    from .common import atoms_option, emit, inputs_of, load_files, trees_to_use

    target = args.to
    if target is None:
        suffix = (args.output or "").rsplit(".", 1)[-1].lower() if args.output and "." in args.output else ""
        target = {"xml": "btcpp", "py": "py_trees"}.get(suffix)
        if target is None:
            raise UsageError("name the runtime with --to btcpp or --to py_trees (or give -o a .xml or .py name)")
    kb, _ = load_files(args)
    original, tree, kind = trees_to_use(kb, args)
    initial = atoms_option(args.state, "--state") if args.state is not None else initial_state(kb)
    # The world settles the initial state (a composite whose parts hold is accomplished), and
    # the runtime starts from what the world starts from.
    start = World(original, initial).atoms
    atoms = sorted(start, key=term_to_text)
    title = (f"{term_to_text(tree.label)} from {', '.join(map(readable_name, args.files))}: {kind} tree of "
             f"{count_nodes(tree)} behaviours, exported by schemalog")
    from ..formats.quoting import Unquotable
    try:
        if target == "btcpp":
            from ..formats.btcpp import export_btcpp
            text = export_btcpp(tree, atoms, title)
        else:
            from ..formats.pytrees import export_pytrees
            text = export_pytrees(tree, atoms, title)
    except Unquotable as err:
        raise Unquotable(f"cannot export {term_to_text(tree.label)} to {target}: {err.message}") from None
    what = "BehaviorTree.CPP v4 XML" if target == "btcpp" else "a py_trees module"
    emit(text, args.output, inputs_of(args, kb.files),
         f"{term_to_text(tree.label)}, {kind} tree of {count_nodes(tree)} behaviours ({what})")
    return 0


def convert_xml(args: argparse.Namespace) -> int:
    """`convert tree.xml`: a BT.CPP v4 document as schema knowledge (or YAML)."""
    from ..errors import SchemalogError, SourcePos
    from ..formats.btcpp import import_btcpp
    from ..formats.documents import YAML_SUFFIXES, to_pl, to_yaml
    from ..formats.render import tree_document
    from ..inputs import read_limited
    from ..logic.parse import Clause
    from ..logic.terms import TRUE, Struct, term_to_text
    from ..task.schema import check_schemas
    from .common import emit, inputs_of, task_term

    if getattr(args, "to", None) not in (None, "pl", "yaml"):
        from ..errors import UsageError
        raise UsageError(f"--to {args.to}: a BT.CPP document converts to pl or yaml")
    def decoded(path: str) -> str:
        data = read_limited(path, args.max_bytes)
        try:
            return data.decode("utf-8-sig")
        except UnicodeDecodeError as err:
            line = data[:err.start].count(b"\n") + 1
            column = err.start - (data.rfind(b"\n", 0, err.start) + 1) + 1
            raise SchemalogError("not UTF-8 text", SourcePos(path, line, column)) from None

    text = decoded(args.input)
    imported = import_btcpp(text, args.input, decoded)
    if args.task and task_term(args.task) != imported.tree.label:
        raise SchemalogError(f"--task {args.task}: the task of {args.input} is {term_to_text(imported.tree.label)}")
    initial = [Clause(Struct("initial", (atom,)), TRUE, None) for atom in imported.initial]
    doc = tree_document(imported.tree, args.input, initial)
    check_schemas(doc.to_kb())     # what is written must load again
    yaml = args.to == "yaml" or (args.to is None and args.output and args.output.endswith(YAML_SUFFIXES))
    out = to_yaml(doc) if yaml else to_pl(doc, header=f"Converted by schemalog from the BehaviorTree.CPP "
                                                      f"document {readable_name(args.input)}.")
    from ..task.tree import count_nodes
    emit(out, args.output, inputs_of(args, imported.includes),
         f"{term_to_text(imported.tree.label)}: {count_nodes(imported.tree)} behaviours as "
         f"{'YAML' if yaml else 'schema text'}")
    return 0
