"""The schema language: task knowledge in the paper's form, read and written.

    schema(Task, [(Sub, Releaser), (Sub, Releaser, Importance), ...], Post).   a task
    schema(Leaf, [], Post).                   a primitive behaviour (a leaf)
    behaviour(Leaf).                          a leaf whose post-condition is `Leaf.done`
    agent(Pattern, Agent).                    who performs matching behaviours (default arm)
    object(O).                                O is an object: arguments that are objects
                                              are what a behaviour acts on
    objects(Pattern, [O, ...]).               the objects of matching behaviours, explicitly
    task(T).   initial(Literal).              the file's task; its initial state

    SchemaDef = (task, entries: tuple[Entry], post: Condition, body: Term, pos)
    Entry     = (behaviour: Term, releaser: Condition, importance: number)

Several files are one program (docs/syntax.md, Several files): what a schema/3,
behaviour/1, task/1, agent/2, objects/2 or origins/2 clause defines is its first
argument's, and belongs to one file; object/1, initial/1, free/1, constraint/1,
no_merge/1 and action/1 are declarations every file adds to (SCHEMA_LANGUAGE).

A schema may be a rule (`schema(en(S), [...], P) :- string(S), ...`): its body runs
when the task is instantiated. `Knowledge` is a whole file as an ordered list of
items, so that text -> YAML -> text round-trips exactly.
"""

from __future__ import annotations

import sys

from dataclasses import dataclass

from . import conditions as cond
from .conditions import Condition, NotACondition
from ..errors import SchemalogError, SourcePos, shown_number
from ..logic.kb import Definitions, KnowledgeBase, StoredClause
from ..logic.terms import (NIL, TRUE, Atom, Float, Int, Struct, Term, Var, conjuncts, list_items, make_list, term_to_text,
                    variable_names)

DEFAULT_AGENT = "arm"
DEFAULT_IMPORTANCE = 1

# How files share the schema language's predicates: a sub-task's schema is defined in one
# file (two files with schemas for unifying tasks are an error), declarations add up.
SCHEMA_LANGUAGE = Definitions(
    by_argument=frozenset({("schema", 3), ("behaviour", 1), ("task", 1), ("agent", 2), ("objects", 2),
                           ("origins", 2), ("task_origins", 2)}),
    shared=frozenset({("object", 1), ("initial", 1), ("free", 1), ("constraint", 1), ("no_merge", 1),
                      ("action", 1)}),
    by_unit=frozenset({("schema", 3)}))


def knowledge_base() -> KnowledgeBase:
    """An empty knowledge base that reads files in the schema language."""
    return KnowledgeBase(definitions=SCHEMA_LANGUAGE)


@dataclass(frozen=True, slots=True)
class Entry:
    """One sub-task of a schema, with its releaser and SEED importance."""

    behaviour: Term
    releaser: Condition
    importance: int | float = DEFAULT_IMPORTANCE


@dataclass(frozen=True, slots=True)
class SchemaDef:
    """A `schema/3` clause, read."""

    task: Term
    entries: tuple[Entry, ...]
    post: Condition
    body: Term = TRUE
    pos: SourcePos | None = None

    @property
    def is_leaf(self) -> bool:
        return not self.entries


class _Text:
    """A message's text, made only if the message is shown: most schemas read have no error."""

    __slots__ = ("make",)

    def __init__(self, make) -> None:
        self.make = make

    def __str__(self) -> str:
        return self.make()


_DEFAULT_WEIGHT = Int(DEFAULT_IMPORTANCE)   # an entry's weight when it gives none (a term: immutable)


def read_entry(term: Term, where: str) -> Entry:
    """Read `(Sub, Releaser)`, `(Sub, Releaser, Importance)` or SEED's `[Sub, Importance, Releasers]`."""
    if isinstance(term, Struct) and term.name == "," and len(term.args) == 2:
        sub, rest = term.args
        importance: Term = _DEFAULT_WEIGHT
        # (Sub, Releaser, W): a releaser is never a number, so a final number is the weight.
        if isinstance(rest, Struct) and rest.name == "," and len(rest.args) == 2 \
                and isinstance(rest.args[1], (Int, Float)):
            rest, importance = rest.args
        return Entry(_behaviour(sub, where), _condition(rest, _Text(lambda: f"the releaser of {term_to_text(sub)}"),
                                                        where),
                     _importance(importance, sub, where))
    items, tail = list_items(term)
    if tail == NIL and len(items) == 3 and isinstance(items[1], (Int, Float)):
        sub, weight, releasers = items
        return Entry(_behaviour(sub, where),
                     _condition(releasers, _Text(lambda: f"the releaser of {term_to_text(sub)}"), where),
                     _importance(weight, sub, where))
    raise SchemalogError(f"{where}: a sub-task must be (Behaviour, Releaser) or "
                         f"[Behaviour, Importance, [Releasers]], not {term_to_text(term)}")


def _importance(weight: Term, sub: Term, where: str) -> int | float:
    """A weight of emphasis: a finite number, at least 0 (NaN or infinity would rank nothing)."""
    problem = importance_problem(weight)
    if problem is not None:
        raise SchemalogError(f"{where}: the importance of {term_to_text(sub)} {problem}")
    return weight.value


def importance_problem(weight: Int | Float) -> str | None:
    """Why `weight` cannot weigh a behaviour, or None: emphasis is computed in floats, so an
    importance is a number from 0 to the largest float (NaN, infinity, a negative number and
    an integer no float holds are refused)."""
    # Compared, never converted: an integer past the float range (10**400) is simply larger
    # than the largest float, where float() or math.isfinite() would raise OverflowError.
    if 0 <= weight.value <= sys.float_info.max:
        return None
    return (f"must be a finite number at least 0 and at most {sys.float_info.max:.3g}, "
            f"not {shown_number(term_to_text(weight))}")


def _behaviour(term: Term, where: str) -> Term:
    if isinstance(term, (Atom, Struct, Var)) and not (isinstance(term, Atom) and term == NIL):
        return term
    raise SchemalogError(f"{where}: a behaviour must be an atom or compound term, not {term_to_text(term)}")


def _condition(term: Term, what: str, where: str) -> Condition:
    try:
        return cond.from_term(term)
    except NotACondition as err:
        raise SchemalogError(f"{where}: {what} is not a condition: {err}") from None


def read_schema(head: Term, body: Term = TRUE, pos: SourcePos | None = None,
                allow_unbound: bool = True) -> SchemaDef:
    """Read a `schema(Task, Subtasks, Post)` clause; raise SchemalogError with its position."""
    assert isinstance(head, Struct) and head.name == "schema" and len(head.args) == 3
    task, subs, post = head.args
    where = _Text(lambda: f"schema {term_to_text(task)}")
    try:
        if isinstance(task, Var) and body is TRUE:
            raise SchemalogError(f"{where}: the task of a schema fact cannot be a variable")
        if isinstance(subs, Var) and allow_unbound and body is not TRUE:
            return SchemaDef(task, (), cond.TRUE, body, pos)  # computed by the body: read when run
        items, tail = list_items(subs)
        if tail is not NIL and tail != NIL:
            raise SchemalogError(f"{where}: the sub-task list must be a list, not {term_to_text(subs)}")
        entries = tuple([read_entry(item, where) for item in items]) if items else ()
        if isinstance(post, Var) and allow_unbound and body is not TRUE:
            post_c = cond.TRUE
        else:
            post_c = _condition(post, "the post-condition", where)
        if not cond.is_conjunction_of_literals(post_c):
            raise SchemalogError(f"{where}: a post-condition must be literals joined by `and` "
                                 f"(what executing the behaviour makes true), not {cond.to_text(post_c)}")
        return SchemaDef(task, entries, post_c, body, pos)
    except SchemalogError as err:
        raise SchemalogError(err.message, err.pos or pos) from None


def static_schema(head: Term, body: Term = TRUE, pos: SourcePos | None = None) -> SchemaDef | None:
    """The schema a `schema/3` clause states in its head, or None when its list or post is
    computed by the body (or it does not read as a schema)."""
    if not (isinstance(head, Struct) and head.name == "schema" and len(head.args) == 3):
        return None
    items, tail = list_items(head.args[1])
    if tail != NIL or isinstance(head.args[2], Var):
        return None
    try:
        return read_schema(head, body, pos)
    except SchemalogError:
        return None


def schema_clauses(kb: KnowledgeBase) -> list[StoredClause]:
    """The user's `schema/3` clauses, in order."""
    return [c for c in kb.clauses("schema", 3) if not c.library]


def check_schemas(kb: KnowledgeBase) -> list[SchemaDef]:
    """Read every schema/3 clause, raising the first malformed one with its position."""
    return [read_schema(c.head, c.body, c.pos) for c in schema_clauses(kb)]


# ---------------------------------------------------------------------------
# Writing: canonical schema text

def entry_term(entry: Entry) -> Term:
    """An entry as the term `(Sub, Releaser)` or `(Sub, Releaser, W)`."""
    releaser = cond.to_term(entry.releaser)
    if entry.importance == DEFAULT_IMPORTANCE and isinstance(entry.importance, int):
        return Struct(",", (entry.behaviour, releaser))
    weight = Int(entry.importance) if isinstance(entry.importance, int) else Float(entry.importance)
    return Struct(",", (entry.behaviour, Struct(",", (releaser, weight))))


def schema_term(s: SchemaDef) -> Term:
    """The schema as a `schema/3` head term."""
    return Struct("schema", (s.task, make_list([entry_term(e) for e in s.entries]), cond.to_term(s.post)))


def write_clause(head: Term, body: Term = TRUE) -> str:
    """Canonical clause text; schemas are laid out one sub-task per line."""
    names = variable_names([head, body])
    if isinstance(head, Struct) and head.name == "schema" and len(head.args) == 3:
        task, subs, post = head.args
        items, tail = list_items(subs)
        if tail == NIL and items:
            pad = " " * len("schema(")
            lines = [f"schema({term_to_text(task, 999, names, spaced=True)},"]
            for i, item in enumerate(items):
                opener = f"{pad}[ " if i == 0 else f"{pad}  "
                closer = " ]," if i == len(items) - 1 else ","
                lines.append(f"{opener}{_entry_text(item, names)}{closer}")
            lines.append(f"{pad}{term_to_text(post, 999, names, spaced=True)})")
            text = "\n".join(lines)
        else:
            text = term_to_text(head, 1199, names)
    else:
        text = term_to_text(head, 1199, names)
    if body is not TRUE:
        text += " :-\n    " + ",\n    ".join(term_to_text(g, 999, names, spaced=True) for g in conjuncts(body))
    return text + "."


def _entry_text(item: Term, names: dict) -> str:
    # `(Sub, Releaser)` with a space after the comma, for reading; still one term.
    if isinstance(item, Struct) and item.name == "," and len(item.args) == 2:
        sub, rest = item.args
        parts = [sub]
        if isinstance(rest, Struct) and rest.name == "," and len(rest.args) == 2 \
                and isinstance(rest.args[1], (Int, Float)):
            parts += [rest.args[0], rest.args[1]]
        else:
            parts.append(rest)
        return "(" + ", ".join(term_to_text(p, 999, names, spaced=True) for p in parts) + ")"
    return term_to_text(item, 999, names, spaced=True)

