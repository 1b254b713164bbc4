"""Arithmetic: `is/2` and the comparisons evaluate a term to a Python int or float.

    evaluate(term, bindings) -> int | float     ISO errors for unbound, non-numeric or
                                                 non-evaluable terms, and for undefined results

Integers are unbounded, as in SWI-Prolog, up to defaults.MAX_INTEGER_BITS: an operation
whose result would be larger raises resource_error(stack) before computing it. Floats are
IEEE doubles; like SWI-Prolog (float_overflow=error, float_undefined=error), no operation
answers a complex number, an infinity or a NaN: those are evaluation errors. The constants
`inf` and `nan` evaluate, and only - + abs sign min max pass them on unchanged.
"""

from __future__ import annotations

import math
from typing import Callable

from .. import defaults
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


MAX_INTEGER_BITS = defaults.MAX_INTEGER_BITS


def _too_big(bits: float) -> None:
    """Refuse an integer result of about `bits` bits before computing it (SWI-Prolog 9 runs
    out of its global stack there: resource_error(stack))."""
    if bits > MAX_INTEGER_BITS:
        raise iso_error(Struct("resource_error", (Atom("stack"),)))


def _times(x, y):
    if isinstance(x, int) and isinstance(y, int) and x and y:
        _too_big(x.bit_length() + y.bit_length() - 1)
    return x * y


def _shift_left(x: int, y: int) -> int:
    """x << y; a negative count shifts the other way, as in SWI-Prolog (1 << -1 is 0)."""
    if y < 0:
        return x >> -y
    if x:
        _too_big(x.bit_length() + y)
    return x << y


def _float_power(x: float, y: float) -> float:
    """A float power without complex results: (-8) ** (1/3) is undefined, as in SWI-Prolog."""
    if x == 0 and y < 0:
        raise ZeroDivisionError
    return math.pow(x, y)  # ValueError (undefined) for a negative base to a fractional power


def _power(x, y):
    """`**` and `^`: exact for integers (1 and -1 to negative powers too), float otherwise."""
    if isinstance(x, int) and isinstance(y, int):
        if y >= 0:
            if x not in (0, 1, -1):
                _too_big(y * math.log2(abs(x)))
            return x ** y
        if x in (1, -1):
            return x ** (-y) if x == 1 or y % 2 == 0 else -1
        return _float_power(float(x), float(y))
    return _float_power(float(x), float(y))


def _log(x):
    if x == 0:
        raise OverflowError  # log(0) is -inf: swipl 9 says float_overflow
    return math.log(x)


def _log2(x):
    if x == 0:
        raise OverflowError
    return math.log2(x)


def _fractional_part(x):
    if isinstance(x, float) and math.isinf(x):
        return 0.0  # as swipl
    return x - math.trunc(x)


def _sign(x):
    if isinstance(x, int):
        return (x > 0) - (x < 0)
    if x != x:
        return x  # sign(nan) is nan, as in swipl
    return math.copysign(1.0, x) if x else 0.0


def _nan(v) -> bool:
    return isinstance(v, float) and v != v


def _min(x, y):  # a NaN argument gives the other, as in swipl: min(nan, 1) is 1
    return x if _nan(y) else y if _nan(x) or y < x else x


def _max(x, y):
    return x if _nan(y) else y if _nan(x) or y > x else x


def _round_half_away(x) -> int:
    return int(math.floor(x + 0.5)) if x >= 0 else -int(math.floor(-x + 0.5))


def _as_int(fn: Callable[[float], float]) -> Callable:
    return lambda x: x if isinstance(x, int) else int(fn(x))


_EVAL2: dict[str, Callable] = {
    "+": lambda x, y: x + y, "-": lambda x, y: x - y, "*": _times,
    "/": _divide,
    "//": _ints(lambda x, y: _truncating_div(x, y)),
    "mod": _ints(lambda x, y: x % y),
    "rem": _ints(lambda x, y: x - y * _truncating_div(x, y)),
    "div": _ints(lambda x, y: x // y),
    "min": _min, "max": _max,
    "**": _power, "^": _power,
    ">>": _ints(lambda x, y: _shift_left(x, -y)), "<<": _ints(_shift_left),
    "/\\": _ints(lambda x, y: x & y), "\\/": _ints(lambda x, y: x | y), "xor": _ints(lambda x, y: x ^ y),
    "gcd": _ints(math.gcd),
    "atan2": math.atan2, "atan": math.atan2, "copysign": math.copysign,
    "log": lambda x, y: _log(y) / _log(x),
}
_EVAL1: dict[str, Callable] = {
    "-": lambda x: -x, "+": lambda x: x, "abs": abs,
    "sign": _sign,
    "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan,
    "asin": math.asin, "acos": math.acos, "atan": math.atan, "exp": math.exp,
    "log": _log, "log2": _log2, "float": float,
    "integer": _as_int(_round_half_away),
    "float_integer_part": lambda x: float(math.trunc(x)), "float_fractional_part": _fractional_part,
    "truncate": _as_int(math.trunc), "round": _as_int(_round_half_away),
    "ceiling": _as_int(math.ceil), "floor": _as_int(math.floor),
    "\\": _int1(lambda x: ~x), "msb": _int1(lambda x: x.bit_length() - 1),
    "succ": lambda x: x + 1,
}
_EVAL0 = {"pi": math.pi, "e": math.e, "inf": math.inf, "nan": math.nan,
          "max_tagged_integer": (1 << 60) - 1, "epsilon": 2.220446049250313e-16}


# What passes an infinity or a NaN on unchanged (swipl: X is -inf, abs(nan), max(1, nan)).
_TRANSPARENT = frozenset({("-", 1), ("+", 1), ("abs", 1), ("sign", 1), ("min", 2), ("max", 2)})
# Arithmetic proper judges its result: inf + 1 overflows, inf - inf and inf * 0 are
# undefined, 1 / inf is 0.0. Any other function of an infinity overflows, as in swipl
# (exp(-inf), atan(inf), sqrt(inf), float(inf)), except float_fractional_part(inf) = 0.0.
_BY_RESULT = frozenset({("+", 2), ("-", 2), ("*", 2), ("/", 2), ("**", 2), ("^", 2),
                        ("float_fractional_part", 1)})


def _evaluation_error(what: str):
    return iso_error(Struct("evaluation_error", (Atom(what),)))


def _apply(name: str, fn: Callable, values: list):
    checked = (name, len(values)) not in _TRANSPARENT
    if checked:
        for v in values:
            if isinstance(v, float) and not math.isfinite(v):
                if v != v:
                    raise _evaluation_error("undefined")
                if (name, len(values)) not in _BY_RESULT:
                    raise _evaluation_error("float_overflow")
    try:
        result = fn(*values)
    except ZeroDivisionError:
        raise _evaluation_error("zero_divisor") from None
    except OverflowError:
        raise _evaluation_error("float_overflow") from None
    except ValueError:
        raise _evaluation_error("undefined") from None
    if isinstance(result, complex):  # pragma: no cover - defensive: _float_power never answers one
        raise _evaluation_error("undefined")
    if checked and isinstance(result, float) and not math.isfinite(result):
        raise _evaluation_error("undefined" if result != result else "float_overflow")
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
