"""Arithmetic: `is/2` and the comparisons evaluate a term to a Python int or float.

    evaluate(term, bindings) -> int | float     ISO errors for unbound, non-numeric or
                                                 non-evaluable terms, and for undefined results

Integers are unbounded, as in SWI-Prolog; floats are IEEE doubles.
"""

from __future__ import annotations

import math
from typing import Callable

from .exceptions import instantiation_error, iso_error, type_error
from .terms import CONS, NIL, Atom, Float, Int, Str, Struct, Term, Var
from .unify import Bindings


def _num(value) -> Term:
    if isinstance(value, bool):
        return Int(int(value))
    if isinstance(value, int):
        return Int(value)
    return Float(value)


def _ints(fn: Callable[[int, int], int]) -> Callable:
    """An integer-only operation: floats are a type error, as in ISO."""
    def run(x, y):
        for v in (x, y):
            if not isinstance(v, int):
                raise type_error("integer", _num(v))
        return fn(x, y)
    return run


def _int1(fn: Callable[[int], int]) -> Callable:
    def run(x):
        if not isinstance(x, int):
            raise type_error("integer", _num(x))
        return fn(x)
    return run


def _truncating_div(x: int, y: int) -> int:
    """x // y rounded toward zero, exactly (SWI-Prolog's default for //)."""
    q = abs(x) // abs(y)
    return q if (x >= 0) == (y >= 0) else -q


def _divide(x, y):
    if isinstance(x, int) and isinstance(y, int):
        if y == 0:
            raise ZeroDivisionError
        return x // y if x % y == 0 else x / y
    if y == 0:
        raise iso_error(Struct("evaluation_error", (Atom("undefined" if x == 0 or x != x else "zero_divisor"),)))
    return x / y


def _power(x, y):
    """`**` and `^`: exact for integers (1 and -1 to negative powers too), float otherwise."""
    if isinstance(x, int) and isinstance(y, int):
        if y >= 0:
            return x ** y
        if x in (1, -1):
            return x ** (-y) if x == 1 or y % 2 == 0 else -1
        return float(x) ** y
    return float(x) ** y


def _round_half_away(x) -> int:
    return int(math.floor(x + 0.5)) if x >= 0 else -int(math.floor(-x + 0.5))


def _as_int(fn: Callable[[float], float]) -> Callable:
    return lambda x: x if isinstance(x, int) else int(fn(x))


_EVAL2: dict[str, Callable] = {
    "+": lambda x, y: x + y, "-": lambda x, y: x - y, "*": lambda x, y: x * y,
    "/": _divide,
    "//": _ints(lambda x, y: _truncating_div(x, y)),
    "mod": _ints(lambda x, y: x % y),
    "rem": _ints(lambda x, y: x - y * _truncating_div(x, y)),
    "div": _ints(lambda x, y: x // y),
    "min": lambda x, y: y if y < x else x, "max": lambda x, y: y if y > x else x,
    "**": _power, "^": _power,
    ">>": _ints(lambda x, y: x >> y), "<<": _ints(lambda x, y: x << y),
    "/\\": _ints(lambda x, y: x & y), "\\/": _ints(lambda x, y: x | y), "xor": _ints(lambda x, y: x ^ y),
    "gcd": _ints(math.gcd),
    "atan2": math.atan2, "atan": math.atan2, "copysign": math.copysign,
    "log": lambda x, y: math.log(y) / math.log(x),
}
_EVAL1: dict[str, Callable] = {
    "-": lambda x: -x, "+": lambda x: x, "abs": abs,
    "sign": lambda x: (x > 0) - (x < 0) if isinstance(x, int) else (math.copysign(1.0, x) if x else 0.0),
    "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan,
    "asin": math.asin, "acos": math.acos, "atan": math.atan, "exp": math.exp,
    "log": math.log, "log2": math.log2, "float": float,
    "integer": _as_int(_round_half_away),
    "float_integer_part": lambda x: float(math.trunc(x)), "float_fractional_part": lambda x: x - math.trunc(x),
    "truncate": _as_int(math.trunc), "round": _as_int(_round_half_away),
    "ceiling": _as_int(math.ceil), "floor": _as_int(math.floor),
    "\\": _int1(lambda x: ~x), "msb": _int1(lambda x: x.bit_length() - 1),
    "succ": lambda x: x + 1,
}
_EVAL0 = {"pi": math.pi, "e": math.e, "inf": math.inf, "infinite": math.inf, "nan": math.nan,
          "max_tagged_integer": (1 << 60) - 1, "epsilon": 2.220446049250313e-16}


def _apply(name: str, fn: Callable, values: list):
    try:
        result = fn(*values)
    except ZeroDivisionError:
        raise iso_error(Struct("evaluation_error", (Atom("zero_divisor"),))) from None
    except OverflowError:
        raise iso_error(Struct("evaluation_error", (Atom("float_overflow"),))) from None
    except ValueError:
        raise iso_error(Struct("evaluation_error", (Atom("undefined"),))) from None
    if isinstance(result, float) and math.isinf(result) and not any(
            isinstance(v, float) and math.isinf(v) for v in values):
        raise iso_error(Struct("evaluation_error", (Atom("float_overflow"),)))
    return result


def evaluate(term: Term, b: Bindings):
    """Evaluate an arithmetic expression to a Python int or float (iteratively)."""
    # Post-order over the expression: (term, None) to expand, (name, fn, n) to apply.
    values: list = []
    work: list = [term]
    while work:
        item = work.pop()
        if isinstance(item, tuple):
            name, fn, n = item
            args = values[len(values) - n:]
            del values[len(values) - n:]
            values.append(_apply(name, fn, args))
            continue
        t = b.walk(item)
        if isinstance(t, Int):
            values.append(t.value)
        elif isinstance(t, Float):
            values.append(t.value)
        elif isinstance(t, Var):
            raise instantiation_error()
        elif isinstance(t, Atom):
            if t.name not in _EVAL0:
                raise type_error("evaluable", Struct("/", (t, Int(0))))
            values.append(_EVAL0[t.name])
        elif isinstance(t, Str) and len(t.value) == 1:
            values.append(ord(t.value))  # "a" evaluates to its character code
        elif isinstance(t, Struct):
            if t.name == CONS and len(t.args) == 2 and b.walk(t.args[1]) == NIL:
                work.append(t.args[0])  # [X] evaluates X
                continue
            table = _EVAL1 if len(t.args) == 1 else _EVAL2 if len(t.args) == 2 else {}
            fn = table.get(t.name)
            if fn is None:
                raise type_error("evaluable", Struct("/", (Atom(t.name), Int(len(t.args)))))
            work.append((t.name, fn, len(t.args)))
            work.extend(reversed(t.args))
        else:
            raise type_error("evaluable", t)
    return values[0]
