"""Checking knowledge as `schemalog check` does: every schema read and validated, the tasks
instantiated, then linted (Knowledge.check).

    Checking(knowledge, task)   .schemas (how many)   .tasks() (each instantiated Task, in turn)
                                .lint(unused)         (the findings, lint's errors among them)
    Checked                     what Knowledge.check() returns: all of it at once

`quiet` is a context the caller may put around the passes that run no Prolog and make no
reference cycles (reading schemas, lint's passes over trees): the command line's turns the
garbage collector off there (cli/common.py, uncollected).
"""

from __future__ import annotations

from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Iterable, Iterator

from .. import defaults

if TYPE_CHECKING:
    from ..errors import SchemalogError
    from ..run.lint import Finding
    from .knowledge import Knowledge
    from .task import Task


@dataclass(frozen=True)
class Checked:
    """Knowledge checked: how many schemas, each task as instantiated (its original's tree
    linted), and lint's findings (None: not linted)."""

    schemas: int
    tasks: tuple[Task, ...]
    findings: tuple[Finding, ...] | None

    @property
    def errors(self) -> int:
        """How many of the findings are errors (which fail `schemalog check`)."""
        return errors(self.findings or ())

    @property
    def ok(self) -> bool:
        return self.errors == 0


class Checking:
    """One check, a step at a time (the command line prints each task's notes as it comes)."""

    def __init__(self, knowledge: Knowledge, task: str | None = None, *, max_depth: int = defaults.MAX_DEPTH,
                 max_nodes: int = defaults.MAX_NODES,
                 quiet: Callable[[], AbstractContextManager] = nullcontext) -> None:
        from ..task.schema import check_schemas, schema_clauses

        from .choosing import choose_tasks

        self.knowledge = knowledge
        self._quiet = quiet
        self._max = (max_depth, max_nodes)
        kb = knowledge._kb
        clauses = schema_clauses(kb)
        # read once: instantiating takes a ground fact's schema from here instead of reading it again
        with quiet():
            self._read: dict | None = {id(c): schema for c, schema in zip(clauses, check_schemas(kb))}
        self.schemas = len(self._read)
        self._terms = choose_tasks(kb, task, every=True)
        self.trees: list = []        # the originals of the tasks instantiated, for lint

    def tasks(self) -> Iterator[tuple[str, Task]]:
        """Each task instantiated in turn (every task/1, or the one named), with its name as
        asked (`add(X)`: the tree's label is the schema found), its notes in `notes`."""
        from ..logic.terms import term_to_text

        from .task import Task

        for term in self._terms:
            task = Task.instantiated(self.knowledge, term, *self._max, read=self._read)
            self.trees.append(task.original.tree)     # a compressed file: lint its original
            yield term_to_text(term), task
        self._read = None                             # the trees hold what they need of it

    def lint(self, unused: bool = True) -> tuple[Finding, ...]:
        """Lint's findings about the clauses and the trees instantiated (unused: also the
        schemas none of them uses); what stops lint is the one finding."""
        from ..errors import SchemalogError
        from ..run.lint import facts_of, lint_knowledge

        kb = self.knowledge._kb
        try:
            facts = facts_of(kb)             # may run Prolog: with the collector on
            with self._quiet():              # lint's passes over the tree make no cycles
                return lint_knowledge(kb, self.trees, facts, unused)
        except SchemalogError as err:
            return (finding_of(err),)


def check(knowledge: Knowledge, task: str | None = None, lint: bool = True, max_depth: int = defaults.MAX_DEPTH,
          max_nodes: int = defaults.MAX_NODES) -> Checked:
    """Knowledge.check(): the whole check at once."""
    checking = Checking(knowledge, task, max_depth=max_depth, max_nodes=max_nodes)
    tasks = tuple(task for _, task in checking.tasks())
    findings = checking.lint(unused=task is None) if lint else None
    return Checked(checking.schemas, tasks, findings)


def errors(findings: Iterable[Finding]) -> int:
    """How many findings are errors (lint's severity)."""
    from ..run.lint import ERROR

    return sum(1 for f in findings if f.severity == ERROR)


def finding_of(err: SchemalogError) -> Finding:
    """A load or instantiation error as lint's error finding (what stops lint is its one finding)."""
    from ..run.lint import error_finding

    return error_finding(err)
