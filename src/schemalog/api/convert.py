"""Knowledge from one format to another, as `schemalog convert` does it: SEED, schema text
and YAML to schema text, YAML or SEED; a BehaviorTree.CPP v4 document to schema text or YAML.

    Conversion(path)            the file read (`notes`: what reading it noted)
      .convert(to, task, output) -> Converted(text, what, files)

What is written must load again: it is checked (and a task named is instantiated) before
any text is made.
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import defaults
from ..errors import SchemalogError, UsageError, readable_name
from ..logic.terms import TRUE, Struct, term_to_text

SEED_SUFFIXES = (".prolog",)


@dataclass(frozen=True)
class Converted:
    """The converted text, what it is (for `wrote FILE: ...`), and every file that was read
    (Conversion.warnings: what instantiating the tasks said)."""

    text: str
    what: str
    files: tuple[str, ...]


class Conversion:
    """A knowledge file read for conversion (schema text, SEED or YAML)."""

    def __init__(self, path: str, max_bytes: int = defaults.MAX_BYTES) -> None:
        from ..formats.documents import read_document

        self.doc = read_document(path, max_bytes)
        self.notes: tuple[str, ...] = tuple(self.doc.notes)
        self.warnings: list[str] = []   # what instantiating said (SEED's left-out sub-tasks), as it comes

    def convert(self, to: str | None = None, task: str | None = None, output: str | None = None, *,
                max_steps: int = defaults.MAX_STEPS, max_depth: int = defaults.MAX_DEPTH,
                max_nodes: int = defaults.MAX_NODES) -> Converted:
        """The knowledge as `to` (pl, yaml, seed; default: from the output's suffix, else pl),
        task/1 of `task` declared (with seed: the task written, default every task/1)."""
        from ..formats.documents import YAML_SUFFIXES, Document, to_pl, to_yaml
        from ..logic.parse import Clause
        from ..task.schema import check_schemas
        from ..task.tree import Instantiator, declared_tasks

        from .choosing import defines, root_candidates, task_term

        doc = self.doc
        if task:
            declaration = Clause(Struct("task", (task_term(task),)), TRUE, None)
            doc = Document((declaration, *doc.items), doc.file, doc.notes, doc.seed)
        loaded = doc.to_kb()
        loaded.max_steps = max_steps
        check_schemas(loaded)  # what is written must load again: check before writing
        target = to or ("yaml" if output and output.endswith(YAML_SUFFIXES) else
                        "seed" if output and output.endswith(SEED_SUFFIXES) else "pl")

        def instantiate(term):
            instantiator = Instantiator(loaded, max_depth=max_depth, max_nodes=max_nodes)
            tree = instantiator.instantiate(term)
            self.warnings.extend(instantiator.warnings)
            return tree

        if task:
            # A task the file does not define would be declared and written: refuse it, and
            # build it, so that a rule that fails or loops is said here rather than on loading.
            term = task_term(task)
            if not defines(loaded, term):
                roots = [r for r in root_candidates(loaded) if r != term_to_text(term)]
                hint = f"; its tasks: {', '.join(roots[:8])}" if roots else ""
                raise SchemalogError(f"{term_to_text(term)} is not a task of {doc.file}: no schema for it "
                                     f"(nothing written){hint}")
            instantiate(term)
        if target == "seed":
            text = _seed(loaded, doc, task, instantiate)
        elif target == "yaml":
            text = to_yaml(doc)
        else:
            origin = "the SEED long-term memory" if doc.seed else ""
            header = f"Converted by schemalog from {origin + ' ' if origin else ''}{readable_name(doc.file)}."
            text = to_pl(doc, header=header)
        tasks = ", ".join(term_to_text(t) for t in declared_tasks(loaded)) or "none declared"
        clauses = len(doc.items)
        what = (f"{clauses} clause{'s' if clauses != 1 else ''} as "
                f"{ {'yaml': 'YAML', 'seed': 'SEED long-term memory'}.get(target, 'schema text')}; "
                f"tasks: {tasks}")
        return Converted(text, what, tuple(loaded.files))


def _seed(kb, doc, task: str | None, instantiate) -> str:
    """The trees of the file's tasks (or `task`) as SEED long-term memory."""
    from ..formats.render import carried_clauses, tree_document
    from ..formats.seed import seed_text

    from .choosing import choose_tasks

    tasks = choose_tasks(kb, task, every=True) or choose_tasks(kb, None)
    clauses: list = []
    for term in tasks:
        for c in tree_document(instantiate(term)).items:
            if c not in clauses:
                clauses.append(c)
    clauses += carried_clauses(kb)
    names = ", ".join(term_to_text(t) for t in tasks)
    return seed_text(clauses, header=f"SEED long-term memory written by schemalog from {readable_name(doc.file)}, "
                                     f"task{'s' if len(tasks) > 1 else ''} {names}.")


def convert_xml(path: str, to: str | None = None, task: str | None = None, output: str | None = None,
                max_bytes: int = defaults.MAX_BYTES) -> Converted:
    """A BT.CPP v4 document as schema knowledge (or YAML)."""
    from ..formats.documents import YAML_SUFFIXES, to_pl, to_yaml
    from ..task.tree import count_nodes

    from .knowledge import task_term, xml_document

    if to not in (None, "pl", "yaml"):
        raise UsageError(f"--to {to}: a BT.CPP document converts to pl or yaml")
    doc, imported = xml_document(path, max_bytes)
    if task and task_term(task) != imported.tree.label:
        raise SchemalogError(f"--task {task}: the task of {path} is {term_to_text(imported.tree.label)}")
    yaml = to == "yaml" or (to is None and output and output.endswith(YAML_SUFFIXES))
    out = to_yaml(doc) if yaml else to_pl(doc, header=f"Converted by schemalog from the BehaviorTree.CPP "
                                                      f"document {readable_name(path)}.")
    return Converted(out, f"{term_to_text(imported.tree.label)}: {count_nodes(imported.tree)} behaviours as "
                          f"{'YAML' if yaml else 'schema text'}", tuple(imported.includes))
