"""Queries and their answers over a workspace, as SWI-Prolog's top level reads and binds them.

    Query  = (goal: Term, names: list[(name, Var)])   the variables the user wrote, in order
    Answer = list[(name, Term)]                        resolved bindings, `X = Y` for aliases

An answer prints `X = f(Y), Z = 1`, or `true` when it binds nothing. Named variables with a
leading `_` are reported too, as SWI-Prolog 9 does (its flag toplevel_print_anon is true);
`_` alone is not. The command line prints these (cli/toplevel.py); the API gives them as
Python values (knowledge.py).
"""

from __future__ import annotations

import json
import math
import secrets
from dataclasses import dataclass
from typing import Callable, Iterator

from ..logic.builtins import compare_terms
from ..logic.opread import parse_term
from ..logic.terms import NIL, Atom, Float, Int, Struct, Term, Var, int_text, iter_vars, list_items, term_to_text, \
    variable_names
from ..logic.unify import Bindings
from .workspace import COMPRESSED, ORIGINAL, Workspace


@dataclass(frozen=True)
class Query:
    """A parsed query and the variables to report."""

    goal: Term
    names: tuple[tuple[str, Var], ...]


def read_query(text: str, file: str = "<query>", operators=None) -> Query:
    """Parse a query (the final '.' is optional) with the operators of `operators` (an
    OperatorTable: the workspace's, which the files' op/3 directives changed; default the
    reader's); syntax errors carry a caret."""
    goal = parse_term(text, file, operators, goal=True)
    seen: dict[Var, None] = {}
    for v in iter_vars(goal):
        seen.setdefault(v, None)
    return Query(goal, tuple((v.name, v) for v in seen if v.name and v.name != "_"))


@dataclass(frozen=True)
class Answer:
    """One answer: each query variable's value, and the print names of the free variables
    in them (a free variable shared by query variables is named after the last of them)."""

    values: tuple[tuple[str, Term], ...]
    names: dict
    # Each value's group: values equal (==) under the bindings share one. Compared before
    # resolving, as rational trees: X = f(X), Y = f(Y) are one group (X = Y, Y = f(Y)),
    # though their finite forms f(X) and f(Y) differ. Empty: compare the values themselves.
    classes: tuple[int, ...] = ()
    ops: object = None      # the Operators values are written with (default: the reader's)

    def groups(self) -> list[tuple[list[str], Term]]:
        """The query variables grouped by equal (==) values, in order of first appearance;
        a group's value is its last member's."""
        groups: list[tuple[list[str], Term]] = []
        found: dict[int, int] = {}
        for i, (name, value) in enumerate(self.values):
            if self.classes:
                at = found.get(self.classes[i])
                if at is None:
                    found[self.classes[i]] = len(groups)
                    groups.append(([name], value))
                else:
                    groups[at][0].append(name)
                    groups[at] = (groups[at][0], value)
                continue
            for members, shared in groups:
                if compare_terms(shared, value) == 0:     # ==, without recursion on deep terms
                    members.append(name)
                    break
            else:
                groups.append(([name], value))
        return groups


def answer_of(query: Query, b: Bindings, ops=None) -> Answer:
    """The bindings of one answer, resolved; `ops` the Operators to write it with."""
    values = tuple((name, b.resolve_finite(v)) for name, v in query.names)
    leaders: list[Var] = []
    classes = []
    for _, v in query.names:
        at = next((i for i, w in enumerate(leaders) if compare_terms(v, w, b) == 0), None)
        if at is None:
            at = len(leaders)
            leaders.append(v)
        classes.append(at)
    answer = Answer(values, variable_names([value for _, value in values]), tuple(classes), ops)
    for v in iter_vars(query.goal):             # `_Z` in the query keeps its name, as in SWI
        if v.name:
            answer.names[v] = v.name
    for members, value in answer.groups():
        if isinstance(value, Var):
            answer.names[value] = members[-1]
    return answer


def answer_text(answer: Answer) -> str:
    """`X = Y, Y = a, Z = [1, 2]` as SWI-Prolog prints it, or `true`."""
    parts = []
    for members, value in answer.groups():
        parts.extend(f"{a} = {b}" for a, b in zip(members, members[1:]))
        if not isinstance(value, Var):
            parts.append(f"{members[-1]} = {term_to_text(value, 699, answer.names, next_argument=True, ops=answer.ops)}")
    return ", ".join(parts) or "true"


def answer_json(answer: Answer) -> dict:
    """{"X": 1, "Y": ["a", 2], "Z": "f(b)"}: integers and floats as JSON numbers, proper lists
    as JSON lists (as the API gives them, Python lists), other terms as Prolog text, a free
    variable as its name."""
    return {name: _json_value(value, answer) for name, value in answer.values}


def _json_value(value: Term, answer: Answer, depth: int = 0):
    if isinstance(value, Int):
        return value.value
    if isinstance(value, Float) and math.isfinite(value.value):
        return value.value
    if depth < _JSON_LISTS:
        items, tail = list_items(value)
        if tail == NIL:
            return [_json_value(item, answer, depth + 1) for item in items]
    return term_to_text(value, 699, answer.names, next_argument=True, ops=answer.ops)


_JSON_LISTS = 100      # lists in lists this deep are JSON lists; deeper ones Prolog text (json's recursion)


def json_text(answers: list[dict]) -> str:
    """The answers as JSON (indented), every integer a JSON number written whole: json.dumps
    writes integers with int.__repr__, which stops at Python's 4,300 digits (ValueError), so a
    larger one is held by a placeholder string and written by int_text, as the text answer is."""
    nonce = secrets.token_hex(8)
    large: dict[str, int] = {}

    def placeholder(value: int) -> str:
        key = f"\0{nonce}:{len(large)}"
        large[key] = value
        return key

    def hold(v):
        if isinstance(v, list):
            return [hold(item) for item in v]
        return placeholder(v) if isinstance(v, int) and v.bit_length() > _REPR_BITS else v

    held = [{name: hold(v) for name, v in answer.items()} for answer in answers]
    text = json.dumps(held, indent=2)
    for key, value in large.items():
        text = text.replace(json.dumps(key), int_text(value), 1)
    return text


_REPR_BITS = 13_000    # about 3,900 digits: int.__repr__ is safe below Python's limit of 4,300


def answers(workspace: Workspace, query: Query, output: Callable[[str], None] | None = None,
            max_steps: int | None = None) -> Iterator[tuple[Answer, bool]]:
    """Every answer of `query`, lazily, each with whether it is the last (no choicepoint
    left, so the REPL does not ask for more); errors propagate."""
    engine = workspace.engine(output, max_steps)
    for b in engine.solve(query.goal):
        yield answer_of(query, b, workspace.kb.operators.view()), engine.deterministic


# Where the relations take a behaviour's id: (name, arity) -> argument positions.
BEHAVIOUR_ARGUMENTS = {
    ("original", 2): (1,), ("compressed", 2): (1,), ("in_tree", 3): (0,), ("node", 2): (0,),
    ("child", 2): (0, 1), ("parent", 2): (0, 1), ("depth", 2): (0,), ("leaf", 1): (0,), ("kind", 2): (0,),
    ("pre", 2): (0,), ("entry", 2): (0,), ("post", 2): (0,), ("agent", 2): (0,), ("objects", 2): (0,),
    ("k", 2): (0,), ("sequential", 2): (0, 1), ("merged", 3): (1,), ("enabled", 1): (0,),
    ("emphasis", 2): (0,), ("next_action", 1): (0,),
}
_CONTROL = {(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1), ("not", 1), ("call", 1)}


def behaviour_variables(query: Query) -> list[str]:
    """The query's variables that name behaviours (an argument of a relation that takes an id)
    and whose label the answer does not already show (no node(B, L) with L reported), in order."""
    reported = {v for _, v in query.names}
    ids: dict[Var, None] = {}
    shown: set[Var] = set()
    stack = [query.goal]
    while stack:
        goal = stack.pop()
        if not isinstance(goal, Struct):
            continue
        key = (goal.name, len(goal.args))
        if key in _CONTROL:
            stack.extend(reversed(goal.args))
            continue
        for i in BEHAVIOUR_ARGUMENTS.get(key, ()):
            if isinstance(goal.args[i], Var):
                ids.setdefault(goal.args[i], None)
        if key == ("node", 2) and isinstance(goal.args[0], Var) and goal.args[1] in reported:
            shown.add(goal.args[0])
    return [name for name, v in query.names if v in ids and v not in shown]


def behaviour_labels(workspace: Workspace) -> dict[int, Term]:
    """Every behaviour's label by its id, as node/2 numbers them (pre-order, per tree)."""
    from ..task.tree import walk

    found: dict[int, Term] = {}
    for view in workspace.views:
        for kind in (ORIGINAL, COMPRESSED):
            found.update((view.first(kind) + i, node.label) for i, node in enumerate(walk(view.tree(kind))))
    return found


def labels_comment(answer: Answer, variables: list[str], labels: dict[int, Term]) -> str:
    """`  % 1: a1(spoon), 5: subtask(mix, spoon)`: the labels of the behaviours an answer names
    by id, after it as a Prolog comment; "" when it names none."""
    values = dict(answer.values)
    said: dict[int, str] = {}
    for name in variables:
        value = values.get(name)
        if isinstance(value, Int) and value.value in labels and value.value not in said:
            said[value.value] = f"{value.value}: {term_to_text(labels[value.value], 999, next_argument=True)}"
    return f"  % {', '.join(said.values())}" if said else ""


