"""The core built-in predicates, in Python: each a function of (machine, args, bindings).

    Builtin       = (machine, args, bindings) -> bool              deterministic: succeed or fail
    NondetBuiltin = (machine, args, bindings) -> Iterator[None]    one yield per solution

A built-in that builds or walks a term of N cells, or writes N characters, first charges N
steps (`Machine.charge`), so the step limit bounds its time and memory as it bounds
resolution; a term it must see whole is resolved by `Bindings.resolve`, which raises
CyclicTermError on a cyclic one (X = f(X)).

A built-in sees the engine only through `Machine`, and the knowledge base only through
`Database`: the two small interfaces this module states, so that the engine (which
assembles the tables, engine.py) and the knowledge base (which consults files, kb.py)
can sit above it without either importing the other's layer back.
"""

from __future__ import annotations

import functools
import math
from decimal import Decimal
from typing import Callable, Iterator, Protocol

from ..errors import SchemalogError

from .arith import _num, evaluate
from .exceptions import CyclicTermError, PrologError, instantiation_error, iso_error, type_error
from .terms import (CONS, NIL, TRUE, Atom, Float, Int, Str, Struct, Term, Var,
                    NO_OPERATORS, canonical_names, int_text, list_items, make_list, term_to_text)
from .unify import Bindings, rename, variant


class Database(Protocol):
    """What the machine and its built-ins read and change of a knowledge base (kb.py)."""

    predicates: dict
    files: list
    flags: dict       # the Prolog flags (set_prolog_flag/2), name -> Term
    operators: dict   # terms.OperatorTable: (name, prefix | infix | postfix) -> (priority, type)

    def clauses(self, name: str, arity: int) -> list: ...
    def add_clause(self, head: Term, body: Term = TRUE, pos=None, front: bool = False) -> None: ...
    def remove(self, clause) -> None: ...
    def remove_all(self, clauses: list) -> None: ...
    def library_predicates(self) -> set[tuple[str, int]]: ...
    def is_library(self, key: tuple[str, int]) -> bool: ...
    def forget_file(self, file: str) -> None: ...
    def abolish(self, name: str, arity: int) -> None: ...
    def declare_dynamic(self, name: str, arity: int) -> None: ...
    def consult(self, path, max_bytes: int = ..., pos=None) -> None: ...


class Machine(Protocol):
    """What a built-in needs of the engine that calls it (engine.py)."""

    kb: Database
    write: Callable[[str], None]
    steps: int
    since: dict[str, int]

    def sub_solve(self, goal: Term, b: Bindings) -> Iterator[Bindings]: ...
    def call_goal(self, goal: Term, b: Bindings) -> Iterator[Bindings]: ...
    def is_builtin(self, name: str, arity: int) -> bool: ...
    def charge(self, work: int) -> None: ...


Builtin = Callable[[Machine, tuple, Bindings], bool]
NondetBuiltin = Callable[[Machine, tuple, Bindings], Iterator[None]]


_CONTROL_ARGS = {(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1)}


def body_term(goal: Term, b: Bindings) -> Term:
    """A meta-called goal as call/1 runs it (ISO 7.6.2, converting a term to a body): checked
    whole first, as SWI-Prolog compiles it, so a number or string where a goal should be
    (`call((fail, 1))`) is type_error(callable, Goal); and every variable in a control position
    (an argument of `,` `;` `->` `*->` `\\+`) that is bound now replaced by its value, so that
    `C = !, call((member(X, L), C))` cuts member/2's alternatives and `C = (A -> B), call((C ; D))`
    is an if-then-else. A variable still unbound stays one and runs as call(V) when reached: its
    cut is local, as in a clause body, whose variable goals were converted when it was read."""
    root = b.walk(goal)
    if isinstance(root, (Int, Float, Str)):
        raise type_error("callable", b.resolve_finite(goal))
    if not _is_control(root):
        return root
    built: dict[int, Term] = {}      # the converted control terms, by the id of the original
    open_: set[int] = set()          # those whose arguments are being converted
    stack: list[tuple[Struct, bool]] = [(root, False)]   # depth first, without recursion
    while stack:
        t, leaving = stack.pop()
        if leaving:
            open_.discard(id(t))
            args = tuple(built.get(id(v), v) for v in map(lambda a: _bound_value(a, b), t.args))
            built[id(t)] = t if all(x is y for x, y in zip(args, t.args)) else Struct(t.name, args)
            continue
        if id(t) in built:
            continue
        if id(t) in open_:           # a cyclic body, G = (a, G): checked once round, run as it is
            _check_cyclic(root, goal, b)
            return root
        open_.add(id(t))
        stack.append((t, True))
        for arg in t.args:
            value = _bound_value(arg, b)
            if isinstance(value, (Int, Float, Str)):
                raise type_error("callable", b.resolve_finite(goal))
            if _is_control(value) and id(value) not in built:
                stack.append((value, False))
    return built[id(root)]


def _bound_value(arg: Term, b: Bindings) -> Term:
    """A control argument's value now: a bound variable's, else the argument itself."""
    if type(arg) is not Var:
        return arg
    value = b.walk(arg)
    return arg if type(value) is Var else value


def _is_control(t: Term) -> bool:
    return type(t) is Struct and (t.name, len(t.args)) in _CONTROL_ARGS


def _check_cyclic(root: Term, goal: Term, b: Bindings) -> None:
    """Check a cyclic body's control skeleton once round (type_error for a number in it)."""
    stack, seen = [root], set()
    while stack:
        t = b.walk(stack.pop())
        if isinstance(t, (Int, Float, Str)):
            raise type_error("callable", b.resolve_finite(goal))
        if _is_control(t) and id(t) not in seen:
            seen.add(id(t))
            stack.extend(t.args)


def check_body(goal: Term, b: Bindings) -> None:
    """Check a meta-called goal whole, as body_term does, without converting it."""
    body_term(goal, b)



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
    seen: set[tuple[int, int]] = set()  # compound pairs met through a binding: see Bindings.unify
    while pairs:
        p, q = pairs.pop()
        via = type(p) is Var or type(q) is Var
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
        if via:  # cyclic terms (X = f(X)) equal where their unfoldings agree, as in SWI-Prolog
            key = (id(p), id(q))
            if key in seen:
                continue
            seen.add(key)
        pairs.extend(reversed(list(zip(p.args, q.args))))
    return 0


def standard_order_key(term: Term):
    """A sort key for the standard order of terms."""
    return functools.cmp_to_key(compare_terms)(term)


def _type_check(pred: Callable[[Term], bool]) -> Builtin:
    return lambda e, a, b: pred(b.walk(a[0]))


def _is_callable(t: Term) -> bool:
    return isinstance(t, (Atom, Struct))


_NAMES: dict[str, Atom] = {}            # one Atom per functor name functor/3 has answered
_ARITIES = tuple(Int(n) for n in range(64))


def _bind_or_unify(b: Bindings, x: Term, value: Term) -> bool:
    """Unify `x` with the non-variable `value`, binding an unbound `x` at once."""
    values = b.values
    while type(x) is Var:
        bound = values.get(x)
        if bound is None:
            values[x] = value
            b.trail.append(x)
            return True
        x = bound
    return b.unify(x, value)


def _functor(e: Machine, a: tuple, b: Bindings) -> bool:
    term = b.walk(a[0])
    if type(term) is Struct:    # the common case first: no Atom or Int made, Name and Arity bound at once
        name = _NAMES.get(term.name)
        if name is None:
            name = Atom(term.name)
            if len(_NAMES) < 10_000:    # bounded: a program making names without end
                _NAMES[term.name] = name
        n = len(term.args)
        return _bind_or_unify(b, a[1], name) and _bind_or_unify(b, a[2], _ARITIES[n] if n < 64 else Int(n))
    if isinstance(term, Var):
        name, arity = b.walk(a[1]), b.walk(a[2])
        if isinstance(name, Var) or isinstance(arity, Var):
            raise instantiation_error()
        if isinstance(name, Struct):
            raise type_error("atomic", name)
        if not isinstance(arity, Int):
            raise type_error("integer", arity)
        if arity.value < 0:
            raise iso_error(Struct("domain_error", (Atom("not_less_than_zero"), arity)))
        if arity.value == 0:
            return b.unify(term, name)
        if not isinstance(name, Atom):
            raise type_error("atomic" if isinstance(name, Struct) else "atom", name)
        e.charge(arity.value)
        b.bind(term, Struct(name.name, tuple([Var("_") for _ in range(arity.value)])))   # term: unbound
        return True
    if isinstance(term, Struct):
        return b.unify(a[1], Atom(term.name)) and b.unify(a[2], Int(len(term.args)))
    return b.unify(a[1], term) and b.unify(a[2], Int(0))


def _univ(e: Machine, a: tuple, b: Bindings) -> bool:
    term = b.walk(a[0])
    if not isinstance(term, Var):
        whole = b.walk(a[1])
        if whole == NIL:
            return False                      # a =.. []: [] is a list, just not this term's (ISO 8.5.3)
        if not isinstance(whole, Var) and not (isinstance(whole, Struct) and whole.name == CONS
                                               and len(whole.args) == 2):
            raise type_error("list", whole)   # f(a) =.. foo, as SWI says
        name = Atom(term.name) if isinstance(term, Struct) else term
        parts = make_list([name, *term.args]) if isinstance(term, Struct) else make_list([term])
        e.charge(len(term.args) if isinstance(term, Struct) else 1)
        if b.unify(whole, parts):
            return True
        # SWI-Prolog checks the arguments' list once the name fits: a =.. [a|b] is
        # type_error(list, b), ab =.. [a|b] fails
        if isinstance(whole, Struct) and _unifiable(whole.args[0], name, b):
            _check_list_or_partial(b, whole.args[1])
        return False
    if isinstance(term, Struct):
        e.charge(len(term.args))
        return b.unify(a[1], make_list([Atom(term.name), *term.args]))
    if not isinstance(term, Var):
        return b.unify(a[1], make_list([term]))
    # The list's spine only: its items become the arguments as they are, unresolved (a
    # resolved copy of each cost a walk of the whole term, derive's `E =.. [Op, A, B]`).
    items, tail = list_spine(b, a[1])
    head = b.walk(items[0]) if items else None
    if isinstance(tail, Var) or isinstance(head, Var):
        raise instantiation_error()
    if tail != NIL:
        raise type_error("list", resolve_list(b, a[1]))
    if not items:
        raise iso_error(Struct("domain_error", (Atom("non_empty_list"), NIL)))
    if len(items) == 1:
        if isinstance(head, Struct):
            raise type_error("atomic", b.resolve_finite(head))
        return b.unify(term, head)
    if not isinstance(head, Atom):
        raise type_error("atom", b.resolve_finite(head))
    return b.unify(term, Struct(head.name, tuple(items[1:])))


def _copy_term(e: Machine, a: tuple, b: Bindings) -> bool:
    return b.unify(a[1], b.copy(a[0]))


def proper_items(b: Bindings, t: Term) -> list[Term]:
    """The items of the proper list `t`, resolved: instantiation_error for a partial list,
    type_error(list, T) for anything else."""
    whole = resolve_list(b, t)
    items, tail = list_items(whole)
    if isinstance(tail, Var):
        raise instantiation_error()
    if tail != NIL:
        raise type_error("list", whole)
    return items


def resolve_list(b: Bindings, t: Term) -> Term:
    """`b.resolve(t)`, where a cyclic term is type_error(list, T), as SWI-Prolog says of a
    cyclic list (X = [a|X])."""
    try:
        return b.resolve(t)
    except CyclicTermError as err:
        raise type_error("list", err.culprit) from None


def list_spine(b: Bindings, t: Term) -> tuple[list[Term], Term]:
    """The items of a list, unresolved, and its walked tail (NIL for a proper list); the
    items may be cyclic terms. A cyclic list (X = [a|X]) is type_error(list, X), as in SWI."""
    items: list[Term] = []
    cell = b.walk(t)
    seen: set[int] = set()
    while isinstance(cell, Struct) and cell.name == CONS and len(cell.args) == 2:
        if id(cell) in seen:
            raise type_error("list", b.resolve_finite(t))
        seen.add(id(cell))
        items.append(cell.args[0])
        cell = b.walk(cell.args[1])
    b.work += len(items)
    return items, cell


def _length(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    items, tail = list_spine(b, a[0])
    whole = a[0]
    n = b.walk(a[1])
    if not isinstance(n, (Var, Int)):       # length([], a): type_error(integer, a), as in SWI
        raise type_error("integer", n)
    if isinstance(n, Int) and n.value < 0:  # before the list's type, as in SWI
        raise iso_error(Struct("domain_error", (Atom("not_less_than_zero"), n)))
    if not isinstance(tail, Var) and tail != NIL:
        raise type_error("list", b.resolve_finite(whole))
    if tail == NIL:
        if b.unify(n, Int(len(items))):
            yield
        return
    if isinstance(n, Int):
        if n.value >= len(items):
            e.charge(n.value - len(items))  # before building: length(L, 10**8) stops at once
            if b.unify(tail, make_list([Var("_") for _ in range(n.value - len(items))])):
                yield
        return
    if not isinstance(n, Var):
        raise type_error("integer", n)
    if n is tail:           # length(L, L): L would have to be a list and its own length
        return
    extra, cells = 0, NIL
    while True:  # enumerate longer and longer open lists, as SWI-Prolog does
        # Each answer is a list one cell longer: charged whole (a caller walks it), so
        # `length(L, N), fail` stops at the limit after ~4,500 answers. The cells of the last
        # answer are reused (their variables are unbound again), so making one is O(1).
        e.charge(extra)
        mark = b.mark()
        if b.unify(tail, cells) and b.unify(n, Int(len(items) + extra)):
            yield
        b.undo(mark)
        extra += 1
        cells = Struct(CONS, (Var("_"), cells))


def _between(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
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
    if isinstance(tail, Var) or any(isinstance(i, Var) for i in items):
        raise instantiation_error()   # a partial list, or an unbound element: as SWI says
    if tail == NIL:
        return _list_text(items)
    raise type_error("atomic", t)


def _list_text(items: list[Term]) -> str:
    """The text of a proper list of bound elements, read as SWI-Prolog reads it: a char
    list when the first element is a char, else a code list (so [ab] and [f(x)] are
    type_error(character_code, _)); another element is type_error(character, E) in a
    char list, type_error(character_code, E) in a code list."""
    out = []
    if items and isinstance(items[0], Atom) and len(items[0].name) == 1:
        for item in items:
            if not (isinstance(item, Atom) and len(item.name) == 1):
                raise type_error("character", item)
            out.append(item.name)
    else:
        for item in items:
            if not isinstance(item, Int):
                raise type_error("character_code", item)
            out.append(code_char(item))
    return "".join(out)


def code_char(code: Int) -> str:
    """The character of a code; type_error(character_code, Code), as SWI-Prolog raises, for
    a negative code, one past Unicode (0x10FFFF), or a surrogate (0xD800-0xDFFF: no text
    can be written with it)."""
    value = code.value
    if not 0 <= value <= 0x10FFFF or 0xD800 <= value <= 0xDFFF:
        raise type_error("character_code", code)
    return chr(value)


def text_of(e: Machine, t: Term, b: Bindings) -> str:
    """The text of an atomic term or a code or char list (resolved: cyclic is
    type_error(list)); the list's cells and the text's characters are charged."""
    t = b.walk(t)
    if isinstance(t, Struct) and t.name == CONS and len(t.args) == 2:
        text = _text_of(resolve_list(b, t))
    else:
        text = _text_of(t)
    e.charge(len(text))
    return text


def _atom_length(e, a, b):
    length = b.walk(a[1])
    t = b.walk(a[0])
    if isinstance(t, Struct):   # SWI-Prolog's word for what atom_length/2 takes: text
        items, tail = list_spine(b, t)
        if isinstance(tail, Var):
            raise instantiation_error()
        if tail != NIL or not (t.name == CONS and len(t.args) == 2):
            raise type_error("text", b.resolve_finite(t))
    # An atom's or a string's length is known without walking its text: nothing to charge,
    # so the length of a 10 MB atom is not a step-limit error.
    text = t.name if type(t) is Atom else t.value if type(t) is Str else text_of(e, a[0], b)
    if not isinstance(length, (Var, Int)):
        raise type_error("integer", length)
    return b.unify(length, Int(len(text)))


def atomic_text(e: Machine, t: Term, b: Bindings, kind: str = "atom") -> str:
    """The text of an atomic first argument of atom_chars/2, sub_atom/5...: an atom, a
    number or a string, as SWI-Prolog takes them; a compound (a list too) is
    type_error(Kind, T); [] is type_error(atom, []), as in SWI-Prolog 7, where [] is no atom."""
    t = b.walk(t)
    if isinstance(t, Var):
        raise instantiation_error()
    if isinstance(t, Struct) or t == NIL:
        raise type_error(kind, t)
    text = _text_of(t)
    e.charge(len(text))
    return text


def text_list(e: Machine, t: Term, b: Bindings) -> str:
    """The text of a list of chars or codes, or of a string, for atom_chars/2,
    number_codes/2...: ISO's errors, in SWI-Prolog's order: a partial list or an unbound
    element is instantiation_error, anything that is no list type_error(list, T), an
    element of the wrong kind as `_list_text` says. SWI-Prolog reads a list of the other
    kind too (atom_codes(A, [a, b]) gives ab): the first element decides the kind."""
    t = b.walk(t)
    if isinstance(t, Str):
        e.charge(len(t.value))
        return t.value
    if isinstance(t, Var):
        raise instantiation_error()
    items = proper_items(b, t)
    e.charge(len(items))
    for item in items:
        if isinstance(item, Var):
            raise instantiation_error()
    return _list_text(items)


def _check_list_or_partial(b: Bindings, t: Term) -> None:
    """type_error(list, T) unless T is a list or a partial list (the output of atom_chars/2)."""
    whole = t = b.walk(t)
    seen: set[int] = set()   # a cyclic list (X = [a|X]) is walked once round
    while isinstance(t, Struct) and t.name == CONS and len(t.args) == 2 and id(t) not in seen:
        seen.add(id(t))
        t = b.walk(t.args[1])
    if not (isinstance(t, Var) or t == NIL or id(t) in seen):
        raise type_error("list", b.resolve_finite(whole))


def _text_split(make_item) -> Builtin:
    """atom_chars/2 and atom_codes/2: an atomic first argument's text as a list, or the
    atom of a list (a string) of chars or codes."""
    def run(e: Machine, a: tuple, b: Bindings) -> bool:
        t = b.walk(a[0])
        if not isinstance(t, Var):
            text = atomic_text(e, t, b)
            whole = b.walk(a[1])
            if _complete_list(b, whole):   # read as text, as SWI-Prolog does: its errors too
                return text_list(e, whole, b) == text
            _check_list_or_partial(b, whole)
            return b.unify(a[1], make_list([make_item(c) for c in text]))
        return b.unify(t, Atom(text_list(e, a[1], b)))
    return run


_atom_codes = _text_split(lambda c: Int(ord(c)))
_atom_chars = _text_split(Atom)


def _atom_string(e, a, b):
    t = b.walk(a[0])
    if not isinstance(t, Var):
        return b.unify(a[1], Str(text_of(e, t, b)))
    return b.unify(t, Atom(text_of(e, a[1], b)))


def _split_string(e, a, b):
    """split_string(+S, +SepChars, +PadChars, -Subs), as SWI-Prolog and ECLiPSe define it: the
    padding is stripped from both ends first, and each field starts after the padding that
    follows its separator, so separators that are also padding run together as one."""
    text, seps, pad = (text_of(e, x, b) for x in a[:3])
    return b.unify(a[3], make_list([Str(p) for p in split_text(text, seps, pad)]))


def split_text(text: str, seps: str, pad: str) -> list[str]:
    """The fields of split_string/4 (SWI-Prolog and ECLiPSe agree on them)."""
    start, end = 0, len(text)
    while start < end and text[start] in pad:
        start += 1
    while end > start and text[end - 1] in pad:
        end -= 1
    parts = []
    while True:
        while start < end and text[start] in pad:
            start += 1
        stop = start
        while stop < end and text[stop] not in seps:
            stop += 1
        field_end = stop
        while field_end > start and text[field_end - 1] in pad:
            field_end -= 1
        parts.append(text[start:field_end])
        if stop >= end:
            break
        start = stop + 1
    return parts


def _term_text(e, a, b, make):
    t = b.walk(a[0])
    if not isinstance(t, Var):
        text = term_to_text(b.resolve_finite(t), ops=e.kb.operators.view())
        e.charge(len(text))
        return b.unify(a[1], make(text))
    from .opread import parse_term  # lark is loaded only when text is read as a term
    from ..errors import SchemalogError as _Err
    try:
        return b.unify(t, parse_term(text_of(e, a[1], b), "<argument>", e.kb.operators))
    except _Err as err:
        raise iso_error(Struct("syntax_error", (Atom(err.message),))) from None


_LAYOUT = " \t\n\r\v\f"


def _read_number(text: str, layout: bool = False) -> Term | None:
    """The number `text` is written as, or None. With `layout`, leading layout is allowed,
    as number_codes/2 allows it (ISO 8.16.7); a sign is read with its number only when
    the digits follow it at once ("-1", "+1"; "- 1" is no number); a comment is no number."""
    from .parse import parse_term  # lark is loaded only when a number is read from text
    if layout:
        text = text.lstrip(_LAYOUT)
    if not text or text != text.rstrip(_LAYOUT) and not text.startswith("0'"):
        return None
    body = text[1:] if text[0] in "+-" else text
    if not body or not body[0].isdigit() or ("/*" in body or "%" in body) and not body.startswith("0'"):
        return None
    try:
        value = parse_term(body)
    except SchemalogError:
        return None
    if not isinstance(value, (Int, Float)):
        return None
    if text[0] == "-":
        return Int(-value.value) if isinstance(value, Int) else Float(-value.value)
    return value


def _atom_number(e, a, b):
    """atom_number(?Atom, ?Number), as SWI-Prolog: text that is no number fails; a Number
    that is no number is type_error(number, N) unless Atom is text that is no number."""
    number, atom = b.walk(a[1]), b.walk(a[0])
    bad_number = not isinstance(number, (Var, Int, Float))
    if isinstance(atom, Var):
        if isinstance(number, Var):
            raise instantiation_error()
        if bad_number:
            raise type_error("number", number)
        return b.unify(atom, Atom(term_to_text(number)))
    try:
        text = text_of(e, atom, b)
    except PrologError:
        text = None
    value = _read_number(text) if text is not None else None
    if text is not None and value is None:
        return False
    if bad_number:
        raise type_error("number", number)
    return value is not None and b.unify(number, value)


def _number_text(make_item) -> Builtin:
    """number_codes/2 and number_chars/2: a complete list (or string) is read as a number
    and unified, so number_codes(33.0, "3.3E+01") holds; else the number is written."""
    def run(e: Machine, a: tuple, b: Bindings) -> bool:
        number, listed = b.walk(a[0]), b.walk(a[1])
        if not isinstance(number, (Var, Int, Float)):
            raise type_error("number", number)
        if isinstance(number, Var) or _complete_list(b, listed):
            value = _read_number(text_list(e, listed, b), layout=True)
            if value is None:
                raise iso_error(Struct("syntax_error", (Atom("illegal_number"),)))
            return b.unify(number, value)
        _check_list_or_partial(b, listed)
        text = term_to_text(number)
        e.charge(len(text))
        return b.unify(listed, make_list([make_item(c) for c in text]))
    return run


def _complete_list(b: Bindings, t: Term) -> bool:
    """Whether `t` is a string or a proper list with no unbound element."""
    if isinstance(t, Str):
        return True
    t = b.walk(t)
    while isinstance(t, Struct) and t.name == CONS and len(t.args) == 2:
        if isinstance(b.walk(t.args[0]), Var):
            return False
        t = b.walk(t.args[1])
    return t == NIL


_number_codes = _number_text(lambda c: Int(ord(c)))
_number_chars = _number_text(Atom)


def _assert(front: bool) -> Builtin:
    def run(e: Machine, a: tuple, b: Bindings) -> bool:
        clause = rename(b.resolve(a[0]))  # cyclic: representation_error(cyclic_term), as SWI
        head, body = (clause.args if isinstance(clause, Struct) and clause.name == ":-"
                      and len(clause.args) == 2 else (clause, TRUE))
        if isinstance(head, Var):
            raise instantiation_error()
        if not isinstance(head, (Atom, Struct)):
            raise type_error("callable", head)
        check_body(body, b)   # (foo :- X, 4): type_error(callable, (X, 4)), as SWI says
        body = body_calls(body)
        key = (head.name, len(head.args) if isinstance(head, Struct) else 0)
        # Adding a clause copies the predicate's clause list when a call in progress holds it
        # (the logical update view) or for asserta: 64 pointers copied cost about one step.
        pred = e.kb.predicates.get(key)
        copies = pred is not None and pred.copies_on_add(front)
        e.charge(1 + (len(pred.clauses) >> 6 if copies else 0))
        if e.is_builtin(*key) or e.kb.is_library(key) or _static(pred):
            raise _modify_static(key)
        if pred is None or not pred.clauses:
            e.kb.declare_dynamic(*key)    # a predicate assert creates is dynamic, as in SWI
        e.kb.add_clause(head, body, front=front)
        return True
    return run


def _static(pred) -> bool:
    """Whether a predicate is a static one of the user's files (assert and retract refuse
    it, as SWI-Prolog does): clauses, not declared dynamic, not the library's."""
    return pred is not None and not pred.dynamic and bool(pred.clauses) and not pred.library_only()


def _modify_static(key: tuple[str, int]) -> PrologError:
    return iso_error(Struct("permission_error", (Atom("modify"), Atom("static_procedure"),
                                                 Struct("/", (Atom(key[0]), Int(key[1]))))))


def body_calls(body: Term) -> Term:
    """A clause body with each variable goal G written call(G), as assert stores it (ISO
    7.6.2): clause(foo(X), B) after assertz((foo(X) :- X)) gives B = call(X). A conjunction's
    right spine is walked in a loop: a body of 100,000 goals is no deeper than one of two."""
    spine: list[Term] = []
    while isinstance(body, Struct) and body.name == "," and len(body.args) == 2:
        spine.append(body.args[0])
        body = body.args[1]
    if isinstance(body, Var):
        result: Term = Struct("call", (body,))
    elif isinstance(body, Struct) and (body.name, len(body.args)) in _CONTROL_ARGS:
        result = Struct(body.name, tuple(body_calls(arg) for arg in body.args))
    else:
        result = body
    for left in reversed(spine):
        result = Struct(",", (body_calls(left), result))
    return result


def _retract(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    target = b.resolve(a[0])
    head, body = (target.args if isinstance(target, Struct) and target.name == ":-"
                  and len(target.args) == 2 else (target, TRUE))
    head = b.walk(head)
    ind = (head.name, len(head.args)) if isinstance(head, Struct) else (
        (head.name, 0) if isinstance(head, Atom) else None)
    if ind is None:
        raise instantiation_error() if isinstance(head, Var) else type_error("callable", head)
    pred = e.kb.predicates.get(ind)
    if e.is_builtin(*ind) and ind != ("[|]", 2) or _static(pred):
        raise _modify_static(ind)
    if pred is None:
        e.charge(1)
        return
    # The clauses the first argument's index names (all of them when it is unbound): a
    # snapshot no assert or retract changes (the logical update view), so retracting one
    # clause costs neither a copy of the predicate nor a look at every clause.
    candidates = pred.candidates(b.walk(head.args[0]) if isinstance(head, Struct) else None)
    e.charge(1 + (len(candidates) >> 6))
    for clause in candidates:
        mark = b.mark()
        h, bd = clause.renamed()
        if b.unify(head, h) and b.unify(body, bd):
            e.kb.remove(clause)
            yield
        b.undo(mark)


def _write(quoted: bool, canonical: bool = False) -> Builtin:
    def run(e: Machine, a: tuple, b: Bindings) -> bool:
        e.write(_written(e, b.resolve_finite(a[0]), quoted, canonical))
        return True
    return run


def _written(e: Machine, term: Term, quoted: bool, canonical: bool = False) -> str:
    """The text write/print/format write for `term` (a cyclic one in its finite form,
    f(_G1) for X = f(X): docs/syntax.md), its length charged: operators as the knowledge
    base's table has them (op/3), none for write_canonical."""
    names = canonical_names(term) if canonical else None
    text = term_to_text(term, quoted=quoted, ops=e.kb.operators.view(), canonical=canonical, names=names)
    e.charge(len(text))
    return text


# write_term/2's options it follows; others are accepted and not followed, as SWI-Prolog
# accepts options it does not know.
_WRITE_OPTIONS = {"quoted", "ignore_ops"}


def _write_term(e: Machine, a: tuple, b: Bindings) -> bool:
    """write_term(+Term, +Options): quoted(Bool) and ignore_ops(Bool) followed; errors as
    swipl's (an option that is no compound is type_error(option, O))."""
    chosen = {"quoted": False, "ignore_ops": False}
    for option in proper_items(b, b.walk(a[1])):
        option = b.walk(option)
        if isinstance(option, Var):
            raise instantiation_error()
        if not isinstance(option, Struct):
            raise type_error("option", option)
        if option.name in _WRITE_OPTIONS and len(option.args) == 1:
            value = b.walk(option.args[0])
            if isinstance(value, Var):
                raise instantiation_error()
            if value not in (TRUE, Atom("false")):
                raise type_error("bool", value)
            chosen[option.name] = value == TRUE
    term = b.resolve_finite(a[0])
    ops = NO_OPERATORS if chosen["ignore_ops"] else e.kb.operators.view()
    text = term_to_text(term, quoted=chosen["quoted"], ops=ops)
    e.charge(len(text))
    e.write(text)
    return True


def _format(e: Machine, a: tuple, b: Bindings) -> bool:
    fmt = text_of(e, a[0], b)
    args_term = b.resolve_finite(a[1]) if len(a) > 1 else NIL
    items, tail = list_items(args_term)
    args = items if tail == NIL and (items or args_term == NIL) else [args_term]
    out, i, n = [], 0, 0

    def next_arg() -> Term:
        nonlocal n
        if n >= len(args):
            raise iso_error(Struct("format", (Str("not enough arguments"),)))
        n += 1
        return args[n - 1]

    while i < len(fmt):
        c = fmt[i]
        if c != "~":
            out.append(c)
            i += 1
            continue
        i += 1
        digits = ""
        if i < len(fmt) and fmt[i] == "*":  # ~*c: the numeric argument is the next argument
            count = next_arg()
            if not isinstance(count, Int) or count.value < 0:
                raise iso_error(Struct("format", (Str("no or negative integer for `*' argument"),)))
            digits = str(count.value) if count.value < 10 ** 18 else "1" + "0" * 18
            i += 1
        while i < len(fmt) and fmt[i].isdigit():
            digits += fmt[i]
            i += 1
        # The numeric argument is a count of characters written: charged before they are
        # made, so ~1000000000d stops at the step limit instead of building a gigabyte.
        count = (int(digits) if len(digits) < 19 else 10 ** 18) if digits else 0
        e.charge(count)
        d = fmt[i] if i < len(fmt) else "~"
        i += 1
        if d == "n":
            out.append("\n" * (count if digits else 1))
            continue
        if d == "~":
            out.append("~")
            continue
        arg = next_arg()
        if d == "a":
            out.append(_text_of(arg))
        elif d == "w":
            out.append(_written(e, arg, False))
        elif d in "pq":
            out.append(_written(e, arg, True))
        elif d == "c":
            if not isinstance(arg, Int):
                raise type_error("integer", arg)
            out.append(code_char(arg) * (count if digits else 1))
        elif d == "d":
            if not isinstance(arg, Int):
                raise type_error("integer", arg)
            text = int_text(abs(arg.value))
            if digits and count > 0:  # ~Nd: N digits after a decimal point
                text = text.rjust(count + 1, "0")
                text = f"{text[:-count]}.{text[-count:]}"
            out.append(("-" if arg.value < 0 else "") + text)
        elif d in "fge":
            out.append(_float_format(evaluate(arg, b), count if digits else 6, d))
        elif d == "s":
            out.append(text_of(e, arg, b))
        else:
            raise iso_error(Struct("format", (Str(f"unknown directive ~{d}"),)))
    text = "".join(out)
    e.charge(len(text))
    e.write(text)
    return True


def _float_format(value: int | float, places: int, kind: str) -> str:
    """~Nf, ~Ne, ~Ng of a number. An integer is written exactly by ~f (10**400 has 401
    digits, as in SWI-Prolog), and by ~e and ~g through decimal when no float holds it."""
    if isinstance(value, int):
        if kind == "f":
            return format(Decimal(value), f".{places}f")
        try:
            value = float(value)
        except OverflowError:  # past 1.8e308: printed as C's printf would print it
            if kind == "e":
                return format(Decimal(value), f".{places}e")
            mantissa, exponent = format(Decimal(value), f".{max(places - 1, 0)}e").split("e")
            if "." in mantissa:  # %g drops trailing zeros
                mantissa = mantissa.rstrip("0").rstrip(".")
            return f"{mantissa}e{exponent}"
    return f"{value:.{places}{kind}}"


def _forall(e: Machine, a: tuple, b: Bindings) -> bool:
    """forall(+Cond, +Action): \\+ (Cond, \\+ Action), Action called (and checked whole)
    only when Cond has a solution: forall(fail, 4) holds, as in SWI-Prolog."""
    check_body(a[0], b)   # the culprit named is Cond itself, not the conjunction run below
    for _ in e.sub_solve(Struct(",", (a[0], Struct("\\+", (Struct("call", (a[1],)),)))), b):
        return False
    return True


def _findall(e: Machine, a: tuple, b: Bindings) -> bool:
    # sub_solve turns the goal into a body first: findall(X, (q(X) ; 4), L) is
    # type_error(callable, (q(X) ; 4)) before q runs, as in SWI-Prolog
    results = [rename(b.resolve(a[0])) for _ in e.sub_solve(a[1], b)]
    return b.unify(a[2], make_list(results))


def _variables(t: Term, b: Bindings, out: list[Var], seen: set[Var]) -> None:
    """The variables of `t` left to right, each once (term_variables/2), without recursion.
    A bound variable's value is walked once: a cyclic term (X = f(X)) ends, a shared one
    is not walked again."""
    values = b.values
    expanded: set[Var] = set()
    stack = [t]
    while stack:
        t = stack.pop()
        while type(t) is Var:
            bound = values.get(t)
            if bound is None:
                break
            if t in expanded:
                t = NIL
                break
            expanded.add(t)
            t = bound
        if type(t) is Var:
            if t not in seen:
                seen.add(t)
                out.append(t)
        elif type(t) is Struct:
            stack.extend(reversed(t.args))


def _ground(e: Machine, a: tuple, b: Bindings) -> bool:
    """ground(@Term): no unbound variable in it (a cyclic term may be ground)."""
    found: list[Var] = []
    _variables(a[0], b, found, set())
    return not found


def _bag(to_set: bool) -> NondetBuiltin:
    """bagof/3 and setof/3 as SWI-Prolog's boot/bags.pl defines them: the goal's free
    variables (those neither in the template nor bound by `V^`) are the witness; answers are
    key-sorted on it and each run of equal (or variant) witnesses is one bag, in that order."""

    def solve(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
        template, goal, bag = a
        goal = b.walk(goal)
        excluded: list[Var] = []
        seen: set[Var] = set()
        _variables(template, b, excluded, seen)
        while isinstance(goal, Struct) and goal.name == "^" and len(goal.args) == 2:
            _variables(goal.args[0], b, excluded, seen)       # Goal = V^G: V is not free
            goal = b.walk(goal.args[1])
        check_body(goal, b)
        witness: list[Var] = []
        _variables(goal, b, witness, seen)
        if not witness:
            results = [rename(b.resolve(template)) for _ in e.sub_solve(goal, b)]
            if not results:
                return
            mark = b.mark()
            if b.unify(bag, make_list(_sorted_set(results) if to_set else results)):
                yield
            b.undo(mark)
            return
        key = Struct("v", tuple(witness))
        pairs = [rename(b.resolve(Struct("-", (key, template)))) for _ in e.sub_solve(goal, b)]
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


def _throw(e: Machine, a: tuple, b: Bindings) -> bool:
    ball = b.resolve_finite(a[0])
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
    """The items of a proper list, unresolved (an item may be cyclic: X = f(X) sorts);
    instantiation_error for a partial list, type_error(list) otherwise (a cyclic list too)."""
    items, tail = list_spine(b, t)
    if isinstance(tail, Var):
        raise instantiation_error()
    if tail != NIL:
        raise type_error("list", b.resolve_finite(t))
    return items


def _order_key(b: Bindings):
    """A sort key for the standard order of terms under the bindings."""
    return functools.cmp_to_key(lambda x, y: compare_terms(x, y, b))


def _msort(e, a, b):
    items = _proper_list(a[0], b)
    return b.unify(a[1], make_list(sorted(items, key=_order_key(b))))


def _sort(e, a, b):
    items = sorted(_proper_list(a[0], b), key=_order_key(b))
    unique: list[Term] = []
    for item in items:
        if not unique or compare_terms(unique[-1], item, b) != 0:
            unique.append(item)
    return b.unify(a[1], make_list(unique))


CORE: dict[tuple[str, int], Builtin] = {
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
    ("cyclic_term", 1): lambda e, a, b: b.is_cyclic(a[0]),
    ("acyclic_term", 1): lambda e, a, b: not b.is_cyclic(a[0]),
    ("is_list", 1): lambda e, a, b: not b.is_cyclic(a[0]) and list_items(b.resolve(a[0]))[1] == NIL,
    ("string", 1): _type_check(lambda t: isinstance(t, Str)),
    ("ground", 1): _ground,
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
    ("number_chars", 2): _number_chars,
    ("assert", 1): _assert(front=False),
    ("assertz", 1): _assert(front=False),
    ("asserta", 1): _assert(front=True),
    ("write", 1): _write(quoted=False),
    ("print", 1): _write(quoted=True),
    ("writeq", 1): _write(quoted=True),
    ("write_canonical", 1): _write(quoted=True, canonical=True),
    ("write_term", 2): _write_term,
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

CORE_NONDET: dict[tuple[str, int], NondetBuiltin] = {
    ("between", 3): _between,
    ("length", 2): _length,
    ("retract", 1): _retract,
    ("bagof", 3): _bag(to_set=False),
    ("setof", 3): _bag(to_set=True),
}


def _unifiable(x: Term, y: Term, b: Bindings) -> bool:
    mark = b.mark()
    ok = b.unify(x, y)
    b.undo(mark)
    return ok
