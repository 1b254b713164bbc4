"""Prolog exceptions: the ball a `throw/1` carries, and the ISO error terms built-ins raise.

    PrologError(ball)        a Prolog exception; catch/3 unifies its ball
    error(Formal, Context)   the ISO shape of every error a built-in raises

`StepLimitExceeded` is schemalog's own: the step budget ran out, and catch/3 does not
intercept it (it is not a Prolog exception).
"""

from __future__ import annotations

from ..errors import SchemalogError
from .terms import Atom, Int, Struct, Term, Var, term_to_text


class PrologError(Exception):
    """A Prolog exception carrying its ball, e.g. error(type_error(integer, a), _)."""

    def __init__(self, ball: Term) -> None:
        super().__init__(term_to_text(ball))
        self.ball = ball


class CyclicTermError(PrologError):
    """A built-in that needs a finite term met a cyclic one (X = f(X)): SWI-Prolog's
    error(representation_error(cyclic_term), _); `culprit` is the term, written finitely."""

    def __init__(self, ball: Term, culprit: Term | None = None) -> None:
        super().__init__(ball)
        self.culprit = culprit


def cyclic_term_error(culprit: Term) -> CyclicTermError:
    """Build the error a built-in raises for a cyclic argument."""
    return CyclicTermError(Struct("error", (Struct("representation_error", (Atom("cyclic_term"),)), Var("_"))),
                           culprit)


class StepLimitExceeded(SchemalogError):
    """The query ran longer than its step budget (runaway recursion?)."""


def iso_error(formal: Term, context: Term | None = None) -> PrologError:
    """Build `error(Formal, Context)`."""
    return PrologError(Struct("error", (formal, context if context is not None else Var("_"))))


def instantiation_error() -> PrologError:
    return iso_error(Atom("instantiation_error"))


def type_error(kind: str, culprit: Term) -> PrologError:
    return iso_error(Struct("type_error", (Atom(kind), culprit)))


def existence_error(name: str, arity: int) -> PrologError:
    return iso_error(Struct("existence_error", (Atom("procedure"),
                                                Struct("/", (Atom(name), Int(arity))))))
