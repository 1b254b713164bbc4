"""Unification over a trail of bindings.

    Bindings = dict[Var, Term] with a trail (list[Var]) recording the order of binding,
    so a failed branch is undone by `undo(mark)` instead of copying the dict.
    Subst   = dict[Var, Term]   (the pure view: `unify_terms(x, y) -> Subst | None`)

No occurs check, as in SWI-Prolog's default `unify/2`; `unify_with_occurs_check` is
available through `Bindings.unify(x, y, occurs_check=True)`.
"""

from __future__ import annotations

from typing import Mapping

from .exceptions import CyclicTermError, cyclic_term_error
from .terms import Struct, Term, Var

Subst = dict[Var, Term]


def _rebuilt(node: Struct, args: list[Term]) -> Struct:
    """`node` with these arguments; `node` itself when none changed (shares subterms)."""
    return node if all(a is b for a, b in zip(args, node.args)) else Struct(node.name, tuple(args))


class Bindings:
    """Variable bindings with a trail; the engine's only mutable state."""

    __slots__ = ("values", "trail", "work", "machines")

    def __init__(self, values: Mapping[Var, Term] | None = None) -> None:
        self.values: dict[Var, Term] = dict(values or {})
        self.trail: list[Var] = list(self.values)
        self.work = 0  # cells `resolve` has built: the engine charges them to the step budget
        self.machines: list = []  # the machines running on these bindings, oldest first (collect.py)

    def mark(self) -> int:
        """Return a point to undo back to."""
        return len(self.trail)

    def undo(self, mark: int) -> None:
        """Forget every binding made since `mark`."""
        trail, values = self.trail, self.values
        while len(trail) > mark:
            del values[trail.pop()]

    def bind(self, var: Var, term: Term) -> None:
        """Bind an unbound variable."""
        self.values[var] = term
        self.trail.append(var)

    def walk(self, term: Term) -> Term:
        """Follow variable bindings until a non-variable or an unbound variable."""
        values = self.values
        while isinstance(term, Var):
            bound = values.get(term)
            if bound is None:
                return term
            term = bound
        return term

    def resolve(self, term: Term) -> Term:
        """Apply the bindings all the way down (iteratively: deep terms are fine).

        A cyclic term (X = f(X), made without the occurs check) has no finite resolution:
        CyclicTermError. The variables dereferenced on the path from the root are kept in
        a set, so the check costs one set insertion per bound variable met, and a DAG's
        shared subterms are not mistaken for cycles."""
        values = self.values
        original = term
        chain: list[Var] = []
        while type(term) is Var:
            bound = values.get(term)
            if bound is None:
                return term
            chain.append(term)
            term = bound
        if type(term) is not Struct:
            return term
        active: set[Var] = set(chain)
        # Post-order rebuild with an explicit stack; shares unchanged subterms.
        stack: list[tuple[Struct, list[Term], list[Var] | None]] = [(term, [], None)]
        result: Term = term
        work = 0
        while stack:
            node, done, entered = stack[-1]
            args = node.args
            work += 1
            if len(done) == len(args):
                stack.pop()
                if entered:
                    active.difference_update(entered)
                rebuilt = _rebuilt(node, done)
                if stack:
                    stack[-1][1].append(rebuilt)
                else:
                    result = rebuilt
                continue
            arg = args[len(done)]
            entered = None
            while type(arg) is Var:
                bound = values.get(arg)
                if bound is None:
                    break
                if arg in active:
                    raise cyclic_term_error(self.resolve_finite(original))
                if entered is None:
                    entered = [arg]
                else:
                    entered.append(arg)
                arg = bound
            if type(arg) is Struct:
                if entered:
                    active.update(entered)
                stack.append((arg, [], entered))
            else:
                done.append(arg)
        self.work += work
        return result

    def copy(self, term: Term) -> Term:
        """A copy of `term` with fresh variables (copy_term/2). A cyclic term's copy is
        cyclic too: the bindings are copied as a graph, each bound variable met getting a
        fresh one bound here to the copy of its value (X = f(X) copies to Y = f(Y))."""
        try:
            return rename(self.resolve(term))
        except CyclicTermError:
            pass
        values = self.values
        mapping: dict[Var, Var] = {}
        result = rename(term, mapping)
        copied = 0
        while copied < len(mapping):  # mapping grows as values are copied: each var once
            v = list(mapping)[copied]
            copied += 1
            if v in values:
                self.bind(mapping[v], rename(values[v], mapping))
        return result

    def is_cyclic(self, term: Term) -> bool:
        """Whether `term` is cyclic under the bindings (cyclic_term/1)."""
        try:
            self.resolve(term)
        except CyclicTermError:
            return True
        return False

    def resolve_finite(self, term: Term) -> Term:
        """Like `resolve`, but where a variable's value contains the variable itself
        (X = f(X), made without the occurs check) the variable is left in place, so the
        result is finite: X resolves to f(X), as SWI-Prolog's top level prints it. A cycle
        back to the term's own value through another variable (Y = X', X' = f(X'), which
        copy_term makes) is closed on `term` itself, so Y resolves to f(Y), not f(X').
        Its nodes count as work, as `resolve`'s do: printing an answer is charged to the query."""
        active: set[Var] = set()
        values = self.values

        def deref(t: Term) -> tuple[Term, list[Var] | None]:
            chain: list[Var] = []
            while type(t) is Var:
                if t in active:
                    return t, None
                bound = values.get(t)
                if bound is None:
                    break
                chain.append(t)
                t = bound
            return t, chain

        root, chain = deref(term)
        if not isinstance(root, Struct) or chain is None:
            return root
        active.update(chain)
        own = set(chain) if type(term) is Var else ()   # the variables standing for the whole term
        stack: list[tuple[Struct, list[Term], list[Var]]] = [(root, [], chain)]
        result: Term = root
        nodes = 1
        while stack:
            node, done, entered = stack[-1]
            if len(done) == len(node.args):
                stack.pop()
                active.difference_update(entered)
                rebuilt = _rebuilt(node, done)
                if stack:
                    stack[-1][1].append(rebuilt)
                else:
                    result = rebuilt
                continue
            arg, chain = deref(node.args[len(done)])
            if own and chain and arg is root:
                # back at the very node the term's value is (Y bound to the value f(X') of X'): Y = f(Y)
                done.append(term)
            elif isinstance(arg, Struct) and chain is not None:
                active.update(chain)
                stack.append((arg, [], chain))
                nodes += 1
            else:
                done.append(term if chain is None and arg in own else arg)
        self.work += nodes
        return result

    def unify(self, x: Term, y: Term, occurs_check: bool = False) -> bool:
        """Unify `x` and `y`, extending the bindings; on failure the caller undoes."""
        if occurs_check:
            return self._unify_checked(x, y)
        # The engine's innermost loop: walk inlined, exact type tests (Var and Struct have
        # no subclasses), locals for attribute look-ups.
        values, trail = self.values, self.trail
        get = values.get
        pairs = [(x, y)]
        pop, push = pairs.pop, pairs.extend
        # Two cyclic terms (X = f(X), Y = f(Y), X = Y) unfold forever: a pair of compound
        # terms reached through a bound variable is compared once, and assumed to unify
        # when met again (rational-tree unification). Only those pairs are recorded: a
        # cycle always passes through a binding, and plain terms pay nothing.
        seen: set | None = None
        while pairs:
            a, b = pop()
            via = False
            while type(a) is Var:
                bound = get(a)
                if bound is None:
                    break
                a = bound
                via = True
            while type(b) is Var:
                bound = get(b)
                if bound is None:
                    break
                b = bound
                via = True
            if a is b:
                continue
            if type(a) is Var:
                values[a] = b
                trail.append(a)
            elif type(b) is Var:
                values[b] = a
                trail.append(b)
            elif type(a) is Struct:
                if type(b) is not Struct or a.name != b.name or len(a.args) != len(b.args):
                    return False
                if via:
                    key = (id(a), id(b))
                    if seen is None:
                        seen = {key}
                    elif key in seen:
                        continue
                    else:
                        seen.add(key)
                push(zip(a.args, b.args))
            elif type(a) is not type(b) or a != b:
                return False
        return True

    def _unify_checked(self, x: Term, y: Term) -> bool:
        """Unification with the occurs check (unify_with_occurs_check/2)."""
        pairs = [(x, y)]
        walk = self.walk
        while pairs:
            a, b = pairs.pop()
            a, b = walk(a), walk(b)
            if a is b:
                continue
            if isinstance(a, Var):
                if self.occurs(a, b):
                    return False
                self.bind(a, b)
            elif isinstance(b, Var):
                if self.occurs(b, a):
                    return False
                self.bind(b, a)
            elif isinstance(a, Struct):
                if not (isinstance(b, Struct) and a.name == b.name and len(a.args) == len(b.args)):
                    return False
                pairs.extend(zip(a.args, b.args))
            elif type(a) is not type(b) or a != b:
                return False
        return True

    def occurs(self, var: Var, term: Term) -> bool:
        """Whether `var` occurs in `term` under the bindings."""
        stack = [term]
        seen: set[int] = set()  # a cyclic term already bound elsewhere is walked once round
        while stack:
            t = self.walk(stack.pop())
            if t is var:
                return True
            if isinstance(t, Struct) and id(t) not in seen:
                seen.add(id(t))
                stack.extend(t.args)
        return False


def unify_terms(x: Term, y: Term, s: Subst | None = None) -> Subst | None:
    """Return the substitution that unifies `x` and `y` (extending `s`), or None."""
    b = Bindings(s)
    return b.values if b.unify(x, y) else None


def rename(term: Term, mapping: dict[Var, Var] | None = None) -> Term:
    """Copy `term` with fresh variables (consistent through `mapping`)."""
    mapping = {} if mapping is None else mapping
    if isinstance(term, Var):
        fresh = mapping.get(term)
        if fresh is None:
            fresh = mapping[term] = Var("_")  # a copy is a new variable: it prints as _G123
        return fresh
    if not isinstance(term, Struct):
        return term
    stack: list[tuple[Struct, list[Term]]] = [(term, [])]
    while True:
        node, done = stack[-1]
        if len(done) == len(node.args):
            stack.pop()
            rebuilt = Struct(node.name, tuple(done))
            if not stack:
                return rebuilt
            stack[-1][1].append(rebuilt)
            continue
        arg = node.args[len(done)]
        if isinstance(arg, Struct):
            stack.append((arg, []))
        elif isinstance(arg, Var):
            fresh = mapping.get(arg)
            if fresh is None:
                fresh = mapping[arg] = Var("_")
            done.append(fresh)
        else:
            done.append(arg)


def variant(x: Term, y: Term) -> bool:
    """Whether `x` and `y` are equal up to a consistent renaming of variables."""
    forward: dict[Var, Var] = {}
    backward: dict[Var, Var] = {}
    pairs = [(x, y)]
    while pairs:
        a, b = pairs.pop()
        if isinstance(a, Var) and isinstance(b, Var):
            if forward.setdefault(a, b) is not b or backward.setdefault(b, a) is not a:
                return False
        elif isinstance(a, Struct) and isinstance(b, Struct):
            if a.name != b.name or len(a.args) != len(b.args):
                return False
            pairs.extend(zip(a.args, b.args))
        elif type(a) is not type(b) or isinstance(a, Var) or a != b:
            return False
    return True


__all__ = ["Bindings", "Subst", "unify_terms", "rename", "variant"]
