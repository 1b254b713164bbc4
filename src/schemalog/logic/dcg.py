"""Definite clause grammars: `Head --> Body` rules as clauses, as SWI-Prolog translates them.

    rule:  Head --> Body              Head = NonTerminal | NonTerminal, PushbackList
    clause: NonTerminal+(S0, S) :- Body'(S0, S)

S0 is the list a rule starts from, S what it leaves; a body goes from one to the other:

    NonTerminal      p(A)+(S0, S)              [a, b]    S0 = [a, b|S]
    []               S0 = S                    "ab"      S0 = [0'a, 0'b|S] (codes, as swipl)
    {Goal}           Goal, S0 = S              !         !, S0 = S
    (A, B)           A'(S0, S1), B'(S1, S)     (A ; B)   A'(S0, S) ; B'(S0, S)
    (A -> B)         A'(S0, S1) -> B'(S1, S)   \\+ A      \\+ A'(S0, _), S0 = S
    call(G, X...)    call(G, X..., S0, S)      Var       phrase(Var, S0, S)

A pushback list is put back after the body: `p, [a] --> q` is `p(S0, S) :- q(S0, S1), S = [a|S1]`.
SWI-Prolog moves a leading terminal list into the head; here it stays a unification in the
body, which answers alike. The variables S0, S1... are fresh Vars.
"""

from __future__ import annotations

from .terms import NIL, TRUE, Atom, Int, Str, Struct, Term, Var, list_items, make_list


class DCGError(Exception):
    """A rule that is no grammar rule: its message says why; `culprit` is the ISO error's term."""

    def __init__(self, message: str, kind: str, culprit: Term) -> None:
        super().__init__(message)
        self.kind, self.culprit = kind, culprit


def _extend(nonterminal: Term, s0: Term, s: Term) -> Term:
    if isinstance(nonterminal, Atom):
        return Struct(nonterminal.name, (s0, s))
    if isinstance(nonterminal, Struct):
        return Struct(nonterminal.name, (*nonterminal.args, s0, s))
    raise DCGError(f"a non-terminal must be callable, not {nonterminal}", "callable", nonterminal)


def _conj(a: Term, b: Term) -> Term:
    return Struct(",", (a, b))


def _eq(a: Term, b: Term) -> Term:
    return Struct("=", (a, b))


def _terminals(items: Term) -> list[Term]:
    """The items of a terminal list (a string: its codes); a partial list is an error."""
    if isinstance(items, Str):
        return [Int(ord(c)) for c in items.value]
    found, tail = list_items(items)
    if tail != NIL:
        raise DCGError(f"a terminal list must be a proper list, not {items}", "list", items)
    return found


def body(term: Term, s0: Term, s: Term) -> Term:
    """The goal that runs the grammar body `term` from list `s0` to list `s`."""
    if isinstance(term, Var):
        return Struct("phrase", (term, s0, s))
    if isinstance(term, Struct) and len(term.args) == 2 and term.name == ",":
        mid = Var("_S")
        return _conj(body(term.args[0], s0, mid), body(term.args[1], mid, s))
    if isinstance(term, Struct) and len(term.args) == 2 and term.name in (";", "|"):
        return Struct(";", (body(term.args[0], s0, s), body(term.args[1], s0, s)))
    if isinstance(term, Struct) and len(term.args) == 2 and term.name == "->":
        mid = Var("_S")
        return Struct("->", (body(term.args[0], s0, mid), body(term.args[1], mid, s)))
    if isinstance(term, Struct) and len(term.args) == 1 and term.name == "\\+":
        return _conj(Struct("\\+", (body(term.args[0], s0, Var("_")),)), _eq(s0, s))
    if isinstance(term, Struct) and len(term.args) == 1 and term.name == "{}":
        return _conj(term.args[0], _eq(s0, s))
    if isinstance(term, Atom) and term.name == "!":
        return _conj(term, _eq(s0, s))
    if term == NIL:
        return _eq(s0, s)
    if isinstance(term, Str) or isinstance(term, Struct) and term.name == "[|]" and len(term.args) == 2:
        return _eq(s0, make_list(_terminals(term), s))
    if isinstance(term, Struct) and term.name == "call":
        return Struct("call", (*term.args, s0, s))
    return _extend(term, s0, s)


def rule(head: Term, rule_body: Term) -> tuple[Term, Term]:
    """The clause (head, body) of the grammar rule `head --> rule_body`."""
    s0, s = Var("S0"), Var("S")
    if isinstance(head, Struct) and head.name == "," and len(head.args) == 2:
        nonterminal, pushback = head.args
        rest = Var("_S")
        goal = _conj(body(rule_body, s0, rest), _eq(s, make_list(_terminals(pushback), rest)))
        return _extend(nonterminal, s0, s), goal
    if isinstance(head, Var):
        raise DCGError("a grammar rule's head must be a non-terminal, not a variable", "instantiation", head)
    return _extend(head, s0, s), body(rule_body, s0, s)


def is_rule(head: Term, clause_body: Term) -> bool:
    """Whether a clause read as `head :- clause_body` is a grammar rule `A --> B`."""
    return clause_body == TRUE and isinstance(head, Struct) and head.name == "-->" and len(head.args) == 2
