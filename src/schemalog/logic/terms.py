"""Immutable Prolog terms and their canonical text.

    Term = Atom | Var | Struct | Int | Float | Str
    List = Struct('[|]', (Head, Tail)) ... ending in Atom('[]')   (SWI-Prolog 7's list cells)
    Condition atom = Struct('.', (Obj, Prop))                       (the paper's `hand.free`)

Atoms, numbers and strings compare by value; a variable is equal only to itself
(renaming a clause makes new `Var` objects). Printing follows SWI-Prolog's
`writeq/1`: quotes where needed, operators infix, minimal parentheses.
"""

from __future__ import annotations

import decimal
import functools
import itertools
import re
from decimal import Decimal
from dataclasses import dataclass
from typing import Iterable, Iterator, Union


@dataclass(frozen=True, slots=True)
class Atom:
    """A constant name: `spoon`, `[]`, `'hello world'`."""

    name: str

    def __str__(self) -> str:
        return term_to_text(self)

    def __reduce__(self):
        # The shared constants come back as themselves (the engine tests `body is TRUE`);
        # any other atom as an atom of that name.
        if _SHARED.get(self.name) is self:
            return (_shared_atom, (self.name,))
        return (Atom, (self.name,))


@dataclass(frozen=True, slots=True)
class Int:
    """An integer; never equal to a float (`1 \\== 1.0`)."""

    value: int

    def __str__(self) -> str:
        return term_to_text(self)


@dataclass(frozen=True, slots=True, eq=False)
class Float:
    """A float; `0.0 \\== -0.0`, and NaN equals itself (compared bit for bit, as SWI-Prolog)."""

    value: float

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Float) and self.value.hex() == other.value.hex()

    def __hash__(self) -> int:
        return hash(self.value.hex())

    def __str__(self) -> str:
        return term_to_text(self)


@dataclass(frozen=True, slots=True)
class Str:
    """A double-quoted string (SWI-Prolog 7 string object)."""

    value: str

    def __str__(self) -> str:
        return term_to_text(self)


_fresh = itertools.count(1)


class Var:
    """A logic variable; identity is the object, the name is only for printing.

    A plain slots class, not a frozen dataclass: the engine makes one per fresh clause
    variable, and a frozen dataclass's constructor costs three times as much. It is never
    changed after construction (by convention: nothing assigns to a term's fields)."""

    __slots__ = ("name", "id")

    def __init__(self, name: str = "", id: int | None = None) -> None:
        self.name = name
        self.id = next(_fresh) if id is None else id

    def __str__(self) -> str:
        return self.name if self.name and not self.name.startswith("_") else f"_G{self.id}"

    def __repr__(self) -> str:
        return f"Var({self.name!r}, {self.id})"

    def __reduce__(self):
        # Unpickled (the cached prelude), a variable is a fresh one, so ids stay unique here;
        # pickle's memo keeps every occurrence of one variable the same object.
        return (Var, (self.name,))


class Struct:
    """A compound term `name(arg1, ..., argN)` with N >= 1.

    A plain slots class for the same reason as Var (clause bodies build many), immutable
    by convention; equal when name and arguments are, hashed as the pair."""

    __slots__ = ("name", "args", "_hash")

    def __init__(self, name: str, args: tuple) -> None:
        self.name = name
        self.args = args
        self._hash = 0

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not Struct:
            return NotImplemented
        return self is other or (self.name == other.name and self.args == other.args)

    def __repr__(self) -> str:
        return f"Struct(name={self.name!r}, args={self.args!r})"

    def __reduce__(self):
        # The cached hash is not kept: string hashes differ from one process to the next.
        return (Struct, (self.name, self.args))

    def __hash__(self) -> int:
        # Computed on first use: the engine builds many terms (clause copies) never hashed.
        h = self._hash
        if not h:
            h = self._hash = hash((self.name, self.args))
        return h

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
_SHARED = {atom.name: atom for atom in (NIL, TRUE, FALSE)}


def _shared_atom(name: str) -> Atom:
    return _SHARED[name]

CONS = "[|]"


def make_list(items: Iterable[Term], tail: Term = NIL) -> Term:
    """Build the list `[i1, ..., iN | tail]`."""
    result = tail
    for item in reversed(list(items)):
        result = Struct(CONS, (item, result))
    return result


def conjuncts(term: Term) -> list[Term]:
    """The goals of a conjunction `(A, B, C)`, in order; any other term is one goal."""
    out = []
    while isinstance(term, Struct) and term.name == "," and len(term.args) == 2:
        out.append(term.args[0])
        term = term.args[1]
    out.append(term)
    return out


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
    stack = [term]  # a loop, not iter_vars' generator: instantiation asks this of every schema
    while stack:
        t = stack.pop()
        if isinstance(t, Struct):
            stack.extend(t.args)
        elif isinstance(t, Var):
            return False
    return True


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
    "**": (200, "xfx"), "^": (200, "xfy"), ":": (600, "xfy"), ".": (100, "xfy"),
}
PREFIX_OPS: dict[str, tuple[int, str]] = {
    ":-": (1200, "fx"), "?-": (1200, "fx"),
    "dynamic": (1150, "fx"), "discontiguous": (1150, "fx"), "multifile": (1150, "fx"),
    "initialization": (1150, "fx"), "table": (1150, "fx"),
    "\\+": (900, "fy"), "not": (900, "fy"), "-": (200, "fy"), "+": (200, "fy"), "\\": (200, "fy"),
}
# Words the grammar reads as prefix operators. As plain atoms they are written bare, as
# SWI-Prolog writes them, set(table) and [dynamic], and bracketed where an operand would be read
# as the operator, X = (table) and - (not) (_expand): both readers read either.
RESERVED_WORDS = frozenset(name for name in PREFIX_OPS if name[0].isalpha())


class Operators:
    """One operator table as the reader and the writer look it up: name -> (priority, type)
    for each of prefix (fy fx), infix (xfx xfy yfx) and postfix (xf yf) operators."""

    __slots__ = ("prefix", "infix", "postfix")

    def __init__(self, prefix: dict, infix: dict, postfix: dict) -> None:
        self.prefix, self.infix, self.postfix = prefix, infix, postfix


DEFAULT_OPERATORS = Operators(PREFIX_OPS, INFIX_OPS, {})
NO_OPERATORS = Operators({}, {}, {})     # write_canonical, ignore_ops(true)
_KINDS = {"fy": "prefix", "fx": "prefix", "xfx": "infix", "xfy": "infix", "yfx": "infix",
          "xf": "postfix", "yf": "postfix"}


def operator_kind(op_type: str) -> str:
    """`prefix`, `infix` or `postfix`: the class of an operator type (fy, xfx, xf, ...)."""
    return _KINDS[op_type]


class OperatorTable(dict):
    """(name, prefix | infix | postfix) -> (priority, type): the table op/3 changes and
    current_op/3 reads, starting as the reader's default; `view()` is the Operators of it
    (kept until the table changes)."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._view: Operators | None = None

    def __setitem__(self, key, value) -> None:
        self._view = None
        super().__setitem__(key, value)

    def pop(self, key, *default):
        self._view = None
        return super().pop(key, *default)

    def update(self, *args, **kwargs) -> None:
        self._view = None
        super().update(*args, **kwargs)

    def copy(self) -> "OperatorTable":
        return OperatorTable(self)

    def view(self) -> Operators:
        """The table as the reader and the writer look it up."""
        if self._view is None:
            parts: dict[str, dict] = {"prefix": {}, "infix": {}, "postfix": {}}
            for (name, kind), op in self.items():
                parts[kind][name] = op
            if parts["prefix"] == PREFIX_OPS and parts["infix"] == INFIX_OPS and not parts["postfix"]:
                self._view = DEFAULT_OPERATORS
            else:
                self._view = Operators(parts["prefix"], parts["infix"], parts["postfix"])
        return self._view


def default_operator_table() -> OperatorTable:
    """A fresh table holding the reader's default operators (terms.py's own table)."""
    table = OperatorTable({(name, "infix"): op for name, op in INFIX_OPS.items()})
    table.update({(name, "prefix"): op for name, op in PREFIX_OPS.items()})
    return table

_SOLO = re.compile(r"[a-z][A-Za-z0-9_]*\Z")
_SYMBOL = re.compile(r"[+\-*/\\^<>=~:?@#&$]+\Z")
# A symbol-char name with a "." in it (=..) is written bare too, but "." alone: where a bare
# symbol atom could be followed by the end of a clause it is bracketed (_expand).
_SYMBOL_DOT_CHAR = re.compile(r"[+\-*/\\^<>=~:?@#&$.]\Z")   # one character that joins a symbol run
_SYMBOL_DOT = re.compile(r"(?!\.\Z)[+\-*/\\^<>=~:?@#&$.]+\Z")
_ESCAPES = {"\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r", "\a": "\\a",
            "\b": "\\b", "\f": "\\f", "\v": "\\v", "\0": "\\0\\", "\x1b": "\\e"}
# Quoting replaces each character that needs an escape in one str.replace pass, the
# backslash first: linear, in C, and only the text's copies in memory. (Joining a string per
# character held an 8-byte pointer per character besides: 80 MB more for a 10 MB atom.)
_IN_QUOTES = tuple(_ESCAPES.items()) + (("'", "\\'"),)
_IN_DOUBLE_QUOTES = tuple(_ESCAPES.items()) + (('"', '\\"'),)


def _escape(text: str, escapes: tuple) -> str:
    for char, escape in escapes:
        if char in text:
            text = text.replace(char, escape)
    if not text.isprintable():
        # What is left unprintable (other control characters, format characters such as U+200B,
        # separators other than space) is written \xHEX\ as SWI-Prolog's writeq does, so the
        # text holds no raw control character (XML refuses them; a terminal acts on them).
        text = _UNPRINTABLE.sub(_hex_escape, text)
    return text


_UNPRINTABLE = re.compile(r"[^\x20-\x7e]")


def _hex_escape(match: re.Match) -> str:
    char = match.group()
    return char if char.isprintable() else f"\\x{ord(char):X}\\"


def quote_atom(name: str) -> str:
    """Write an atom name so that it reads back as the same atom."""
    if name in ("[]", "{}", "!", ";"):
        return name
    if _SOLO.match(name):
        return name
    if _SYMBOL_DOT.match(name) and not name.startswith("/*"):
        return name
    return f"'{_escape(name, _IN_QUOTES)}'"


def _quote_string(value: str) -> str:
    return f'"{_escape(value, _IN_DOUBLE_QUOTES)}"'


def _float_text(value: float) -> str:
    """Shortest text that reads back as `value`, in SWI-Prolog's style: 1.0e+15, 1.0e-5, 1.0Inf."""
    if value != value:
        return "1.5NaN"
    if value in (float("inf"), float("-inf")):
        return "1.0Inf" if value > 0 else "-1.0Inf"
    text = repr(value)
    if "e" not in text and abs(value) >= 1e15:
        digits = Decimal(text).normalize()
        sign, ds, exponent = digits.as_tuple()
        mantissa = "".join(map(str, ds))
        text = f"{'-' if sign else ''}{mantissa[0]}.{mantissa[1:] or '0'}e{exponent + len(ds) - 1}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        if "." not in mantissa:
            mantissa += ".0"
        sign = "-" if exponent.startswith("-") else "+"
        text = f"{mantissa}e{sign}{exponent.lstrip('+-').lstrip('0') or '0'}"
    elif "." not in text:
        text += ".0"
    return text


# Python refuses str(int) past 4,300 digits (its guard against quadratic conversion), and
# its int <-> str conversions are quadratic beyond. Larger integers convert by halves, through
# decimal's fast multiplication one way and int's Karatsuba the other: the largest integer
# `is` makes (defaults.MAX_INTEGER_BITS, 2.5 million digits) prints in ~1 s and reads in ~8 s.
_SMALL_BITS = 12_000     # about 3,600 digits: plain str()
_SMALL_DIGITS = 3_000


def int_text(value: int) -> str:
    """The decimal text of an integer of any size."""
    if value.bit_length() <= _SMALL_BITS:
        return str(value)
    context = decimal.Context(prec=decimal.MAX_PREC, Emax=decimal.MAX_EMAX, Emin=decimal.MIN_EMIN)
    power = functools.lru_cache(None)(lambda bits: context.power(context.create_decimal(2), bits))

    def convert(v: int, bits: int) -> Decimal:
        if bits <= _SMALL_BITS:
            return context.create_decimal(v)
        half = bits >> 1
        high, low = v >> half, v & ((1 << half) - 1)
        return context.add(context.multiply(convert(high, bits - half), power(half)), convert(low, half))

    magnitude = abs(value)
    text = format(convert(magnitude, magnitude.bit_length()), "f")
    return "-" + text if value < 0 else text


def int_of_digits(digits: str) -> int:
    """The integer a string of decimal digits denotes, of any length (see int_text)."""
    if len(digits) <= _SMALL_DIGITS:
        return int(digits)
    ten = functools.lru_cache(None)(lambda k: 10 ** k)

    def convert(text: str) -> int:
        if len(text) <= _SMALL_DIGITS:
            return int(text)
        k = len(text) >> 1
        return convert(text[:-k]) * ten(k) + convert(text[-k:])

    return convert(digits)


Names = dict  # dict[Var, str]: print names for variables (see `variable_names`)


def term_to_text(term: Term, max_priority: int = 1200, names: Names | None = None,
                 quoted: bool = True, spaced: bool = False, next_argument: bool = False,
                 spaced_operators: bool = False, ops: Operators | None = None, canonical: bool = False) -> str:
    """Write `term` as SWI-Prolog's writeq would (write/1 with quoted=False).

    `spaced` puts spaces around word operators everywhere, `(a or b) and c`, where
    writeq writes `(a or b)and c`; both read back the same. `next_argument` puts a space
    after each argument's comma, `f(a, [b, c])`, as SWI-Prolog's top level prints answers.
    `spaced_operators` puts a space on both sides of every infix operator but the comma,
    `a :- b, c * (1 + 2)`, as ECLiPSe's writeq does. `ops` is the operator table to write
    operators by (default: the reader's own); `canonical` writes every compound in functional
    notation, `{}(a)` too, as write_canonical does (lists stay lists)."""
    style = _Style(names or {}, quoted, spaced, next_argument)
    style.operators = spaced_operators
    if canonical:
        style.ops, style.curly = NO_OPERATORS, False
    elif ops is not None:
        style.ops = ops
    return "".join(_write(term, max_priority, style))


class _Style:
    """How to write: variable print names, and whether to quote atoms and strings."""

    __slots__ = ("names", "quoted", "spaced", "comma", "dots", "operators", "ops", "curly")

    def __init__(self, names: Names, quoted: bool, spaced: bool = False, next_argument: bool = False) -> None:
        self.names = names
        self.quoted = quoted
        self.spaced = spaced
        self.operators = False   # a space on both sides of every infix operator (ECLiPSe)
        self.ops = DEFAULT_OPERATORS   # the operator table terms are written by
        self.curly = True              # {a} for '{}'(a); write_canonical writes {}(a)
        self.comma = ", " if next_argument else ","
        # id(a '.'/2 term) -> whether it is written infix (obj.prop); the term is alive
        # for the whole write, so its id is stable. See _dot_infix.
        self.dots: dict[int, bool] = {}


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


def canonical_names(term: Term) -> Names:
    """write_canonical's variable names, as SWI-Prolog's: `_` for a variable that occurs
    once, `A`, `B`, ... for the others, in order of first occurrence."""
    counts: dict[Var, int] = {}
    for v in iter_vars(term):
        counts[v] = counts.get(v, 0) + 1
    letters = (f"{chr(65 + i % 26)}{i // 26 or ''}" for i in itertools.count())
    return {v: "_" if n == 1 else next(letters) for v, n in counts.items()}


def _write(term: Term, max_priority: int, style: _Style) -> Iterator[str]:
    """Yield the text of `term`; an explicit stack, so deep terms print without recursion."""
    out: list[str] = []
    stack: list = [(term, max_priority)]
    while stack:
        task = stack.pop()
        if isinstance(task, str):
            out.append(task)
        elif isinstance(task, _InfixOp):
            out.append(task.text(out, style))
        else:
            _expand(task[0], task[1], style, out, stack)
    yield "".join(out)


class _InfixOp:
    """An infix operator whose spacing depends on the text written just before it."""

    __slots__ = ("name", "right_first", "postfix")

    def __init__(self, name: str, right_first: str, postfix: bool = False) -> None:
        self.name, self.right_first, self.postfix = name, right_first, postfix

    def text(self, out: list[str], style: "_Style") -> str:
        name = self.name
        if name == ",":
            return style.comma
        if style.operators:
            return f" {name} "
        last = next((chunk[-1] for chunk in reversed(out) if chunk), "")
        if name[0].isalpha():  # a word operator: apart from names, not after a bracket
            before = '' if last in ')]}' and not style.spaced else ' '
            return f"{before}{name}" if self.postfix else f"{before}{name} "
        op = name
        # Keep symbol runs apart so they do not read as one token: `1- -1`, `a= \\+b`,
        # `a* ./(b)` (a bare `./` is a symbol atom: `.` joins the run).
        if last and _SYMBOL_DOT_CHAR.match(last):
            op = " " + op
        if self.right_first and _SYMBOL_DOT_CHAR.match(self.right_first):
            op = op + " "
        return op


def _expand(term: Term, max_priority: int, style: _Style, out: list[str], stack: list) -> None:
    """Write the head of `term` to `out`, and push what follows onto `stack` (reversed)."""
    if isinstance(term, Atom):
        text = quote_atom(term.name) if style.quoted else term.name
        # A symbol-char atom is bare as an argument or list element, f(-) and [:-], and
        # bracketed anywhere else, X=(:-) and (+), where it would read as an operator.
        if style.ops is NO_OPERATORS:
            pass          # no operators (write_canonical, ignore_ops): no atom needs brackets
        elif max_priority != 999 and (text == ";" or _SYMBOL_DOT.match(text)):
            text = f"({text})"
        # A word operator or ',' '|' as an operand reads back only bracketed: X = (is),
        # (nicht);a (not at the top, 1200, nor as an argument, 999).
        elif max_priority != 999 and max_priority < 1200 and (term.name in style.ops.infix or term.name in style.ops.prefix
                                     or term.name in style.ops.postfix or term.name in (",", "|")):
            text = f"({text})"
        out.append(text)
    elif isinstance(term, Var):
        out.append(style.names.get(term) or str(term))
    elif isinstance(term, Int):
        out.append(int_text(term.value))
    elif isinstance(term, Float):
        out.append(_float_text(term.value))
    elif isinstance(term, Str):
        out.append(_quote_string(term.value) if style.quoted else term.value)
    elif isinstance(term, Struct):
        _expand_struct(term, max_priority, style, out, stack)
    else:  # pragma: no cover - defensive: only terms reach here
        raise TypeError(f"not a term: {term!r}")


def _push_args(items: list[Term], priority: int, stack: list, sep: str) -> None:
    for i in range(len(items) - 1, -1, -1):
        stack.append((items[i], priority))
        if i:
            stack.append(sep)


def _expand_struct(term: Struct, max_priority: int, style: _Style, out: list[str], stack: list) -> None:
    name, args = term.name, term.args
    if name == CONS and len(args) == 2:
        items, tail = list_items(term)
        out.append("[")
        stack.append("]")
        if tail != NIL:
            stack.append((tail, 999))
            stack.append("|")
        _push_args(items, 999, stack, style.comma)
        return
    if name == "{}" and len(args) == 1 and style.curly:
        out.append("{")
        stack.append("}")
        stack.append((args[0], 1200))
        return
    # obj.prop reads back only when prop starts with a letter: else '.'(a,1).
    ops = style.ops
    if len(args) == 2 and name in ops.infix and (name != "." or _dot_infix(term, style)):
        priority, kind = ops.infix[name]
        left_max = priority if kind == "yfx" else priority - 1
        right_max = priority if kind == "xfy" else priority - 1
        bracket = priority > max_priority
        if bracket:
            out.append("(")
            stack.append(")")
        stack.append((args[1], right_max))
        stack.append(_InfixOp(name, _first_char(args[1], right_max, style)))
        stack.append((args[0], left_max))
        return
    if len(args) == 1 and name in ops.prefix:
        priority, kind = ops.prefix[name]
        arg_max = priority if kind == "fy" else priority - 1
        operand = args[0]
        if isinstance(operand, Atom) and (operand.name in ops.infix or operand.name in ops.prefix
                                          or operand.name in ops.postfix):
            arg_max = min(arg_max, 998)   # an operator atom bracketed, `- (is)`, as swipl writes it
        first = _first_char(operand, arg_max, style)
        # `- 1` is -(1) and `-1` the number; `\\+ -a` keeps its symbol runs apart.
        # `- {a}`: SWI-Prolog 7 reads `-{a}` as a dict.
        sep = " " if name[0].isalpha() or (first and (_SYMBOL_DOT_CHAR.match(first) or first in "({" or
                                                     name == "-" and first.isdigit())) else ""
        bracket = priority > max_priority
        if bracket:
            out.append("(")
            stack.append(")")
        out.append(quote_atom(name) if style.quoted and name not in RESERVED_WORDS else name)
        out.append(sep)
        stack.append((args[0], arg_max))
        return
    if len(args) == 1 and name in ops.postfix:
        priority, kind = ops.postfix[name]
        bracket = priority > max_priority
        if bracket:
            out.append("(")
            stack.append(")")
        stack.append(_InfixOp(name, "", postfix=True))
        stack.append((args[0], priority if kind == "yf" else priority - 1))
        return
    # Functional notation: `-(a,b)` and `not(a,b)` read back as compounds, unquoted;
    # `'[]'(a)` and `'{}'(a)` keep their quotes.
    if not style.quoted or _SYMBOL_DOT.match(name) and not name.startswith("/*") or name in RESERVED_WORDS:
        out.append(name)
    else:
        out.append(quote_atom(name) if name not in _QUOTED_FUNCTORS else f"'{name}'")
    out.append("(")
    stack.append(")")
    _push_args(list(args), 999, stack, style.comma)


# Atoms that read bare but not as functors: '[]'(a) (SWI-Prolog 7 reads [](a) as another
# atom's), '|'(a,b), ','(a,b); `{}(a)`, `!(a)` and `;(a,b,c)` read as functors, as in SWI-Prolog.
_QUOTED_FUNCTORS = frozenset({"[]", "|", ","})


def _starts_name(char: str) -> bool:
    return char == "_" or char.isascii() and char.isalpha()


def _dot_infix(term: Struct, style: _Style) -> bool:
    """Whether `'.'(A, B)` is written `A.B`: when B's text starts with a name.

    B's first character depends on whether B, if a '.' term too, is written infix, and so
    on down the right spine of a chain `a.b.c...`. Deciding each node by walking the rest
    of the chain made printing quadratic (and recursive); instead the spine is decided
    once, from its far end, and each node's answer kept in `style.dots`."""
    dots = style.dots
    known = dots.get(id(term))
    if known is not None:
        return known
    spine = []
    node: Term = term
    while isinstance(node, Struct) and node.name == "." and len(node.args) == 2 and id(node) not in dots:
        spine.append(node)
        node = node.args[1]
    for node in reversed(spine):  # node.args[1] is decided already: _first_char stops there
        dots[id(node)] = _starts_name(_first_char(node.args[1], style.ops.infix["."][0], style))
    return dots[id(term)]


def _first_char(term: Term, max_priority: int, style: _Style) -> str:
    """The first character `term` will be written with, found down its left spine."""
    while True:
        if isinstance(term, Struct):
            name, args = term.name, term.args
            if name == CONS and len(args) == 2:
                return "["
            if name == "{}" and len(args) == 1 and style.curly:
                return "{"
            ops = style.ops
            if len(args) == 2 and name in ops.infix:
                if name == "." and not _dot_infix(term, style):
                    return "'"  # written '.'(A,B): see _expand_struct
                priority, kind = ops.infix[name]
                if priority > max_priority:
                    return "("
                term, max_priority = args[0], priority if kind == "yfx" else priority - 1
                continue
            if len(args) == 1 and name in ops.prefix:
                return "(" if ops.prefix[name][0] > max_priority else name[0]
            if len(args) == 1 and name in ops.postfix:
                if ops.postfix[name][0] > max_priority:
                    return "("
                term, max_priority = args[0], ops.postfix[name][0] - (ops.postfix[name][1] == "xf")
                continue
            return name[0] if not style.quoted or _SYMBOL.match(name) or name in RESERVED_WORDS \
                else quote_atom(name)[0]
        out: list[str] = []
        _expand(term, max_priority, style, out, [])
        return out[0][:1] if out else ""
