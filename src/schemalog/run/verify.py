"""Verification: a compressed task against its original, by exploring every choice.

    State  = frozenset of true atoms, a settled state of the ORIGINAL task's world
    Model  = a tree over that world: its enabled leaves in a state, and what each one does
    Step   = (behaviour, actions): one decision of a tree, its original actions expanded

The paper checked its compression with 10 executions; here every behaviour enabled in every
reachable state is tried, not only the emphasis winner. Properties (docs/semantics.md):

1. soundness   every step of the compressed tree, action by action, is a step the original
               can take in turn (no perceptual aliasing)
2. completion  no reachable state is a dead end of the compressed tree unless it is one of
               the original; the same initial states can complete
3. flexibility the compressed tree can start wherever the original can
4. traces      how many complete original traces the compressed tree no longer produces
5. selection   whether winner-take-all runs of both trees give the same trace in a scene
"""

from __future__ import annotations

import functools
import itertools
import time
from collections import Counter, deque
from dataclasses import dataclass, field, replace

from .. import defaults
from ..task import conditions as cond
from ..task.conditions import Condition
from ..errors import SchemalogError
from ..memory import CeilingReached, near_ceiling
from .execute import Executive, Plan, blocked_reasons, enabled_indices
from . import parts
from .scene import NO_SCENE, Scene
from ..logic.terms import Atom, Struct, Term, Var, term_to_text
from ..task.tree import Behaviour
from .world import World, state_atoms

State = frozenset
Code = int                                # a state kept by the explorer: one bit per atom (Codec)
Action = tuple[Term, Condition]           # an original action: its label and post-condition

DEFAULT_MAX_STATES = defaults.MAX_STATES
METHODS = ("auto", "symbolic", "explicit")   # auto: symbolic where it is exact, else explicit
DEFAULT_MAX_NODES = 5_000_000                # decision-diagram nodes alive at once (about 32 bytes each)
LONGEST_SYMBOLIC_STEP = 256                  # auto: a longer merged leaf is explored explicitly (its
                                             # symbolic step costs the square of its actions: 1,000 took 19 s)
WORK_PER_STATE = defaults.WORK_PER_STATE
MAX_FREE_ATOMS = 16
CACHE_LIMIT = 20_000    # memoised steps and enabled sets per tree: bounded, states can be large


# ---------------------------------------------------------------------------
# Work: what bounds a verification besides its number of states

class OutOfWork(Exception):
    """The work budget of an exploration is spent."""


class Meter:
    """Counts work (nodes tested for enabling, ancestors checked, atoms copied into states)
    against a budget, so that --max-states bounds the time spent even where one state costs
    much: a 10,000-sibling tree, a merged leaf of 10,000 actions, a 100,000-literal condition."""

    def __init__(self, limit: int | None = None) -> None:
        self.work = 0
        self.limit = limit       # None: counting, never stopping (the diagnostics after exploring)
        self.spent = False       # the budget ran out at least once
        self._look = MEMORY_EVERY

    def spend(self, units: int) -> None:
        self.work += units
        if self.limit is not None and self.work > self.limit:
            self.spent = True
            raise OutOfWork
        if self.work >= self._look:       # near the memory ceiling: stop while there is room to say so
            self._look = self.work + MEMORY_EVERY
            if near_ceiling():
                raise CeilingReached("near the memory ceiling")


MEMORY_EVERY = 1 << 16          # units of work between two looks at the memory in use


# ---------------------------------------------------------------------------
# States as integers: what the explorer keeps

class Codec:
    """States as integers, one bit per atom: an explored state costs a few hundred bytes, not
    a frozenset of its atoms (about 32 KB for 700 true atoms). Atoms get bits as first seen."""

    def __init__(self) -> None:
        self.bit: dict[Term, int] = {}
        self.atoms: list[Term] = []

    def index(self, atom: Term) -> int:
        """The bit of `atom`, given one if it has none yet."""
        i = self.bit.get(atom)
        if i is None:
            i = self.bit[atom] = len(self.atoms)
            self.atoms.append(atom)
        return i

    def encode(self, state: State) -> Code:
        code = 0
        index = self.index
        for atom in state:
            code |= 1 << index(atom)
        return code

    def decode(self, code: Code) -> State:
        atoms = self.atoms
        return frozenset(atoms[i] for i in bits(code))


def bits(x: int):
    """The positions of the 1 bits of `x`, lowest first. Taking the lowest bit off costs a
    pass over the whole integer, so a dense `x` is read byte by byte instead: never the bits
    set times the length (a 10,000-atom state decoded that way took 2.7 ms)."""
    if x.bit_count() <= 32:
        while x:
            low = x & -x
            yield low.bit_length() - 1
            x ^= low
        return
    for i, byte in enumerate(x.to_bytes((x.bit_length() + 7) // 8, "little")):
        while byte:
            low = byte & -byte
            yield 8 * i + low.bit_length() - 1
            byte ^= low


# ---------------------------------------------------------------------------
# Exploring on Codes: one live state moved by differences

class Cursor:
    """One mutable state (a set of atoms) that the explorer moves from Code to Code by their
    difference, and on which the world executes actions in place. Exploring a state then
    costs what changes, not what is true: a chain of N steps has N + 1 states of up to N
    atoms, which decoded whole, copied into each successor and scanned cost N^2."""

    def __init__(self, codec: Codec, world: World, meter: Meter) -> None:
        self.codec, self.world, self.meter = codec, world, meter
        self.atoms: set[Term] = set()
        self.code: Code = 0

    def goto(self, code: Code) -> None:
        diff = code ^ self.code
        if diff:
            atoms, live = self.codec.atoms, self.atoms
            n = 0
            for i in bits(diff):
                a = atoms[i]
                if a in live:
                    live.discard(a)
                else:
                    live.add(a)
                n += 1
            self.meter.spend(n)
            self.code = code

    def perform(self, post: Condition) -> None:
        """Execute a leaf with post-condition `post` here: the world settles on this state."""
        world = self.world
        world._atoms = self.atoms          # the world's own set is this one while it acts
        world._hash = None
        change = world.perform(post)
        code, index = self.code, self.codec.index
        n = 1
        for a in change.added:
            code ^= 1 << index(a)
            n += 1
        for a in change.removed:
            code ^= 1 << index(a)
            n += 1
        self.meter.spend(n)
        self.code = code


LIVE_LIMIT = 1_000_000     # leaf indices kept in a Walker's enabled sets before they are dropped


class Walker:
    """A tree's enabled leaves and steps on Codes, through a Cursor. The enabled set of a
    state reached by a step is derived from the state before: only behaviours whose pre- or
    post-condition reads an atom the step changed can change activity, so only the leaves
    below them are tested again (the incremental selector's index, applied to exploring)."""

    def __init__(self, model: Model, cursor: Cursor) -> None:
        self.model, self.cursor = model, cursor
        plan = model.plan
        n = len(plan)
        size = [1] * n
        for i in range(n - 1, 0, -1):
            size[plan.parent[i]] += size[i]
        self.size = size                    # pre-order: i's subtree is i .. i + size[i] - 1
        readers: dict[Term, list[int]] = {}
        for i in range(n):
            for c in (plan.pre[i], plan.post[i]):
                for lit in cond.literals(c):
                    found = readers.setdefault(lit.atom, [])
                    if not found or found[-1] != i:
                        found.append(i)
        self.readers = readers
        self._enabled: dict[Code, list[int]] = {}
        self._kept = 0
        self._steps: dict[tuple[Code, int], tuple[tuple[Action, ...], tuple[Code, ...]]] = {}
        self._done: dict[Code, bool] = {}

    def accomplished_at(self, k: Code) -> bool:
        found = self._done.get(k)
        if found is None:
            self.cursor.goto(k)
            found = self._done[k] = self.model.accomplished(self.cursor.atoms)
        return found

    def enabled_at(self, k: Code) -> list[int]:
        """The enabled leaves in `k`, in tree order ([] when the task is accomplished)."""
        found = self._enabled.get(k)
        if found is None:
            plan = self.model.plan
            self.cursor.goto(k)
            self.cursor.meter.spend(len(plan))
            found = enabled_indices(plan, self.cursor.atoms)
            self._keep(k, found)
        return found

    def _keep(self, k: Code, leaves: list[int]) -> None:
        if self._kept > LIVE_LIMIT:
            self._enabled.clear()
            self._kept = 0
        self._enabled[k] = leaves
        self._kept += len(leaves) + 1

    def outcome(self, k: Code, leaf: int, check=None) -> tuple[tuple[Action, ...], tuple[Code, ...], int]:
        """The actions leaf `leaf` executes from `k` (accomplished ones skipped), the Code after
        each, and the index of the first action `check(state, action)` refuses in the state
        where it runs (-1: none, or no check). A computed step leaves the cursor after it."""
        key = (k, leaf)
        if check is None:
            found = self._steps.get(key)
            if found is not None:
                return (*found, -1)
        cur = self.cursor
        before = self.enabled_at(k)             # for the state after: derived from this one
        cur.goto(k)
        live = cur.atoms
        actions: list[Action] = []
        codes: list[Code] = []
        refused = -1
        for label, post in self.model.plan.steps[leaf]:
            if cond.holds(post, live):
                continue
            if check is not None and refused < 0 and not check(live, (label, post)):
                refused = len(actions)
            cur.perform(post)
            actions.append((label, post))
            codes.append(cur.code)
        after = cur.code
        if after not in self._enabled:
            self._keep(after, self._update(before, k ^ after))
        if len(self._steps) > CACHE_LIMIT:
            self._steps.clear()
        self._steps[key] = (tuple(actions), tuple(codes))
        return tuple(actions), tuple(codes), refused

    def _update(self, enabled: list[int], diff: Code) -> list[int]:
        """The enabled leaves after a change `diff` (the cursor there), from those before."""
        from bisect import bisect_left

        plan, atoms, meter = self.model.plan, self.cursor.codec.atoms, self.cursor.meter
        affected: set[int] = set()
        for i in bits(diff):
            affected.update(self.readers.get(atoms[i], ()))
        if not affected:
            return enabled
        meter.spend(len(affected))
        out: list[int] = []
        pos, end, size = 0, -1, self.size
        for t in sorted(affected):
            if t < end:                       # below an affected behaviour: collected with it
                continue
            end = t + size[t]
            lo = bisect_left(enabled, t, pos)
            out.extend(enabled[pos:lo])
            pos = bisect_left(enabled, end, lo)
            if self._above_live(t):
                self._collect(t, out)
        out.extend(enabled[pos:])
        return out

    def _above_live(self, t: int) -> bool:
        plan, live, meter = self.model.plan, self.cursor.atoms, self.cursor.meter
        j = plan.parent[t]
        while j >= 0:
            meter.spend(1)
            if not plan.pre_check[j](live) or plan.post_check[j](live):
                return False
            j = plan.parent[j]
        return True

    def _collect(self, t: int, out: list[int]) -> None:
        """The enabled leaves of `t`'s subtree, its ancestors live, in tree order."""
        plan, live, meter = self.model.plan, self.cursor.atoms, self.cursor.meter
        stack = [t]
        while stack:
            i = stack.pop()
            meter.spend(1)
            if plan.pre_check[i](live) and not plan.post_check[i](live):
                kids = plan.children[i]
                if kids:
                    stack.extend(reversed(kids))
                else:
                    out.append(i)


# ---------------------------------------------------------------------------
# A tree over the shared world

class Model:
    """The enabled leaves of one tree in any state, and the steps they take (memoised)."""

    def __init__(self, tree: Behaviour, world: World, meter: Meter | None = None,
                 compiled: dict | None = None) -> None:
        self.tree = tree
        self.plan = Plan.of(tree, compiled)
        self.world = world
        self.meter = meter or Meter()
        self._enabled: dict[State, list[int]] = {}
        self._steps: dict[tuple[State, int], tuple[tuple[Action, ...], tuple[State, ...]]] = {}
        self._leaves_of: dict[Action, list[int]] = {}
        for i in self.plan.leaves:
            self._leaves_of.setdefault(self.plan.steps[i][0], []).append(i)

    def accomplished(self, state: State) -> bool:
        return cond.holds(self.plan.post[0], state)

    def enabled(self, state: State) -> list[int]:
        found = self._enabled.get(state)
        if found is None:
            self.meter.spend(len(self.plan))
            if len(self._enabled) > CACHE_LIMIT:
                self._enabled.clear()
            found = self._enabled[state] = [] if self.accomplished(state) else enabled_indices(self.plan, state)
        return found

    def first_action(self, state: State, leaf: int) -> Term | None:
        """The first action leaf `leaf` would execute from `state` (None: all accomplished),
        without computing the states after each of them."""
        return next((label for label, post in self.plan.steps[leaf] if not cond.holds(post, state)), None)

    def step(self, state: State, leaf: int) -> tuple[tuple[Action, ...], tuple[State, ...]]:
        """The actions leaf `leaf` executes from `state` (accomplished ones skipped), and the
        state after each."""
        key = (state, leaf)
        found = self._steps.get(key)
        if found is None:
            actions: list[Action] = []
            states: list[State] = []
            current = state
            for label, post in self.plan.steps[leaf]:
                if cond.holds(post, current):
                    continue
                self.meter.spend(len(current) + 1)      # successor copies the state
                current = self.world.successor(current, post)
                actions.append((label, post))
                states.append(current)
            if len(self._steps) > CACHE_LIMIT:
                self._steps.clear()
            found = self._steps[key] = (tuple(actions), tuple(states))
        return found

    def allows(self, state: State, action: Action) -> bool:
        """Whether this (original) tree enables a leaf doing `action` in `state`: that leaf and
        every ancestor active, the task not accomplished."""
        if self.accomplished(state):
            return False
        plan = self.plan
        for i in self._leaves_of.get(action, ()):
            j = i
            while j >= 0 and plan.pre_check[j](state) and not plan.post_check[j](state):
                self.meter.spend(1)
                j = plan.parent[j]
            if j < 0:
                return True
        return False

    def label(self, leaf: int) -> Term:
        return self.plan.nodes[leaf].label

    def path_name(self, i: int) -> str:
        names = []
        while i >= 0:
            names.append(self.plan.nodes[i].name)
            i = self.plan.parent[i]
        return " > ".join(reversed(names))

    def why_not(self, state: State, action: Action) -> list[str]:
        """Why this (original) tree would not take `action` in `state`: for each leaf with that
        label, the first behaviour on its way down that is not active."""
        label, post = action
        reasons = []
        for i in self.plan.leaves:
            if self.plan.steps[i][0][0] != label:
                continue
            chain = []
            j = i
            while j >= 0:
                chain.append(j)
                j = self.plan.parent[j]
            for j in reversed(chain):
                node = self.plan.nodes[j]
                if cond.holds(self.plan.post[j], state):
                    what = "it is" if j == i else f"{node.name} is"
                    reasons.append(f"{self.path_name(i)}: {what} accomplished "
                                   f"({cond.to_text(self.plan.post[j])} holds)")
                    break
                if not cond.holds(self.plan.pre[j], state):
                    false = [cond.to_text(lit) for lit in cond.literals(cond.canonical(self.plan.pre[j]))
                             if not cond.holds(lit, state)]
                    whose = "its" if j == i else f"{node.name}'s"
                    reasons.append(f"{self.path_name(i)}: {whose} pre-condition {cond.to_text(self.plan.pre[j])} "
                                   f"is false (false: {', '.join(dict.fromkeys(false))})")
                    break
        return reasons or [f"the original task has no action {term_to_text(label)}"]


# ---------------------------------------------------------------------------
# Results

@dataclass(frozen=True)
class Step:
    """One decision of the compressed tree: the behaviour and its original actions."""

    behaviour: Term
    actions: tuple[Term, ...]


@dataclass(frozen=True)
class Counterexample:
    """A run of the compressed tree that ends in a bad step or a bad state, and why."""

    initial: State
    path: tuple[Step, ...]
    state: State
    behaviour: Term | None = None       # soundness: what the compressed tree does next
    where: str = ""                     # ... its place in the compressed tree
    done_first: tuple[Term, ...] = ()   # ... the actions of that behaviour that the original allows
    action: Term | None = None          # ... and the one it would not take
    reasons: tuple[str, ...] = ()


@dataclass
class Verdict:
    """One property: whether it holds, a one-line summary, and a counterexample if not."""

    name: str
    holds: bool | None
    summary: str
    counterexample: Counterexample | None = None
    details: dict = field(default_factory=dict)


@dataclass
class Report:
    """Everything `verify` found."""

    task: Term
    initial_states: list[State]
    properties: dict[str, Verdict]
    compressed_states: int
    original_states: int
    seconds: float
    exhaustive: bool = True
    sampled: bool = False
    parts: int = 1
    limit: str = ""          # the limit that stopped the exploration early, in words ("" if none)
    method: str = "explicit" # how the states were explored: one by one, or as sets ("symbolic")
    nodes: int = 0           # symbolic: the most decision-diagram nodes alive at once
    note: str = ""           # why the method asked for was not used ("" if it was)
    original_completes: bool | None = None   # by parts, one initial state: whether the original can
                                             # complete from it, as the proof found (None: not known)

    @property
    def sound(self) -> bool:
        return bool(self.properties["soundness"].holds)

    @property
    def violated(self) -> bool:
        """A counterexample was found (to soundness or completion)."""
        return self.properties["soundness"].holds is False or self.properties["completion"].holds is False

    @property
    def complete(self) -> bool:
        return bool(self.properties["completion"].holds)


# ---------------------------------------------------------------------------
# Initial states

def free_atoms(kb, original: Behaviour) -> list[Term]:
    """The atoms `--states all` varies: `free/1` facts, else every atom the task's conditions
    read or set except actions' `done` markers."""
    if kb is not None and kb.clauses("free", 1):
        from ..logic.engine import Engine

        x = Var("X")
        found = []
        for b in Engine(kb, max_steps=100_000).solve(Struct("free", (x,))):
            found.extend(state_atoms(b.resolve(x), "free/1"))
        return list(dict.fromkeys(found))
    atoms: dict[Term, None] = {}
    plan = Plan.of(original)
    for i in range(len(plan)):
        for c in (plan.pre[i], plan.post[i]):
            for lit in cond.literals(c):
                a = lit.atom
                if not (isinstance(a, Struct) and a.name == "." and len(a.args) == 2 and a.args[1] == Atom("done")):
                    atoms.setdefault(a)
    return list(atoms)


def constraints(kb) -> list[Condition]:
    """The integrity constraints every covered initial state satisfies: `constraint/1` answers."""
    if kb is None or not kb.clauses("constraint", 1):
        return []
    from ..logic.engine import Engine

    x = Var("C")
    found = []
    for b in Engine(kb, max_steps=1_000_000).solve(Struct("constraint", (x,))):
        term = b.resolve(x)
        try:
            found.append(cond.from_term(term))
        except cond.NotACondition as err:
            raise SchemalogError(f"constraint({term_to_text(term)}) is not a condition: {err}") from None
    return found


def all_states(world: World, atoms: list[Term], rules: list[Condition]) -> list[State]:
    """Every assignment of `atoms` that satisfies `rules`, settled by the world, distinct."""
    if len(atoms) > MAX_FREE_ATOMS:
        raise SchemalogError(f"--states all would try 2^{len(atoms)} assignments of "
                             f"{', '.join(term_to_text(a) for a in atoms[:6])}, ...: declare the atoms "
                             f"that vary with free/1 (at most {MAX_FREE_ATOMS})")
    seen: dict[State, None] = {}
    for bits in itertools.product((False, True), repeat=len(atoms)):
        chosen = frozenset(a for a, bit in zip(atoms, bits) if bit)
        if all(cond.holds(r, chosen) for r in rules):
            world.reset(chosen)
            seen.setdefault(frozenset(world.atoms))
    return list(seen)


# ---------------------------------------------------------------------------
# Exploration

class Verifier:
    """Explores the compressed tree from the initial states and checks each property."""

    def __init__(self, original: Behaviour, compressed: Behaviour, world: World,
                 max_states: int = DEFAULT_MAX_STATES) -> None:
        self.world = world
        self.max_states = max_states
        self.meter = Meter()
        compiled: dict = {}         # the two trees' conditions, each compiled once for both
        self.original = Model(original, world, self.meter, compiled)
        self.compressed = Model(compressed, world, self.meter, compiled)
        self.codec = Codec()
        self.cursor = Cursor(self.codec, world, self.meter)

    # The walkers are built when first explored: a whole task's Verifier often only answers the
    # diagnostics.
    @functools.cached_property
    def c_walk(self) -> Walker:
        return Walker(self.compressed, self.cursor)

    @functools.cached_property
    def o_walk(self) -> Walker:
        return Walker(self.original, self.cursor)

    @property
    def max_work(self) -> int:
        return self.max_states * WORK_PER_STATE

    def limit_text(self) -> str:
        """Which limit stopped the exploration, in words."""
        if self.meter.spent:
            return (f"{self.max_work:,} units of work ({WORK_PER_STATE:,} per state of --max-states "
                    f"{self.max_states:,}: condition tests and state atoms)")
        return f"{self.max_states:,} states (--max-states)"

    def verify(self, initial: list[State], scene: Scene | None = None, task: Term | None = None) -> Report:
        started = time.perf_counter()
        self.meter.limit = self.meter.work + self.max_work
        parent, succ, order, sound, stuck, exhaustive = self._explore_compressed(initial)
        props: dict[str, Verdict] = {}
        good_o, original_states, o_exhaustive = self._can_complete_original(order)
        self.meter.limit = None
        props["soundness"] = self._soundness(sound, parent, exhaustive, len(order))
        exhaustive = exhaustive and o_exhaustive
        good_c = _backward(order, succ, self.c_walk.accomplished_at)
        props["completion"] = self._completion(initial, parent, order, stuck, good_o, good_c, exhaustive)
        props["flexibility"] = self._flexibility(initial)
        props["traces"] = self._traces(initial, good_o) if exhaustive else Verdict(
            "traces", None, "not counted: a limit of --max-states was reached")
        props["selection"] = self._selection(initial, scene)
        return Report(task if task is not None else self.compressed.tree.label, initial, props, len(order),
                      original_states, time.perf_counter() - started, exhaustive,
                      limit="" if exhaustive else self.limit_text())

    def sample(self, initial: list[State], runs: int, seed: int = 0, scene: Scene | None = None,
               task: Term | None = None, max_length: int = 10_000, progress=None) -> Report:
        """Random runs of the compressed tree, every step checked: finds violations, proves nothing.

        The work budget of --max-states bounds it as it bounds exploring; `progress(done, runs)`
        is called about once a second."""
        import random

        started = time.perf_counter()
        rng = random.Random(seed)
        visited: set[State] = set()
        found: dict = {"unsound": None, "stuck": None, "steps": 0}
        done = 0
        shown = started
        self.meter.limit = self.meter.work + self.max_work
        try:
            for done in range(runs):
                if progress is not None and time.perf_counter() - shown > 1:
                    shown = time.perf_counter()
                    progress(done, runs)
                self._sample_run(rng, initial, max_length, visited, found)
            done = runs
        except OutOfWork:
            pass
        finally:
            self.meter.limit = None
        return self._sampled(initial, runs, done, found["steps"], visited, found["unsound"], found["stuck"],
                             scene, task, started)

    def _sample_run(self, rng, initial, max_length, visited, found: dict) -> None:
        """One random run, every step checked; records the first unsound step and stuck state
        in `found` as they happen (a run the budget interrupts keeps what it found)."""
        c, o = self.compressed, self.original
        first = rng.choice(initial)
        s, path = first, []
        for _ in range(max_length):
            visited.add(s)
            if c.accomplished(s):
                break
            leaves = c.enabled(s)
            if not leaves:
                if o.enabled(s) and found["stuck"] is None:
                    found["stuck"] = (first, tuple(path), s)
                break
            leaf = rng.choice(leaves)
            actions, states = c.step(s, leaf)
            before = s
            for k, action in enumerate(actions):
                if not o.allows(before, action):
                    if found["unsound"] is None:
                        found["unsound"] = (first, tuple(path), s, leaf, k, before)
                    break
                before = states[k]
            found["steps"] += 1
            path.append(Step(c.label(leaf), tuple(a for a, _ in actions)))
            s = states[-1] if states else s

    def _sampled(self, initial, runs, done, steps_taken, visited, unsound, stuck, scene, task, started) -> Report:
        c, o = self.compressed, self.original
        props: dict[str, Verdict] = {}
        stopped = "" if done == runs else f" (stopped after {done:,} of {runs:,} runs at the limit of {self.limit_text()})"
        note = f"{done:,} random runs, {steps_taken:,} steps, {len(visited):,} distinct states{stopped}: not a proof"
        if unsound is None:
            props["soundness"] = Verdict("soundness", None, f"no violation found in {note}")
        else:
            first, path, s, leaf, k, before = unsound
            props["soundness"] = self._unsound(first, path, s, leaf, k, before)
        if stuck is None:
            props["completion"] = Verdict("completion", None, f"no state where only the compressed tree is "
                                                              f"stuck, in {note}")
        else:
            first, path, s = stuck
            offered = ", ".join(dict.fromkeys(term_to_text(o.label(i)) for i in o.enabled(s)))
            self.world.load(s)
            props["completion"] = Verdict("completion", False, "the compressed tree gets stuck where the original "
                                                               "does not", Counterexample(first, path, s, reasons=(
                f"the original could still take: {offered}",
                *blocked_reasons(c.plan, self.world, set(), Counter()))))
        props["flexibility"] = self._flexibility(initial)
        props["traces"] = Verdict("traces", None, "not counted when sampling")
        props["selection"] = self._selection(initial, scene)
        return Report(task if task is not None else c.tree.label, initial, props, len(visited), 0,
                      time.perf_counter() - started, exhaustive=False, sampled=True,
                      limit="" if done == runs else self.limit_text())

    def _explore_compressed(self, initial: list[State]):
        """Breadth first over every enabled behaviour; the first unsound step and stuck state.
        States are kept as Codes (parent, successors, order, stuck); the cursor moves between
        them by their differences (Walker), so a state costs what its steps change."""
        cw, o = self.c_walk, self.original
        encode, decode = self.codec.encode, self.codec.decode
        parent: dict[Code, tuple[Code, int] | None] = {}
        succ: dict[Code, list[Code]] = {}
        order: list[Code] = []
        queue: deque[Code] = deque()
        for s in initial:
            k = encode(s)
            if k not in parent:
                parent[k] = None
                queue.append(k)
        unsound = None
        stuck: list[Code] = []
        exhaustive = True
        while queue:
            k = queue.popleft()
            try:
                done = cw.accomplished_at(k)
                leaves = [] if done else cw.enabled_at(k)
            except OutOfWork:
                exhaustive = False
                break
            order.append(k)
            nexts = succ[k] = []
            if done:
                continue
            if not leaves:
                stuck.append(k)
                continue
            try:
                for leaf in leaves:
                    actions, codes, refused = cw.outcome(k, leaf, o.allows if unsound is None else None)
                    if refused >= 0:
                        unsound = (decode(k), leaf, refused, decode(codes[refused - 1] if refused else k))
                    after = codes[-1] if codes else k
                    if after in parent:
                        nexts.append(after)
                        continue
                    if len(parent) >= self.max_states:
                        exhaustive = False
                        continue
                    nexts.append(after)
                    parent[after] = (k, leaf)
                    queue.append(after)
            except OutOfWork:     # the budget ran out inside this state: what was found stands
                exhaustive = False
                break
        return parent, succ, order, unsound, stuck, exhaustive

    def _decoded(self, test):
        """`test` on a state, asked of its Code."""
        decode = self.codec.decode
        return lambda k: test(decode(k))

    def _path(self, parent, state: State | Code) -> tuple[State, tuple[Step, ...]]:
        """The run from an initial state to `state` (a State or its Code) in `parent`."""
        k = self.codec.encode(state) if isinstance(state, frozenset) else state
        steps = []
        while parent[k] is not None:
            before, leaf = parent[k]
            actions = self.c_walk.outcome(before, leaf)[0]
            steps.append(Step(self.compressed.label(leaf), tuple(a for a, _ in actions)))
            k = before
        return self.codec.decode(k), tuple(reversed(steps))

    def _soundness(self, unsound, parent, exhaustive: bool, explored: int) -> Verdict:
        if unsound is None:
            scope = "every" if exhaustive else f"the first {explored:,} (not all: a limit of --max-states was reached)"
            return Verdict("soundness", True if exhaustive else None,
                           f"{scope} reachable state: each step of the compressed tree is a run of the original")
        s, leaf, k, before = unsound
        initial, path = self._path(parent, s)
        return self._unsound(initial, path, s, leaf, k, before)

    def _unsound(self, initial: State, path: tuple[Step, ...], s: State, leaf: int, k: int,
                 before: State) -> Verdict:
        """The verdict for leaf `leaf` of the compressed tree taken in `s`, whose k-th action the
        original would not take in `before`."""
        c = self.compressed
        actions, _ = c.step(s, leaf)
        action = actions[k]
        ce = Counterexample(initial, path, before, c.label(leaf), c.path_name(leaf),
                            tuple(a for a, _ in actions[:k]), action[0], tuple(self.original.why_not(before, action)))
        return Verdict("soundness", False, f"the compressed tree can take {term_to_text(action[0])} where the "
                                           f"original would not (perceptual aliasing)", ce)

    def _can_complete_original(self, seeds: list[Code]) -> tuple[set[Code], int, bool]:
        """The states, reachable by the original from the compressed tree's states, from which
        the original can complete (as Codes)."""
        ow = self.o_walk
        succ: dict[Code, list[Code]] = {}
        queue = deque(seeds)
        seen: set[Code] = set(seeds)
        budget = len(seen) + self.max_states                  # its own budget beyond the seeds
        order = []
        exhaustive = True
        while queue:
            k = queue.popleft()
            try:
                moves = [ow.outcome(k, leaf)[1] for leaf in ow.enabled_at(k)]
                ow.accomplished_at(k)
            except OutOfWork:
                exhaustive = False
                break
            order.append(k)
            nexts = succ[k] = []
            for codes in moves:
                after = codes[-1] if codes else k
                if after in seen:
                    nexts.append(after)
                    continue
                if len(seen) >= budget:
                    exhaustive = False
                    continue
                seen.add(after)
                nexts.append(after)
                queue.append(after)
        return _backward(order, succ, ow.accomplished_at), len(order), exhaustive

    def _completion(self, initial, parent, order, stuck, good_o, good_c, exhaustive) -> Verdict:
        o, c = self.original, self.compressed
        decode, encode = self.codec.decode, self.codec.encode
        for k in stuck:
            s = decode(k)
            if o.enabled(s):
                first, path = self._path(parent, s)
                world = self.world
                world.load(s)
                blocked = blocked_reasons(c.plan, world, set(), Counter())
                offered = ", ".join(dict.fromkeys(term_to_text(o.label(i)) for i in o.enabled(s)))
                ce = Counterexample(first, path, s, reasons=(
                    f"the original could still take: {offered}", *blocked))
                return Verdict("completion", False, "the compressed tree gets stuck where the original does not", ce)
        if not exhaustive:   # dead ends and completing states need the whole graph
            return Verdict("completion", None, "no state where only the compressed tree is stuck among the "
                                               "explored ones; the rest needs the whole graph (a limit of "
                                               "--max-states reached: not a proof)")
        for k in order:
            if k in good_o and k not in good_c:
                first, path = self._path(parent, k)
                ce = Counterexample(first, path, decode(k), reasons=(
                    "from this state the original can still complete the task, the compressed tree cannot "
                    "(every continuation loops or gets stuck)",))
                return Verdict("completion", False, "the compressed tree reaches a state it cannot complete from, "
                                                    "where the original can", ce)
        both = sum(1 for s in initial if encode(s) in good_o)
        lost = [s for s in initial if (encode(s) in good_o) != (encode(s) in good_c)]
        if lost:
            return Verdict("completion", False, f"{len(lost)} initial state(s) complete with one tree only",
                           Counterexample(lost[0], (), lost[0]))
        scope = "" if exhaustive else " (within the state limit: not a proof)"
        return Verdict("completion", True if exhaustive else None,
                       f"no dead end that the original does not share; {both} of {len(initial)} initial "
                       f"state(s) can complete, in both trees{self._already_done(initial)}{scope}")

    def _already_done(self, initial) -> str:
        """How many of the states that can complete are complete already, in words ("" if none)."""
        done = sum(1 for s in initial if self.original.accomplished(s))
        return (f" ({done} of them done already: the task's post-condition holds there, no action "
                f"needed)") if done else ""

    def _flexibility(self, initial) -> Verdict:
        o, c = self.original, self.compressed
        rows = []
        for s in initial:
            first_o = sorted({term_to_text(o.label(i)) for i in o.enabled(s)})
            first_c = sorted({term_to_text(a) for a in (c.first_action(s, i) for i in c.enabled(s))
                              if a is not None})
            rows.append({"state": state_text(s), "original": first_o, "compressed": first_c,
                         "done": o.accomplished(s)})
        startable = [r for r in rows if r["original"]]
        blocked = [r for r in startable if not r["compressed"]]
        narrower = [r for r in startable if r["compressed"] and set(r["compressed"]) < set(r["original"])]
        summary = (f"the original can start from {len(startable)} of {len(rows)} initial state(s), the "
                   f"compressed tree from {len(startable) - len(blocked)} of those")
        done = sum(1 for r in rows if r["done"] and not r["original"])
        idle = len(rows) - len(startable) - done
        if done or idle:      # why the others cannot start, so the count reads without docs
            why = [f"{done} {'are' if done > 1 else 'is'} done already (nothing to start)"] if done else []
            why += [f"{idle} {'enable' if idle > 1 else 'enables'} no action of the task"] if idle else []
            summary += f"; of the other {len(rows) - len(startable)}, {' and '.join(why)}"
        if narrower:
            summary += f"; from {len(narrower)} it offers fewer first actions"
        if blocked:
            summary += f"; it cannot start from {blocked[0]['state']}"
        return Verdict("flexibility", not blocked, summary, None, {"states": rows})

    def _traces(self, initial, good_o) -> Verdict:
        encode = self.codec.encode
        starts = list(dict.fromkeys(encode(s) for s in initial))
        o_counts = count_words(starts, _original_moves(self.o_walk), self.o_walk.accomplished_at)
        c_counter = _CompressedTraces(self.c_walk)
        rows = []
        example = None
        for s in initial:
            n_c = c_counter.count(encode(s)) if o_counts is not None else None
            if o_counts is None or n_c is None:
                return Verdict("traces", None, "not counted: too many traces to enumerate "
                                               "(more than 500,000 automaton states)")
            n_o = o_counts.get(encode(s), 0)
            rows.append({"state": state_text(s), "original": _num(n_o), "compressed": _num(n_c)})
            if example is None and n_o != n_c:
                example = _missing_trace(self.o_walk, c_counter, encode(s))
                if example is not None:
                    example = (s, example)
        total_o = _total(r["original"] for r in rows)
        total_c = _total(r["compressed"] for r in rows)
        summary = (f"the original has {_count_text(total_o)} complete trace(s), the compressed tree "
                   f"{_count_text(total_c)}")
        details = {"states": rows}
        if example:
            details["lost_example"] = {"state": state_text(example[0]),
                                       "trace": [term_to_text(a) for a in example[1]]}
            summary += "; e.g. this original trace is no longer produced: " + \
                ", ".join(term_to_text(a) for a in example[1])
        return Verdict("traces", total_o == total_c, summary, None, details)

    def _selection(self, initial, scene: Scene | None) -> Verdict:
        scene = scene or NO_SCENE
        rows = []
        was = self.world.atoms          # the runs move the world: it is put back after them
        for s in initial:
            traces = []
            for model in (self.original, self.compressed):
                world = self.world            # the original's world, put in `s` for each run
                world.load(s)
                ex = Executive(model.tree, world, scene, plan=model.plan)
                ex.run()
                traces.append((ex.trace, ex.outcome.status.value))
                del ex              # its decisions and loop journal, before the other tree's run
            (t_o, st_o), (t_c, st_c) = traces
            diff = next((k for k, (a, b) in enumerate(zip(t_o, t_c)) if a != b),
                        None if len(t_o) == len(t_c) else min(len(t_o), len(t_c)))
            rows.append({"state": state_text(s), "same": diff is None and st_o == st_c,
                         "first_difference": diff, "original": [term_to_text(a) for a in t_o],
                         "compressed": [term_to_text(a) for a in t_c],
                         "original_status": st_o, "compressed_status": st_c})
        self.world.load(was)
        same = sum(1 for r in rows if r["same"])
        where = ("with no scene (every distance neutral)" if scene == NO_SCENE
                 else f"in scene {scene.name}")
        summary = f"winner-take-all runs {where} give the same trace from {same} of {len(rows)} state(s)"
        first = next((r for r in rows if not r["same"]), None)
        if first is not None:
            k = first["first_difference"]
            summary += (f"; from {first['state']} they first differ at action {k + 1}" if k is not None
                        else f"; from {first['state']} they end differently")
        return Verdict("selection", same == len(rows), summary, None, {"states": rows})


def _backward(order: list[State], succ: dict[State, list[State]], accomplished) -> set[State]:
    """The states from which an accomplished state can be reached."""
    preds: dict[State, list[State]] = {}
    for s, nexts in succ.items():
        for n in nexts:
            preds.setdefault(n, []).append(s)
    good = {s for s in order if accomplished(s)}
    queue = deque(good)
    while queue:
        s = queue.popleft()
        for p in preds.get(s, ()):
            if p not in good:
                good.add(p)
                queue.append(p)
    return good


def state_text(s: State) -> str:
    """A state as text: its true atoms, sorted."""
    return ", ".join(sorted(term_to_text(a) for a in s)) or "(nothing true)"


INFINITE = float("inf")


def _num(n):
    return "infinite" if n == INFINITE else n


def _count_text(n) -> str:
    return n if isinstance(n, str) else f"{n:,}"


def _total(values) -> int | str:
    total = 0
    for v in values:
        if v == "infinite":
            return "infinitely many"
        total += v
    return total


def count_words(starts, moves, accepting, limit: int = 500_000) -> dict:
    """How many accepted words each start has (INFINITE when a loop can still be accepted):
    the graph is explored, pruned to the nodes that can accept, then counted bottom up."""
    succ: dict = {}
    queue = deque(starts)
    seen = set(starts)
    while queue:
        node = queue.popleft()
        succ[node] = list(moves(node).values())
        for n in succ[node]:
            if n not in seen:
                if len(seen) >= limit:
                    return None
                seen.add(n)
                queue.append(n)
    good = _backward(list(succ), succ, accepting)
    counts: dict = {}
    for root in starts:
        if root in counts:
            continue
        if root not in good:
            counts[root] = 0
            continue
        stack = [(root, iter(succ[root]))]
        on_path = {root}
        loops: set = set()
        while stack:
            node, it = stack[-1]
            for n in it:
                if n not in good or n in counts:
                    continue
                if n in on_path:
                    loops.add(node)
                    continue
                on_path.add(n)
                stack.append((n, iter(succ[n])))
                break
            else:
                stack.pop()
                on_path.discard(node)
                total = int(accepting(node))
                for n in succ[node]:
                    if n in good:
                        total += counts.get(n, INFINITE)
                counts[node] = INFINITE if node in loops else total
    return counts


def _original_moves(o: Walker):
    def moves(k: Code) -> dict:
        plan = o.model.plan
        return {plan.steps[leaf][0]: o.outcome(k, leaf)[1][-1] for leaf in o.enabled_at(k)}
    return moves


class _CompressedTraces:
    """The compressed tree's complete traces as words of original actions (determinised).
    A node is a state (its Code) and the merged behaviours in progress there."""

    def __init__(self, c: Walker) -> None:
        self.c = c
        self._counts: dict[tuple, int | float] = {}

    def start(self, k: Code) -> tuple:
        return (k, frozenset({(k, -1, 0)}))          # (decision state, leaf, actions done)

    def moves(self, node: tuple) -> dict[Action, tuple]:
        """Determinised transitions on each original action."""
        state, items = node
        out: dict[Action, set] = {}
        for (origin, leaf, done) in items:
            if leaf < 0:
                if self.c.accomplished_at(origin):
                    continue
                for l in self.c.enabled_at(origin):
                    actions = self.c.outcome(origin, l)[0]
                    if actions:
                        out.setdefault(actions[0], set()).add(self._item(origin, l, 1))
            else:
                actions = self.c.outcome(origin, leaf)[0]
                out.setdefault(actions[done], set()).add(self._item(origin, leaf, done + 1))
        result = {}
        for action, new in out.items():
            nxt_state = self._state_of(next(iter(new)))
            result[action] = (nxt_state, frozenset(new))
        return result

    def _item(self, origin: Code, leaf: int, done: int) -> tuple:
        actions, codes, _ = self.c.outcome(origin, leaf)
        if done >= len(actions):
            return (codes[-1], -1, 0)                 # back at a decision
        return (origin, leaf, done)

    def _state_of(self, item: tuple) -> Code:
        origin, leaf, done = item
        return origin if leaf < 0 else self.c.outcome(origin, leaf)[1][done - 1]

    def accepting(self, node: tuple) -> bool:
        return any(leaf < 0 and self.c.accomplished_at(origin) for origin, leaf, _ in node[1])

    def count(self, k: Code) -> int | float | None:
        root = self.start(k)
        counts = count_words([root], self.moves, self.accepting)
        return None if counts is None else counts.get(root, 0)


def _missing_trace(o: Walker, c: _CompressedTraces, k: Code) -> list[Term] | None:
    """A shortest complete original trace from `k` that the compressed tree cannot produce."""
    start = (k, c.start(k))
    parent = {start: None}
    queue = deque([start])
    moves_o = _original_moves(o)
    while queue:
        node = queue.popleft()
        state, cnode = node
        if o.accomplished_at(state):
            if cnode is None or not c.accepting(cnode):
                return _word(parent, node)
            continue
        moves = c.moves(cnode) if cnode is not None else {}
        for action, after in moves_o(state).items():
            nxt = (after, moves.get(action))
            if nxt not in parent:
                parent[nxt] = (node, action[0])
                queue.append(nxt)
        if len(parent) > 200_000:
            return None
    return None


def _word(parent, node) -> list[Term]:
    word = []
    while parent[node] is not None:
        node, label = parent[node]
        word.append(label)
    return list(reversed(word))



# ---------------------------------------------------------------------------
# Parts and phases: exact reductions (run/parts.py; docs/semantics.md, "Independent parts",
# "Sequential phases"). Each Part is explored; what it found is combined up the pieces.

@dataclass(slots=True)      # one per part, 50,000 parts at 111,111 behaviours: no __dict__ each
class Facts:
    """What exploring a piece found, in its own states: a state of a piece is its start with
    its own atoms changed, so it reads the same in every piece around it."""

    atoms: frozenset
    start: State
    soundness: Verdict                  # its counterexample a run from `start`
    quiet: State | None                 # reachable, not ended, nothing enabled in the compressed tree
    done: State | None                  # reachable and ended
    stuck: State | None                 # a quiet state where the original enables something
    offered: str                        # ... what the original could take there
    dead: State | None                  # reachable; the original can end from it, the compressed tree cannot
    can: State | None                   # reachable, and the original can end from it
    o_init: bool                        # the original can end from `start`
    c_init: bool                        # the compressed tree can
    path: object                        # state -> the compressed tree's run from `start` to it
    states: int
    o_states: int
    exhaustive: bool
    limit: str = ""
    nodes: int = 0
    parts: int = 1


def _view(state: State, f: Facts) -> State:
    """A state of an enclosing piece as a state of `f`."""
    return (f.start - f.atoms) | (state & f.atoms)


def _put(state: State, f: Facts, inner: State) -> State:
    """`state` with `f`'s atoms as in `inner`, a state of `f`."""
    return (state - f.atoms) | (inner & f.atoms)


def _moved(ce: Counterexample, f: Facts, base: State, start: State, before: tuple) -> Counterexample:
    """A counterexample found in `f` as a run of the enclosing piece: from `start`, the runs
    `before` that bring the other pieces to `base`, then `f`'s run."""
    return replace(ce, initial=start, path=(*before, *ce.path), state=_put(base, f, ce.state))


class _NeedsPaths(Exception):
    """A lean combination (no runs kept) met a counterexample whose run it must build."""


def _facts(piece, explored: "_Explored", lean: bool = False) -> Facts:
    """The piece's facts, combined from its parts'. `lean`: without the runs to its states
    (path None), so that each piece's facts are dropped once combined into its parent's
    (50,000 parts at 111,111 behaviours); raises _NeedsPaths where a run is needed."""
    if isinstance(piece, parts.Group):
        return _group([_facts(p, explored, lean) for p in piece.pieces], piece, lean)
    if isinstance(piece, parts.Chain):
        return _chain([_facts(p, explored, lean) for p in piece.phases], piece, lean)
    found = explored.facts(piece)
    return replace(found, path=None) if lean else found


class _Explored:
    """Explores parts, and remembers the facts of each shape found without a violation: a part
    of the same shape (parts.shape_of: the same trees and start up to a one-to-one renaming of
    atoms and labels) has the same facts, renamed. A generated task of 100,000 behaviours has
    about 40,000 parts and a few dozen shapes."""

    def __init__(self, method: str, max_states: int, max_nodes: int) -> None:
        self.method, self.max_states, self.max_nodes = method, max_states, max_nodes
        self.shapes: dict[parts.Shape, tuple[Facts, list[Term], list[Term]]] = {}
        self.explored = 0

    def facts(self, part) -> Facts:
        shape, atoms, labels = parts.shape_of(part)
        known = self.shapes.get(shape)
        if known is not None:
            facts, atoms_then, labels_then = known
            return _renamed(facts, part, dict(zip(atoms_then, atoms)), dict(zip(labels_then, labels)))
        facts = self.explore(part)
        if facts.exhaustive and facts.soundness.holds and facts.stuck is None and facts.dead is None:
            self.shapes[shape] = (facts, atoms, labels)
        return facts

    def explore(self, part, keep: bool = False) -> Facts:
        """A part's facts; its run to a state is found again when asked for (`keep`: kept),
        so that thousands of explored parts do not keep their models alive."""
        self.explored += 1
        if self.method == "symbolic":
            facts = _symbolic_part(part, self.max_nodes, self.max_states)
        else:
            facts = _explicit_part(part, self.max_states)
        if not keep:
            facts.path = lambda state: self.explore(part, keep=True).path(state)
        return facts


def _renamed(facts: Facts, part, atoms: dict, labels: dict) -> Facts:
    """The facts of a part of the same shape as the one `facts` is about (clean facts: no
    counterexample to rename), through its atoms' and labels' correspondence."""
    back = {new: old for old, new in atoms.items()}

    def state(s: State | None) -> State | None:
        return None if s is None else frozenset(atoms[a] for a in s)

    def path(s: State) -> tuple[Step, ...]:
        return tuple(Step(labels[step.behaviour], tuple(labels[a] for a in step.actions))
                     for step in facts.path(frozenset(back[a] for a in s)))

    return replace(facts, atoms=part.atoms, start=state(facts.start), quiet=state(facts.quiet),
                   done=state(facts.done), can=state(facts.can), path=path)


def _group(facts: list[Facts], piece, lean: bool = False) -> Facts:
    """Independent pieces: every combination of their reachable states is reachable, the
    group has ended when each has, it is quiet where each is quiet or has ended."""
    start = piece.start

    def at(chosen: dict[int, State]) -> State:
        state = start
        for k, f in enumerate(facts):
            state = _put(state, f, chosen.get(k, f.start))
        return state

    def path(state: State) -> tuple[Step, ...]:
        return tuple(step for f in facts for step in f.path(_view(state, f)))

    soundness = next((f.soundness for f in facts if f.soundness.holds is False), None)
    if soundness is not None:
        k = next(k for k, f in enumerate(facts) if f.soundness is soundness)
        ce = _moved(soundness.counterexample, facts[k], start, start, ())
        soundness = Verdict("soundness", False, soundness.summary, ce)
    else:
        exhaustive = all(f.soundness.holds for f in facts)
        soundness = Verdict("soundness", True if exhaustive else None,
                            "holds in every part" + ("" if exhaustive else " explored (a limit was reached: not a proof)"))
    resting = [f.quiet if f.quiet is not None else f.done for f in facts]     # an empty state is a state
    quiet = stuck = dead = None
    offered = ""
    if all(r is not None for r in resting):
        if any(f.quiet is not None for f in facts):
            quiet = at(dict(enumerate(resting)) | {k: f.quiet for k, f in enumerate(facts) if f.quiet is not None})
        k = next((k for k, f in enumerate(facts) if f.stuck is not None), None)
        if k is not None:
            stuck, offered = at(dict(enumerate(resting)) | {k: facts[k].stuck}), facts[k].offered
    done = at({k: f.done for k, f in enumerate(facts)}) if all(f.done is not None for f in facts) else None
    can = at({k: f.can for k, f in enumerate(facts)}) if all(f.can is not None for f in facts) else None
    k = next((k for k, f in enumerate(facts) if f.dead is not None), None)
    if k is not None and all(f.can is not None for j, f in enumerate(facts) if j != k):
        dead = at({j: f.can for j, f in enumerate(facts) if j != k} | {k: facts[k].dead})
    return Facts(piece.atoms, start, soundness, quiet, done, stuck, offered, dead, can,
                 all(f.o_init for f in facts), all(f.c_init for f in facts), None if lean else path,
                 sum(f.states for f in facts), sum(f.o_states for f in facts), all(f.exhaustive for f in facts),
                 next((f.limit for f in facts if f.limit), ""), max(f.nodes for f in facts),
                 sum(f.parts for f in facts))


def _chain(facts: list[Facts], piece, lean: bool = False) -> Facts:
    """Sequential phases: phase i runs from the end of phase i - 1 (it is reachable when every
    earlier phase can end), the others stay as they are; the chain ends with its last phase,
    and it can end from a state of phase i when phase i can and every later phase can from
    its start (what a phase does never depends on how the earlier ones ended)."""
    start = piece.start
    bases: list[State] = [start]          # the state at the start of each reachable phase
    for f in facts:
        if f.done is None:
            break
        bases.append(_put(bases[-1], f, f.done))
    reachable = facts[:len(bases)]

    def run_to(i: int) -> tuple[Step, ...]:
        """The run to the start of phase i: the earlier phases' runs to their ends."""
        return tuple(step for f in facts[:i] for step in f.path(f.done))

    def later_can(i: int) -> bool:
        return all(f.o_init for f in facts[i + 1:])

    def first(field: str, also=lambda i: True) -> State | None:
        for i, f in enumerate(reachable):
            found = getattr(f, field)
            if found is not None and also(i):
                return _put(bases[i], f, found)
        return None

    def path(state: State) -> tuple[Step, ...]:
        steps: tuple = ()
        for f, d in zip(facts, piece.ends):
            steps += f.path(_view(state, f))
            if d not in state:
                break
        return steps

    i = next((i for i, f in enumerate(reachable) if f.soundness.holds is False), None)
    if i is not None:
        if lean:
            raise _NeedsPaths
        found = reachable[i].soundness
        soundness = Verdict("soundness", False, found.summary,
                            _moved(found.counterexample, reachable[i], bases[i], start, run_to(i)))
    else:
        exhaustive = all(f.soundness.holds for f in reachable)
        soundness = Verdict("soundness", True if exhaustive else None,
                            "holds in every phase" + ("" if exhaustive else " explored (a limit was reached: not a proof)"))
    i = next((i for i, f in enumerate(reachable) if f.stuck is not None), None)
    stuck = _put(bases[i], reachable[i], reachable[i].stuck) if i is not None else None
    return Facts(piece.atoms, start, soundness, first("quiet"),
                 bases[-1] if len(bases) == len(facts) + 1 else None,
                 stuck, reachable[i].offered if i is not None else "",
                 first("dead", later_can), first("can", later_can),
                 all(f.o_init for f in facts), all(f.c_init for f in facts), None if lean else path,
                 sum(f.states for f in facts), sum(f.o_states for f in facts), all(f.exhaustive for f in facts),
                 next((f.limit for f in facts if f.limit), ""), max(f.nodes for f in facts),
                 sum(f.parts for f in facts))


def _offered(o: "Model", state: State) -> str:
    return ", ".join(dict.fromkeys(term_to_text(o.label(i)) for i in o.enabled(state)))


def _explicit_part(part, max_states: int) -> Facts:
    world = World(part.original)
    world.reset(part.start)
    start = frozenset(world.atoms)
    v = Verifier(part.original, part.compressed, world, max_states)
    v.meter.limit = v.max_work
    parent, succ, order, unsound, stuck, exhaustive = v._explore_compressed([start])
    good_o, o_states, o_exhaustive = v._can_complete_original(order)
    v.meter.limit = None
    decode, encode = v.codec.decode, v.codec.encode
    good_c = _backward(order, succ, v.c_walk.accomplished_at)
    stuck_state = next((decode(q) for q in stuck if v.original.enabled(decode(q))), None)
    return Facts(
        part.atoms, start, v._soundness(unsound, parent, exhaustive, len(order)),
        next((decode(q) for q in stuck), None),
        next((decode(q) for q in order if v.c_walk.accomplished_at(q)), None),
        stuck_state, _offered(v.original, stuck_state) if stuck_state is not None else "",
        next((decode(q) for q in order if q in good_o and q not in good_c), None),
        next((decode(q) for q in order if q in good_o), None),
        encode(start) in good_o, encode(start) in good_c,
        lambda state, v=v, parent=parent: v._path(parent, state)[1],
        len(order), o_states, exhaustive and o_exhaustive,
        "" if exhaustive and o_exhaustive else v.limit_text())


def _symbolic_part(part, max_nodes: int, max_states: int) -> Facts:
    """A part explored as sets of states (run/symbolic.py)."""
    from . import symbolic

    world = World(part.original)
    world.reset(part.start)
    start = frozenset(world.atoms)
    try:
        m = symbolic.SymbolicModel(part.original, part.compressed, world, start, max_nodes)
        found = symbolic.explore(m, [start])
    except symbolic.OutOfNodes as blowup:
        names = ", ".join(term_to_text(k.label) for k in part.original.children[:4])
        more = ", ..." if len(part.original.children) > 4 else ""
        raise symbolic.OutOfNodes(f"in the part of {term_to_text(part.label)} made of {names}{more} "
                                  f"({len(part.atoms):,} atoms), {blowup.message}") from None
    bdd, c = m.bdd, m.c
    verifier: list[Verifier] = []        # the explicit model, built only for a run or a counterexample

    def explicit() -> Verifier:
        if not verifier:
            verifier.append(Verifier(part.original, part.compressed, world, max_states))
        return verifier[0]

    def one(u):
        return None if u == bdd.false else m.pick(u)

    def path(state: State) -> tuple[Step, ...]:
        return _run_to(symbolic, m, explicit().compressed, [start], m.state(state), found.unsound)[1]

    if found.unsound == bdd.false:
        soundness = Verdict("soundness", True, "every reachable state (as sets): each step of the compressed "
                                               "tree is a run of the original")
    else:
        first, steps, s = _run_to(symbolic, m, explicit().compressed, [start], found.unsound)
        soundness = _first_refused(explicit(), first, steps, s)
    stuck = one(found.stuck)
    return Facts(part.atoms, start, soundness,
                 one(found.reachable & ~c.any_enabled & ~c.accomplished), one(found.reachable & c.accomplished),
                 stuck, _offered(explicit().original, stuck) if stuck is not None else "",
                 one(found.dead), one(found.reachable & found.can_o),
                 m.member(start, found.can_o), m.member(start, found.can_c), path,
                 m.count(found.reachable), 0, True, nodes=found.peak_nodes)


def verify_by_parts(original: Behaviour, compressed: Behaviour, world: World, initial: list[State],
                    scene: Scene | None = None, task: Term | None = None,
                    max_states: int = DEFAULT_MAX_STATES, method: str = "explicit",
                    max_nodes: int = DEFAULT_MAX_NODES, phases: bool = True) -> Report | None:
    """Verify each part on its own and combine exactly (None if the task does not split, or
    when more than one initial state is covered). `method` "symbolic" explores each part as
    sets of states (raising symbolic.Unsupported where that would not be exact)."""
    if len(initial) != 1:
        return None
    piece = parts.decompose(original, compressed, initial[0], phases)
    if piece is None:
        return None
    started = time.perf_counter()
    whole_initial = initial[0]
    try:        # first without the runs to the parts' states: only a counterexample needs them
        top = _facts(piece, _Explored(method, max_states, max_nodes), lean=True)
    except _NeedsPaths:
        top = None
    if top is None or top.stuck is not None or top.dead is not None:
        top = _facts(piece, _Explored(method, max_states, max_nodes))     # again, with the runs
    del piece               # the split and its parts' facts, before the whole task's models are built
    whole = Verifier(original, compressed, world, max_states)
    props: dict[str, Verdict] = {}
    count = top.parts
    if top.soundness.holds is False:
        props["soundness"] = _refused_in_whole(whole, whole_initial, top.soundness.counterexample)
    else:
        props["soundness"] = Verdict("soundness", top.soundness.holds,
                                     f"holds in each of {count} parts" + ("" if top.exhaustive else
                                                                          " (within the state limit: not a proof)"))
    props["completion"] = _completion_of(top, whole, whole_initial, count)
    props["flexibility"] = whole._flexibility(initial)
    props["traces"] = Verdict("traces", None, f"not counted: the task was verified in {count} parts, whose "
                                              f"interleavings are not enumerated")
    props["selection"] = whole._selection(initial, scene)
    return Report(task if task is not None else compressed.label, initial, props, top.states, top.o_states,
                  time.perf_counter() - started, top.exhaustive, parts=count, limit=top.limit,
                  method=method, nodes=top.nodes, original_completes=top.o_init if top.exhaustive else None)


def _replay(v: "Verifier", initial: State, path: tuple[Step, ...]) -> State:
    """Where a run of the compressed tree found in the parts leads in the whole task's model
    (whose world also completes the ancestors the parts leave out)."""
    c = v.compressed
    state = initial
    for step in path:
        for leaf in c.enabled(state):
            if c.label(leaf) == step.behaviour:
                actions, states = c.step(state, leaf)
                if tuple(a for a, _ in actions) == step.actions:
                    state = states[-1] if states else state
                    break
        else:
            raise AssertionError(f"the parts' run takes {term_to_text(step.behaviour)}, which the whole "
                                 f"task does not enable there")
    return state


def _refused_in_whole(v: "Verifier", initial: State, ce: Counterexample) -> Verdict:
    """A part's soundness counterexample, replayed and explained in the whole task."""
    s = _replay(v, initial, ce.path)
    c, o = v.compressed, v.original
    for leaf in c.enabled(s):
        if c.label(leaf) != ce.behaviour:
            continue
        actions, states = c.step(s, leaf)
        before = s
        for j, action in enumerate(actions):
            if not o.allows(before, action):
                return v._unsound(initial, ce.path, s, leaf, j, before)
            before = states[j]
    raise AssertionError("the whole task allows the step a part refuses")


def _completion_of(top: Facts, whole: "Verifier", initial: State, count: int) -> Verdict:
    """Completion of the whole from the top piece's facts."""
    if not top.exhaustive:
        return Verdict("completion", None, "not decided: a part reached the state limit (not a proof)")
    if top.stuck is not None:
        path = top.path(top.stuck)
        state = _replay(whole, initial, path)
        world = whole.world
        world.load(state)
        blocked = blocked_reasons(whole.compressed.plan, world, set(), Counter())
        ce = Counterexample(initial, path, state,
                            reasons=(f"the original could still take: {_offered(whole.original, state)}", *blocked))
        return Verdict("completion", False, "the compressed tree gets stuck where the original does not", ce)
    if top.dead is not None:
        path = top.path(top.dead)
        ce = Counterexample(initial, path, _replay(whole, initial, path), reasons=(
            "from this state the original can still complete the task, the compressed tree cannot "
            "(every continuation loops or gets stuck)",))
        return Verdict("completion", False, "the compressed tree reaches a state it cannot complete from, "
                                            "where the original can", ce)
    if top.o_init != top.c_init:
        return Verdict("completion", False, "the initial state completes with one tree only",
                       Counterexample(initial, (), initial))
    return Verdict("completion", True, f"holds, from the {count} parts combined; the initial state "
                                       f"{'can' if top.o_init else 'cannot'} complete, in both trees")


def _run_to(symbolic, *args):
    """symbolic.path_to, its steps as Steps."""
    first, steps, last = symbolic.path_to(*args)
    return first, tuple(Step(label, actions) for label, actions in steps), last


def _first_refused(v: "Verifier", first: State, path: tuple[Step, ...], s: State) -> Verdict:
    """The soundness verdict for the first leaf enabled in `s` whose step the original refuses,
    at the first action it refuses."""
    c, o = v.compressed, v.original
    for leaf in c.enabled(s):
        actions, states = c.step(s, leaf)
        before = s
        for j, action in enumerate(actions):
            if not o.allows(before, action):
                return v._unsound(first, path, s, leaf, j, before)
            before = states[j]
    raise AssertionError("the symbolic and the explicit model disagree on soundness")


__all__ = ["Verifier", "Report", "Verdict", "Counterexample", "Step", "Model", "free_atoms", "constraints",
           "all_states", "state_text", "DEFAULT_MAX_STATES", "verify_by_parts",
           "verify_symbolic", "METHODS", "DEFAULT_MAX_NODES"]


# ---------------------------------------------------------------------------
# Proof by sets of states (run/symbolic.py; docs/semantics.md, "Proof by sets of states")


def verify_symbolic(original: Behaviour, compressed: Behaviour, world: World, initial: list[State],
                    scene: Scene | None = None, task: Term | None = None,
                    max_nodes: int = DEFAULT_MAX_NODES, max_states: int = DEFAULT_MAX_STATES) -> Report:
    """Soundness and completion from every covered initial state at once, with sets of states
    as decision diagrams; counterexamples replayed with the explicit model. Raises
    symbolic.Unsupported where the encoding would not be exact, symbolic.OutOfNodes at the
    node limit."""
    from . import symbolic

    started = time.perf_counter()
    extra = {a for s in initial for a in s}
    m = symbolic.SymbolicModel(original, compressed, world, extra, max_nodes)
    found = symbolic.explore(m, initial)
    v = Verifier(original, compressed, world, max_states)
    c, o = v.compressed, v.original
    bdd = m.bdd
    reachable = m.count(found.reachable)
    props: dict[str, Verdict] = {}
    if found.unsound == bdd.false:
        props["soundness"] = Verdict("soundness", True, f"every reachable state ({reachable:,}, as sets): each "
                                                        f"step of the compressed tree is a run of the original")
    else:   # a shortest run to a bad state: every step before it is sound
        first, path, s = _run_to(symbolic, m, c, initial, found.unsound)
        props["soundness"] = _first_refused(v, first, path, s)
    if found.stuck != bdd.false:
        first, path, s = _run_to(symbolic, m, c, initial, found.stuck, found.unsound)
        world.load(s)
        blocked = blocked_reasons(c.plan, world, set(), Counter())
        offered = ", ".join(dict.fromkeys(term_to_text(o.label(i)) for i in o.enabled(s)))
        props["completion"] = Verdict("completion", False, "the compressed tree gets stuck where the original does "
                                      "not", Counterexample(first, path, s, reasons=(
                                          f"the original could still take: {offered}", *blocked)))
    elif found.dead != bdd.false:
        first, path, s = _run_to(symbolic, m, c, initial, found.dead, found.unsound)
        props["completion"] = Verdict("completion", False, "the compressed tree reaches a state it cannot complete "
                                      "from, where the original can", Counterexample(first, path, s, reasons=(
                                          "from this state the original can still complete the task, the compressed "
                                          "tree cannot (every continuation loops or gets stuck)",)))
    else:
        can_o = [m.member(s, found.can_o) for s in initial]
        lost = [s for s, yes in zip(initial, can_o) if yes != m.member(s, found.can_c)]
        if lost:
            props["completion"] = Verdict("completion", False, f"{len(lost)} initial state(s) complete with one "
                                          f"tree only", Counterexample(lost[0], (), lost[0]))
        else:
            props["completion"] = Verdict("completion", True, f"no dead end that the original does not share; "
                                          f"{sum(can_o)} of {len(initial)} initial state(s) can complete, in "
                                          f"both trees{v._already_done(initial)}")
    props["flexibility"] = v._flexibility(initial)
    props["traces"] = Verdict("traces", None, "not counted: the states were explored as sets, whose traces "
                                              "are not enumerated (--method explicit counts them)")
    props["selection"] = v._selection(initial, scene)
    return Report(task if task is not None else compressed.label, initial, props, reachable, 0,
                  time.perf_counter() - started, True, method="symbolic", nodes=found.peak_nodes)


def _leaves_of(tree: Behaviour):
    stack = [tree]
    while stack:
        n = stack.pop()
        if not n.children:
            yield n
        stack.extend(n.children)


def prove(original: Behaviour, compressed: Behaviour, world: World, initial: list[State],
          scene: Scene | None = None, task: Term | None = None, method: str = "auto",
          max_states: int = DEFAULT_MAX_STATES, max_nodes: int = DEFAULT_MAX_NODES, split: bool = True) -> Report:
    """Verify as `schemalog verify --method METHOD` does: symbolic by independent parts, else
    symbolic whole, where the encoding is exact; explicit (by parts where it splits) for
    `explicit`, or under `auto` where it is not (a merged behaviour of more than
    LONGEST_SYMBOLIC_STEP actions, a blow-up past `max_nodes`), the report saying why. Under
    `symbolic`, a blow-up gives a report that proves nothing."""
    from . import symbolic

    note = ""
    longest = max((len(n.origins) for n in _leaves_of(compressed)), default=1)
    if method == "auto" and longest > LONGEST_SYMBOLIC_STEP:
        note = (f"explored one state at a time: a merged behaviour of {longest:,} actions (a symbolic step "
                f"grows with the square of its actions; --method symbolic forces it)")
    elif method != "explicit":
        try:
            report = None
            with symbolic.memory_guard():
                if split:
                    try:
                        report = verify_by_parts(original, compressed, world, initial, scene, task, max_states,
                                                 "symbolic", max_nodes)
                    except symbolic.Unsupported:     # a part's root (its children's posts) may not settle
                        report = None               # monotonically while the whole does
                return report or verify_symbolic(original, compressed, world, initial, scene, task, max_nodes,
                                                 max_states)
        except symbolic.Unsupported as why:
            if method == "symbolic":
                from ..errors import UsageError      # the request, not the input, is at fault: exit 2
                raise UsageError(f"--method symbolic cannot verify this task exactly: {why}; use "
                                 f"--method explicit or auto") from None
            note = f"explored one state at a time: {why}"
        except RuntimeError as err:          # CUDD refused memory (--max-memory): out of memory
            if "CUDD" in str(err):
                raise MemoryError(str(err)) from None
            raise
        except symbolic.OutOfNodes as blowup:
            if method == "auto":      # the explorer may still prove it: say so, and try it
                note = f"explored one state at a time: {blowup.message}"
            else:
                unknown = {name: Verdict(name, None, "not decided: " + blowup.message)
                           for name in ("soundness", "completion", "flexibility", "traces", "selection")}
                return Report(task if task is not None else compressed.label, initial, unknown, 0, 0, 0.0,
                              exhaustive=False, method="symbolic",
                              limit=f"{max_nodes:,} decision-diagram nodes (--max-bdd-nodes)")
    report = verify_by_parts(original, compressed, world, initial, scene, task, max_states) if split else None
    report = report or Verifier(original, compressed, world, max_states).verify(initial, scene, task)
    report.note = note
    return report


__all__ += ["prove"]
