"""Conditions: releasers and post-conditions as a small boolean algebra over literals.

    Condition = Const | Lit | Not | And | Or
    Lit       = (atom: Term, positive: bool)        `hand.free`, `not hand.free`

Every way the knowledge files write a condition reads to the same value:

    true  "TRUE"  []                         -> Const(True)
    false  fail                              -> Const(False)
    A and B   (A, B)   [A, B]                -> And
    A or B    (A ; B)                        -> Or
    not A   \\+ A   -A (SEED)                 -> a negated literal, or Not
    obj.prop   [obj|prop] (SWI-7 reading of SEED's dot)   on(a, b)   done   -> Lit

Conditions print in the paper's words: `hand.free or spoon.taken`, `not hand.free`.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from collections.abc import Set as AbstractSet
from dataclasses import dataclass

from .. import defaults
from ..logic.terms import CONS, NIL, Atom, Float, Int, Str, Struct, Term, Var, list_items, term_to_text


@dataclass(frozen=True, slots=True)
class Const:
    """`true` or `false`."""

    value: bool


@dataclass(frozen=True, slots=True)
class Lit:
    """A ground or parameterised atom, possibly negated."""

    atom: Term
    positive: bool = True

    def negate(self) -> "Lit":
        return Lit(self.atom, not self.positive)


@dataclass(frozen=True, slots=True)
class Not:
    """The negation of a compound condition (a negated literal is a `Lit`)."""

    item: "Condition"


@dataclass(frozen=True, slots=True)
class And:
    """All of `items` (two or more)."""

    items: tuple


@dataclass(frozen=True, slots=True)
class Or:
    """At least one of `items` (two or more)."""

    items: tuple


Condition = Const | Lit | Not | And | Or
TRUE = Const(True)
FALSE = Const(False)


class NotACondition(ValueError):
    """A term that cannot be read as a condition; the message says why."""


_TRUE_WORDS = {"true"}
_FALSE_WORDS = {"false", "fail"}


def from_term(term: Term) -> Condition:
    """Read a condition from its term, or raise NotACondition."""
    if type(term) is Struct and term.name == "." and len(term.args) == 2:
        return Lit(term)    # `cup.taken`, the most common condition: what the checks below give it
    if isinstance(term, Var):
        raise NotACondition("a variable is not a condition (is the schema instantiated?)")
    if isinstance(term, (Int, Float)):
        raise NotACondition(f"the number {term_to_text(term)} is not a condition")
    if isinstance(term, Str):
        if term.value.upper() == "TRUE":  # SEED writes the always-true releaser as "TRUE"
            return TRUE
        if term.value.upper() == "FALSE":
            return FALSE
        raise NotACondition(f"the string {term_to_text(term)} is not a condition")
    if isinstance(term, Atom):
        if term.name in _TRUE_WORDS or term == NIL:
            return TRUE
        if term.name in _FALSE_WORDS:
            return FALSE
        return Lit(term)
    assert isinstance(term, Struct)
    name, args = term.name, term.args
    if name == CONS and len(args) == 2:
        items, tail = list_items(term)
        if tail == NIL:  # [A, B, ...]: SEED's releaser list, literals in AND
            return conjoin([from_term(i) for i in items])
        if len(items) == 1 and not isinstance(tail, Struct):
            return Lit(Struct(".", (items[0], tail)))  # [hand|free] is SWI-7's hand.free
        raise NotACondition(f"{term_to_text(term)} is a partial list, not a condition")
    if len(args) == 2 and name in _AND_WORDS:
        return conjoin([from_term(t) for t in _operands(term, _AND_WORDS)])
    if len(args) == 2 and name in _OR_WORDS:
        return disjoin([from_term(t) for t in _operands(term, _OR_WORDS)])
    if len(args) == 1 and name in ("not", "\\+", "-"):
        return negate(from_term(args[0]))
    if name in (":-", "->", "=", "is") and len(args) == 2:
        raise NotACondition(f"{term_to_text(term)} is a goal, not a condition")
    return Lit(term)


_AND_WORDS = ("and", ",")
_OR_WORDS = ("or", ";")


def _operands(term: Struct, words: tuple[str, ...]) -> list[Term]:
    """The operands of a chain of one operator (`a and b and c ...`), left to right, iteratively:
    a 100,000-literal `and` nests 100,000 deep and must neither recurse nor be re-flattened per level."""
    found: list[Term] = []
    stack: list[Term] = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Struct) and len(t.args) == 2 and t.name in words:
            stack.append(t.args[1])
            stack.append(t.args[0])
        else:
            found.append(t)
    return found


def conjoin(items: list[Condition]) -> Condition:
    """AND of `items`, flattened; constants absorbed."""
    flat: list[Condition] = []
    for item in items:
        if item == TRUE:
            continue
        if item == FALSE:
            return FALSE
        flat.extend(item.items if isinstance(item, And) else (item,))
    if not flat:
        return TRUE
    return flat[0] if len(flat) == 1 else And(tuple(flat))


def disjoin(items: list[Condition]) -> Condition:
    """OR of `items`, flattened; constants absorbed."""
    flat: list[Condition] = []
    for item in items:
        if item == FALSE:
            continue
        if item == TRUE:
            return TRUE
        flat.extend(item.items if isinstance(item, Or) else (item,))
    if not flat:
        return FALSE
    return flat[0] if len(flat) == 1 else Or(tuple(flat))


def negate(c: Condition) -> Condition:
    """NOT `c`: flips literals and constants, keeps other negations explicit."""
    if isinstance(c, Const):
        return Const(not c.value)
    if isinstance(c, Lit):
        return c.negate()
    if isinstance(c, Not):
        return c.item
    return Not(c)


def to_term(c: Condition) -> Term:
    """The condition as a term in the paper's words (`and`, `or`, `not`)."""
    if isinstance(c, Const):
        return Atom("true" if c.value else "false")
    if isinstance(c, Lit):
        return c.atom if c.positive else Struct("not", (c.atom,))
    if isinstance(c, Not):
        return Struct("not", (to_term(c.item),))
    op = "and" if isinstance(c, And) else "or"
    result = to_term(c.items[-1])
    for item in reversed(c.items[:-1]):
        result = Struct(op, (to_term(item), result))
    return result


def to_text(c: Condition) -> str:
    """Print a condition: `hand.free or spoon.taken`, `not hand.free`."""
    return term_to_text(to_term(c), 999, spaced=True)


def literals(c: Condition) -> list[Lit]:
    """The literals of `c`, left to right."""
    if isinstance(c, Lit):
        return [c]
    if isinstance(c, Not):
        return literals(c.item)
    if isinstance(c, (And, Or)):
        return [lit for item in c.items for lit in literals(item)]
    return []


def is_conjunction_of_literals(c: Condition) -> bool:
    """Whether `c` is `true`, a literal, or an AND of literals (what a post-condition must be)."""
    if type(c) is Lit:
        return True         # never equal to FALSE, a Const
    if isinstance(c, (Lit, Const)):
        return c != FALSE
    return isinstance(c, And) and all(isinstance(i, Lit) for i in c.items)


# ---------------------------------------------------------------------------
# The algebra: canonical form, a fast exact DNF path, sympy for the rest.
#
#     DNF = frozenset[frozenset[Lit]]    an OR of ANDs of literals; {} is false, {{}} is true

DNF = frozenset

DEFAULT_SYMPY_BUDGET = defaults.SYMPY_BUDGET
MAX_SYMPY_BUDGET = defaults.MAX_SYMPY_BUDGET
DEFAULT_DNF_LIMIT = 512       # clauses; distributing AND over OR beyond this is refused


@functools.lru_cache(maxsize=1 << 20)  # bounded: a long REPL session must not grow without end
def _atom_text(atom: Term) -> str:
    return term_to_text(atom)


def _key(c: Condition) -> tuple:
    """A total order on conditions, for canonical sorting (the same in every run)."""
    if isinstance(c, Const):
        return (0, c.value)
    if isinstance(c, Lit):
        return (1, _atom_text(c.atom), not c.positive)
    if isinstance(c, Not):
        return (2, _key(c.item))
    return (3 if isinstance(c, And) else 4, tuple(_key(i) for i in c.items))


def nnf(c: Condition) -> Condition:
    """Negation normal form: NOT only on literals."""
    if isinstance(c, Not):
        inner = c.item
        if isinstance(inner, And):
            return disjoin([nnf(negate(i)) for i in inner.items])
        if isinstance(inner, Or):
            return conjoin([nnf(negate(i)) for i in inner.items])
        return nnf(negate(inner))
    if isinstance(c, And):
        return conjoin([nnf(i) for i in c.items])
    if isinstance(c, Or):
        return disjoin([nnf(i) for i in c.items])
    return c


def canonical(c: Condition) -> Condition:
    """A canonical form: NNF, flattened, items sorted and deduplicated, constants absorbed.

    Two conditions written differently but with the same structure up to order
    (`a and b`, `b and a`, `[b, a]`) have the same canonical form."""
    c = nnf(c)
    if isinstance(c, (And, Or)):
        # a child's canonical form may be of the parent's own kind (`not (a or b)` under an `and`
        # is an `and`): its items join the parent's before sorting and deduplicating, or the
        # result held `a and b and a`, whose own canonical form differs
        flat: list[Condition] = []
        for item in c.items:
            k = canonical(item)
            flat.extend(k.items if type(k) is type(c) else (k,))
        items = {_key(i): i for i in flat}
        ordered = [items[k] for k in sorted(items)]
        return conjoin(ordered) if isinstance(c, And) else disjoin(ordered)
    return c


def to_dnf(c: Condition, limit: int = DEFAULT_DNF_LIMIT) -> DNF | None:
    """The DNF of `c` with complementary clauses dropped and absorption applied, or None
    when it would have more than `limit` clauses."""
    c = nnf(c)
    if isinstance(c, Const):
        return frozenset({frozenset()}) if c.value else frozenset()
    if isinstance(c, Lit):
        return frozenset({frozenset({c})})
    parts = [to_dnf(i, limit) for i in c.items]
    if any(p is None for p in parts):
        return None
    if isinstance(c, Or):
        return _absorb(frozenset().union(*parts))
    # The single-clause parts (literals, mostly) form one clause at once: joining them one by
    # one would copy a growing clause per literal, quadratic in a 100,000-literal `and`.
    base: set[Lit] = set()
    for part in parts:
        if len(part) == 1:
            base.update(next(iter(part)))
        elif not part:
            return frozenset()
    first = frozenset(base)
    if _clashes(first):
        return frozenset()
    result: set[frozenset] = {first}
    for part in parts:
        if len(part) > 1:
            result = {a | b for a in result for b in part if not _clashes(a | b)}
            if len(result) > limit:
                return None
    return _absorb(frozenset(result))


def _clashes(clause: frozenset) -> bool:
    return any(lit.negate() in clause for lit in clause if lit.positive)


def _absorb(dnf: DNF) -> DNF:
    """x or (x and y) = x: drop every clause that contains another clause.

    Only a strictly shorter clause can absorb one (equal ones are already merged by the
    set), and it must share all its literals: candidates come from a literal index, so
    an OR of n distinct clauses of one length costs O(n), not O(n^2)."""
    clauses = sorted((c for c in dnf if not _clashes(c)), key=len)
    kept: list[frozenset] = []
    by_literal: dict[Lit, list[int]] = {}
    pending: list[tuple[frozenset, int]] = []  # kept, but not yet indexed (same length)
    length = -1
    for clause in clauses:
        if len(clause) != length:  # clauses of the previous length may now absorb
            for k, index in pending:
                for lit in k:
                    by_literal.setdefault(lit, []).append(index)
            pending, length = [], len(clause)
        if not clause:
            return frozenset({clause})  # true absorbs everything
        hits: dict[int, int] = {}
        absorbed = False
        for lit in clause:
            for index in by_literal.get(lit, ()):
                hits[index] = hits.get(index, 0) + 1
                if hits[index] == len(kept[index]):
                    absorbed = True
                    break
            if absorbed:
                break
        if not absorbed:
            pending.append((clause, len(kept)))
            kept.append(clause)
    return frozenset(kept)


def from_dnf(dnf: DNF, order: dict[Lit, int] | None = None) -> Condition:
    """The condition of a DNF: literals and clauses in `order` (first appearance in what
    was simplified), else canonically ordered."""
    if order is None:
        return canonical(disjoin([conjoin(sorted(clause, key=_key)) for clause in dnf]))
    def rank(lit: Lit) -> tuple:
        return (order.get(lit, len(order)), _key(lit))
    clauses = [sorted(clause, key=rank) for clause in dnf]
    clauses.sort(key=lambda clause: [rank(lit) for lit in clause])
    return disjoin([conjoin(list(clause)) for clause in clauses])


def _appearance(c: Condition) -> dict[Lit, int]:
    order: dict[Lit, int] = {}
    for lit in literals(nnf(c)):
        order.setdefault(lit, len(order))
    return order


def variables(c: Condition) -> set[Term]:
    """The atoms `c` mentions."""
    return {lit.atom for lit in literals(c)}


def _needs_more_than_fast_rules(dnf: DNF) -> bool:
    """Whether a literal and its negation occur in different clauses (x or not x, consensus):
    the fast rules may then leave a non-minimal form."""
    seen = {lit for clause in dnf for lit in clause}
    return any(lit.negate() in seen for lit in seen)


@dataclass
class Simplifier:
    """Simplifies conditions, fast path first, and counts what needed sympy.

    Never silent: a condition it could not fully simplify is recorded in `notes`."""

    sympy_budget: int = DEFAULT_SYMPY_BUDGET
    dnf_limit: int = DEFAULT_DNF_LIMIT
    calls: int = 0
    sympy_calls: int = 0
    notes: list = None  # type: ignore[assignment]
    _memo: dict = None  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.notes is None:
            self.notes = []
        self._memo = {}

    def simplify(self, c: Condition) -> Condition:
        """An equivalent, simpler condition in canonical DNF (each distinct one computed once)."""
        self.calls += 1
        known = self._memo.get(c)
        if known is None:
            known = self._memo[c] = self._simplify(c)
        return known

    def _simplify(self, c: Condition) -> Condition:
        dnf = to_dnf(c, self.dnf_limit)
        if dnf is None:
            self.notes.append(f"kept as written (its DNF has more than {self.dnf_limit} clauses): "
                              f"{_abridged(to_text(c))}")
            return canonical(c)
        order = _appearance(c)
        if not _needs_more_than_fast_rules(dnf):
            return from_dnf(dnf, order)
        names = variables(c)
        flat = from_dnf(dnf, order)
        if len(names) > self.sympy_budget:
            self.notes.append(f"kept the fast-path form ({len(names)} variables, over the sympy "
                              f"budget of {self.sympy_budget}): {_abridged(to_text(flat))}")
            return flat
        if len(names) <= 16 and equivalent(flat, TRUE):  # sympy leaves `x or not x` as it is
            return TRUE
        self.sympy_calls += 1
        simplified = _sympy_simplify(flat)
        again = to_dnf(simplified, self.dnf_limit)
        return from_dnf(again, order) if again is not None else simplified


def _abridged(text: str, limit: int = 160) -> str:
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text):,} characters)"


def simplify(c: Condition, sympy_budget: int = DEFAULT_SYMPY_BUDGET) -> Condition:
    """An equivalent, simpler condition (see `Simplifier`)."""
    return Simplifier(sympy_budget).simplify(c)


def _to_sympy(c: Condition, symbols: dict):
    import sympy

    if isinstance(c, Const):
        return sympy.true if c.value else sympy.false
    if isinstance(c, Lit):
        key = term_to_text(c.atom)
        sym = symbols.setdefault(key, (sympy.Symbol(f"v{len(symbols)}"), c.atom))[0]
        return sym if c.positive else sympy.Not(sym)
    if isinstance(c, Not):
        return sympy.Not(_to_sympy(c.item, symbols))
    parts = [_to_sympy(i, symbols) for i in c.items]
    return sympy.And(*parts) if isinstance(c, And) else sympy.Or(*parts)


def _from_sympy(expr, atoms: dict) -> Condition:
    import sympy

    if expr is sympy.true:
        return TRUE
    if expr is sympy.false:
        return FALSE
    if isinstance(expr, sympy.Symbol):
        return Lit(atoms[expr])
    if isinstance(expr, sympy.Not):
        return negate(_from_sympy(expr.args[0], atoms))
    items = [_from_sympy(a, atoms) for a in expr.args]
    return conjoin(items) if isinstance(expr, sympy.And) else disjoin(items)


def _sympy_simplify(c: Condition) -> Condition:
    from sympy.logic.boolalg import simplify_logic

    symbols: dict = {}
    expr = _to_sympy(c, symbols)
    atoms = {sym: atom for sym, atom in symbols.values()}
    # force=True: without it sympy returns its input unchanged above 8 variables.
    return canonical(_from_sympy(simplify_logic(expr, form="dnf", force=True), atoms))


def equivalent(a: Condition, b: Condition) -> bool:
    """Whether `a` and `b` hold in exactly the same states."""
    names = sorted(variables(a) | variables(b), key=term_to_text)
    if len(names) <= 16:  # a truth table is faster than a SAT call here
        for bits in range(1 << len(names)):
            state = {n for i, n in enumerate(names) if bits >> i & 1}
            if holds(a, state) != holds(b, state):
                return False
        return True
    return not satisfiable(disjoin([conjoin([a, negate(b)]), conjoin([negate(a), b])]))


def satisfiable(c: Condition) -> bool:
    """Whether some state makes `c` true: a Tseitin encoding (linear in the size of `c`,
    where sympy's own to_cnf distributes and can explode) solved by sympy's DPLL2."""
    import sympy
    from sympy.assumptions.cnf import EncodedCNF
    from sympy.logic.algorithms.dpll2 import dpll_satisfiable

    atoms: dict[str, int] = {}
    clauses: list[set[int]] = []
    count = 0

    def fresh() -> int:
        nonlocal count
        count += 1
        return count

    def encode(x: Condition) -> int:
        if isinstance(x, Const):
            t = fresh()
            clauses.append({t} if x.value else {-t})
            return t
        if isinstance(x, Lit):
            key = term_to_text(x.atom)
            if key not in atoms:
                atoms[key] = fresh()
            return atoms[key] if x.positive else -atoms[key]
        if isinstance(x, Not):
            return -encode(x.item)
        parts = [encode(i) for i in x.items]
        t = fresh()
        if isinstance(x, And):  # t <-> AND(parts)
            clauses.extend({-t, p} for p in parts)
            clauses.append({t, *(-p for p in parts)})
        else:  # t <-> OR(parts)
            clauses.append({-t, *parts})
            clauses.extend({t, -p} for p in parts)
        return t

    clauses.append({encode(c)})
    encoding = {sympy.Symbol(f"x{i}"): i for i in range(1, count + 1)}
    return dpll_satisfiable(EncodedCNF(clauses, encoding)) is not False


def holds(c: Condition, state: set | frozenset) -> bool:
    """Whether `c` is true in `state`, a set of true ground atoms (closed world)."""
    if isinstance(c, Const):
        return c.value
    if isinstance(c, Lit):
        return (c.atom in state) == c.positive
    if isinstance(c, Not):
        return not holds(c.item, state)
    if isinstance(c, And):
        return all(holds(i, state) for i in c.items)
    return any(holds(i, state) for i in c.items)


def assign(c: Condition, values: dict[Term, bool]) -> Condition:
    """`c` with the atoms of `values` replaced by their truth value, constants folded: it agrees
    with `c` on every state that gives those atoms those values.

    >>> assign(from_term(Struct("and", (Atom("a"), Struct("not", (Atom("b"),))))), {Atom("a"): True})
    Lit(atom=Atom(name='b'), positive=False)
    """
    if isinstance(c, Const):
        return c
    if isinstance(c, Lit):
        value = values.get(c.atom)
        return c if value is None else Const(value == c.positive)
    if isinstance(c, Not):
        return negate(assign(c.item, values))
    items = [assign(i, values) for i in c.items]
    return conjoin(items) if isinstance(c, And) else disjoin(items)


Check = Callable[[AbstractSet[Term]], bool]


def compile_check(c: Condition, limit: int = 64) -> Check:
    """A function deciding `holds(c, state)` with set operations: each DNF clause becomes
    `positives <= state and negatives.isdisjoint(state)`, done in C, so the cost barely
    grows with the number of literals. Falls back to `holds` beyond `limit` clauses.

    A check is a bound set method or a partial of a function below, never a closure: the
    worlds and plans that hold checks are pickled with a Task, a Run or a Report."""
    if type(c) is Lit:                 # most conditions of a large tree: `b12.done`
        atoms = frozenset((c.atom,))
        return atoms.issubset if c.positive else atoms.isdisjoint
    dnf = to_dnf(c, limit)
    if dnf is None:
        return functools.partial(holds, c)
    clauses = tuple((frozenset(l.atom for l in clause if l.positive),
                     frozenset(l.atom for l in clause if not l.positive)) for clause in dnf)
    if not clauses:
        return functools.partial(_constant, False)
    if len(clauses) > 1:
        return functools.partial(_any_clause_holds, clauses)
    pos, neg = clauses[0]
    if not pos and not neg:
        return functools.partial(_constant, True)
    if not neg:
        return pos.issubset
    if not pos:
        return neg.isdisjoint
    return functools.partial(_clause_holds, pos, neg)


def _constant(value: bool, state: AbstractSet[Term]) -> bool:
    return value


def _clause_holds(pos: frozenset, neg: frozenset, state: AbstractSet[Term]) -> bool:
    return pos <= state and neg.isdisjoint(state)


def _any_clause_holds(clauses: tuple[tuple[frozenset, frozenset], ...], state: AbstractSet[Term]) -> bool:
    return any(pos <= state and neg.isdisjoint(state) for pos, neg in clauses)

