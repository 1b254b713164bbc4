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

import itertools
import time
from collections import Counter, deque
from dataclasses import dataclass, field

from .. import defaults
from ..task import conditions as cond
from ..task.conditions import Condition
from ..errors import SchemalogError
from .execute import Executive, Plan, blocked_reasons, enabled_indices
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

    def spend(self, units: int) -> None:
        self.work += units
        if self.limit is not None and self.work > self.limit:
            self.spent = True
            raise OutOfWork


# ---------------------------------------------------------------------------
# States as integers: what the explorer keeps

class Codec:
    """States as integers, one bit per atom: an explored state costs a few hundred bytes, not
    a frozenset of its atoms (about 32 KB for 700 true atoms). Atoms get bits as first seen."""

    def __init__(self) -> None:
        self.bit: dict[Term, int] = {}
        self.atoms: list[Term] = []

    def encode(self, state: State) -> Code:
        code = 0
        bit = self.bit
        for atom in state:
            i = bit.get(atom)
            if i is None:
                i = bit[atom] = len(self.atoms)
                self.atoms.append(atom)
            code |= 1 << i
        return code

    def decode(self, code: Code) -> State:
        atoms = self.atoms
        found = []
        while code:
            low = code & -code
            found.append(atoms[low.bit_length() - 1])
            code ^= low
        return frozenset(found)


# ---------------------------------------------------------------------------
# A tree over the shared world

class Model:
    """The enabled leaves of one tree in any state, and the steps they take (memoised)."""

    def __init__(self, tree: Behaviour, world: World, meter: Meter | None = None) -> None:
        self.tree = tree
        self.plan = Plan.of(tree)
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
        self.original = Model(original, world, self.meter)
        self.compressed = Model(compressed, world, self.meter)
        self.codec = Codec()

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
        good_c = _backward(order, succ, self._decoded(self.compressed.accomplished))
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
        States are kept as Codes (parent, successors, order, stuck), expanded one at a time."""
        c, o = self.compressed, self.original
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
            s = decode(k)
            try:
                leaves = [] if c.accomplished(s) else c.enabled(s)
            except OutOfWork:
                exhaustive = False
                break
            order.append(k)
            nexts = succ[k] = []
            if c.accomplished(s):
                continue
            if not leaves:
                stuck.append(k)
                continue
            try:
                for leaf in leaves:
                    actions, states = c.step(s, leaf)
                    if unsound is None:
                        before = s
                        for j, action in enumerate(actions):
                            if not o.allows(before, action):
                                unsound = (s, leaf, j, before)
                                break
                            before = states[j]
                    after = encode(states[-1]) if states else k
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
            actions, _ = self.compressed.step(self.codec.decode(before), leaf)
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
        o = self.original
        encode, decode = self.codec.encode, self.codec.decode
        succ: dict[Code, list[Code]] = {}
        queue = deque(seeds)
        seen: set[Code] = set(seeds)
        budget = len(seen) + self.max_states                  # its own budget beyond the seeds
        order = []
        exhaustive = True
        while queue:
            k = queue.popleft()
            s = decode(k)
            try:
                moves = [o.step(s, leaf)[1] for leaf in o.enabled(s)]
            except OutOfWork:
                exhaustive = False
                break
            order.append(k)
            nexts = succ[k] = []
            for states in moves:
                after = encode(states[-1]) if states else k
                if after in seen:
                    nexts.append(after)
                    continue
                if len(seen) >= budget:
                    exhaustive = False
                    continue
                seen.add(after)
                nexts.append(after)
                queue.append(after)
        return _backward(order, succ, self._decoded(o.accomplished)), len(order), exhaustive

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
                       f"state(s) can complete, in both trees{scope}")

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
        if narrower:
            summary += f"; from {len(narrower)} it offers fewer first actions"
        if blocked:
            summary += f"; it cannot start from {blocked[0]['state']}"
        return Verdict("flexibility", not blocked, summary, None, {"states": rows})

    def _traces(self, initial, good_o) -> Verdict:
        o_counts = count_words(list(dict.fromkeys(initial)), _original_moves(self.original),
                               self.original.accomplished)
        c_counter = _CompressedTraces(self.compressed)
        rows = []
        example = None
        for s in initial:
            n_c = c_counter.count(s) if o_counts is not None else None
            if o_counts is None or n_c is None:
                return Verdict("traces", None, "not counted: too many traces to enumerate "
                                               "(more than 500,000 automaton states)")
            n_o = o_counts.get(s, 0)
            rows.append({"state": state_text(s), "original": _num(n_o), "compressed": _num(n_c)})
            if example is None and n_o != n_c:
                example = _missing_trace(self.original, c_counter, s)
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
        for s in initial:
            traces = []
            for tree in (self.original.tree, self.compressed.tree):
                world = World(self.original.tree)
                world.load(s)
                ex = Executive(tree, world, scene)
                ex.run()
                traces.append((ex.trace, ex.outcome.status.value))
            (t_o, st_o), (t_c, st_c) = traces
            diff = next((k for k, (a, b) in enumerate(zip(t_o, t_c)) if a != b),
                        None if len(t_o) == len(t_c) else min(len(t_o), len(t_c)))
            rows.append({"state": state_text(s), "same": diff is None and st_o == st_c,
                         "first_difference": diff, "original": [term_to_text(a) for a in t_o],
                         "compressed": [term_to_text(a) for a in t_c],
                         "original_status": st_o, "compressed_status": st_c})
        same = sum(1 for r in rows if r["same"])
        where = ("with no scene (every distance neutral)" if scene is NO_SCENE
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


def _original_moves(o: Model):
    def moves(state: State) -> dict:
        return {o.plan.steps[leaf][0]: o.step(state, leaf)[1][-1] for leaf in o.enabled(state)}
    return moves


class _CompressedTraces:
    """The compressed tree's complete traces as words of original actions (determinised)."""

    def __init__(self, c: Model) -> None:
        self.c = c
        self._counts: dict[tuple, int | float] = {}

    def start(self, s: State) -> tuple:
        return (s, frozenset({(s, -1, 0)}))          # (decision state, leaf, actions done)

    def moves(self, node: tuple) -> dict[Action, tuple]:
        """Determinised transitions on each original action."""
        state, items = node
        out: dict[Action, set] = {}
        for (origin, leaf, done) in items:
            if leaf < 0:
                if self.c.accomplished(origin):
                    continue
                for l in self.c.enabled(origin):
                    actions, states = self.c.step(origin, l)
                    if actions:
                        out.setdefault(actions[0], set()).add(self._item(origin, l, 1))
            else:
                actions, states = self.c.step(origin, leaf)
                out.setdefault(actions[done], set()).add(self._item(origin, leaf, done + 1))
        result = {}
        for action, new in out.items():
            nxt_state = self._state_of(next(iter(new)))
            result[action] = (nxt_state, frozenset(new))
        return result

    def _item(self, origin: State, leaf: int, done: int) -> tuple:
        actions, states = self.c.step(origin, leaf)
        if done >= len(actions):
            return (states[-1], -1, 0)                 # back at a decision
        return (origin, leaf, done)

    def _state_of(self, item: tuple) -> State:
        origin, leaf, done = item
        return origin if leaf < 0 else self.c.step(origin, leaf)[1][done - 1]

    def accepting(self, node: tuple) -> bool:
        return any(leaf < 0 and self.c.accomplished(origin) for origin, leaf, _ in node[1])

    def count(self, s: State) -> int | float | None:
        root = self.start(s)
        counts = count_words([root], self.moves, self.accepting)
        return None if counts is None else counts.get(root, 0)


def _missing_trace(o: Model, c: _CompressedTraces, s: State) -> list[Term] | None:
    """A shortest complete original trace from `s` that the compressed tree cannot produce."""
    start = (s, c.start(s))
    parent = {start: None}
    queue = deque([start])
    while queue:
        node = queue.popleft()
        state, cnode = node
        if o.accomplished(state):
            if cnode is None or not c.accepting(cnode):
                return _word(parent, node)
            continue
        moves = c.moves(cnode) if cnode is not None else {}
        for action, after in _original_moves(o)(state).items():
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
# Independent parts: an exact reduction (docs/semantics.md, "Independent parts")

def _atoms_of(node: Behaviour) -> set[Term]:
    """Every atom a condition of `node`'s subtree reads or sets."""
    found: set[Term] = set()
    stack = [node]
    while stack:
        n = stack.pop()
        for c in (n.pre, n.post):
            found.update(lit.atom for lit in cond.literals(c))
        stack.extend(n.children)
    return found


def _written_inside(node: Behaviour) -> set[Term]:
    """The atoms the post-conditions below `node` set (its own post excluded)."""
    found: set[Term] = set()
    stack = list(node.children)
    while stack:
        n = stack.pop()
        found.update(lit.atom for lit in cond.literals(n.post))
        stack.extend(n.children)
    return found


def _read_inside(node: Behaviour) -> set[Term]:
    found: set[Term] = set()
    for child in node.children:
        found |= _atoms_of(child)
    return found


@dataclass
class Part:
    """One independent part: the original behaviours and their compressed counterparts."""

    label: Term
    original: Behaviour
    compressed: Behaviour
    atoms: frozenset


def independent_parts(original: Behaviour, compressed: Behaviour, initial: list[State]) -> list[Part] | None:
    """Split a task into parts that share no atom, recursively, where that is exact; None when
    the task does not split.

    At a behaviour X (the root, then an unmerged behaviour alone in its part), the children are
    grouped by shared atoms. Splitting is exact when X's post-condition is set only by X's
    completion and read by none of its descendants, and X's pre-condition is set by none of them,
    holds, and X's post does not, in every covered initial state: then X stays active until all
    its children are accomplished, each group runs on its own atoms, and a group whose children
    are all accomplished is frozen. Compression merges only siblings that share an atom, so each
    compressed child falls in one group."""
    parts: list[Part] = []
    if not _split(original, compressed, initial, parts, depth=0):
        return None
    return parts if len(parts) > 1 else None


def _split(o: Behaviour, c: Behaviour, initial: list[State], parts: list[Part], depth: int) -> bool:
    # X stands for itself in both trees: the same conditions, active in every initial state
    if cond.canonical(o.pre) != cond.canonical(c.pre) or cond.canonical(o.post) != cond.canonical(c.post):
        return False
    if not all(cond.holds(o.pre, s) for s in initial):
        return False
    post_atoms = {lit.atom for lit in cond.literals(o.post)}
    inside = _read_inside(o)
    if not o.children or post_atoms & inside or {lit.atom for lit in cond.literals(o.pre)} & _written_inside(o):
        return False
    if any(cond.holds(o.post, s) for s in initial):
        return False
    atoms = [_atoms_of(child) for child in o.children]
    group = list(range(len(o.children)))

    def find(i: int) -> int:
        while group[i] != i:
            group[i] = group[group[i]]
            i = group[i]
        return i

    owner: dict[Term, int] = {}
    for i, found in enumerate(atoms):
        for atom in found:
            if atom in owner:
                group[find(i)] = find(owner[atom])
            else:
                owner[atom] = i
    members: dict[int, list[int]] = {}
    for i in range(len(o.children)):
        members.setdefault(find(i), []).append(i)
    mapped: dict[int, list[Behaviour]] = {}
    for child in c.children:
        positions = {origin.position for origin in child.origins if origin.slot == 0}
        if not child.origins or len(positions) != len(child.origins):
            return False
        roots = {find(p) for p in positions if p < len(o.children)}
        if len(roots) != 1:
            return False
        mapped.setdefault(roots.pop(), []).append(child)
    if len(members) == 1 and depth > 0:
        return False
    for root, indices in members.items():
        o_kids = tuple(o.children[i] for i in indices)
        c_kids = tuple(mapped.get(root, ()))
        group_atoms = frozenset().union(*(atoms[i] for i in indices))
        if len(o_kids) == 1 and len(c_kids) == 1 and len(c_kids[0].origins) == 1:
            projected = list(dict.fromkeys(frozenset(s & group_atoms) for s in initial))
            nested: list[Part] = []
            if _split(o_kids[0], c_kids[0], projected, nested, depth + 1):
                parts.extend(nested)
                continue
        post = cond.conjoin([k.post for k in o_kids])
        parts.append(Part(o.label, Behaviour(o.label, post=post, children=o_kids),
                          Behaviour(o.label, post=post, children=c_kids, origins=c.origins[:1]), group_atoms))
    return True


def verify_by_parts(original: Behaviour, compressed: Behaviour, world: World, initial: list[State],
                    scene: Scene | None = None, task: Term | None = None,
                    max_states: int = DEFAULT_MAX_STATES, method: str = "explicit",
                    max_nodes: int = DEFAULT_MAX_NODES) -> Report | None:
    """Verify each independent part on its own and combine exactly (None if the task does not
    split, or when more than one initial state is covered). `method` "symbolic" explores each
    part as sets of states (raising symbolic.Unsupported where that would not be exact)."""
    if len(initial) != 1:
        return None
    parts = independent_parts(original, compressed, initial)
    if parts is None:
        return None
    started = time.perf_counter()
    whole_initial = initial[0]
    facts = []
    limit = ""
    nodes = 0
    for part in parts:
        part_world = World(part.original)
        part_world.reset(whole_initial & part.atoms)
        start = frozenset(part_world.atoms)
        if method == "symbolic":
            facts.append(_symbolic_part(part, part_world, start, max_states, max_nodes))
            nodes = max(nodes, facts[-1]["nodes"])
            continue
        v = Verifier(part.original, part.compressed, part_world, max_states)
        v.meter.limit = v.max_work
        parent, succ, order, unsound, stuck, exhaustive = v._explore_compressed([start])
        good_o, o_states, o_exhaustive = v._can_complete_original(order)
        v.meter.limit = None
        if not (exhaustive and o_exhaustive):
            limit = limit or v.limit_text()
        good_c = _backward(order, succ, v._decoded(v.compressed.accomplished))
        decode, encode = v.codec.decode, v.codec.encode
        quiet = next((decode(q) for q in order if not v.compressed.enabled(decode(q))), None)
        facts.append({
            "part": part, "verifier": v, "parent": parent, "start": start, "states": len(order),
            "o_states": o_states, "exhaustive": exhaustive and o_exhaustive,
            "soundness": v._soundness(unsound, parent, exhaustive, len(order)),
            "quiet": quiet,                                        # a reachable quiescent state
            "stuck": next((decode(q) for q in stuck if v.original.enabled(decode(q))), None),
            "dead": next((decode(q) for q in order if q in good_o and q not in good_c), None),
            "can": next((decode(q) for q in order if q in good_o), None),
            "o_init": encode(start) in good_o, "c_init": encode(start) in good_c,
            "path": lambda state, v=v, parent=parent: v._path(parent, state)[1]})
    whole = Verifier(original, compressed, world, max_states)
    exhaustive = all(f["exhaustive"] for f in facts)
    props: dict[str, Verdict] = {}
    failed = next((f for f in facts if f["soundness"].holds is False), None)
    if failed is not None:
        v = failed["soundness"]
        props["soundness"] = Verdict("soundness", False, v.summary, _lift(v.counterexample, failed["part"], whole_initial))
    else:
        props["soundness"] = Verdict("soundness", True if exhaustive else None,
                                     f"holds in each of {len(parts)} independent parts"
                                     + ("" if exhaustive else " (within the state limit: not a proof)"))
    props["completion"] = _combined_completion(facts, whole_initial, exhaustive, len(parts))
    props["flexibility"] = whole._flexibility(initial)
    props["traces"] = Verdict("traces", None, f"not counted: the task was verified in {len(parts)} "
                                              f"independent parts, whose interleavings are not enumerated")
    props["selection"] = whole._selection(initial, scene)
    return Report(task if task is not None else compressed.label, initial, props,
                  sum(f["states"] for f in facts), sum(f["o_states"] for f in facts),
                  time.perf_counter() - started, exhaustive, parts=len(parts), limit=limit,
                  method=method, nodes=nodes)


def _symbolic_part(part: Part, world: World, start: State, max_states: int, max_nodes: int) -> dict:
    """The facts verify_by_parts combines, for one part explored as sets of states."""
    from . import symbolic

    try:
        m = symbolic.SymbolicModel(part.original, part.compressed, world, start, max_nodes)
        found = symbolic.explore(m, [start])
    except symbolic.OutOfNodes as blowup:
        names = ", ".join(term_to_text(k.label) for k in part.original.children[:4])
        more = ", ..." if len(part.original.children) > 4 else ""
        raise symbolic.OutOfNodes(f"in the independent part of {term_to_text(part.label)} made of {names}{more} "
                                  f"({len(part.atoms):,} atoms), {blowup.message}") from None
    v = Verifier(part.original, part.compressed, world, max_states)
    bdd = m.bdd

    def one(u):
        return None if u == bdd.false else m.pick(u)

    def path(state: State) -> tuple[Step, ...]:
        return _run_to(symbolic, m, v.compressed, [start], m.state(state), found.unsound)[1]

    if found.unsound == bdd.false:
        soundness = Verdict("soundness", True, "every reachable state (as sets): each step of the compressed "
                                               "tree is a run of the original")
    else:
        first, steps, s = _run_to(symbolic, m, v.compressed, [start], found.unsound)
        soundness = _first_refused(v, first, steps, s)
    return {"part": part, "verifier": v, "start": start, "states": m.count(found.reachable), "o_states": 0,
            "exhaustive": True, "soundness": soundness,
            "quiet": one(found.reachable & ~m.c.any_enabled), "stuck": one(found.stuck), "dead": one(found.dead),
            "can": one(found.reachable & found.can_o), "o_init": m.member(start, found.can_o),
            "c_init": m.member(start, found.can_c), "path": path, "nodes": found.peak_nodes}


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


def _combined_completion(facts: list[dict], initial: State, exhaustive: bool, count: int) -> Verdict:
    """Completion of the whole from its parts' facts. Parts are independent, so every
    combination of their reachable states is reachable: the whole is stuck where every part is
    quiescent (nothing enabled); it can complete from a state when every part can."""
    def run_to(chosen: dict[int, State]) -> Counterexample:
        path: list[Step] = []
        state = set(initial)
        for k, f in enumerate(facts):
            target = chosen.get(k, f["start"])
            path.extend(f["path"](target))
            state = (state - f["part"].atoms) | target
        return Counterexample(initial, tuple(path), frozenset(state))

    if not exhaustive:
        return Verdict("completion", None, "not decided: a part reached the state limit (not a proof)")
    stuck = next((k for k, f in enumerate(facts) if f["stuck"] is not None), None)
    if stuck is not None and all(f["quiet"] is not None for f in facts):
        chosen = {k: f["quiet"] for k, f in enumerate(facts)}
        chosen[stuck] = facts[stuck]["stuck"]
        ce = run_to(chosen)
        o = facts[stuck]["verifier"].original
        offered = ", ".join(dict.fromkeys(term_to_text(o.label(i)) for i in o.enabled(chosen[stuck])))
        ce = Counterexample(ce.initial, ce.path, ce.state, reasons=(f"the original could still take: {offered}",))
        return Verdict("completion", False, "the compressed tree gets stuck where the original does not", ce)
    dead = next((k for k, f in enumerate(facts) if f["dead"] is not None), None)
    if dead is not None and all(f["can"] is not None for k, f in enumerate(facts) if k != dead):
        chosen = {k: f["can"] for k, f in enumerate(facts)}
        chosen[dead] = facts[dead]["dead"]
        ce = run_to(chosen)
        ce = Counterexample(ce.initial, ce.path, ce.state, reasons=(
            "from this state the original can still complete the task, the compressed tree cannot "
            "(every continuation loops or gets stuck)",))
        return Verdict("completion", False, "the compressed tree reaches a state it cannot complete from, "
                                            "where the original can", ce)
    o_init = all(f["o_init"] for f in facts)
    if o_init != all(f["c_init"] for f in facts):
        return Verdict("completion", False, "the initial state completes with one tree only",
                       Counterexample(initial, (), initial))
    return Verdict("completion", True, f"holds, from the {count} independent parts combined; the initial "
                                       f"state {'can' if o_init else 'cannot'} complete, in both trees")


def _lift(ce: Counterexample | None, part: Part, whole: State) -> Counterexample | None:
    """A part's counterexample as a run of the whole task: the other parts stay as they were."""
    if ce is None:
        return None
    outside = whole - part.atoms
    return Counterexample(whole, ce.path, outside | ce.state, ce.behaviour, ce.where, ce.done_first,
                          ce.action, ce.reasons)


__all__ = ["Verifier", "Report", "Verdict", "Counterexample", "Step", "Model", "free_atoms", "constraints",
           "all_states", "state_text", "DEFAULT_MAX_STATES", "verify_by_parts", "independent_parts", "Part",
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
                                          f"both trees")
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
