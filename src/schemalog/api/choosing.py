"""Choosing a task in knowledge: a task named on the command line (`--task take(cup)`), or the
ones task/1 declares, else a helpful message naming the candidates (schemas no other uses).

Below knowledge.py (which re-exports these), so that what knowledge calls lazily (check.py)
can use them without an import circle.
"""

from __future__ import annotations

from ..errors import SchemalogError, UsageError
from ..logic.kb import KnowledgeBase
from ..logic.opread import parse_term
from ..logic.terms import Struct, Term, Var, term_to_text
from ..logic.unify import Bindings


def task_term(text: str) -> Term:
    """A task named in text, `prepareboth` or `take(cup)`."""
    try:
        return parse_term(text, "--task")
    except SchemalogError as err:
        raise UsageError(f"--task {text!r} is not a term: {err.message}") from None


def root_candidates(kb: KnowledgeBase) -> list[str]:
    """Schemas never used as a sub-task: likely tasks, for a helpful message."""
    from ..task.schema import check_schemas

    schemas = check_schemas(kb)
    used = {term_to_text(e.behaviour) for s in schemas for e in s.entries}
    return [term_to_text(s.task) for s in schemas if s.entries and term_to_text(s.task) not in used]


def choose_task(kb: KnowledgeBase, name: str | None) -> Term:
    """The task named (it must have a schema), or the first task/1."""
    return choose_tasks(kb, name)[0]


def choose_tasks(kb: KnowledgeBase, task: str | None, every: bool = False) -> list[Term]:
    """The task named, or the declared ones (every: all of them, else the first)."""
    from ..task.tree import declared_tasks

    if task is not None:
        term = task_term(task)
        if not defines(kb, term):
            known = [term_to_text(t) for t in declared_tasks(kb)] or root_candidates(kb)
            hint = f"; tasks here: {', '.join(known[:8])}" if known else ""
            raise SchemalogError(f"unknown task {term_to_text(term)}: no schema({term_to_text(term)}, "
                                 f"Subtasks, Post) in {', '.join(kb.files) or 'the knowledge'}{hint}")
        return [term]
    declared = declared_tasks(kb)
    if declared:
        return declared if every else declared[:1]
    if every:
        return []
    roots = root_candidates(kb)
    hint = f" (candidates: {', '.join(roots[:8])})" if roots else ""
    raise UsageError(f"no task declared with task/1: name one with --task{hint}")


def defines(kb: KnowledgeBase, task: Term) -> bool:
    """Whether some schema/3 head unifies with `task`."""
    goal = Struct("schema", (task, Var("_"), Var("_")))
    return any(Bindings().unify(c.head, goal) for c in kb.candidates("schema", 3, task) or [])
