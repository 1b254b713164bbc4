"""Conditions: releasers and post-conditions as a small boolean algebra over literals.

    Condition = Const | Lit | Not | And | Or
    Lit       = (atom: Term, positive: bool)        `hand.free`, `not hand.free`

Every way the knowledge files write a condition reads to the same value:

    true  "TRUE"  []                         -> Const(True)
    false  fail                              -> Const(False)
    A and B   (A, B)   [A, B]                -> And
    A or B    (A ; B)                        -> Or
    not A   \\+ A   -A (SEED)                 -> a negated literal, or Not
    obj.prop   [obj|prop] (SWI-7 reading of SEED's dot)   on(a, b)   done   -> Lit

Conditions print in the paper's words: `hand.free or spoon.taken`, `not hand.free`.
"""

from __future__ import annotations

from dataclasses import dataclass

from .terms import CONS, NIL, Atom, Float, Int, Str, Struct, Term, Var, list_items, term_to_text


@dataclass(frozen=True, slots=True)
class Const:
    """`true` or `false`."""

    value: bool


@dataclass(frozen=True, slots=True)
class Lit:
    """A ground or parameterised atom, possibly negated."""

    atom: Term
    positive: bool = True

    def negate(self) -> "Lit":
        return Lit(self.atom, not self.positive)


@dataclass(frozen=True, slots=True)
class Not:
    """The negation of a compound condition (a negated literal is a `Lit`)."""

    item: "Condition"


@dataclass(frozen=True, slots=True)
class And:
    """All of `items` (two or more)."""

    items: tuple


@dataclass(frozen=True, slots=True)
class Or:
    """At least one of `items` (two or more)."""

    items: tuple


Condition = Const | Lit | Not | And | Or
TRUE = Const(True)
FALSE = Const(False)


class NotACondition(ValueError):
    """A term that cannot be read as a condition; the message says why."""


_TRUE_WORDS = {"true"}
_FALSE_WORDS = {"false", "fail"}


def from_term(term: Term) -> Condition:
    """Read a condition from its term, or raise NotACondition."""
    if isinstance(term, Var):
        raise NotACondition("a variable is not a condition (is the schema instantiated?)")
    if isinstance(term, (Int, Float)):
        raise NotACondition(f"the number {term_to_text(term)} is not a condition")
    if isinstance(term, Str):
        if term.value.upper() == "TRUE":  # SEED writes the always-true releaser as "TRUE"
            return TRUE
        if term.value.upper() == "FALSE":
            return FALSE
        raise NotACondition(f"the string {term_to_text(term)} is not a condition")
    if isinstance(term, Atom):
        if term.name in _TRUE_WORDS or term == NIL:
            return TRUE
        if term.name in _FALSE_WORDS:
            return FALSE
        return Lit(term)
    assert isinstance(term, Struct)
    name, args = term.name, term.args
    if name == CONS and len(args) == 2:
        items, tail = list_items(term)
        if tail == NIL:  # [A, B, ...]: SEED's releaser list, literals in AND
            return conjoin([from_term(i) for i in items])
        if len(items) == 1 and not isinstance(tail, Struct):
            return Lit(Struct(".", (items[0], tail)))  # [hand|free] is SWI-7's hand.free
        raise NotACondition(f"{term_to_text(term)} is a partial list, not a condition")
    if len(args) == 2 and name in ("and", ","):
        return conjoin([from_term(args[0]), from_term(args[1])])
    if len(args) == 2 and name in ("or", ";"):
        return disjoin([from_term(args[0]), from_term(args[1])])
    if len(args) == 1 and name in ("not", "\\+", "-"):
        return negate(from_term(args[0]))
    if name in (":-", "->", "=", "is") and len(args) == 2:
        raise NotACondition(f"{term_to_text(term)} is a goal, not a condition")
    return Lit(term)


def conjoin(items: list[Condition]) -> Condition:
    """AND of `items`, flattened; constants absorbed."""
    flat: list[Condition] = []
    for item in items:
        if item == TRUE:
            continue
        if item == FALSE:
            return FALSE
        flat.extend(item.items if isinstance(item, And) else (item,))
    if not flat:
        return TRUE
    return flat[0] if len(flat) == 1 else And(tuple(flat))


def disjoin(items: list[Condition]) -> Condition:
    """OR of `items`, flattened; constants absorbed."""
    flat: list[Condition] = []
    for item in items:
        if item == FALSE:
            continue
        if item == TRUE:
            return TRUE
        flat.extend(item.items if isinstance(item, Or) else (item,))
    if not flat:
        return FALSE
    return flat[0] if len(flat) == 1 else Or(tuple(flat))


def negate(c: Condition) -> Condition:
    """NOT `c`: flips literals and constants, keeps other negations explicit."""
    if isinstance(c, Const):
        return Const(not c.value)
    if isinstance(c, Lit):
        return c.negate()
    if isinstance(c, Not):
        return c.item
    return Not(c)


def to_term(c: Condition) -> Term:
    """The condition as a term in the paper's words (`and`, `or`, `not`)."""
    if isinstance(c, Const):
        return Atom("true" if c.value else "false")
    if isinstance(c, Lit):
        return c.atom if c.positive else Struct("not", (c.atom,))
    if isinstance(c, Not):
        return Struct("not", (to_term(c.item),))
    op = "and" if isinstance(c, And) else "or"
    result = to_term(c.items[-1])
    for item in reversed(c.items[:-1]):
        result = Struct(op, (to_term(item), result))
    return result


def to_text(c: Condition) -> str:
    """Print a condition: `hand.free or spoon.taken`, `not hand.free`."""
    return term_to_text(to_term(c), 999, spaced=True)


def literals(c: Condition) -> list[Lit]:
    """The literals of `c`, left to right."""
    if isinstance(c, Lit):
        return [c]
    if isinstance(c, Not):
        return literals(c.item)
    if isinstance(c, (And, Or)):
        return [lit for item in c.items for lit in literals(item)]
    return []


def is_conjunction_of_literals(c: Condition) -> bool:
    """Whether `c` is `true`, a literal, or an AND of literals (what a post-condition must be)."""
    if isinstance(c, (Lit, Const)):
        return c != FALSE
    return isinstance(c, And) and all(isinstance(i, Lit) for i in c.items)
