"""SLD resolution: depth-first, backtracking, iterative, with a step limit.

    Goals       = (goal: Term | Marker, cut_barrier: int, rest: Goals) | None   (a linked list)
    ChoicePoint = (kind, trail_mark, ...)                                        (a stack)

The machine pops a goal, rewrites control constructs into goals and choicepoints,
resolves user predicates against the knowledge base's argument indexes, and
calls builtins. Prolog recursion therefore never becomes Python recursion. A cut
removes the choicepoints above its barrier (the height when its clause was
called); `catch/3` leaves a choicepoint that an exception unwinds to.

ISO errors are raised as `PrologError(term)`; running past the step limit raises
`StepLimitExceeded`, which catch/3 does not intercept.
"""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Callable, Iterator

from ..errors import SchemalogError
from .terms import (CONS, NIL, TRUE, Atom, Float, Int, Str, Struct, Term, Var,
                    is_ground, list_items, make_list, term_to_text)
from .unify import Bindings, rename, variant

if TYPE_CHECKING:  # pragma: no cover
    from .kb import KnowledgeBase

DEFAULT_MAX_STEPS = 10_000_000


class PrologError(Exception):
    """A Prolog exception carrying its ball, e.g. error(type_error(integer, a), _)."""

    def __init__(self, ball: Term) -> None:
        super().__init__(term_to_text(ball))
        self.ball = ball


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


# Markers: goals that only the machine itself pushes.
class _CutTo:
    """Remove choicepoints down to `height` (the then-branch of if-then-else)."""

    __slots__ = ("height",)

    def __init__(self, height: int) -> None:
        self.height = height


class _FailAfterCut(_CutTo):
    """`\\+ G` succeeded in proving G: cut G's alternatives, then fail."""


class _SoftCut:
    """`C *-> T ; E`: C has succeeded, so E is no longer an alternative (C's own stay)."""

    __slots__ = ("height",)

    def __init__(self, height: int) -> None:
        self.height = height


class _ExitCatch:
    """The goal of catch/3 exited: its catcher no longer applies."""

    __slots__ = ("height",)

    def __init__(self, height: int) -> None:
        self.height = height


# Choicepoint kinds (_DEAD: an else-branch a soft cut disabled, popped on backtracking)
_CLAUSES, _ALT, _NONDET, _CATCH, _DEAD = range(5)

Builtin = Callable[["Engine", tuple, Bindings], bool]
NondetBuiltin = Callable[["Engine", tuple, Bindings], Iterator[None]]


class Engine:
    """Answers goals against one knowledge base."""

    def __init__(self, kb: "KnowledgeBase", max_steps: int = DEFAULT_MAX_STEPS,
                 output: Callable[[str], None] | None = None, *,
                 builtins: dict[tuple[str, int], "Builtin"] | None = None,
                 nondet: dict[tuple[str, int], "NondetBuiltin"] | None = None) -> None:
        """`builtins` and `nondet` add predicates written in Python for this engine only
        (schemalog's relations over a workspace, relations.py)."""
        self.kb = kb
        self.max_steps = max_steps
        self.write = output or (lambda text: print(text, end=""))
        self.interrupted = False  # set from another thread (Ctrl-C in the REPL)
        self.deterministic = False  # while an answer is yielded: no alternative is left
        self.builtins = {**BUILTINS, **builtins} if builtins else BUILTINS
        self.nondet = {**NONDET_BUILTINS, **nondet} if nondet else NONDET_BUILTINS

    # -- public API -----------------------------------------------------------
    def solve(self, goal: Term, bindings: Bindings | None = None) -> Iterator[Bindings]:
        """Yield once per proof of `goal`; the bindings hold that answer while yielded."""
        b = bindings if bindings is not None else Bindings()
        _check_body(goal, b)
        return self._run(goal, b)

    def first(self, goal: Term, bindings: Bindings | None = None) -> Bindings | None:
        """Return the bindings of the first proof of `goal`, or None."""
        for b in self.solve(goal, bindings):
            return b
        return None

    def succeeds(self, goal: Term) -> bool:
        """Whether `goal` has a proof."""
        return self.first(goal) is not None

    def answers(self, goal: Term, limit: int | None = None) -> list[Term]:
        """The instances of `goal`, one per proof, resolved (at most `limit`)."""
        out = []
        for b in self.solve(goal):
            out.append(b.resolve(goal))
            if limit is not None and len(out) >= limit:
                break
        return out

    # -- the machine ----------------------------------------------------------
    def _run(self, goal: Term, b: Bindings) -> Iterator[Bindings]:
        cps: list[tuple] = []
        goals = (goal, 0, None)
        kb = self.kb
        builtins = self.builtins
        nondet = self.nondet
        predicates = kb.predicates
        max_steps = self.max_steps
        steps = 0  # per query: each solve (and each findall inside it) has the whole budget
        while True:
            try:
                if goals is None:
                    self.deterministic = not cps
                    yield b
                    steps += 1  # an answer counts: between(1, inf, X) alone stops at the limit
                    if steps > max_steps:
                        raise StepLimitExceeded(
                            f"step limit of {max_steps:,} resolution steps exceeded (runaway recursion?)")
                    goals = self._backtrack(cps, b)
                    if goals is False:
                        return
                    continue
                term, cutb, rest = goals
                steps += 1
                if steps > max_steps:
                    raise StepLimitExceeded(
                        f"step limit of {max_steps:,} resolution steps exceeded (runaway recursion?)")
                if self.interrupted:
                    self.interrupted = False
                    raise SchemalogError("interrupted")
                if not isinstance(term, (Atom, Struct, Var)):
                    if isinstance(term, _CutTo):
                        del cps[term.height:]
                        if isinstance(term, _FailAfterCut):
                            goals = self._backtrack(cps, b)
                            if goals is False:
                                return
                            continue
                        goals = rest
                        continue
                    if isinstance(term, _SoftCut):
                        cps[term.height] = (_DEAD, cps[term.height][1])
                        goals = rest
                        continue
                    if isinstance(term, _ExitCatch):
                        cp = cps[term.height] if term.height < len(cps) else None
                        if cp is not None and cp[0] == _CATCH:
                            cps[term.height] = (_CATCH, cp[1], None, cp[3], cp[4], cp[5])
                        goals = rest
                        continue
                    raise type_error("callable", term)
                if isinstance(term, Var):  # `G` as a goal means call(G): its cut is local
                    term = b.walk(term)
                    if isinstance(term, Var):
                        raise instantiation_error()
                    _check_body(term, b)
                    cutb = len(cps)
                if isinstance(term, Atom):
                    name, args = term.name, ()
                elif isinstance(term, Struct):
                    name, args = term.name, term.args
                else:
                    raise type_error("callable", term)
                arity = len(args)

                # Control constructs ------------------------------------------
                key = (name, arity)
                if key in CONTROL or name == "call":  # one test for the common case, a user predicate
                    if arity == 2 and name == ",":
                        goals = (args[0], cutb, (args[1], cutb, rest))
                        continue
                    if arity == 0:
                        if name == "true":
                            goals = rest
                            continue
                        if name in ("fail", "false"):
                            goals = self._backtrack(cps, b)
                            if goals is False:
                                return
                            continue
                        if name == "!":
                            del cps[cutb:]
                            goals = rest
                            continue
                    if arity == 2 and name == ";":
                        left = args[0]  # not walked: `(C ; B)` with C bound to (X -> Y) is call(C) ; B
                        if isinstance(left, Struct) and left.name == "*->" and len(left.args) == 2:
                            height = len(cps)
                            cps.append((_ALT, b.mark(), (args[1], cutb, rest)))
                            goals = (left.args[0], height + 1, (_SoftCut(height), cutb, (left.args[1], cutb, rest)))
                            continue
                        if isinstance(left, Struct) and left.name == "->" and len(left.args) == 2:
                            height = len(cps)
                            cps.append((_ALT, b.mark(), (args[1], cutb, rest)))
                            goals = (left.args[0], height + 1, (_CutTo(height), cutb, (left.args[1], cutb, rest)))
                            continue
                        cps.append((_ALT, b.mark(), (args[1], cutb, rest)))
                        goals = (left, cutb, rest)
                        continue
                    if arity == 2 and name == "*->":  # (C *-> T) without else: (C, T), cut in C local
                        goals = (args[0], len(cps), (args[1], cutb, rest))
                        continue
                    if arity == 2 and name == "->":  # (C -> T) without else: fails when C fails
                        height = len(cps)
                        goals = (args[0], height, (_CutTo(height), cutb, (args[1], cutb, rest)))
                        continue
                    if arity == 1 and name in ("\\+", "not"):
                        height = len(cps)
                        cps.append((_ALT, b.mark(), rest))
                        goals = (args[0], height + 1, (_FailAfterCut(height), cutb, None))
                        continue
                    if name == "call" and arity >= 1:
                        target = b.walk(args[0])
                        if arity > 1:
                            target = _add_args(target, args[1:])
                        _check_body(target, b)
                        goals = (target, len(cps), rest)
                        continue
                    if arity == 3 and name == "catch":
                        height = len(cps)
                        cps.append((_CATCH, b.mark(), args[1], args[2], rest, cutb))
                        # the goal is meta-called, call/1 style, inside the frame: its errors are caught
                        goals = (Struct("call", (args[0],)), height + 1, (_ExitCatch(height), cutb, rest))
                        continue
                # Builtins ----------------------------------------------------
                fn = builtins.get(key)
                if fn is not None:
                    mark = b.mark()
                    if fn(self, args, b):
                        goals = rest
                    else:
                        b.undo(mark)
                        goals = self._backtrack(cps, b)
                        if goals is False:
                            return
                    continue
                gen_fn = nondet.get(key)
                if gen_fn is not None:
                    mark = b.mark()
                    gen = gen_fn(self, args, b)
                    cps.append((_NONDET, mark, gen, rest))
                    goals = self._backtrack(cps, b)  # takes the generator's first answer
                    if goals is False:
                        return
                    continue

                # User predicates ---------------------------------------------
                pred = predicates.get(key)
                if pred is None:
                    raise existence_error(name, arity)
                candidates = pred.select(args, b)
                if len(candidates) == 1:  # one clause to try: no choicepoint to leave
                    clause = candidates[0]
                    mark = b.mark()
                    match = clause._matcher
                    body = match(term, b) if match is not None else clause.match(term, b)
                    if body is None:
                        b.undo(mark)
                        goals = self._backtrack(cps, b)
                        if goals is False:
                            return
                    else:
                        goals = rest if body is TRUE else (body, len(cps), rest)
                    continue
                height = len(cps)
                cps.append((_CLAUSES, b.mark(), term, candidates, 0, rest, height))
                goals = self._backtrack(cps, b)
                if goals is False:
                    return
            except PrologError as err:
                goals = self._handle_throw(err, cps, b)

    def _backtrack(self, cps: list, b: Bindings):
        """Resume the newest choicepoint; return the goals to continue with, or False."""
        while cps:
            cp = cps[-1]
            kind, mark = cp[0], cp[1]
            b.undo(mark)
            if kind == _CLAUSES:
                _, _, term, candidates, index, rest, height = cp
                while index < len(candidates):
                    clause = candidates[index]
                    index += 1
                    body = clause.match(term, b)
                    if body is not None:
                        if index < len(candidates):
                            cps[-1] = (_CLAUSES, mark, term, candidates, index, rest, height)
                        else:
                            cps.pop()
                        return rest if body is TRUE else (body, height, rest)
                    b.undo(mark)
                cps.pop()
                continue
            if kind == _ALT:
                cps.pop()
                return cp[2]
            if kind == _NONDET:
                gen, rest = cp[2], cp[3]
                try:
                    next(gen)
                    return rest
                except StopIteration:
                    cps.pop()
                    b.undo(mark)
                    continue
            cps.pop()  # a catch frame is transparent to backtracking
        return False

    def _handle_throw(self, err: PrologError, cps: list, b: Bindings):
        ball = b.resolve(err.ball)
        while cps:
            cp = cps.pop()
            if cp[0] != _CATCH or cp[2] is None:
                continue
            _, mark, catcher, recovery, rest, cutb = cp
            b.undo(mark)
            before = b.mark()
            if b.unify(catcher, rename(ball)):
                return (recovery, len(cps), rest)  # the recovery goal is called: its cut is local
            b.undo(before)
        raise err.__class__(ball) if isinstance(err, PrologError) else err

    def _sub_solve(self, goal: Term, b: Bindings) -> Iterator[Bindings]:
        """Solve `goal` in a sub-machine sharing the bindings (findall, forall)."""
        mark = b.mark()
        try:
            for _ in self._run(goal, b):
                yield b
        finally:
            b.undo(mark)


_CONTROL_ARGS = {(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1)}


def _check_body(goal: Term, b: Bindings) -> None:
    """A meta-called goal is checked whole first, as SWI-Prolog compiles it: a number or
    string where a goal should be (`call((fail, 1))`) is type_error(callable, Goal)."""
    stack = [goal]
    while stack:
        t = b.walk(stack.pop())
        if isinstance(t, (Int, Float, Str)):
            raise type_error("callable", b.resolve(goal))
        if isinstance(t, Struct) and (t.name, len(t.args)) in _CONTROL_ARGS:
            stack.extend(t.args)


def _add_args(goal: Term, extra: tuple) -> Term:
    if isinstance(goal, Atom):
        return Struct(goal.name, tuple(extra))
    if isinstance(goal, Struct):
        return Struct(goal.name, goal.args + tuple(extra))
    if isinstance(goal, Var):
        raise instantiation_error()
    raise type_error("callable", goal)


# ---------------------------------------------------------------------------
# Arithmetic

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


# ---------------------------------------------------------------------------
# Builtins: each a pure function of (engine, args, bindings) -> success.

def _compare_numbers(op: Callable[[object, object], bool]) -> Builtin:
    return lambda e, a, b: op(evaluate(a[0], b), evaluate(a[1], b))


def _order_class(t: Term) -> int:
    # SWI-Prolog 9's observed standard order: Var < Number < String < Atom < Compound.
    if isinstance(t, Var):
        return 0
    if isinstance(t, (Int, Float)):
        return 1
    if isinstance(t, Str):
        return 2
    if isinstance(t, Atom):
        return 3
    return 4


def compare_terms(x: Term, y: Term, b: Bindings | None = None) -> int:
    """-1, 0 or 1 by the standard order of terms (iteratively: deep terms are fine)."""
    walk = b.walk if b is not None else (lambda t: t)
    pairs = [(x, y)]
    while pairs:
        p, q = pairs.pop()
        p, q = walk(p), walk(q)
        if p is q:
            continue
        cp, cq = _order_class(p), _order_class(q)
        if cp != cq:
            return -1 if cp < cq else 1
        if cp == 0:
            return -1 if p.id < q.id else 1
        if cp == 1:
            if p.value != q.value:
                return -1 if p.value < q.value else 1
            fp, fq = isinstance(p, Float), isinstance(q, Float)
            if fp != fq:  # equal values: Float before Int
                return -1 if fp else 1
            if p != q:  # -0.0 before 0.0
                return -1 if str(p).startswith("-") else 1
            continue
        if cp in (2, 3):
            a, c = (p.value, q.value) if cp == 2 else (p.name, q.name)
            if a != c:
                return -1 if a < c else 1
            continue
        if len(p.args) != len(q.args):
            return -1 if len(p.args) < len(q.args) else 1
        if p.name != q.name:
            return -1 if p.name < q.name else 1
        pairs.extend(reversed(list(zip(p.args, q.args))))
    return 0


def standard_order_key(term: Term):
    """A sort key for the standard order of terms."""
    return functools.cmp_to_key(compare_terms)(term)


def _type_check(pred: Callable[[Term], bool]) -> Builtin:
    return lambda e, a, b: pred(b.walk(a[0]))


def _is_callable(t: Term) -> bool:
    return isinstance(t, (Atom, Struct))


def _functor(e: Engine, a: tuple, b: Bindings) -> bool:
    term = b.walk(a[0])
    if isinstance(term, Var):
        name, arity = b.walk(a[1]), b.walk(a[2])
        if isinstance(name, Var) or isinstance(arity, Var):
            raise instantiation_error()
        if not isinstance(arity, Int):
            raise type_error("integer", arity)
        if arity.value < 0:
            raise iso_error(Struct("domain_error", (Atom("not_less_than_zero"), arity)))
        if arity.value == 0:
            return b.unify(term, name)
        if not isinstance(name, Atom):
            raise type_error("atomic" if isinstance(name, Struct) else "atom", name)
        return b.unify(term, Struct(name.name, tuple(Var("_") for _ in range(arity.value))))
    if isinstance(term, Struct):
        return b.unify(a[1], Atom(term.name)) and b.unify(a[2], Int(len(term.args)))
    return b.unify(a[1], term) and b.unify(a[2], Int(0))


def _univ(e: Engine, a: tuple, b: Bindings) -> bool:
    term = b.walk(a[0])
    if isinstance(term, Struct):
        return b.unify(a[1], make_list([Atom(term.name), *term.args]))
    if not isinstance(term, Var):
        return b.unify(a[1], make_list([term]))
    items, tail = list_items(b.resolve(a[1]))
    if tail == NIL and not items:
        raise iso_error(Struct("domain_error", (Atom("non_empty_list"), NIL)))
    if tail != NIL or not items:
        raise instantiation_error()
    head = items[0]
    if len(items) == 1:
        return b.unify(term, head)
    if not isinstance(head, Atom):
        raise type_error("atom", head)
    return b.unify(term, Struct(head.name, tuple(items[1:])))


def _copy_term(e: Engine, a: tuple, b: Bindings) -> bool:
    return b.unify(a[1], rename(b.resolve(a[0])))


def _length(e: Engine, a: tuple, b: Bindings) -> Iterator[None]:
    items, tail = list_items(b.resolve(a[0]))
    n = b.walk(a[1])
    if not isinstance(tail, Var) and tail != NIL:
        raise type_error("list", b.resolve(a[0]))
    if isinstance(n, Int) and n.value < 0:
        raise iso_error(Struct("domain_error", (Atom("not_less_than_zero"), n)))
    if tail == NIL:
        if b.unify(n, Int(len(items))):
            yield
        return
    if isinstance(n, Int):
        if n.value >= len(items) and b.unify(tail, make_list([Var("_") for _ in range(n.value - len(items))])):
            yield
        return
    if not isinstance(n, Var):
        raise type_error("integer", n)
    if n is tail:           # length(L, L): L would have to be a list and its own length
        return
    extra = 0
    while True:  # enumerate longer and longer open lists, as SWI-Prolog does
        mark = b.mark()
        if b.unify(tail, make_list([Var("_") for _ in range(extra)])) and b.unify(n, Int(len(items) + extra)):
            yield
        b.undo(mark)
        extra += 1


def _between(e: Engine, a: tuple, b: Bindings) -> Iterator[None]:
    """between(+Low, +High, ?X): integers only, as in SWI-Prolog (no evaluation); High may be inf."""
    def integer(t: Term) -> int:
        if isinstance(t, Var):
            raise instantiation_error()
        if not isinstance(t, Int):
            raise type_error("integer", t)
        return t.value

    low, high, x = integer(b.walk(a[0])), b.walk(a[1]), b.walk(a[2])
    top = math.inf if isinstance(high, Atom) and high.name in ("inf", "infinite") else integer(high)
    if not isinstance(x, (Var, Int)):
        raise type_error("integer", x)
    if isinstance(x, Int):
        if low <= x.value <= top:
            yield
        return
    i = low
    while i <= top:
        mark = b.mark()
        if b.unify(x, Int(i)):
            yield
        b.undo(mark)
        i += 1


def _text_of(t: Term) -> str:
    if isinstance(t, Atom):
        return t.name
    if isinstance(t, Str):
        return t.value
    if isinstance(t, (Int, Float)):
        return term_to_text(t)
    if isinstance(t, Var):
        raise instantiation_error()
    items, tail = list_items(t)
    if tail == NIL and all(isinstance(i, (Int, Atom)) for i in items):
        return "".join(chr(i.value) if isinstance(i, Int) else i.name for i in items)
    raise type_error("atomic", t)


def _atom_length(e, a, b):
    length = b.walk(a[1])
    text = _text_of(b.walk(a[0]))
    if not isinstance(length, (Var, Int)):
        raise type_error("integer", length)
    return b.unify(length, Int(len(text)))


def _atom_codes(e, a, b):
    t = b.walk(a[0])
    if not isinstance(t, Var):
        return b.unify(a[1], make_list([Int(ord(c)) for c in _text_of(t)]))
    return b.unify(t, Atom(_text_of(b.resolve(a[1]))))


def _atom_chars(e, a, b):
    t = b.walk(a[0])
    if not isinstance(t, Var):
        return b.unify(a[1], make_list([Atom(c) for c in _text_of(t)]))
    return b.unify(t, Atom(_text_of(b.resolve(a[1]))))


def _atom_string(e, a, b):
    t = b.walk(a[0])
    if not isinstance(t, Var):
        return b.unify(a[1], Str(_text_of(t)))
    return b.unify(t, Atom(_text_of(b.walk(a[1]))))


def _split_string(e, a, b):
    text, seps, pad = (_text_of(b.walk(x)) for x in a[:3])
    if seps:
        parts, current = [], []
        for ch in text:
            if ch in seps:
                parts.append("".join(current))
                current = []
            else:
                current.append(ch)
        parts.append("".join(current))
    else:
        parts = [text]
    return b.unify(a[3], make_list([Str(p.strip(pad) if pad else p) for p in parts]))


def _term_text(e, a, b, make):
    t = b.walk(a[0])
    if not isinstance(t, Var):
        return b.unify(a[1], make(term_to_text(b.resolve(t))))
    from .parse import parse_term  # parse.py imports nothing from here: no cycle at load time
    from ..errors import SchemalogError as _Err
    try:
        return b.unify(t, parse_term(_text_of(b.walk(a[1]))))
    except _Err as err:
        raise iso_error(Struct("syntax_error", (Atom(err.message),))) from None


def _read_number(text: str) -> Term | None:
    from .parse import parse_term  # parse.py does not import the engine: no cycle
    if not text or text != text.strip():
        return None
    try:
        value = parse_term(text)
    except SchemalogError:
        return None
    return value if isinstance(value, (Int, Float)) else None


def _atom_number(e, a, b):
    atom = b.walk(a[0])
    if isinstance(atom, Var):
        number = b.walk(a[1])
        if isinstance(number, Var):
            raise instantiation_error()
        return b.unify(atom, Atom(term_to_text(number)))
    value = _read_number(_text_of(atom))
    return value is not None and b.unify(a[1], value)


def _number_codes(e, a, b):
    number = b.walk(a[0])
    if not isinstance(number, Var):
        return b.unify(a[1], make_list([Int(ord(c)) for c in term_to_text(number)]))
    value = _read_number(_text_of(b.resolve(a[1])))
    if value is None:
        raise iso_error(Struct("syntax_error", (Atom("illegal_number"),)))
    return b.unify(number, value)


def _assert(front: bool) -> Builtin:
    def run(e: Engine, a: tuple, b: Bindings) -> bool:
        clause = rename(b.resolve(a[0]))
        head, body = (clause.args if isinstance(clause, Struct) and clause.name == ":-"
                      and len(clause.args) == 2 else (clause, TRUE))
        if isinstance(head, Var):
            raise instantiation_error()
        if not isinstance(head, (Atom, Struct)):
            raise type_error("callable", head)
        if isinstance(body, (Int, Float, Str)):
            raise type_error("callable", body)
        key = (head.name, len(head.args) if isinstance(head, Struct) else 0)
        if is_builtin(*key) or key in e.kb.library_predicates():
            raise iso_error(Struct("permission_error", (Atom("modify"), Atom("static_procedure"),
                                                        Struct("/", (Atom(key[0]), Int(key[1]))))))
        e.kb.add_clause(head, body, front=front)
        return True
    return run


def _retract(e: Engine, a: tuple, b: Bindings) -> Iterator[None]:
    target = b.resolve(a[0])
    head, body = (target.args if isinstance(target, Struct) and target.name == ":-"
                  and len(target.args) == 2 else (target, TRUE))
    head = b.walk(head)
    ind = (head.name, len(head.args)) if isinstance(head, Struct) else (
        (head.name, 0) if isinstance(head, Atom) else None)
    if ind is None:
        raise instantiation_error() if isinstance(head, Var) else type_error("callable", head)
    for clause in list(e.kb.clauses(*ind)):
        mark = b.mark()
        h, bd = clause.renamed()
        if b.unify(head, h) and b.unify(body, bd):
            e.kb.remove(clause)
            yield
        b.undo(mark)


def _write(quoted: bool) -> Builtin:
    def run(e: Engine, a: tuple, b: Bindings) -> bool:
        e.write(term_to_text(b.resolve(a[0]), quoted=quoted))
        return True
    return run


def _format(e: Engine, a: tuple, b: Bindings) -> bool:
    fmt = _text_of(b.walk(a[0]))
    args_term = b.resolve(a[1]) if len(a) > 1 else NIL
    items, tail = list_items(args_term)
    args = items if tail == NIL and (items or args_term == NIL) else [args_term]
    out, i, n = [], 0, 0
    while i < len(fmt):
        c = fmt[i]
        if c != "~":
            out.append(c)
            i += 1
            continue
        i += 1
        digits = ""
        while i < len(fmt) and fmt[i].isdigit():
            digits += fmt[i]
            i += 1
        d = fmt[i] if i < len(fmt) else "~"
        i += 1
        if d == "n":
            out.append("\n" * (int(digits) if digits else 1))
            continue
        if d == "~":
            out.append("~")
            continue
        if n >= len(args):
            raise iso_error(Struct("format", (Str("not enough arguments"),)))
        arg = args[n]
        n += 1
        if d == "a":
            out.append(_text_of(arg))
        elif d == "w":
            out.append(term_to_text(arg, quoted=False))
        elif d == "p":
            out.append(term_to_text(arg))
        elif d == "q":
            out.append(term_to_text(arg))
        elif d == "d":
            if not isinstance(arg, Int):
                raise type_error("integer", arg)
            text = str(abs(arg.value))
            if digits and int(digits) > 0:  # ~Nd: N digits after a decimal point
                places = int(digits)
                text = text.rjust(places + 1, "0")
                text = f"{text[:-places]}.{text[-places:]}"
            out.append(("-" if arg.value < 0 else "") + text)
        elif d in "fge":
            value = evaluate(arg, b)
            out.append(f"{value:.{int(digits) if digits else 6}{d}}")
        elif d == "s":
            out.append(_text_of(arg))
        else:
            raise iso_error(Struct("format", (Str(f"unknown directive ~{d}"),)))
    e.write("".join(out))
    return True


def _forall(e: Engine, a: tuple, b: Bindings) -> bool:
    for _ in e._sub_solve(Struct(",", (a[0], Struct("\\+", (a[1],)))), b):
        return False
    return True


def _findall(e: Engine, a: tuple, b: Bindings) -> bool:
    results = [rename(b.resolve(a[0])) for _ in e._sub_solve(a[1], b)]
    return b.unify(a[2], make_list(results))


def _variables(t: Term, b: Bindings, out: list[Var], seen: set[Var]) -> None:
    """The variables of `t` left to right, each once (term_variables/2), without recursion."""
    stack = [t]
    while stack:
        t = b.walk(stack.pop())
        if isinstance(t, Var):
            if t not in seen:
                seen.add(t)
                out.append(t)
        elif isinstance(t, Struct):
            stack.extend(reversed(t.args))


def _bag(to_set: bool) -> NondetBuiltin:
    """bagof/3 and setof/3 as SWI-Prolog's boot/bags.pl defines them: the goal's free
    variables (those neither in the template nor bound by `V^`) are the witness; answers are
    key-sorted on it and each run of equal (or variant) witnesses is one bag, in that order."""

    def solve(e: Engine, a: tuple, b: Bindings) -> Iterator[None]:
        template, goal, bag = a
        goal = b.walk(goal)
        excluded: list[Var] = []
        seen: set[Var] = set()
        _variables(template, b, excluded, seen)
        while isinstance(goal, Struct) and goal.name == "^" and len(goal.args) == 2:
            _variables(goal.args[0], b, excluded, seen)       # Goal = V^G: V is not free
            goal = b.walk(goal.args[1])
        witness: list[Var] = []
        _variables(goal, b, witness, seen)
        if not witness:
            results = [rename(b.resolve(template)) for _ in e._sub_solve(goal, b)]
            if not results:
                return
            mark = b.mark()
            if b.unify(bag, make_list(_sorted_set(results) if to_set else results)):
                yield
            b.undo(mark)
            return
        key = Struct("v", tuple(witness))
        pairs = [rename(b.resolve(Struct("-", (key, template)))) for _ in e._sub_solve(goal, b)]
        if to_set:
            pairs = _sorted_set(pairs)
        else:
            pairs.sort(key=lambda pair: standard_order_key(pair.args[0]))   # keysort: stable
        while pairs:
            first = pairs[0].args[0]
            group, rest = [pairs[0]], []
            for pair in pairs[1:]:
                (group if not rest and (compare_terms(pair.args[0], first) == 0
                                        or variant(pair.args[0], first)) else rest).append(pair)
            pairs = rest
            mark = b.mark()
            ok = all(b.unify(pair.args[0], first) for pair in group[1:]) and b.unify(key, first)
            items = [pair.args[1] for pair in group]
            if ok and b.unify(bag, make_list(_sorted_set([b.resolve(i) for i in items]) if to_set else items)):
                yield
            b.undo(mark)

    return solve


def _sorted_set(items: list[Term]) -> list[Term]:
    """sort/2: standard order, duplicates removed."""
    result: list[Term] = []
    for item in sorted(items, key=standard_order_key):
        if not result or compare_terms(result[-1], item) != 0:
            result.append(item)
    return result


def _throw(e: Engine, a: tuple, b: Bindings) -> bool:
    ball = b.resolve(a[0])
    if isinstance(ball, Var):
        raise instantiation_error()
    raise PrologError(ball)


def _compare(e, a, b):
    """compare(?Order, +X, +Y): Order must be unbound or one of <, =, >."""
    order = b.walk(a[0])
    if not isinstance(order, Var):
        if not isinstance(order, Atom):
            raise type_error("atom", order)
        if order.name not in ("<", "=", ">"):
            raise iso_error(Struct("domain_error", (Atom("order"), order)))
    return b.unify(order, Atom("<=>"[compare_terms(a[1], a[2], b) + 1]))


def _proper_list(t: Term, b: Bindings) -> list[Term]:
    """The items of a proper list; instantiation_error for a partial list, type_error(list) otherwise."""
    whole = b.resolve(t)
    items, tail = list_items(whole)
    if isinstance(tail, Var):
        raise instantiation_error()
    if tail != NIL:
        raise type_error("list", whole)
    return items


def _msort(e, a, b):
    items = _proper_list(a[0], b)
    return b.unify(a[1], make_list(sorted(items, key=standard_order_key)))


def _sort(e, a, b):
    items = _proper_list(a[0], b)
    return b.unify(a[1], make_list(_sorted_set(items)))


BUILTINS: dict[tuple[str, int], Builtin] = {
    ("=", 2): lambda e, a, b: b.unify(a[0], a[1]),
    ("\\=", 2): lambda e, a, b: not _unifiable(a[0], a[1], b),
    ("unify_with_occurs_check", 2): lambda e, a, b: b.unify(a[0], a[1], occurs_check=True),
    ("==", 2): lambda e, a, b: compare_terms(a[0], a[1], b) == 0,
    ("\\==", 2): lambda e, a, b: compare_terms(a[0], a[1], b) != 0,
    ("@<", 2): lambda e, a, b: compare_terms(a[0], a[1], b) < 0,
    ("@>", 2): lambda e, a, b: compare_terms(a[0], a[1], b) > 0,
    ("@=<", 2): lambda e, a, b: compare_terms(a[0], a[1], b) <= 0,
    ("@>=", 2): lambda e, a, b: compare_terms(a[0], a[1], b) >= 0,
    ("compare", 3): _compare,
    ("is", 2): lambda e, a, b: b.unify(a[0], _num(evaluate(a[1], b))),
    ("=:=", 2): _compare_numbers(lambda x, y: x == y),
    ("=\\=", 2): _compare_numbers(lambda x, y: x != y),
    ("<", 2): _compare_numbers(lambda x, y: x < y),
    (">", 2): _compare_numbers(lambda x, y: x > y),
    ("=<", 2): _compare_numbers(lambda x, y: x <= y),
    (">=", 2): _compare_numbers(lambda x, y: x >= y),
    ("var", 1): _type_check(lambda t: isinstance(t, Var)),
    ("nonvar", 1): _type_check(lambda t: not isinstance(t, Var)),
    ("atom", 1): _type_check(lambda t: isinstance(t, Atom)),
    ("number", 1): _type_check(lambda t: isinstance(t, (Int, Float))),
    ("integer", 1): _type_check(lambda t: isinstance(t, Int)),
    ("float", 1): _type_check(lambda t: isinstance(t, Float)),
    ("atomic", 1): _type_check(lambda t: isinstance(t, (Atom, Int, Float, Str))),
    ("compound", 1): _type_check(lambda t: isinstance(t, Struct)),
    ("callable", 1): _type_check(_is_callable),
    ("is_list", 1): lambda e, a, b: list_items(b.resolve(a[0]))[1] == NIL,
    ("string", 1): _type_check(lambda t: isinstance(t, Str)),
    ("ground", 1): lambda e, a, b: is_ground(b.resolve(a[0])),
    ("functor", 3): _functor,
    ("=..", 2): _univ,
    ("copy_term", 2): _copy_term,
    ("atom_length", 2): _atom_length,
    ("atom_codes", 2): _atom_codes,
    ("atom_chars", 2): _atom_chars,
    ("atom_string", 2): _atom_string,
    ("atom_number", 2): _atom_number,
    ("atom_to_term", 2): lambda e, a, b: _term_text(e, (a[1], a[0]), b, Atom),
    ("term_to_atom", 2): lambda e, a, b: _term_text(e, a, b, Atom),
    ("term_string", 2): lambda e, a, b: _term_text(e, a, b, Str),
    ("split_string", 4): _split_string,
    ("number_codes", 2): _number_codes,
    ("assert", 1): _assert(front=False),
    ("assertz", 1): _assert(front=False),
    ("asserta", 1): _assert(front=True),
    ("write", 1): _write(quoted=False),
    ("print", 1): _write(quoted=True),
    ("writeq", 1): _write(quoted=True),
    ("write_canonical", 1): _write(quoted=True),
    ("writeln", 1): lambda e, a, b: _write(False)(e, a, b) and (e.write("\n") or True),
    ("nl", 0): lambda e, a, b: e.write("\n") or True,
    ("format", 1): _format,
    ("format", 2): _format,
    ("forall", 2): _forall,
    ("findall", 3): _findall,
    ("throw", 1): _throw,
    ("msort", 2): _msort,
    ("sort", 2): _sort,
}

NONDET_BUILTINS: dict[tuple[str, int], NondetBuiltin] = {
    ("between", 3): _between,
    ("length", 2): _length,
    ("retract", 1): _retract,
    ("bagof", 3): _bag(to_set=False),
    ("setof", 3): _bag(to_set=True),
}

# Control constructs the machine handles itself (so `is_builtin` knows them).
CONTROL = frozenset({(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1), ("not", 1), ("!", 0),
                     ("true", 0), ("fail", 0), ("false", 0), ("catch", 3)}
                    | {("call", n) for n in range(1, 9)})


def is_builtin(name: str, arity: int) -> bool:
    """Whether `name/arity` is built in (so it cannot be redefined)."""
    key = (name, arity)
    return key in BUILTINS or key in NONDET_BUILTINS or key in CONTROL


def _unifiable(x: Term, y: Term, b: Bindings) -> bool:
    mark = b.mark()
    ok = b.unify(x, y)
    b.undo(mark)
    return ok


# Built-ins beyond the core (text, sorting, the database), defined in library.py.
from .library import EXTRA, EXTRA_NONDET  # noqa: E402  (library.py imports this module's helpers)

BUILTINS.update(EXTRA)
NONDET_BUILTINS.update(EXTRA_NONDET)
for _key in EXTRA_NONDET:       # a nondeterministic version replaces a one-mode one
    BUILTINS.pop(_key, None)
