"""ECLiPSe's string built-ins where they differ from SWI-Prolog's same-named ones.

    Builtin = (machine, args, bindings) -> bool      (deterministic, as in library.py)
    ECLIPSE = {(name, arity): Builtin}                eclipse_term_string/2 ...
    RENAMED = {(name, arity): eclipse name}           term_string/2 -> eclipse_term_string

SEED's rules run on ECLiPSe CLP. The engine's `term_string/2`, `atom_string/2` and
`split_string/4` are SWI-Prolog's (the conformance suite holds them to it), so the SEED
importer calls these instead in the bodies it keeps (formats/seed.py), and the SEED
exporter writes the ECLiPSe names back. The behaviour is ECLiPSe's reference manual's,
example by example (tests/logic/test_eclipse.py):

- term_string(?T, ?S): S a string is read as one term and unified with T (so
  `term_string(2.6, "2.60")` holds); S unbound gets T as writeq writes it, with a space
  after each argument's and list element's comma (`"f(1, 2)"`, `"[a, 1]"`) and around
  each infix operator (`"head :- body"`, `"1 ^ 2 * (3 + 4)"`); S anything
  else is type_error(string, S).
- atom_string(?A, ?S): A must be an atom (`[]` included) and S a string, else type_error;
  both unbound is an instantiation error.
- split_string(+S, +Seps, +Pad, -Subs): the first three must be strings, else type_error
  (unbound: instantiation error); Subs must be unbound or a list.
"""

from __future__ import annotations

from .builtins import Machine, split_text
from .exceptions import instantiation_error, iso_error, type_error
from .terms import CONS, NIL, Atom, Str, Struct, Term, Var, iter_vars, make_list, term_to_text
from .unify import Bindings


def _string(t: Term) -> str:
    """The text of an argument ECLiPSe types as a string."""
    if isinstance(t, Var):
        raise instantiation_error()
    if not isinstance(t, Str):
        raise type_error("string", t)
    return t.value


def _term_string(e: Machine, a: tuple, b: Bindings) -> bool:
    s = b.walk(a[1])
    if isinstance(s, Var):
        term = b.resolve_finite(a[0])
        # a variable is written as ECLiPSe's writeq writes one (`_g94`), never as its source name
        names = {v: f"_g{i}" for i, v in enumerate(dict.fromkeys(iter_vars(term)), 1)}
        text = term_to_text(term, names=names, next_argument=True, spaced_operators=True)
        e.charge(len(text))
        return b.unify(s, Str(text))
    text = _string(s)
    e.charge(len(text))
    from .opread import parse_term  # lark is loaded only when text is read as a term
    from ..errors import SchemalogError
    try:
        return b.unify(a[0], parse_term(text))
    except SchemalogError as err:
        raise iso_error(Struct("syntax_error", (Atom(err.message),))) from None


def _atom_string(e: Machine, a: tuple, b: Bindings) -> bool:
    atom, s = b.walk(a[0]), b.walk(a[1])
    if not isinstance(s, (Var, Str)):
        raise type_error("string", s)
    if isinstance(atom, Var):
        if isinstance(s, Var):
            raise instantiation_error()
        e.charge(len(s.value))
        return b.unify(atom, NIL if s.value == "[]" else Atom(s.value))
    if atom == NIL:
        name = "[]"   # ECLiPSe's [] is an atom
    elif isinstance(atom, Atom):
        name = atom.name
    else:
        raise type_error("atom", atom)
    e.charge(len(name))
    return b.unify(s, Str(name))


def _split_string(e: Machine, a: tuple, b: Bindings) -> bool:
    text, seps, pad = (_string(b.walk(x)) for x in a[:3])
    subs = b.walk(a[3])
    if not (isinstance(subs, Var) or subs == NIL or isinstance(subs, Struct) and subs.name == CONS
            and len(subs.args) == 2):
        raise type_error("list", subs)
    e.charge(len(text))
    return b.unify(subs, make_list([Str(p) for p in split_text(text, seps, pad)]))


ECLIPSE = {
    ("eclipse_term_string", 2): _term_string,
    ("eclipse_atom_string", 2): _atom_string,
    ("eclipse_split_string", 4): _split_string,
}

RENAMED = {("term_string", 2): "eclipse_term_string", ("atom_string", 2): "eclipse_atom_string",
           ("split_string", 4): "eclipse_split_string"}

__all__ = ["ECLIPSE", "RENAMED"]
