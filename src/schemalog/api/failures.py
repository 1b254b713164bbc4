"""What stops an API call besides a SchemalogError, and how it reads: a Prolog exception
nothing caught (PrologError, its ball an ISO error term), the step limit (StepLimitExceeded,
a SchemalogError), a term nested past Python's recursion limit.

    error_text(err, raise_limit, memory_words)   the one message a user reads

Light: it loads the terms and the exceptions, not the engine (the command line's top level
imports it for every command).
"""

from __future__ import annotations

from typing import Callable

from .. import defaults
from ..logic.exceptions import PrologError, StepLimitExceeded
from ..logic.terms import Atom, Struct, Term, term_to_text, variable_names

__all__ = ["PrologError", "StepLimitExceeded", "error_text"]


def error_text(err: BaseException, raise_limit: str = "--max-steps N",
               memory_words: Callable[[], str] | None = None) -> str:
    """An uncaught exception as the user should read it (`memory_words`: what running out of
    memory means where the call runs, e.g. the command line's ceiling)."""
    if isinstance(err, RecursionError):
        return "error: a term nests too deeply for schemalog to process (Python's recursion limit)"
    if isinstance(err, PrologError):
        return f"error: uncaught exception: {_explain(err.ball, memory_words)}"
    if isinstance(err, StepLimitExceeded):
        return f"error: {err.message}; raise it with {raise_limit}"
    return str(err)


def _explain(ball: Term, memory_words: Callable[[], str] | None) -> str:
    """`error(type_error(integer, a), _)` with a plain-words gloss for the ISO errors."""
    text = term_to_text(ball, names=variable_names([ball]))
    if isinstance(ball, Struct) and ball.name == "error" and len(ball.args) == 2:
        formal = ball.args[0]
        name = formal.name if isinstance(formal, (Atom, Struct)) else ""
        args = formal.args if isinstance(formal, Struct) else ()
        if name == "existence_error" and len(args) == 2 and args[0] == Atom("procedure"):
            return f"{text}\n  unknown procedure {term_to_text(args[1])}"
        if name == "instantiation_error":
            return f"{text}\n  arguments are not sufficiently instantiated"
        if name == "type_error" and len(args) == 2:
            return f"{text}\n  {term_to_text(args[0])} expected, found {term_to_text(args[1])}"
        if name == "evaluation_error" and len(args) == 1:
            return f"{text}\n  arithmetic: {term_to_text(args[0])}"
        if name == "resource_error" and len(args) == 1:
            return f"{text}\n  {_resource_words(term_to_text(args[0]), memory_words)}"
    return text


def _resource_words(resource: str, memory_words: Callable[[], str] | None) -> str:
    """What a resource error means here, and the limit behind it."""
    if resource == "memory":
        return memory_words() if memory_words is not None else "out of memory"
    if resource == "stack":
        return (f"an integer result would exceed {defaults.MAX_INTEGER_BITS:,} bits (a fixed limit, "
                f"as swipl's 1 GB stack is: docs/syntax.md)")
    return f"resource: {resource}"
