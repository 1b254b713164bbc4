"""The emulated world of a task, derived from its ORIGINAL tree (DESIGN.md section 3).

    State  = set of true ground atoms (closed world)      {hand.free, a1.done}
    Effect = (adds, removes): what a post-condition does   not hand.free -> ((), (hand.free,))
    Change = the atoms an action added and removed, completion included

Executing a leaf applies its post-condition's literals. When all the original children of a
composite behaviour are accomplished, the world asserts that composite's post-condition: it
emulates perception (once the grasp is done, `spoon.taken` holds). A compressed tree runs
against the world of its original, so compression changes the controller, never the
environment.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

from ..task import conditions as cond
from ..task.conditions import Condition
from ..errors import SchemalogError, SourcePos
from ..logic.terms import TRUE, Struct, Term, Var, is_ground, term_to_text
from ..task.tree import Behaviour, walk

Effect = tuple[tuple[Term, ...], tuple[Term, ...]]

_MIX = 0x9E3779B97F4A7C15
_MASK = (1 << 64) - 1


def atom_key(atom: Term) -> int:
    """A well-spread 64-bit key of an atom, XOR-ed into the state's hash."""
    return (hash(atom) * _MIX) & _MASK


def effect_of(post: Condition) -> Effect:
    """What executing a behaviour with post-condition `post` adds and removes."""
    if isinstance(post, cond.Const):
        return (), ()
    items = post.items if isinstance(post, cond.And) else (post,)
    adds: list[Term] = []
    removes: list[Term] = []
    for item in items:
        if not isinstance(item, cond.Lit):
            raise SchemalogError(f"the post-condition {cond.to_text(post)} is not a conjunction of literals")
        (adds if item.positive else removes).append(item.atom)
    return tuple(adds), tuple(removes)


@dataclass(frozen=True)
class Change:
    """The atoms that became true and false during one step of the world."""

    added: frozenset[Term] = frozenset()
    removed: frozenset[Term] = frozenset()

    @property
    def atoms(self) -> frozenset[Term]:
        return self.added | self.removed


@dataclass(frozen=True)
class _Completion:
    """A composite of the original tree: its post-condition and its children's."""

    label: Term
    post: Condition
    children: tuple[Condition, ...]
    source: SourcePos | None = None


class World:
    """The state of the emulated environment and the rules that change it."""

    def __init__(self, original: Behaviour, initial: Iterable[Term] = ()) -> None:
        self.original = original
        completions: dict[tuple, _Completion] = {}
        known: set[Term] = set()
        for node in walk(original):
            known.update(lit.atom for lit in cond.literals(node.pre))
            known.update(lit.atom for lit in cond.literals(node.post))
            if node.children and node.post != cond.TRUE:
                c = _Completion(node.label, node.post, tuple(ch.post for ch in node.children), node.source)
                completions.setdefault((c.post, c.children), c)  # add(water) twice: one rule
        self.completions = tuple(completions.values())
        self.known_atoms = frozenset(known)
        self._reads: dict[Term, list[int]] = {}
        # A rule is looked at again when an atom of its children's posts or of its own post
        # changes: the world is settled when no composite has its children accomplished and
        # its own post false.
        for i, c in enumerate(self.completions):
            for atom in {lit.atom for part in (*c.children, c.post) for lit in cond.literals(part)}:
                self._reads.setdefault(atom, []).append(i)
        compiled: dict[Condition, cond.Check] = {}
        def check(c: Condition) -> cond.Check:
            found = compiled.get(c)
            if found is None:
                found = compiled[c] = cond.compile_check(c)
            return found
        self._post_checks = [check(c.post) for c in self.completions]
        self._child_checks = [[check(ch) for ch in c.children] for c in self.completions]
        # Each rule first re-tests the child last found false: children mostly complete in
        # order, so settling after an action costs O(1), not O(children) (10,000 siblings).
        self._watch = [0] * len(self.completions)
        self._effects: dict[Condition, Effect] = {}
        self._atoms: set[Term] = set()
        self._before: dict[Term, bool] = {}
        self._hash: int | None = 0
        self.reset(initial)

    # -- reading --------------------------------------------------------------
    @property
    def atoms(self) -> frozenset[Term]:
        """The true atoms now."""
        return frozenset(self._atoms)

    def __contains__(self, atom: Term) -> bool:
        return atom in self._atoms

    def holds(self, c: Condition) -> bool:
        """Whether `c` is true now."""
        return cond.holds(c, self._atoms)

    def unknown(self, atoms: Iterable[Term]) -> list[Term]:
        """The atoms that no condition of the task reads or writes (likely typing errors)."""
        return [a for a in atoms if a not in self.known_atoms]

    # -- changing -------------------------------------------------------------
    def reset(self, atoms: Iterable[Term]) -> Change:
        """Make exactly `atoms` true, then let completed composites settle."""
        self._before: dict[Term, bool] = {}
        for atom in list(self._atoms):
            self._set(atom, False)
        for atom in atoms:
            self._set(atom, True)
        self._settle(range(len(self.completions)))
        return self._change()

    @property
    def hash(self) -> int:
        """A 64-bit hash of the state, kept up to date as atoms change (the executive's loop check)."""
        if self._hash is None:
            self._hash = 0
            for atom in self._atoms:
                self._hash ^= atom_key(atom)
        return self._hash

    def load(self, atoms: frozenset[Term]) -> None:
        """Put the world in a state known to be settled (one it produced), without settling."""
        self._atoms = set(atoms)
        self._hash = None

    def successor(self, atoms: frozenset[Term], post: Condition) -> frozenset[Term]:
        """The settled state after executing a leaf with post-condition `post` in state `atoms`."""
        self.load(atoms)
        self._before = {}
        self._settle(sorted(self._apply(post)))
        return frozenset(self._atoms)

    def perform(self, post: Condition) -> Change:
        """Execute a leaf whose post-condition is `post`; return what changed, completion included."""
        self._before = {}
        touched = self._apply(post)
        self._settle(sorted(touched))
        return self._change()

    def _set(self, atom: Term, value: bool) -> bool:
        """Make `atom` true or false; whether that changed it."""
        if (atom in self._atoms) == value:
            return False
        self._before.setdefault(atom, not value)
        if value:
            self._atoms.add(atom)
        else:
            self._atoms.discard(atom)
        if self._hash is not None:
            self._hash ^= atom_key(atom)
        return True

    def _apply(self, post: Condition) -> set[int]:
        """Apply a post-condition's literals; return the completion rules that read a changed atom."""
        effect = self._effects.get(post)
        if effect is None:
            effect = self._effects[post] = effect_of(post)
        adds, removes = effect
        changed = [a for a in removes if self._set(a, False)] + [a for a in adds if self._set(a, True)]
        return {i for atom in changed for i in self._reads.get(atom, ())}

    def _change(self) -> Change:
        """The net change since `_before` was cleared: atoms whose value differs now."""
        added = frozenset(a for a, was in self._before.items() if not was and a in self._atoms)
        removed = frozenset(a for a, was in self._before.items() if was and a not in self._atoms)
        return Change(added, removed)

    def _settle(self, candidates: Iterable[int]) -> None:
        """Assert the post-condition of every composite whose children are all accomplished."""
        pending = list(candidates)
        queued = set(pending)
        budget = 4 * len(self.completions) + 16
        while pending:
            i = pending.pop()
            queued.discard(i)
            c = self.completions[i]
            if self._post_checks[i](self._atoms) or not self._children_done(i):
                continue
            budget -= 1
            if budget < 0:
                raise SchemalogError(f"the world does not settle: completing {term_to_text(c.label)} "
                                     f"({cond.to_text(c.post)}) keeps undoing other completions "
                                     f"(post-conditions that contradict)", c.source)
            for j in self._apply(c.post):
                if j not in queued:
                    queued.add(j)
                    pending.append(j)

    def _children_done(self, i: int) -> bool:
        """Whether every child of completion rule `i` is accomplished, the watched one first."""
        checks, atoms = self._child_checks[i], self._atoms
        n, start = len(checks), self._watch[i]
        for k in range(n):
            j = start + k if start + k < n else start + k - n
            if not checks[j](atoms):
                self._watch[i] = j
                return False
        return True


def initial_state(kb) -> list[Term]:
    """The initial state a task file declares with `initial(Literal)` facts, in order."""
    from ..logic.engine import Engine

    atoms: list[Term] = []
    clauses = [c for c in kb.clauses("initial", 1) if not c.library]
    if not clauses:
        return atoms
    if all(c.body == TRUE for c in clauses):       # facts: each error at its own place
        for c in clauses:
            try:
                atoms.extend(state_atoms(c.head.args[0], "initial/1"))
            except SchemalogError as err:
                raise SchemalogError(err.message, c.pos) from None
        return list(dict.fromkeys(atoms))
    from ..logic.exceptions import PrologError, StepLimitExceeded

    x = Var("X")
    where = f"initial/1 ({clauses[0].pos})" if clauses[0].pos else "initial/1"
    try:
        for b in Engine(kb, max_steps=100_000).solve(Struct("initial", (x,))):
            atoms.extend(state_atoms(b.resolve(x), where))
    except (PrologError, StepLimitExceeded) as err:
        raise SchemalogError(f"{where}: asking the initial state failed: {err}") from None
    return list(dict.fromkeys(atoms))


def state_atoms(term: Term, where: str) -> list[Term]:
    """The atoms of a state written as a condition: `hand.free, spoon.taken` (positive literals)."""
    try:
        c = cond.from_term(term)
    except cond.NotACondition as err:
        raise SchemalogError(f"{where}: {err}") from None
    if c == cond.TRUE:
        return []
    items = c.items if isinstance(c, cond.And) else (c,)
    atoms = []
    for item in items:
        if not (isinstance(item, cond.Lit) and item.positive):
            raise SchemalogError(f"{where}: a state lists the atoms that are true (closed world), "
                                 f"so {cond.to_text(item)} cannot be part of one")
        if not is_ground(item.atom):
            raise SchemalogError(f"{where}: {term_to_text(item.atom)} has variables; a state is ground")
        atoms.append(item.atom)
    return list(dict.fromkeys(atoms))


__all__ = ["World", "Change", "effect_of", "atom_key", "initial_state", "state_atoms"]
