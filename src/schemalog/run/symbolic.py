"""Symbolic verification: the explorer's model, with sets of states as binary decision diagrams.

    Set      = a BDD (dd.cudd) over one variable `x<i>` per atom: the states it contains
               (a state is the set of atoms whose variable is true)
    Function = {variable: BDD}: a deterministic step, each atom it may change as a function of
               the state before; an atom not in it keeps its value
    Relation = the BDD of a Function over `x<i>` (before) and `y<i>` (after), for images

The model is the explicit explorer's (run/verify.py, docs/semantics.md "Proof by sets of
states"): the same enabled leaves, the same skipping of accomplished constituents, the same
world with its completion rules. What changes is that every reachable state is kept in one
set, and steps are applied to sets: sibling sub-tasks that interleave give a product of their
sets, not the product of their numbers of states. Counterexamples are replayed with the
explicit model (verify.Model), so each is a real run of both trees.
"""

from __future__ import annotations

import weakref
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from ..errors import SchemalogError
from ..memory import CeilingReached, ceiling, data_in_use, headroom, near_ceiling
from ..logic.terms import Term, term_to_text
from ..task import conditions as cond
from ..task.conditions import Condition
from ..task.tree import Behaviour, walk
from .execute import Plan
from .world import World, effect_of

MEMORY_PER_ATOM = 32 * 2**10    # bytes CUDD sizes its tables for at first, per atom (it grows past
MEMORY_ESTIMATE = (2**20, 256 * 2**20)     # them), within these bounds: a small part stays small


def room_below_ceiling() -> int | None:
    """The bytes this process may still take before the headroom below its memory ceiling (None:
    no ceiling, or no way to tell)."""
    limit, used = ceiling(), data_in_use()
    if limit is None or used is None:
        return None
    return max(0, limit - headroom(limit) - used)


@contextmanager
def memory_guard() -> Iterator[None]:
    """Decision diagrams past their memory: CUDD returns NULL for a node it may not make, which
    dd raises as a ValueError; that is the memory ceiling (CeilingReached), not a fault."""
    try:
        yield
    except ValueError as err:
        if "`NULL` pointer" in str(err):
            raise CeilingReached("the decision diagrams reached the memory ceiling") from None
        raise


class Unsupported(Exception):
    """The symbolic encoding would not be exact for this task (the explorer is used instead)."""


class OutOfNodes(SchemalogError):
    """The BDDs grew past the node limit: no proof, and which part of the work blew up."""


@dataclass(frozen=True)
class Found:
    """What the symbolic method found: the sets the verdicts are read from."""

    reachable: object            # the compressed tree's reachable states
    unsound: object              # the reachable states where some step is refused by the original
    stuck: object                # reachable, not accomplished, nothing enabled, the original enables
    dead: object                 # reachable, the original can complete, the compressed tree cannot
    can_o: object                # states from which the original can complete
    can_c: object                # reachable states from which the compressed tree can complete
    peak_nodes: int
    sweeps: int


def monotone_settling(world: World) -> str | None:
    """Why settling the world is not a monotone closure (None when it is).

    Settling is monotone when no atom is set true by one completion rule and false by another,
    and no completion rule's children read an atom with the polarity a completion sets against
    it: then a rule that can fire stays able to, each fires at most once, and the settled state
    is the same whatever the order (docs/semantics.md)."""
    sets: dict[Term, tuple[bool, Term]] = {}
    for c in world.completions:
        for lit in cond.literals(c.post):
            known = sets.setdefault(lit.atom, (lit.positive, c.label))
            if known[0] != lit.positive:
                return (f"completing {term_to_text(known[1])} and {term_to_text(c.label)} set "
                        f"{term_to_text(lit.atom)} to opposite values")
    for c in world.completions:
        for child in c.children:
            for lit in cond.literals(child):
                if lit.atom in sets and sets[lit.atom][0] != lit.positive:
                    return (f"completing {term_to_text(sets[lit.atom][1])} makes "
                            f"{cond.to_text(lit)} false, which completing {term_to_text(c.label)} reads")
    return None


class SymbolicModel:
    """Both trees over one BDD manager: their enabled sets, steps and the original's permissions."""

    def __init__(self, original: Behaviour, compressed: Behaviour, world: World, extra_atoms=(),
                 max_nodes: int = 5_000_000) -> None:
        from dd import cudd

        why = monotone_settling(world)
        if why is not None:
            raise Unsupported(f"settling is not a monotone closure: {why}")
        self.world = world
        self.max_nodes = max_nodes
        self.peak = 0
        atoms: dict[Term, None] = {}
        for tree in (original, compressed):
            for node in walk(tree):                       # pre-order: a sub-task's atoms together
                # a merged leaf's constituents too: compressing a compressed task gives leaves
                # whose steps set atoms (a1.done) that no node's own conditions mention
                for c in (node.post, node.pre, *(o.post for o in node.origins)):
                    atoms.update((lit.atom, None) for lit in cond.literals(c))
        atoms.update((a, None) for a in world.known_atoms)
        atoms.update((a, None) for a in extra_atoms)
        self.atoms = list(atoms)
        self.index = {a: i for i, a in enumerate(self.atoms)}
        low, high = MEMORY_ESTIMATE
        room = room_below_ceiling()
        # CUDD sizes its tables and grows them by what it is told it may use: under a ceiling, a
        # part of the room left (a table doubled at once past the ceiling fails in CUDD's own
        # malloc, which prints to stderr)
        estimate = min(high, max(low, MEMORY_PER_ATOM * len(self.atoms)), *([max(low, room // 4)] if room else []))
        self.bdd = cudd.BDD(memory_estimate=estimate, initial_cache_size=max(2**12, estimate // 256))
        self.bdd.configure(reordering=False)
        if room is not None:
            # CUDD's own hard limit, under the process's ceiling: past it CUDD refuses a node (a
            # NULL, raised by dd as ValueError; memory_guard) where malloc failing at the ceiling
            # inside CUDD would not unwind; and its cache (32-byte entries) kept to an eighth of
            # the room, since it grows by doubling, in one allocation
            cache = min(self.bdd.configure()["max_cache_hard"], max(2**12, room // 256))
            self.bdd.configure(max_memory=max(room, low), max_cache_hard=cache)
        names = []
        for i in range(len(self.atoms)):
            names += [f"x{i}", f"y{i}"]                   # after next to before: small relations
        self.bdd.declare(*names)
        self.x = [self.bdd.var(f"x{i}") for i in range(len(self.atoms))]
        self.rename = {f"y{i}": f"x{i}" for i in range(len(self.atoms))}
        self._conds: dict[Condition, object] = {}
        self._actions: dict[Condition, dict[str, object]] = {}
        self.o = _Tree(self, original)
        self.c = _Tree(self, compressed)
        self.allowed: dict[tuple, object] = {}
        for i in self.o.plan.leaves:
            action = self.o.plan.steps[i][0]
            self.allowed[action] = self.allowed.get(action, self.bdd.false) | self.o.enabled[i]
        self.check("building the trees' conditions")

    # -- building ---------------------------------------------------------------
    def check(self, what: str) -> None:
        """Stop at the node limit, saying what was being computed, and near the memory ceiling."""
        nodes = len(self.bdd)
        self.peak = max(self.peak, nodes)
        if nodes > self.max_nodes:
            raise OutOfNodes(f"the decision diagrams grew past {self.max_nodes:,} nodes while {what} "
                             f"(--max-bdd-nodes): no proof")
        if near_ceiling():
            raise CeilingReached(f"near the memory ceiling while {what}")

    def condition(self, c: Condition):
        found = self._conds.get(c)
        if found is None:
            if isinstance(c, cond.Const):
                found = self.bdd.true if c.value else self.bdd.false
            elif isinstance(c, cond.Lit):
                v = self.x[self.index[c.atom]]
                found = v if c.positive else ~v
            elif isinstance(c, cond.Not):
                found = ~self.condition(c.item)
            elif isinstance(c, (cond.And, cond.Or)):
                # Joined from the bottom of the variable order up: a literal above everything
                # joined so far costs one node, where one below cost a walk of the whole
                # diagram (a 20,000-literal `and` took 106 s, issue 32). Conjunction and
                # disjunction are commutative: the order changes the cost, not the result.
                parts = sorted((self.condition(item) for item in c.items), key=lambda u: u.level, reverse=True)
                found = self.bdd.true if isinstance(c, cond.And) else self.bdd.false
                if isinstance(c, cond.And):
                    for u in parts:
                        found = u & found
                else:
                    for u in parts:
                        found = u | found
            else:
                raise Unsupported(f"{cond.to_text(c)} is not a condition the symbolic method reads")
            self._conds[c] = found
        return found

    def compose(self, f: dict, u):
        """u after the step f: each variable f changes replaced by its new value."""
        return self.bdd.let(f, u) if f else u

    def action(self, post: Condition) -> dict:
        """The Function of executing an original action with post-condition `post`: its
        literals, then the completion rules they can set off, to their monotone closure."""
        found = self._actions.get(post)
        if found is not None:
            return found
        adds, removes = effect_of(post)
        f = {f"x{self.index[a]}": self.bdd.false for a in removes}
        f.update({f"x{self.index[a]}": self.bdd.true for a in adds})
        w = self.world
        rules: set[int] = set()
        frontier = [a for a in (*adds, *removes)]
        while frontier:
            atom = frontier.pop()
            for i in w._reads.get(atom, ()):
                if i not in rules:
                    rules.add(i)
                    frontier.extend(lit.atom for lit in cond.literals(w.completions[i].post))
        order = sorted(rules, reverse=True)     # pre-order reversed: a composite's children first
        for _ in range(len(order) + 2):
            changed = False
            for i in order:
                rule = w.completions[i]
                trigger = self.condition(cond.conjoin([*rule.children, cond.negate(rule.post)]))
                fires = self.compose(f, trigger)
                if fires == self.bdd.false:
                    continue
                for lit in cond.literals(rule.post):
                    name = f"x{self.index[lit.atom]}"
                    now = f.get(name, self.x[self.index[lit.atom]])
                    new = self.bdd.ite(fires, self.bdd.true if lit.positive else self.bdd.false, now)
                    if new != now:
                        f[name] = new
                        changed = True
            if not changed:
                break
        else:     # monotone settling stabilises within one pass per rule; this would be a bug
            raise Unsupported("settling did not stabilise symbolically")
        self._actions[post] = f
        return f

    def state(self, atoms) -> object:
        """The set holding exactly the state `atoms`."""
        return self.bdd.cube({f"x{i}": a in atoms for i, a in enumerate(self.atoms)})

    def pick(self, u) -> frozenset:
        """One state of the set `u`."""
        values = self.bdd.pick(u, care_vars={f"x{i}" for i in range(len(self.atoms))})
        return frozenset(a for i, a in enumerate(self.atoms) if values[f"x{i}"])

    def member(self, atoms: frozenset, u) -> bool:
        """Whether the state `atoms` is in the set `u`: one path down the diagram, walked here,
        where CUDD's substitution recursed once per level and overflowed the C stack on a
        condition of 100,000 atoms (a crash, issue 32)."""
        true, false = self.bdd.true, self.bdd.false
        while u != true and u != false:
            child = u.high if self.atoms[int(u.var[1:])] in atoms else u.low
            u = ~child if u.negated else child   # dd gives the children of the regular node
        return u == true

    def count(self, u) -> int:
        """How many states `u` holds: CUDD counts in a double (exact to 2^53; past 2^1024 it
        fails, and the count is given as 2^1024, a lower bound)."""
        if u == self.bdd.false:
            return 0
        support = len(self.bdd.support(u))
        try:
            found = self.bdd.count(u)
        except RuntimeError:
            return 2 ** 1024
        return min(2 ** 1024, int(round(found)) * 2 ** (len(self.atoms) - support))


class _Tree:
    """One tree's enabled set per leaf and its leaves' steps as Functions."""

    def __init__(self, m: SymbolicModel, tree: Behaviour) -> None:
        # A weak reference: the model holds its trees, and a cycle through the BDD manager
        # would be freed by the collector in any order, the manager before its nodes
        # (dd.cudd then says "Still N nodes referenced upon shutdown" on stderr).
        self.m = weakref.proxy(m)
        self.tree = tree
        self.plan = plan = Plan.of(tree)
        self.accomplished = m.condition(plan.post[0])
        live: list = [None] * len(plan)
        self.enabled: dict[int, object] = {}
        for i in range(len(plan)):
            up = plan.parent[i]
            here = m.condition(plan.pre[i]) & ~m.condition(plan.post[i])
            live[i] = here if up < 0 else live[up] & here
            if not plan.children[i]:
                self.enabled[i] = live[i]
        self.any_enabled = m.bdd.false
        for u in self.enabled.values():
            self.any_enabled |= u
        self._steps: dict[int, tuple] = {}
        self._relations: dict[int, tuple] = {}

    def step(self, leaf: int) -> tuple[dict, list[tuple[dict, object]]]:
        """The leaf's whole step as a Function, and before each constituent the Function of the
        steps so far with the set where that constituent is already accomplished (skipped)."""
        found = self._steps.get(leaf)
        if found is None:
            m = self.m
            f: dict = {}
            before = []
            for label, post in self.plan.steps[leaf]:
                skipped = m.compose(f, m.condition(post))
                before.append((f, skipped))
                g = {v: m.compose(f, u) for v, u in m.action(post).items()}
                new = {}
                for v in {*f, *g}:
                    now = f.get(v, m.x[int(v[1:])])
                    new[v] = m.bdd.ite(skipped, now, g.get(v, now))
                f = new
            found = self._steps[leaf] = (f, before)
            if len(self._steps) % 256 == 0 or len(before) > 64:     # counting nodes costs: not each time
                m.check(f"building the step of {term_to_text(self.plan.nodes[leaf].label)}")
        return found

    def relation(self, leaf: int) -> tuple[object, list[str]]:
        found = self._relations.get(leaf)
        if found is None:
            m = self.m
            f, _ = self.step(leaf)
            r = self.enabled[leaf]
            for v, u in f.items():
                r &= m.bdd.apply("equiv", m.bdd.var("y" + v[1:]), u)
            found = self._relations[leaf] = (r, list(f))
        return found

    def image(self, leaf: int, states):
        """The states after taking `leaf` from any state of `states` where it is enabled."""
        from dd import cudd

        m = self.m
        r, changed = self.relation(leaf)
        if not changed:
            return states & self.enabled[leaf]
        after = cudd.and_exists(states, r, changed)
        return m.bdd.let({"y" + v[1:]: v for v in changed}, after)

    def preimage(self, leaf: int, states):
        """The states where `leaf` is enabled and its step ends in `states`."""
        f, _ = self.step(leaf)
        return self.enabled[leaf] & self.m.compose(f, states)


def explore(m: SymbolicModel, initial_states: list) -> Found:
    """The compressed tree's reachable set, and the sets each verdict is read from."""
    bdd, c, o = m.bdd, m.c, m.o
    init = bdd.false
    for s in initial_states:
        init |= m.state(s)
    reach = init
    sweeps = 0
    leaves = list(c.enabled)
    while True:                          # chaining: each leaf's image at once joins the set
        sweeps += 1
        old = reach
        for leaf in leaves:
            reach |= c.image(leaf, reach)
        m.check(f"computing the reachable states (sweep {sweeps})")
        if reach == old:
            break
    unsound = bdd.false           # every decision state with some step the original refuses
    for leaf in leaves:
        _, before = c.step(leaf)
        for k, (f, skipped) in enumerate(before):
            action = c.plan.steps[leaf][k]
            bad = c.enabled[leaf] & ~skipped
            if bad != bdd.false:
                bad &= ~m.compose(f, m.allowed.get(action, bdd.false))
            if bad != bdd.false:
                unsound |= bad & reach
    m.check("checking soundness")
    m.sweeps = sweeps
    stuck = reach & ~c.accomplished & ~c.any_enabled & o.any_enabled
    can_o = _backward(o, o.accomplished, bdd.true, "the original's completing states")
    can_c = _backward(c, reach & c.accomplished, reach, "the compressed tree's completing states")
    dead = reach & can_o & ~can_c
    return Found(reach, unsound, stuck, dead, can_o, can_c, m.peak, sweeps)


def _backward(t: _Tree, goal, within, what: str):
    """The states of `within` from which `t` can reach `goal` (a least fixpoint, chained)."""
    m = t.m
    can = goal
    leaves = list(reversed(t.enabled))     # completion flows back from the last steps: one sweep
    while True:                            # mostly carries it up a chain
        old = can
        for leaf in leaves:
            can |= within & t.preimage(leaf, can)
        m.check(f"computing {what}")
        if can == old:
            return can


def path_to(m: SymbolicModel, explicit, initial, target, avoid=None):
    """A shortest run of the compressed tree from an initial state to a state of `target`, found
    by backward layers and replayed with the explicit model: (initial, steps, last state).
    With `avoid`, a run through none of its states if there is one (a completion
    counterexample whose steps are all sound, hence runs of the original too). A step is
    (the leaf's label, its actions)."""
    bdd, c = m.bdd, m.c
    init = bdd.false
    for s in initial:
        init |= m.state(s)
    layers = [target]
    seen = target | (avoid if avoid is not None else bdd.false)
    while (layers[-1] & init) == bdd.false:
        pre = bdd.false
        for leaf in c.enabled:
            pre |= c.preimage(leaf, layers[-1])
        pre &= ~seen
        if pre == bdd.false:
            if avoid is not None:
                return path_to(m, explicit, initial, target)
            raise AssertionError("a reachable state has no path from the initial states")
        seen |= pre
        layers.append(pre)
        m.check("finding a counterexample's run")
    state = m.pick(layers[-1] & init)
    first = state
    steps = []
    for layer in reversed(layers[:-1]):
        for leaf in explicit.enabled(state):
            actions, states = explicit.step(state, leaf)
            after = states[-1] if states else state
            if m.member(after, layer):
                steps.append((explicit.label(leaf), tuple(a for a, _ in actions)))
                state = after
                break
        else:
            raise AssertionError("the symbolic and the explicit model disagree on a step")
    return first, tuple(steps), state


__all__ = ["SymbolicModel", "Unsupported", "OutOfNodes", "Found", "explore", "path_to", "monotone_settling"]
