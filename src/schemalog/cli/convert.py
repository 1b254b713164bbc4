"""`schemalog convert FILE`: knowledge between SEED, schema text and YAML."""

from __future__ import annotations

import argparse
import sys

from ..logic.terms import Struct, TRUE, term_to_text
from .options import Parents


def register(sub, parents: Parents) -> None:
    """Add `schemalog convert` and its arguments to the command line."""
    p = sub.add_parser("convert", parents=[parents.limits, parents.resources],
                       help="convert knowledge: SEED or schema text or YAML -> schema text or YAML")
    p.add_argument("input", metavar="FILE", help="the knowledge to convert: the authors' SEED format, schema text (.pl) or YAML (.yaml)")
    p.add_argument("-o", "--output", help="output file; its suffix (.pl, .yaml) picks the format")
    p.add_argument("--to", choices=["pl", "yaml"], help="output format (default: from -o, else pl)")
    p.add_argument("--task", help="declare this task (task/1) in the output")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Convert knowledge between SEED, schema text and YAML."""
    from ..formats.documents import Document, YAML_SUFFIXES, read_document, to_pl, to_yaml
    from ..logic.parse import Clause
    from ..task.schema import check_schemas
    from ..task.tree import declared_tasks
    from .common import check_output, emit, inputs_of, task_term

    check_output(args.output, inputs_of(args))
    doc = read_document(args.input, args.max_bytes)
    for note in doc.notes:
        print(note, file=sys.stderr)
    if args.task:
        declaration = Clause(Struct("task", (task_term(args.task),)), TRUE, None)
        doc = Document((declaration, *doc.items), doc.file, doc.notes, doc.seed)
    loaded = doc.to_kb()
    check_schemas(loaded)  # what is written must load again: check before writing
    target = args.to or ("yaml" if args.output and args.output.endswith(YAML_SUFFIXES) else "pl")
    if target == "yaml":
        text = to_yaml(doc)
    else:
        origin = "the SEED long-term memory" if doc.seed else ""
        header = f"Converted by schemalog from {origin + ' ' if origin else ''}{doc.file}."
        text = to_pl(doc, header=header)
    tasks = ", ".join(term_to_text(t) for t in declared_tasks(loaded)) or "none declared"
    clauses = len(doc.items)
    emit(text, args.output, inputs_of(args, loaded.files),
         f"{clauses} clause{'s' if clauses != 1 else ''} as {'YAML' if target == 'yaml' else 'schema text'}; "
         f"tasks: {tasks}")
    return 0
