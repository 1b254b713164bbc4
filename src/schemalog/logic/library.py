"""Built-in predicates beyond the core machine, in Python: SWI-Prolog's behaviour, mode by mode.

    Builtin       = (machine, args, bindings) -> bool              (deterministic)
    NondetBuiltin = (machine, args, bindings) -> Iterator[None]    (one yield per solution)

They see the engine through builtins.Machine, as the core ones do; engine.py merges EXTRA and
EXTRA_NONDET into its tables. Library predicates that read best in
Prolog (permutation/2, predsort/3, nth0/4, aggregate_all/3...) are in prelude.pl instead.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Iterator

from .arith import evaluate
from .builtins import (Machine, _read_number, atomic_text, _text_of, _variables, code_char, compare_terms, proper_items, resolve_list,
                       standard_order_key, text_of)
from ..inputs import missing
from .exceptions import PrologError, instantiation_error, iso_error, type_error
from .terms import NIL, is_ground, Atom, Float, Int, Str, Struct, Term, Var, list_items, make_list, term_to_text
from .unify import Bindings, rename


def _domain_error(domain: str, culprit: Term):
    return iso_error(Struct("domain_error", (Atom(domain), culprit)))


def _integer(t: Term, allow_var: bool = True) -> int | None:
    """The value of an integer argument, None for an unbound one; ISO errors otherwise."""
    if isinstance(t, Var):
        if allow_var:
            return None
        raise instantiation_error()
    if not isinstance(t, Int):
        raise type_error("integer", t)
    return t.value


def _count(t: Term) -> int | None:
    """A length or position argument: None for an unbound one; a negative integer is
    domain_error(not_less_than_zero, N), as ISO's sub_atom/5 and length/2 say."""
    value = _integer(t)
    if value is not None and value < 0:
        raise _domain_error("not_less_than_zero", t)
    return value


def _natural(t: Term) -> int | None:
    value = _integer(t)
    if value is not None and value < 0:
        raise type_error("not_less_than_zero", t)
    return value


# -- arithmetic relations --------------------------------------------------------

_STARTED = time.monotonic()   # when this process started running Prolog: walltime's origin


def _statistics(e: Machine, a: tuple, b: Bindings) -> bool:
    """statistics(Key, Value) for the keys a program times itself with, as SWI-Prolog gives them:
    runtime and walltime as [milliseconds since start, since the last such call], cputime and
    process_cputime in seconds, real_time in whole seconds since the epoch, inferences (steps)."""
    key = b.walk(a[0])
    if isinstance(key, Var):
        raise instantiation_error()
    if not isinstance(key, Atom):
        raise type_error("atom", key)
    name = key.name
    if name in ("runtime", "walltime"):
        now = int((time.process_time() if name == "runtime" else time.monotonic() - _STARTED) * 1000)
        since = e.since.get(name, 0)
        e.since[name] = now
        value: Term = make_list([Int(now), Int(now - since)])
    elif name in ("cputime", "process_cputime"):
        value = Float(time.process_time())
    elif name == "real_time":
        value = make_list([Int(int(time.time())), Int(0)])
    elif name == "inferences":
        value = Int(e.steps)
    else:
        raise iso_error(Struct("domain_error", (Atom("statistics_key"), key)))
    return b.unify(a[1], value)


def _succ(e: Machine, a: tuple, b: Bindings) -> bool:
    """succ(?X, ?Y): Y = X + 1, both natural numbers."""
    x, y = _natural(b.walk(a[0])), _natural(b.walk(a[1]))
    if x is not None:
        return b.unify(a[1], Int(x + 1))
    if y is None:
        raise instantiation_error()
    return y > 0 and b.unify(a[0], Int(y - 1))


def _plus(e: Machine, a: tuple, b: Bindings) -> bool:
    """plus(?X, ?Y, ?Z): Z = X + Y, any two known."""
    x, y, z = (_integer(b.walk(t)) for t in a)
    if x is not None and y is not None:
        return b.unify(a[2], Int(x + y))
    if x is not None and z is not None:
        return b.unify(a[1], Int(z - x))
    if y is not None and z is not None:
        return b.unify(a[0], Int(z - y))
    raise instantiation_error()


# -- text ------------------------------------------------------------------------

def _char_code(e: Machine, a: tuple, b: Bindings) -> bool:
    char, code = b.walk(a[0]), b.walk(a[1])
    if isinstance(char, Atom):
        if len(char.name) != 1:
            raise type_error("character", char)
        if not isinstance(code, (Var, Int)):
            raise type_error("integer", code)
        return b.unify(code, Int(ord(char.name)))
    if not isinstance(char, Var):
        raise type_error("character", char)
    value = _integer(code)
    if value is None:
        raise instantiation_error()
    return b.unify(char, Atom(code_char(Int(value))))


def _convert(make, fn) -> callable:
    """A text-to-text relation such as upcase_atom/2: the first argument must be text."""
    def run(e: Machine, a: tuple, b: Bindings) -> bool:
        return b.unify(a[1], make(fn(text_of(e, a[0], b))))
    return run


def _string_to_atom(e: Machine, a: tuple, b: Bindings) -> bool:
    s = b.walk(a[0])
    if not isinstance(s, Var):
        return b.unify(a[1], Atom(text_of(e, s, b)))
    return b.unify(s, Str(text_of(e, a[1], b)))


def _number_string(e: Machine, a: tuple, b: Bindings) -> bool:
    """number_string(?N, +S): S read as a number, with no white space around it; fails when S
    is not a number (SWI-Prolog and ECLiPSe agree)."""
    s = b.walk(a[1])
    if isinstance(s, Var):
        n = b.walk(a[0])
        if isinstance(n, Var):
            raise instantiation_error()
        if not isinstance(n, (Int, Float)):
            raise type_error("number", n)
        return b.unify(s, Str(term_to_text(n)))
    text = text_of(e, s, b)
    # A leading + belongs to the number here (`"+12"` is 12), not to an operator term.
    value = _read_number(text[1:] if text[:1] == "+" and text[1:2].isdigit() else text)
    return value is not None and b.unify(a[0], value)


def _concat_string(e: Machine, a: tuple, b: Bindings) -> bool:
    """concat_string(+List, ?Dest): ECLiPSe's; Dest is the string of List's atomic terms
    (atoms, strings, numbers) one after the other."""
    whole = b.walk(a[0])
    if isinstance(whole, Var):
        raise instantiation_error()
    items = proper_items(b, whole)
    for item in items:
        if isinstance(item, Var):
            raise instantiation_error()
        if not isinstance(item, (Atom, Str, Int, Float)):
            raise type_error("atomic", item)
    dest = b.walk(a[1])
    if not isinstance(dest, (Var, Str)):
        raise type_error("string", dest)
    text = "".join(_text_of(i) for i in items)
    e.charge(len(text))
    return b.unify(dest, Str(text))


def _string_code(e: Machine, a: tuple, b: Bindings) -> bool:
    """string_code(+I, +S, -C): the I-th (from 1) code of S; fails out of range."""
    index = _integer(b.walk(a[0]), allow_var=False)
    text = text_of(e, a[1], b)
    if index < 0:
        raise type_error("not_less_than_zero", Int(index))
    return 1 <= index <= len(text) and b.unify(a[2], Int(ord(text[index - 1])))


def _sub_text(make) -> callable:
    """sub_atom/5 and sub_string/5: Sub is the text of length L after B characters, A after it."""
    # sub_atom/5 takes atomic text only (type_error(atom, f(a)), as ISO and SWI say).
    read = atomic_text if make is Atom else text_of

    def run(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
        text = read(e, a[0], b)
        n = len(text)
        before, length, after = (_count(b.walk(t)) for t in a[1:4])
        sub = b.walk(a[4])
        if not isinstance(sub, Var):                     # known Sub: each place it occurs
            part = read(e, sub, b)
            starts = [i for i in range(n - len(part) + 1) if text.startswith(part, i)]
            triples = [(i, len(part), n - i - len(part)) for i in starts]
        elif before is not None and length is not None:
            triples = [(before, length, n - before - length)]
        elif before is not None and after is not None:
            triples = [(before, n - before - after, after)]
        elif length is not None and after is not None:
            triples = [(n - length - after, length, after)]
        elif before is not None:
            triples = ((before, k, n - before - k) for k in range(n - before + 1))
        elif length is not None:
            triples = ((i, length, n - i - length) for i in range(n - length + 1))
        elif after is not None:
            triples = ((i, n - after - i, after) for i in range(n - after + 1))
        else:  # a generator: the n**2/2 answers are made one by one, as asked for
            triples = ((i, k, n - i - k) for i in range(n + 1) for k in range(n - i + 1))
        for i, k, rest in triples:
            if i < 0 or k < 0 or rest < 0:
                continue
            e.charge(k + 1)  # the sub-text made
            mark = b.mark()
            if (b.unify(a[1], Int(i)) and b.unify(a[2], Int(k)) and b.unify(a[3], Int(rest))
                    and b.unify(a[4], make(text[i:i + k]))):
                yield
            b.undo(mark)
    return run


def _atom_to_term(e: Machine, a: tuple, b: Bindings) -> bool:
    """atom_to_term(+Atom, -Term, -Bindings): Bindings = ['X'=_A, ...] in order of appearance."""
    from .opread import parse_term

    text = text_of(e, a[0], b)
    term = parse_term(text, "<argument>", e.kb.operators)
    names: dict[str, Var] = {}
    order: list[str] = []

    def collect(t: Term) -> None:
        stack = [t]
        while stack:
            t = stack.pop()
            if isinstance(t, Var) and not t.name.startswith("_") and t.name not in names:
                names[t.name] = t
                order.append(t.name)
            elif isinstance(t, Struct):
                stack.extend(reversed(t.args))

    collect(term)
    mapping = {v: Var(f"_{v.name}") for v in names.values()}
    fresh = rename(term, mapping)
    pairs = make_list([Struct("=", (Atom(name), mapping[names[name]])) for name in order])
    return b.unify(a[1], fresh) and b.unify(a[2], pairs)


def _concat(make) -> callable:
    """atom_concat/3 and string_concat/3 in every mode: with the whole known and a part
    unknown, each split of the whole that fits the known part, in order."""
    def read(e: Machine, t: Term, b: Bindings) -> str:
        if make is Atom and isinstance(t, Struct):   # atom_concat(f(a), b, X): type_error(atomic, f(a))
            raise type_error("atomic", b.resolve_finite(t))
        return text_of(e, t, b)

    def run(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
        left, right, whole = (b.walk(t) for t in a)
        for part in (left, right, whole):
            if make is Atom and isinstance(part, Struct):
                read(e, part, b)
        if not isinstance(left, Var) and not isinstance(right, Var):
            mark = b.mark()
            if b.unify(whole, make(text_of(e, left, b) + text_of(e, right, b))):
                yield
            b.undo(mark)
            return
        if isinstance(whole, Var):
            raise instantiation_error()
        text = text_of(e, whole, b)
        for i in range(len(text) + 1):
            e.charge(len(text))  # each split copies the whole text
            mark = b.mark()
            if b.unify(left, make(text[:i])) and b.unify(right, make(text[i:])):
                yield
            b.undo(mark)
    return run


def _text_list(element) -> callable:
    """string_chars/2 and string_codes/2 both ways: the list of a string, or the string of a list."""
    def run(e: Machine, a: tuple, b: Bindings) -> bool:
        s = b.walk(a[0])
        if not isinstance(s, Var):
            return b.unify(a[1], make_list([element(c) for c in text_of(e, s, b)]))
        items, tail = list_items(resolve_list(b, a[1]))
        if tail != NIL or any(isinstance(i, Var) for i in items):
            raise instantiation_error()
        return b.unify(s, Str(_text_of(make_list(items)) if items else ""))
    return run


def _atomic_list_concat(e: Machine, a: tuple, b: Bindings) -> bool:
    """atomic_list_concat(+List, +Sep, -Atom), or with a non-empty Sep and a known Atom,
    split it: atomic_list_concat(L, '-', 'a-b') gives L = [a, b]."""
    items, tail = list_items(resolve_list(b, a[0]))
    sep = text_of(e, a[1], b) if len(a) == 3 else ""
    if tail == NIL and not any(isinstance(i, Var) for i in items):
        text = sep.join(_text_of(i) for i in items)
        e.charge(len(text))
        return b.unify(a[-1], Atom(text))
    whole = b.walk(a[-1])
    if len(a) == 3 and sep and not isinstance(whole, Var):
        return b.unify(a[0], make_list([Atom(part) for part in text_of(e, whole, b).split(sep)]))
    raise instantiation_error()


def _arg(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """arg(?N, +Term, ?Arg): with N unbound, each argument in turn."""
    n, term = b.walk(a[0]), b.walk(a[1])
    if isinstance(term, Var):
        raise instantiation_error()
    if not isinstance(term, Struct):
        raise type_error("compound", term)
    if isinstance(n, Int):
        if n.value < 0:
            raise _domain_error("not_less_than_zero", n)
        if 1 <= n.value <= len(term.args):
            mark = b.mark()
            if b.unify(a[2], term.args[n.value - 1]):
                yield
            b.undo(mark)
        return
    if not isinstance(n, Var):
        raise type_error("integer", n)
    for i, arg in enumerate(term.args, 1):
        mark = b.mark()
        if b.unify(n, Int(i)) and b.unify(a[2], arg):
            yield
        b.undo(mark)


def arg_bound(e: Machine, a: tuple, b: Bindings) -> bool:
    """arg(+N, +Term, ?Arg) with N bound to an integer: deterministic, no choicepoint (a
    compiled clause calls it when N is an integer as the clause is entered; compile.py).
    The same answers and errors as _arg's with N bound."""
    values = b.values
    get = values.get
    n = a[0]
    while type(n) is Var:
        n = values[n]
    term = a[1]
    while type(term) is Var:
        bound = get(term)
        if bound is None:
            raise instantiation_error()
        term = bound
    if type(term) is not Struct:
        raise type_error("compound", term)
    k = n.value
    args = term.args
    if not 1 <= k <= len(args):
        if k < 0:
            raise _domain_error("not_less_than_zero", n)
        return False
    x, v = a[2], args[k - 1]
    while type(x) is Var:
        bound = get(x)
        if bound is None:
            break
        x = bound
    while type(v) is Var:
        bound = get(v)
        if bound is None:
            break
        v = bound
    if x is v:
        return True
    if type(x) is Var:          # the common case: Arg a fresh variable
        values[x] = v
        b.trail.append(x)
        return True
    return b.unify(x, v)


# -- terms and lists -----------------------------------------------------------

def _term_variables(e: Machine, a: tuple, b: Bindings) -> bool:

    out: list[Var] = []
    _variables(a[0], b, out, set())
    return b.unify(a[1], make_list(out))


def _keysort(e: Machine, a: tuple, b: Bindings) -> bool:
    items = proper_items(b, a[0])
    for item in items:
        if isinstance(item, Var):
            raise instantiation_error()
        if not (isinstance(item, Struct) and item.name == "-" and len(item.args) == 2):
            raise type_error("pair", item)
    return b.unify(a[1], make_list(sorted(items, key=lambda p: standard_order_key(p.args[0]))))


def _sort4(e: Machine, a: tuple, b: Bindings) -> bool:
    """sort(+Key, +Order, +List, -Sorted): on the Key-th argument (0: the whole term);
    @< and @> drop elements whose key equals an earlier one's; the sort is stable."""
    key = _natural(b.walk(a[0]))
    if key is None:
        raise instantiation_error()
    order = b.walk(a[1])
    if isinstance(order, Var):
        raise instantiation_error()
    if not (isinstance(order, Atom) and order.name in ("@<", "@=<", "@>", "@>=")):
        raise _domain_error("order", order)
    items = proper_items(b, a[2])

    def key_of(t: Term) -> Term:
        if key == 0:
            return t
        if not isinstance(t, Struct):
            raise type_error("compound", t)
        if key > len(t.args):
            raise type_error("compound", t)     # SWI: too few arguments
        return t.args[key - 1]

    keyed = [(key_of(t), t) for t in items]
    descending = order.name in ("@>", "@>=")
    keyed.sort(key=lambda kt: standard_order_key(kt[0]), reverse=descending)   # stable both ways
    if order.name in ("@<", "@>"):
        unique = []
        for k, t in keyed:
            if not unique or compare_terms(unique[-1][0], k) != 0:
                unique.append((k, t))
        keyed = unique
    return b.unify(a[3], make_list([t for _, t in keyed]))


# -- the database and output -----------------------------------------------------

def _retractall(e: Machine, a: tuple, b: Bindings) -> bool:
    """retractall(+Head): remove every clause whose head unifies; always succeeds."""
    head = b.walk(a[0])
    if isinstance(head, Var):
        raise instantiation_error()
    if not isinstance(head, (Atom, Struct)):
        raise type_error("callable", head)
    name, arity = head.name, len(head.args) if isinstance(head, Struct) else 0
    pred = e.kb.predicates.get((name, arity))
    if e.is_builtin(name, arity) or pred is not None and not pred.dynamic and pred.clauses \
            and not pred.library_only():
        raise iso_error(Struct("permission_error", (Atom("modify"), Atom("static_procedure"),
                                                    Struct("/", (Atom(name), Int(arity))))))
    if pred is None or not pred.clauses:
        e.kb.declare_dynamic(name, arity)     # as in SWI: the predicate now exists, dynamic
        return True
    matched = []
    # the first argument's bucket (a snapshot), then one pass removing what matched
    for clause in pred.candidates(b.walk(head.args[0]) if isinstance(head, Struct) else None):
        mark = b.mark()
        h, _ = clause.renamed()
        if b.unify(head, h):
            matched.append(clause)
        b.undo(mark)
    e.kb.remove_all(matched)
    return True


def _tab(e: Machine, a: tuple, b: Bindings) -> bool:
    count = evaluate(a[0], b)
    if not isinstance(count, int):
        raise type_error("integer", Float(count))
    if count >= 1 << 63:  # SWI-Prolog's tab/1 takes a 64-bit integer
        raise iso_error(Struct("evaluation_error", (Atom("int_overflow"),)))
    e.charge(max(0, count))  # before the spaces are made: tab(10**12) stops at the step limit
    e.write(" " * max(0, count))
    return True


def _consult(e: Machine, a: tuple, b: Bindings) -> bool:
    """consult(+File) and [File, ...]: load Prolog files; loading a file again replaces the
    clauses it defined before, as in SWI-Prolog."""
    target = b.resolve(a[0]) if len(a) == 1 else Struct("[|]", (b.resolve(a[0]), b.resolve(a[1])))
    items, tail = list_items(target) if isinstance(target, Struct) and target.name == "[|]" else ([target], NIL)
    if isinstance(tail, Var):
        raise instantiation_error()
    for item in items:
        if isinstance(item, Var):
            raise instantiation_error()
        if not isinstance(item, (Atom, Str)):
            raise type_error("atom", item)
        path = Path(item.value if isinstance(item, Str) else item.name)
        if missing(path) and path.suffix == "":
            path = path.with_suffix(".pl")
        if not os.path.isfile(path):     # False, not OSError, for a name too long
            raise iso_error(Struct("existence_error", (Atom("source_sink"), item)))
        e.kb.forget_file(str(path))
        e.kb.consult(path)
    return True


# -- clauses and predicates (ISO 8.8, 8.9) -----------------------------------------

def _indicator(t: Term) -> Struct:
    return Struct("/", (Atom(t[0]), Int(t[1]))) if isinstance(t, tuple) else t


def _permission(action: str, kind: str, key: tuple[str, int]):
    return iso_error(Struct("permission_error", (Atom(action), Atom(kind), _indicator(key))))


def _head_key(head: Term) -> tuple[str, int]:
    """The predicate a clause head names; instantiation_error, type_error(callable) else."""
    if isinstance(head, Var):
        raise instantiation_error()
    if isinstance(head, Atom):
        return head.name, 0
    if isinstance(head, Struct):
        return head.name, len(head.args)
    raise type_error("callable", head)


# Control constructs and [X|Y] (consult): clause/2 fails on them, as in SWI-Prolog.
_NO_CLAUSES = frozenset({(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1), ("!", 0), ("[|]", 2)})


def _clause(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """clause(+Head, ?Body): each clause of a user predicate whose head and body unify,
    in order (the clauses when it was called: the logical update view). A built-in is
    permission_error(access, private_procedure, PI); the library's predicates are not
    visible, as SWI-Prolog's are not before they are autoloaded."""
    head, body = b.walk(a[0]), b.walk(a[1])
    key = _head_key(head)
    if key in _NO_CLAUSES:
        return
    if e.is_builtin(*key):
        raise _permission("access", "private_procedure", key)
    if e.kb.is_library(key):
        return
    for clause in e.kb.clauses(*key):
        mark = b.mark()
        h, bd = clause.renamed()
        e.charge(1)
        if b.unify(head, h) and b.unify(body, bd):
            yield
        b.undo(mark)


def _predicate_indicator(e: Machine, t: Term, b: Bindings, *, open_ok: bool) -> tuple[Term, Term]:
    """Name and Arity of Name/Arity; with `open_ok` either may be unbound (current_predicate/1),
    else instantiation_error (abolish/1)."""
    t = b.walk(t)
    if isinstance(t, Var):
        if open_ok:
            return t, Var("_")
        raise instantiation_error()
    if not (isinstance(t, Struct) and t.name == "/" and len(t.args) == 2):
        raise type_error("predicate_indicator", b.resolve_finite(t))
    name, arity = b.walk(t.args[0]), b.walk(t.args[1])
    if open_ok:
        if not isinstance(name, (Var, Atom)) or not isinstance(arity, (Var, Int)):
            raise type_error("predicate_indicator", b.resolve_finite(t))
        return name, arity
    if isinstance(name, Var) or isinstance(arity, Var):
        raise instantiation_error()
    if not isinstance(name, Atom):
        raise type_error("atom", name)
    if not isinstance(arity, Int):
        raise type_error("integer", arity)
    if arity.value < 0:
        raise _domain_error("not_less_than_zero", arity)
    return name, arity


# The library predicates SWI-Prolog has built in (abolish/1 refuses them); its others come
# from autoloaded libraries, and abolish/1 of one succeeds and leaves it callable.
_SYSTEM_LIBRARY = {("once", 1), ("phrase", 2), ("phrase", 3), ("repeat", 0)}


def _abolish(e: Machine, a: tuple, b: Bindings) -> bool:
    """abolish(+Name/Arity): forget the predicate, clauses and all; a built-in is
    permission_error(modify, static_procedure, PI), and so is a library predicate swipl has
    built in (once/1, phrase/2...); another library predicate (append/3) stays, as swipl
    autoloads it again. A static user predicate is abolished too, as SWI-Prolog does (ISO
    would refuse it)."""
    name, arity = _predicate_indicator(e, a[0], b, open_ok=False)
    key = (name.name, arity.value)
    if e.is_builtin(*key) or key in _SYSTEM_LIBRARY and e.kb.is_library(key):
        raise _permission("modify", "static_procedure", key)
    if e.kb.is_library(key):
        return True
    e.kb.abolish(*key)
    return True


def _visible(e: Machine) -> list[tuple[str, int]]:
    """The user's predicates: with clauses or declared dynamic, not the library's."""
    return [key for key, pred in list(e.kb.predicates.items())
            if (pred.clauses or pred.dynamic) and not pred.library_only()]


def _current_predicate(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """current_predicate(?Name/?Arity): the user's predicates, and a built-in named whole."""
    name, arity = _predicate_indicator(e, a[0], b, open_ok=True)
    if isinstance(name, Atom) and isinstance(arity, Int):
        key = (name.name, arity.value)
        if e.is_builtin(*key) or key in _visible(e):
            mark = b.mark()
            if b.unify(a[0], _indicator(key)):
                yield
            b.undo(mark)
        return
    for key in _visible(e):
        mark = b.mark()
        if b.unify(a[0], _indicator(key)):
            yield
        b.undo(mark)


def _predicate_property(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """predicate_property(?Head, ?Property): built_in, defined, dynamic, static,
    number_of_clauses(N) (not of a built-in), visible."""
    head = b.walk(a[0])
    if isinstance(head, Var):
        keys = _visible(e)
    elif isinstance(head, (Atom, Struct)):
        keys = [_head_key(head)]
    else:
        return    # predicate_property(1, P) fails, as in SWI-Prolog
    for key in keys:
        builtin = e.is_builtin(*key)
        pred = e.kb.predicates.get(key)
        if not builtin and (pred is None or not (pred.clauses or pred.dynamic) or pred.library_only()):
            continue
        dynamic = pred is not None and pred.dynamic and not builtin
        props = [Atom("visible"), Atom("defined"), Atom("dynamic" if dynamic else "static")]
        if builtin:
            props.append(Atom("built_in"))
        else:
            props.append(Struct("number_of_clauses", (Int(len(pred.clauses)),)))
        for prop in props:
            mark = b.mark()
            if b.unify(a[0], Struct(key[0], tuple(Var("_") for _ in range(key[1]))) if key[1] else Atom(key[0])) \
                    and b.unify(a[1], prop):
                yield
            b.undo(mark)


# -- flags (ISO 8.17) ------------------------------------------------------------

# The values a flag may take; a flag not named here takes any atomic value.
_FLAG_VALUES = {
    "unknown": ("error", "fail", "warning"),
    "double_quotes": ("string",),   # the reader always reads "..." as a string: docs/queries.md
    "debug": ("true", "false"),
    "occurs_check": ("false",),
    "char_conversion": ("false",),
}
_READ_ONLY_FLAGS = ("bounded", "max_arity")


def _flag_name(t: Term, allow_var: bool) -> str | None:
    if isinstance(t, Var):
        if allow_var:
            return None
        raise instantiation_error()
    if not isinstance(t, Atom):
        raise type_error("atom", t)
    return t.name


def _current_prolog_flag(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """current_prolog_flag(?Flag, ?Value), in the knowledge base's flags."""
    name = _flag_name(b.walk(a[0]), allow_var=True)
    flags = e.kb.flags
    names = [name] if name is not None else list(flags)
    for flag in names:
        if flag not in flags:
            continue
        mark = b.mark()
        if b.unify(a[0], Atom(flag)) and b.unify(a[1], flags[flag]):
            yield
        b.undo(mark)


def _set_prolog_flag(e: Machine, a: tuple, b: Bindings) -> bool:
    """set_prolog_flag(+Flag, +Value): a read-only flag is permission_error(modify, flag, F),
    a value the flag does not take domain_error(F, Value), as SWI-Prolog says; a new flag
    is created, as SWI-Prolog does. double_quotes keeps `string` (the reader's only mode):
    another value is permission_error(modify, flag, double_quotes)."""
    name = _flag_name(b.walk(a[0]), allow_var=False)
    value = b.walk(a[1])
    if isinstance(value, Var):
        raise instantiation_error()
    if name in _READ_ONLY_FLAGS:
        raise iso_error(Struct("permission_error", (Atom("modify"), Atom("flag"), Atom(name))))
    allowed = _FLAG_VALUES.get(name)
    if allowed is not None:
        if name == "double_quotes" and isinstance(value, Atom) and value.name in ("codes", "chars", "atom"):
            raise iso_error(Struct("permission_error", (Atom("modify"), Atom("flag"), Atom(name))))
        if not (isinstance(value, Atom) and value.name in allowed):
            raise _domain_error(name, value)
    elif not is_ground(b.resolve_finite(value)):
        raise instantiation_error()
    else:
        value = b.resolve(value)
    e.kb.flags[name] = value
    return True


# -- operators (ISO 8.14.3, 8.14.4) --------------------------------------------------

_OP_TYPES = {"xfx": "infix", "xfy": "infix", "yfx": "infix", "fy": "prefix", "fx": "prefix",
             "xf": "postfix", "yf": "postfix"}


def _op_priority(t: Term, allow_var: bool) -> int | None:
    if isinstance(t, Var):
        if allow_var:
            return None
        raise instantiation_error()
    if not isinstance(t, Int):
        raise type_error("integer", t)
    if not 0 <= t.value <= 1200:
        raise _domain_error("operator_priority", t)
    return t.value


def _op_type(t: Term, allow_var: bool) -> str | None:
    if isinstance(t, Var):
        if allow_var:
            return None
        raise instantiation_error()
    if not isinstance(t, Atom):
        raise type_error("atom", t)
    if t.name not in _OP_TYPES:
        raise _domain_error("operator_specifier", t)
    return t.name


def _op(e: Machine, a: tuple, b: Bindings) -> bool:
    """op(+Priority, +Type, +Name or [Name, ...]): define (priority 0: remove) operators in
    the knowledge base's table, which the reader, the writers and current_op/3 follow
    (docs/syntax.md, Declaring operators)."""
    # SWI-Prolog's order of checks: the types of Type and Priority, their domains, the names
    kind_term, priority_term = b.walk(a[1]), b.walk(a[0])
    if isinstance(kind_term, Var):
        raise instantiation_error()
    if not isinstance(kind_term, Atom):
        raise type_error("atom", kind_term)
    priority = _op_priority(priority_term, allow_var=False)
    kind = _op_type(kind_term, allow_var=False)
    names = b.walk(a[2])
    if isinstance(names, Var):
        raise instantiation_error()
    if isinstance(names, Atom) and names != NIL:
        items = [names]
    else:
        items = proper_items(b, names)
    for item in items:
        if isinstance(item, Var):
            raise instantiation_error()
        if not isinstance(item, Atom):
            raise type_error("atom", item)
        if item.name == ",":
            raise iso_error(Struct("permission_error", (Atom("modify"), Atom("operator"), item)))
        if item.name == "|" and (_OP_TYPES[kind] != "infix" or 0 < priority < 1001):
            raise iso_error(Struct("permission_error", (Atom("create"), Atom("operator"), item)))
        if item.name in ("[]", "{}"):
            raise iso_error(Struct("permission_error", (Atom("create"), Atom("operator"), item)))
    for item in items:
        key = (item.name, _OP_TYPES[kind])
        if priority == 0:
            e.kb.operators.pop(key, None)
        else:
            e.kb.operators[key] = (priority, kind)
    return True


def _current_op(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """current_op(?Priority, ?Type, ?Name): the operators of the table op/3 changes."""
    name = b.walk(a[2])   # SWI-Prolog's order of checks: the name, the type, the priority
    if not isinstance(name, (Var, Atom)):
        raise type_error("atom", name)
    _op_priority(b.walk(a[0]), allow_var=True)
    _op_type(b.walk(a[1]), allow_var=True)
    order = {"prefix": 0, "infix": 1, "postfix": 2}
    table = sorted(e.kb.operators.items(), key=lambda item: (item[0][0], order[item[0][1]]))
    for (op, _), (priority, kind) in table:
        if isinstance(name, Atom) and name.name != op:
            continue
        mark = b.mark()
        if b.unify(a[0], Int(priority)) and b.unify(a[1], Atom(kind)) and b.unify(a[2], Atom(op)):
            yield
        b.undo(mark)


# -- cleanup (SWI-Prolog's setup_call_cleanup/3) -------------------------------------

def _run_cleanup(e: Machine, goal: Term, b: Bindings, quiet: bool = False) -> None:
    """once(Cleanup): its bindings stay (as SWI-Prolog's do after a deterministic exit), its
    failure is ignored, its exception raised, unless `quiet` (the goal raised already:
    that exception wins, as in SWI-Prolog)."""
    run = e.call_goal(goal, b)
    try:
        next(run, None)
    except PrologError:
        if not quiet:
            raise
    finally:
        run.close()


def _setup_call_cleanup(e: Machine, a: tuple, b: Bindings) -> Iterator[None]:
    """setup_call_cleanup(+Setup, +Goal, +Cleanup): once(Setup), then Goal's answers;
    Cleanup runs once Goal is done: it failed, raised, gave its last answer (no
    alternative left), or was cut (this generator is closed then)."""
    setup = b.walk(a[0])
    if isinstance(setup, Var):
        raise instantiation_error()
    start = b.mark()
    run = e.call_goal(setup, b)
    try:
        if next(run, None) is None:
            return
    finally:
        run.close()
    goal, cleanup = b.walk(a[1]), b.walk(a[2])
    if isinstance(goal, Var) or isinstance(cleanup, Var):
        raise instantiation_error()
    run = e.call_goal(goal, b)
    done = False
    try:
        while True:
            if next(run, None) is None:
                done = True
                _run_cleanup(e, cleanup, b)
                return
            if e.deterministic:   # the last answer: clean up before it is seen, as SWI does
                done = True
                run.close()
                _run_cleanup(e, cleanup, b)
                yield
                return
            # The engine undoes this call's bindings before it asks for the next answer;
            # the sub-machine still in progress counts on them: bind them again.
            made = [(v, b.values[v]) for v in b.trail[start:]]
            yield
            for v, value in made:
                if v not in b.values:
                    b.bind(v, value)
    except PrologError:
        if not done:
            done = True
            run.close()
            _run_cleanup(e, cleanup, b, quiet=True)
        raise
    except GeneratorExit:
        if not done:
            done = True
            run.close()
            _run_cleanup(e, cleanup, b)
        raise


def _dcg_body(e: Machine, a: tuple, b: Bindings) -> bool:
    """'$dcg_body'(+Body, ?S0, ?S, -Goal): the goal that runs grammar body Body from S0 to S
    (phrase/3, in prelude.pl), with swipl's errors for a body or list that cannot be one."""
    from . import dcg

    grammar = b.walk(a[0])
    if isinstance(grammar, Var):
        raise instantiation_error()
    if not isinstance(grammar, (Atom, Struct, Str)):
        raise type_error("callable", grammar)
    for text in (a[1], a[2]):     # as swipl, only the first cell is looked at
        cell = b.walk(text)
        if not (isinstance(cell, Var) or cell == NIL or isinstance(cell, Struct) and cell.name == "[|]"
                and len(cell.args) == 2):
            raise type_error("list", cell)
    try:
        goal = dcg.body(b.resolve_finite(grammar), a[1], a[2])
    except dcg.DCGError as err:
        raise type_error(err.kind, err.culprit) from None
    return b.unify(a[3], goal)


EXTRA = {
    ("$dcg_body", 4): _dcg_body,
    ("abolish", 1): _abolish,
    ("set_prolog_flag", 2): _set_prolog_flag,
    ("op", 3): _op,
    ("consult", 1): _consult,
    ("[|]", 2): _consult,
    ("succ", 2): _succ,
    ("statistics", 2): _statistics,
    ("plus", 3): _plus,
    ("char_code", 2): _char_code,
    ("upcase_atom", 2): _convert(Atom, str.upper),
    ("downcase_atom", 2): _convert(Atom, str.lower),
    ("string_upper", 2): _convert(Str, str.upper),
    ("string_lower", 2): _convert(Str, str.lower),
    ("string_length", 2): lambda e, a, b: b.unify(a[1], Int(len(text_of(e, a[0], b)))),
    ("string_to_atom", 2): _string_to_atom,
    ("number_string", 2): _number_string,
    ("concat_string", 2): _concat_string,
    ("string_code", 3): _string_code,
    ("atom_to_term", 3): _atom_to_term,
    ("term_variables", 2): _term_variables,
    ("keysort", 2): _keysort,
    ("sort", 4): _sort4,
    ("retractall", 1): _retractall,
    ("tab", 1): _tab,
    ("string_chars", 2): _text_list(lambda c: Atom(c)),
    ("string_codes", 2): _text_list(lambda c: Int(ord(c))),
    ("atomic_list_concat", 2): _atomic_list_concat,
    ("atomic_list_concat", 3): _atomic_list_concat,
}

EXTRA_NONDET = {
    ("clause", 2): _clause,
    ("current_predicate", 1): _current_predicate,
    ("predicate_property", 2): _predicate_property,
    ("current_prolog_flag", 2): _current_prolog_flag,
    ("current_op", 3): _current_op,
    ("setup_call_cleanup", 3): _setup_call_cleanup,
    ("call_cleanup", 2): lambda e, a, b: _setup_call_cleanup(e, (Atom("true"), *a), b),
    ("sub_atom", 5): _sub_text(Atom),
    ("sub_string", 5): _sub_text(Str),
    ("atom_concat", 3): _concat(Atom),
    ("string_concat", 3): _concat(Str),
    ("arg", 3): _arg,
}

__all__ = ["EXTRA", "EXTRA_NONDET"]
