"""Immutable Prolog terms and their canonical text.

    Term = Atom | Var | Struct | Int | Float | Str
    List = Struct('[|]', (Head, Tail)) ... ending in Atom('[]')   (SWI-Prolog 7's list cells)
    Condition atom = Struct('.', (Obj, Prop))                       (the paper's `hand.free`)

Atoms, numbers and strings compare by value; a variable is equal only to itself
(renaming a clause makes new `Var` objects). Printing follows SWI-Prolog's
`writeq/1`: quotes where needed, operators infix, minimal parentheses.
"""

from __future__ import annotations

import itertools
import re
from dataclasses import dataclass, field
from typing import Iterable, Iterator, Union


@dataclass(frozen=True, slots=True)
class Atom:
    """A constant name: `spoon`, `[]`, `'hello world'`."""

    name: str

    def __str__(self) -> str:
        return term_to_text(self)


@dataclass(frozen=True, slots=True)
class Int:
    """An integer; never equal to a float (`1 \\== 1.0`)."""

    value: int

    def __str__(self) -> str:
        return term_to_text(self)


@dataclass(frozen=True, slots=True)
class Float:
    """A float."""

    value: float

    def __str__(self) -> str:
        return term_to_text(self)


@dataclass(frozen=True, slots=True)
class Str:
    """A double-quoted string (SWI-Prolog 7 string object)."""

    value: str

    def __str__(self) -> str:
        return term_to_text(self)


_fresh = itertools.count(1)


@dataclass(frozen=True, slots=True, eq=False)
class Var:
    """A logic variable; identity is the object, the name is only for printing."""

    name: str = ""
    id: int = field(default_factory=lambda: next(_fresh))

    def __str__(self) -> str:
        return self.name if self.name and not self.name.startswith("_") else f"_G{self.id}"

    def __repr__(self) -> str:
        return f"Var({self.name!r}, {self.id})"


@dataclass(frozen=True, slots=True)
class Struct:
    """A compound term `name(arg1, ..., argN)` with N >= 1."""

    name: str
    args: tuple
    _hash: int = field(default=0, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_hash", hash((self.name, self.args)))

    def __hash__(self) -> int:
        return self._hash

    @property
    def arity(self) -> int:
        return len(self.args)

    def __str__(self) -> str:
        return term_to_text(self)


Term = Union[Atom, Var, Struct, Int, Float, Str]
Number = Union[Int, Float]

NIL = Atom("[]")
TRUE = Atom("true")
FALSE = Atom("false")
CONS = "[|]"


def make_list(items: Iterable[Term], tail: Term = NIL) -> Term:
    """Build the list `[i1, ..., iN | tail]`."""
    result = tail
    for item in reversed(list(items)):
        result = Struct(CONS, (item, result))
    return result


def list_items(term: Term) -> tuple[list[Term], Term]:
    """Split a list into its items and its tail (`NIL` for a proper list)."""
    items = []
    while isinstance(term, Struct) and term.name == CONS and len(term.args) == 2:
        items.append(term.args[0])
        term = term.args[1]
    return items, term


def is_proper_list(term: Term) -> bool:
    """Whether `term` is a list ending in `[]`."""
    return list_items(term)[1] == NIL


def indicator(term: Term) -> tuple[str, int] | None:
    """The predicate indicator `(name, arity)` of a callable term, else None."""
    if isinstance(term, Atom):
        return (term.name, 0)
    if isinstance(term, Struct):
        return (term.name, len(term.args))
    return None


def iter_vars(term: Term) -> Iterator[Var]:
    """Yield the variables of `term`, depth-first, left to right, with repeats."""
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Var):
            yield t
        elif isinstance(t, Struct):
            stack.extend(reversed(t.args))


def is_ground(term: Term) -> bool:
    """Whether `term` has no variables."""
    return next(iter_vars(term), None) is None


# ---------------------------------------------------------------------------
# Printing (writeq). The operator table mirrors grammar/schemalog.lark.

# name -> (priority, type) for infix and prefix operators.
INFIX_OPS: dict[str, tuple[int, str]] = {
    ":-": (1200, "xfx"), "-->": (1200, "xfx"),
    ";": (1100, "xfy"), "->": (1050, "xfy"), "*->": (1050, "xfy"),
    ",": (1000, "xfy"), "or": (990, "xfy"), "and": (980, "xfy"),
    **{op: (700, "xfx") for op in ("=", "\\=", "==", "\\==", "@<", "@>", "@=<", "@>=",
                                   "=..", "is", "=:=", "=\\=", "<", ">", "=<", ">=")},
    **{op: (500, "yfx") for op in ("+", "-", "/\\", "\\/", "xor")},
    **{op: (400, "yfx") for op in ("*", "/", "//", "mod", "rem", "div", "<<", ">>")},
    "**": (200, "xfx"), "^": (200, "xfy"), ".": (100, "xfy"),
}
PREFIX_OPS: dict[str, tuple[int, str]] = {
    ":-": (1200, "fx"), "?-": (1200, "fx"),
    "dynamic": (1150, "fx"), "discontiguous": (1150, "fx"),
    "initialization": (1150, "fx"), "table": (1150, "fx"),
    "\\+": (900, "fy"), "not": (900, "fy"), "-": (200, "fy"), "\\": (200, "fy"),
}
# Words the grammar reads as prefix operators: as plain atoms they must be quoted.
RESERVED_WORDS = frozenset(name for name in PREFIX_OPS if name[0].isalpha())

_SOLO = re.compile(r"[a-z][A-Za-z0-9_]*\Z")
_SYMBOL = re.compile(r"[+\-*/\\^<>=~:?@#&$]+\Z")
_ESCAPES = {"\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r", "\a": "\\a",
            "\b": "\\b", "\f": "\\f", "\v": "\\v", "\0": "\\0\\"}


def quote_atom(name: str) -> str:
    """Write an atom name so that it reads back as the same atom."""
    if name in ("[]", "{}", "!", ";"):
        return name
    if _SOLO.match(name) and name not in RESERVED_WORDS:
        return name
    if _SYMBOL.match(name) and not name.startswith("/*") and name not in PREFIX_OPS:
        return name
    body = "".join(_ESCAPES.get(c, c) for c in name).replace("'", "\\'")
    return f"'{body}'"


def _quote_string(value: str) -> str:
    body = "".join(_ESCAPES.get(c, c) for c in value).replace('"', '\\"')
    return f'"{body}"'


def _float_text(value: float) -> str:
    text = repr(value)
    if "inf" in text or "nan" in text:
        return {"inf": "inf", "-inf": "-inf"}.get(text, "nan")
    if "." not in text and "e" not in text:
        text += ".0"
    if "e" in text and "." not in text.split("e")[0]:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}.0e{exponent}"
    return text


Names = dict  # dict[Var, str]: print names for variables (see `variable_names`)


def term_to_text(term: Term, max_priority: int = 1200, names: Names | None = None) -> str:
    """Write `term` as SWI-Prolog's writeq would, with `max_priority` as context."""
    return "".join(_write(term, max_priority, names or {}))


def variable_names(terms: Iterable[Term]) -> Names:
    """Stable print names for a clause's variables: `_` when single, else `_A`, `_B`...

    Variables named in the source keep their names.
    """
    counts: dict[Var, int] = {}
    for t in terms:
        for v in iter_vars(t):
            counts[v] = counts.get(v, 0) + 1
    taken = {v.name for v in counts if v.name and not v.name.startswith("_")}
    names: Names = {}
    fresh = (f"_{chr(65 + i % 26)}{i // 26 or ''}" for i in itertools.count())
    for v, n in counts.items():
        if v.name and not v.name.startswith("_"):
            names[v] = v.name
        elif n == 1:
            names[v] = "_"
        else:
            name = next(fresh)
            while name in taken:
                name = next(fresh)
            names[v] = name
    return names


def _write(term: Term, max_priority: int, names: Names) -> Iterator[str]:
    if isinstance(term, Atom):
        text = quote_atom(term.name)
        # An operator standing alone as an argument is bracketed: f((-)), [(:-)].
        if (term.name in INFIX_OPS or term.name in PREFIX_OPS) and max_priority < 1200 \
                and not text.startswith("'") and term.name not in ("[]", "{}"):
            if term.name in PREFIX_OPS or term.name in (",", "|"):
                yield f"({text})"
                return
        yield text
    elif isinstance(term, Var):
        yield names.get(term) or str(term)
    elif isinstance(term, Int):
        yield str(term.value)
    elif isinstance(term, Float):
        yield _float_text(term.value)
    elif isinstance(term, Str):
        yield _quote_string(term.value)
    elif isinstance(term, Struct):
        yield from _write_struct(term, max_priority, names)
    else:  # pragma: no cover - defensive: only terms reach here
        raise TypeError(f"not a term: {term!r}")


def _write_struct(term: Struct, max_priority: int, names: Names) -> Iterator[str]:
    name, args = term.name, term.args
    if name == CONS and len(args) == 2:
        items, tail = list_items(term)
        yield "["
        for i, item in enumerate(items):
            if i:
                yield ","
            yield from _write(item, 999, names)
        if tail != NIL:
            yield "|"
            yield from _write(tail, 999, names)
        yield "]"
        return
    if name == "{}" and len(args) == 1:
        yield "{"
        yield from _write(args[0], 1200, names)
        yield "}"
        return
    if len(args) == 2 and name in INFIX_OPS:
        priority, kind = INFIX_OPS[name]
        left_max = priority if kind == "yfx" else priority - 1
        right_max = priority if kind == "xfy" else priority - 1
        left = term_to_text(args[0], left_max, names)
        right = term_to_text(args[1], right_max, names)
        if name == ",":
            op = ","
        elif name[0].isalpha() or name in ("->", ":-", "-->", "*->"):
            op = f" {name} " if name[0].isalpha() else name
        else:
            op = name
        # Keep symbol runs apart so they do not lex as one token: `1- -1`, `a= \\+b`.
        if not name[0].isalpha() and name != ",":
            if right and _SYMBOL.match(right[0]) and right[0] not in "([{":
                op = op + " "
            if left and _SYMBOL.match(left[-1]):
                op = " " + op
        text = f"{left}{op}{right}"
        yield f"({text})" if priority > max_priority else text
        return
    if len(args) == 1 and name in PREFIX_OPS and name != "-" or (
            name == "-" and len(args) == 1 and not isinstance(args[0], (Int, Float))):
        priority, kind = PREFIX_OPS[name]
        arg_max = priority if kind == "fy" else priority - 1
        arg = term_to_text(args[0], arg_max, names)
        sep = " " if name[0].isalpha() or (arg and (_SYMBOL.match(arg[0]) or arg[0] in "(0123456789")) else ""
        text = f"{name}{sep}{arg}"
        yield f"({text})" if priority > max_priority else text
        return
    # Functional notation: `-(1)` and `not(a)` read back as compounds, unquoted.
    yield name if _SYMBOL.match(name) or name in RESERVED_WORDS else quote_atom(name)
    yield "("
    for i, arg in enumerate(args):
        if i:
            yield ","
        yield from _write(arg, 999, names)
    yield ")"
