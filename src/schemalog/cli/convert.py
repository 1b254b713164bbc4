"""`schemalog convert FILE`: knowledge between SEED, schema text and YAML, and BT.CPP XML in."""

from __future__ import annotations

import argparse
import sys

from ..errors import readable_name
from ..logic.terms import Struct, TRUE, term_to_text
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
    """Convert knowledge between SEED, schema text and YAML."""
    from ..formats.documents import Document, YAML_SUFFIXES, read_document, to_pl, to_yaml
    from ..logic.parse import Clause
    from ..task.schema import check_schemas
    from ..errors import SchemalogError
    from .common import check_output, defines, emit, inputs_of, instantiate_task, root_candidates, task_term
    from ..task.tree import declared_tasks

    check_output(args.output, inputs_of(args))
    if args.input.lower().endswith(".xml"):          # BehaviorTree.CPP v4 (formats/btcpp.py)
        from .export import convert_xml
        return convert_xml(args)
    doc = read_document(args.input, args.max_bytes)
    for note in doc.notes:
        print(note, file=sys.stderr)
    if args.task:
        declaration = Clause(Struct("task", (task_term(args.task),)), TRUE, None)
        doc = Document((declaration, *doc.items), doc.file, doc.notes, doc.seed)
    loaded = doc.to_kb()
    loaded.max_steps = args.max_steps
    check_schemas(loaded)  # what is written must load again: check before writing
    target = args.to or ("yaml" if args.output and args.output.endswith(YAML_SUFFIXES) else
                         "seed" if args.output and args.output.endswith(SEED_SUFFIXES) else "pl")
    if args.task:
        # A task the file does not define would be declared and written: refuse it, and
        # build it, so that a rule that fails or loops is said here rather than on loading.
        term = task_term(args.task)
        if not defines(loaded, term):
            roots = [r for r in root_candidates(loaded) if r != term_to_text(term)]
            hint = f"; its tasks: {', '.join(roots[:8])}" if roots else ""
            raise SchemalogError(f"{term_to_text(term)} is not a task of {doc.file}: no schema for it "
                                 f"(nothing written){hint}")
        instantiate_task(loaded, term, args)
    if target == "seed":
        text = _seed(loaded, doc, args)
    elif target == "yaml":
        text = to_yaml(doc)
    else:
        origin = "the SEED long-term memory" if doc.seed else ""
        header = f"Converted by schemalog from {origin + ' ' if origin else ''}{readable_name(doc.file)}."
        text = to_pl(doc, header=header)
    tasks = ", ".join(term_to_text(t) for t in declared_tasks(loaded)) or "none declared"
    clauses = len(doc.items)
    emit(text, args.output, inputs_of(args, loaded.files),
         f"{clauses} clause{'s' if clauses != 1 else ''} as "
         f"{ {'yaml': 'YAML', 'seed': 'SEED long-term memory'}.get(target, 'schema text')}; "
         f"tasks: {tasks}")
    return 0


SEED_SUFFIXES = (".prolog",)


def _seed(kb, doc, args: argparse.Namespace) -> str:
    """The trees of the file's tasks (or --task) as SEED long-term memory."""
    from ..formats.render import carried_clauses, tree_document
    from ..formats.seed import seed_text
    from .common import choose_tasks, instantiate_task

    tasks = choose_tasks(kb, args.task, every=True) or choose_tasks(kb, None)
    clauses: list = []
    for task in tasks:
        for c in tree_document(instantiate_task(kb, task, args)).items:
            if c not in clauses:
                clauses.append(c)
    clauses += carried_clauses(kb)
    names = ", ".join(term_to_text(t) for t in tasks)
    return seed_text(clauses, header=f"SEED long-term memory written by schemalog from {readable_name(doc.file)}, "
                                     f"task{'s' if len(tasks) > 1 else ''} {names}.")
