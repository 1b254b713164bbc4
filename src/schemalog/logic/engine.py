"""SLD resolution: depth-first, backtracking, iterative, with a step limit.

    Goals       = (goal: Term | Call | UserCall | Control | Marker, cut_barrier: int, rest: Goals) | None
                                                      (a linked list)
    Call        = (Builtin, args)                     a built-in a compiled clause found (compile.py)
    UserCall    = ((name, arity), args)               another call a compiled clause made (compile.py)
    Control     = Or | IfThenElse | IfThen | Not      a control construct a compiled clause found
    ChoicePoint = (kind, trail_mark, ...)                                               (a stack)

The machine pops a goal, rewrites control constructs into goals and choicepoints,
resolves user predicates against the knowledge base's argument indexes, and
calls builtins. Calling a clause pushes its body's goals, flattened (compile.py). Prolog recursion therefore never becomes Python recursion. A cut
removes the choicepoints above its barrier (the height when its clause was
called); `catch/3` leaves a choicepoint that an exception unwinds to.

The machine reads its knowledge base through `builtins.Database` (kb.py provides it) and
assembles the built-in tables from builtins.py (the core) and library.py (the rest).
ISO errors are raised as `PrologError(term)`; running past the step limit raises
`StepLimitExceeded`, which catch/3 does not intercept. One step budget covers the whole
query: each goal, each answer, the sub-machines of findall/forall, and the work built-ins
charge (`Engine.charge`: a list of N cells costs N steps), so the limit bounds its time.
A MemoryError inside a built-in becomes the catchable error(resource_error(memory), _).
Every 10,000 bindings or so the newest machine forgets the bindings no machine's goals,
choicepoints or query reach (collect.py), so a long deterministic loop runs in constant memory.
"""

from __future__ import annotations

from typing import Callable, Iterator

from .. import defaults
from ..errors import SchemalogError
from .builtins import CORE, CORE_NONDET, Builtin, Database, NondetBuiltin, body_term
from .exceptions import (PrologError, StepLimitExceeded, existence_error, instantiation_error, iso_error,
                         type_error)
from .eclipse import ECLIPSE
from .collect import LIVE_FACTOR, MIN_GROWTH, collect
from .library import EXTRA, EXTRA_NONDET
from .terms import Atom, Struct, Term, Var
from ..memory import CeilingReached, near_ceiling
from .unify import Bindings, rename

DEFAULT_MAX_STEPS = defaults.MAX_STEPS


# Markers: goals that only the machine itself pushes.
class _CutTo:
    """Remove choicepoints down to `height` (the then-branch of if-then-else)."""

    __slots__ = ("height",)

    def __init__(self, height: int) -> None:
        self.height = height


class _FailAfterCut(_CutTo):
    """`\\+ G` succeeded in proving G: cut G's alternatives, then fail."""


class _SoftCut:
    """`C *-> T ; E`: C has succeeded, so E is no longer an alternative (C's own stay)."""

    __slots__ = ("height",)

    def __init__(self, height: int) -> None:
        self.height = height


class _ExitCatch:
    """The goal of catch/3 exited: its catcher no longer applies."""

    __slots__ = ("height",)

    def __init__(self, height: int) -> None:
        self.height = height


# Control constructs a compiled clause body found (compile.py): each part is a branch, the
# tuple of its goal list entries, pushed when the construct is called. Interpreted, the same
# constructs are terms the machine takes apart on every call.
class Or:
    """`A ; B`, A not an if-then(-else)."""

    __slots__ = ("left", "right")

    def __init__(self, left: tuple, right: tuple) -> None:
        self.left = left
        self.right = right


class IfThenElse:
    """`C -> T ; E`."""

    __slots__ = ("cond", "then", "otherwise")

    def __init__(self, cond: tuple, then: tuple, otherwise: tuple) -> None:
        self.cond = cond
        self.then = then
        self.otherwise = otherwise


class SoftIfThenElse(IfThenElse):
    """`C *-> T ; E`."""

    __slots__ = ()


class IfThen:
    """`C -> T` without an else-branch."""

    __slots__ = ("cond", "then")

    def __init__(self, cond: tuple, then: tuple) -> None:
        self.cond = cond
        self.then = then


class Not:
    """`\\+ G`."""

    __slots__ = ("goal",)

    def __init__(self, goal: tuple) -> None:
        self.goal = goal


def _push(branch: tuple, cutb: int, rest):
    """The goal list with a compiled branch's entries in front of `rest`, each cutting to `cutb`."""
    for entry in reversed(branch):
        rest = (entry, cutb, rest)
    return rest


_CONTROL_FIELDS = {Or: ("left", "right"), IfThenElse: ("cond", "then", "otherwise"),
                   SoftIfThenElse: ("cond", "then", "otherwise"), IfThen: ("cond", "then"), Not: ("goal",)}

_POLL = 256   # steps between two looks at `interrupted` (a few hundred microseconds)
_MEMORY_MASK = 2048 - 1   # and at the memory ceiling, about every 2,048 steps (memory.py)

# Choicepoint kinds (_DEAD: an else-branch a soft cut disabled, popped on backtracking)
_CLAUSES, _ALT, _NONDET, _CATCH, _DEAD, _RECATCH = range(6)
# _RECATCH (kind, mark, height, frame): left above a catch frame whose goal exited with
# choicepoints; backtracking over it puts the frame's catcher back, so an error raised on a
# redo of the goal is caught as ISO says (catch/3 is transparent to backtracking).

class Machine:
    """What a running machine holds, for a collection run by it or by a machine inside it."""

    __slots__ = ("query", "goals", "cps")

    def __init__(self, query: Term) -> None:
        self.query = query   # its variables are the answer's: the caller reads them
        self.goals = None    # the goal list, as of the last built-in called or collection
        self.cps: list = []


class Engine:
    """Answers goals against one knowledge base."""

    def __init__(self, kb: Database, max_steps: int = DEFAULT_MAX_STEPS,
                 output: Callable[[str], None] | None = None, *,
                 builtins: dict[tuple[str, int], Builtin] | None = None,
                 nondet: dict[tuple[str, int], NondetBuiltin] | None = None) -> None:
        """`builtins` and `nondet` add predicates written in Python for this engine only
        (schemalog's relations over a workspace, api/workspace.py)."""
        self.kb = kb
        self.max_steps = max_steps
        self.write = output or (lambda text: print(text, end=""))
        self.interrupted = False  # set from another thread (Ctrl-C in the REPL)
        self.deterministic = False  # while an answer is yielded: no alternative is left
        # Steps taken by the current query, sub-machines (findall, forall) and the work
        # built-ins charge (`charge`) included: one budget bounds the query's whole time.
        self.steps = 0
        # trail growth between two collections of unreachable bindings (collect.py)
        self.collect_growth = MIN_GROWTH
        self.collect_factor = LIVE_FACTOR   # and at least this many times what was live after the last
        self.since: dict[str, int] = {}   # statistics/2: runtime and walltime at their last call
        self.builtins = {**BUILTINS, **builtins} if builtins else BUILTINS
        self.nondet = {**NONDET_BUILTINS, **nondet} if nondet else NONDET_BUILTINS
        self._special = _special_goals(self.builtins, self.nondet)   # 3 us: built per engine

    # -- public API -----------------------------------------------------------
    def solve(self, goal: Term, bindings: Bindings | None = None) -> Iterator[Bindings]:
        """Yield once per proof of `goal`; the bindings hold that answer while yielded."""
        b = bindings if bindings is not None else Bindings()
        goal = body_term(goal, b)
        self.steps = 0
        return self._run(goal, b)

    def first(self, goal: Term, bindings: Bindings | None = None) -> Bindings | None:
        """Return the bindings of the first proof of `goal`, or None."""
        for b in self.solve(goal, bindings):
            return b
        return None

    def succeeds(self, goal: Term) -> bool:
        """Whether `goal` has a proof."""
        return self.first(goal) is not None

    def answers(self, goal: Term, limit: int | None = None) -> list[Term]:
        """The instances of `goal`, one per proof, resolved (at most `limit`)."""
        out = []
        for b in self.solve(goal):
            out.append(b.resolve_finite(goal))  # a cyclic answer (X = f(X)) in its finite form
            if limit is not None and len(out) >= limit:
                break
        return out

    def charge(self, work: int) -> None:
        """Count `work` steps against the budget (a built-in about to build or walk that many
        cells); raise StepLimitExceeded, before the work is done, when it would not fit."""
        self.steps += work
        if self.steps > self.max_steps:
            raise self._over()

    def _charge_work(self, b: Bindings) -> None:
        work, b.work = b.work, 0
        self.charge(work)

    def _over(self) -> StepLimitExceeded:
        return StepLimitExceeded(
            f"step limit of {self.max_steps:,} resolution steps exceeded (runaway recursion?)")

    # -- the machine ----------------------------------------------------------
    def _run(self, goal: Term, b: Bindings) -> Iterator[Bindings]:
        state = Machine(goal)
        b.machines.append(state)
        try:
            yield from self._machine(goal, b, state)
        finally:
            machines = b.machines
            for i in range(len(machines) - 1, -1, -1):
                if machines[i] is state:
                    del machines[i]
                    break

    def _machine(self, goal: Term, b: Bindings, state: Machine) -> Iterator[Bindings]:
        cps: list[tuple] = []
        state.cps = cps
        goals = (goal, 0, None)
        base = len(b.trail)   # bindings below were made before this machine: never collected
        collect_at = base + self.collect_growth
        kb = self.kb
        special = self._special
        nondet = self.nondet
        # A UserCall's key is no built-in (compile.py made sure of it): only this engine's
        # own relations, when it has any, can answer it before the knowledge base does.
        relations = self.builtins is not BUILTINS or self.nondet is not NONDET_BUILTINS
        get = b.values.get
        predicates = kb.predicates
        max_steps = self.max_steps
        check = self.steps   # the count at which the limit and Ctrl-C are looked at next
        while True:
            try:
                if goals is None:
                    # no alternative left: an exited catch frame and a disabled else-branch are none
                    self.deterministic = not cps or all(
                        cp[0] == _DEAD or cp[0] == _RECATCH or cp[0] == _CATCH and cp[2] is None
                        for cp in reversed(cps))
                    yield b
                    if b.work:       # the answer's printing (resolve_finite) is the query's work too
                        self._charge_work(b)
                    self.steps += 1  # an answer counts: between(1, inf, X) alone stops at the limit
                    if self.steps > max_steps:
                        raise self._over()
                    goals = self._backtrack(cps, b)
                    if goals is False:
                        return
                    continue
                term, cutb, rest = goals
                # An attribute, not a local: built-ins and sub-machines add to the same count
                # (read once per step). One test per step: Ctrl-C is looked for every _POLL
                # steps, with the limit.
                steps = self.steps + 1
                self.steps = steps
                if steps > check:
                    if steps > max_steps:
                        raise self._over()
                    if self.interrupted:
                        self.interrupted = False
                        raise SchemalogError("interrupted")
                    if steps & _MEMORY_MASK < _POLL and near_ceiling():
                        # stop while there is room to say so (memory.py: at the ceiling itself
                        # CPython can spin in failing allocations instead of raising)
                        raise CeilingReached("near the memory ceiling")
                    if len(b.trail) > collect_at and b.machines[-1] is state:
                        # the newest machine: the others wait in a built-in (findall) or are
                        # suspended; every mark they hold is at most `base`
                        state.goals = goals
                        live = collect(b.machines, cps, b, base, _CONTROL_FIELDS, _RECATCH)
                        # 0: at every look (the tests' stress mode)
                        collect_at = len(b.trail) + (max(self.collect_growth, self.collect_factor * live) if self.collect_growth else 0)
                    check = min(max_steps, steps + _POLL)
                kind = type(term)
                if kind is tuple:
                    key, args = term
                    if type(key) is tuple:   # a UserCall: a user predicate's call (compile.py)
                        name, arity = key
                        entry = special.get(key) if relations else None
                    else:                    # a Call: the built-in a compiled body found
                        entry = key
                else:
                    if kind is Struct:
                        name, args = term.name, term.args
                    elif kind is Atom:
                        name, args = term.name, ()
                    elif kind is Var:  # `G` as a goal means call(G): its cut is local
                        term = b.walk(term)
                        if isinstance(term, Var):
                            raise instantiation_error()
                        term = body_term(term, b)
                        cutb = len(cps)
                        if isinstance(term, Atom):
                            name, args = term.name, ()
                        elif isinstance(term, Struct):
                            name, args = term.name, term.args
                        else:
                            raise type_error("callable", term)
                    elif kind is Or:
                        cps.append((_ALT, len(b.trail), _push(term.right, cutb, rest)))
                        goals = _push(term.left, cutb, rest)
                        continue
                    elif kind is Not:
                        height = len(cps)
                        cps.append((_ALT, len(b.trail), rest))
                        goals = _push(term.goal, height + 1, (_FailAfterCut(height), cutb, None))
                        continue
                    elif kind is IfThenElse or kind is SoftIfThenElse:
                        height = len(cps)
                        cps.append((_ALT, len(b.trail), _push(term.otherwise, cutb, rest)))
                        commit = _CutTo(height) if kind is IfThenElse else _SoftCut(height)
                        goals = _push(term.cond, height + 1, (commit, cutb, _push(term.then, cutb, rest)))
                        continue
                    elif kind is IfThen:
                        height = len(cps)
                        goals = _push(term.cond, height, (_CutTo(height), cutb, _push(term.then, cutb, rest)))
                        continue
                    else:
                        if isinstance(term, _CutTo):
                            del cps[term.height:]
                            if isinstance(term, _FailAfterCut):
                                goals = self._backtrack(cps, b)
                                if goals is False:
                                    return
                                continue
                            goals = rest
                            continue
                        if isinstance(term, _SoftCut):
                            cps[term.height] = (_DEAD, cps[term.height][1])
                            goals = rest
                            continue
                        if isinstance(term, _ExitCatch):
                            cp = cps[term.height] if term.height < len(cps) else None
                            if cp is not None and cp[0] == _CATCH:
                                cps[term.height] = (_CATCH, cp[1], None, cp[3], cp[4], cp[5])
                                if len(cps) > term.height + 1:    # the goal can be redone
                                    cps.append((_RECATCH, len(b.trail), term.height, cp))
                            goals = rest
                            continue
                        raise type_error("callable", term)
                    arity = len(args)
                    key = (name, arity)
                    entry = special.get(key)   # one lookup for the common case, a user predicate
                    if entry is None and name == "call" and arity:   # call/N past call/8
                        entry = _CONTROL_ENTRY

                # User predicates -----------------------------------------------
                if entry is None:
                    pred = predicates.get(key)
                    if pred is None:
                        if getattr(kb, "flags", {}).get("unknown") in _UNKNOWN_FAILS:  # set_prolog_flag(unknown, fail)
                            goals = self._backtrack(cps, b)
                            if goals is False:
                                return
                            continue
                        raise existence_error(name, arity)
                    # Predicate.select, its commonest case inline: a first argument bound to a
                    # compound or an atom, looked up in the index already built.
                    index = pred._index
                    if index:
                        first = args[0]
                        while type(first) is Var:
                            bound = get(first)
                            if bound is None:
                                break
                            first = bound
                        kind = type(first)
                        if kind is Struct:
                            candidates = index.get(("s", first.name, len(first.args)), pred._unindexed)
                        elif kind is Atom:
                            candidates = index.get(("a", first.name), pred._unindexed)
                        else:
                            candidates = pred.select(args, b)
                    else:
                        candidates = pred.select(args, b)
                    # The first clause whose head matches is tried here, and a choicepoint left
                    # only when clauses remain (as _backtrack would, without a round trip).
                    height = len(cps)
                    mark = len(b.trail)
                    count = len(candidates)
                    index = 0
                    while index < count:
                        clause = candidates[index]
                        index += 1
                        activation = clause._activation
                        goals = (activation(args, b, height, rest) if activation is not None
                                 else clause.activate(args, b, height, rest))
                        if goals is not False:
                            if index < count:
                                cps.append((_CLAUSES, mark, args, candidates, index, rest, height))
                            break
                        b.undo(mark)
                    else:
                        goals = self._backtrack(cps, b)
                        if goals is False:
                            return
                    continue

                # Control constructs ------------------------------------------
                if entry is _CONTROL_ENTRY:
                    if arity == 2 and name == ",":
                        goals = (args[0], cutb, (args[1], cutb, rest))
                        continue
                    if arity == 0:
                        if name == "true":
                            goals = rest
                            continue
                        if name in ("fail", "false"):
                            goals = self._backtrack(cps, b)
                            if goals is False:
                                return
                            continue
                        if name == "!":
                            del cps[cutb:]
                            goals = rest
                            continue
                    if arity == 2 and name == ";":
                        left = args[0]  # not walked: `(C ; B)` with C bound to (X -> Y) is call(C) ; B
                        if isinstance(left, Struct) and left.name == "*->" and len(left.args) == 2:
                            height = len(cps)
                            cps.append((_ALT, b.mark(), (args[1], cutb, rest)))
                            goals = (left.args[0], height + 1, (_SoftCut(height), cutb, (left.args[1], cutb, rest)))
                            continue
                        if isinstance(left, Struct) and left.name == "->" and len(left.args) == 2:
                            height = len(cps)
                            cps.append((_ALT, b.mark(), (args[1], cutb, rest)))
                            goals = (left.args[0], height + 1, (_CutTo(height), cutb, (left.args[1], cutb, rest)))
                            continue
                        cps.append((_ALT, b.mark(), (args[1], cutb, rest)))
                        goals = (left, cutb, rest)
                        continue
                    if arity == 2 and name == "*->":  # (C *-> T) without else: (C, T), cut in C local
                        goals = (args[0], len(cps), (args[1], cutb, rest))
                        continue
                    if arity == 2 and name == "->":  # (C -> T) without else: fails when C fails
                        height = len(cps)
                        goals = (args[0], height, (_CutTo(height), cutb, (args[1], cutb, rest)))
                        continue
                    if arity == 1 and name in ("\\+", "not"):
                        height = len(cps)
                        cps.append((_ALT, b.mark(), rest))
                        goals = (args[0], height + 1, (_FailAfterCut(height), cutb, None))
                        continue
                    if name == "call" and arity >= 1:
                        target = b.walk(args[0])
                        if arity > 1:
                            target = _add_args(target, args[1:])
                        goals = (body_term(target, b), len(cps), rest)
                        continue
                    if arity == 3 and name == "catch":
                        height = len(cps)
                        cps.append((_CATCH, b.mark(), args[1], args[2], rest, cutb))
                        # the goal is meta-called, call/1 style, inside the frame: its errors are caught
                        goals = (Struct("call", (args[0],)), height + 1, (_ExitCatch(height), cutb, rest))
                        continue
                    raise existence_error(name, arity)   # unreachable: CONTROL holds only the above
                # Builtins (a Call's too) ---------------------------------------
                if entry is _NONDET_ENTRY:
                    gen_fn = nondet[key]
                    mark = b.mark()
                    gen = gen_fn(self, args, b)
                    cps.append((_NONDET, mark, gen, rest))
                    goals = self._backtrack(cps, b)  # takes the generator's first answer
                    if goals is False:
                        return
                    continue
                mark = len(b.trail)
                state.goals = goals   # roots, if the built-in runs a machine that collects
                ok = entry(self, args, b)
                if b.work:  # the cells the built-in resolved (a copy, an assert, a sort)
                    self._charge_work(b)
                if ok:
                    goals = rest
                else:
                    b.undo(mark)
                    goals = self._backtrack(cps, b)
                    if goals is False:
                        return
            except PrologError as err:
                goals = self._handle_throw(err, cps, b)
            except CeilingReached:
                raise
            except MemoryError:
                # A built-in ran out of memory; what it had built is garbage now, so the
                # query can go on: as in SWI-Prolog, a catchable resource error.
                goals = self._handle_throw(iso_error(Struct("resource_error", (Atom("memory"),))), cps, b)

    def _backtrack(self, cps: list, b: Bindings):
        """Resume the newest choicepoint; return the goals to continue with, or False."""
        while cps:
            cp = cps[-1]
            kind, mark = cp[0], cp[1]
            b.undo(mark)
            if kind == _CLAUSES:
                _, _, args, candidates, index, rest, height = cp
                while index < len(candidates):
                    clause = candidates[index]
                    index += 1
                    activation = clause._activation
                    goals = (activation(args, b, height, rest) if activation is not None
                             else clause.activate(args, b, height, rest))
                    if goals is not False:
                        if index < len(candidates):
                            cps[-1] = (_CLAUSES, mark, args, candidates, index, rest, height)
                        else:
                            cps.pop()
                        return goals
                    b.undo(mark)
                cps.pop()
                continue
            if kind == _ALT:
                cps.pop()
                return cp[2]
            if kind == _NONDET:
                gen, rest = cp[2], cp[3]
                try:
                    next(gen)
                    # each further solution of a built-in is a step: findall(X, between(1,
                    # inf, X), L) runs no goal between two of them, so it is counted, and the
                    # memory ceiling looked at, here
                    steps = self.steps = self.steps + 1
                    if steps > self.max_steps:
                        raise self._over()
                    if steps & _MEMORY_MASK == 0 and near_ceiling():
                        raise CeilingReached("near the memory ceiling")
                    if b.work:
                        self._charge_work(b)
                    return rest
                except StopIteration:
                    cps.pop()
                    b.undo(mark)
                    continue
            if kind == _RECATCH:
                cps[cp[2]] = cp[3]      # the goal is redone: its catcher is active again
            cps.pop()  # a catch frame is transparent to backtracking
        return False

    def _handle_throw(self, err: PrologError, cps: list, b: Bindings):
        ball = b.resolve_finite(err.ball)  # a cyclic ball (X = f(X), throw(X)) stays finite
        while cps:
            cp = cps.pop()
            if cp[0] != _CATCH or cp[2] is None:
                continue
            _, mark, catcher, recovery, rest, cutb = cp
            b.undo(mark)
            before = b.mark()
            if b.unify(catcher, rename(ball)):
                # the recovery goal is called (call/1: its cut is local, its body checked whole)
                return (Struct("call", (recovery,)), len(cps), rest)
            b.undo(before)
        raise err.__class__(ball) if isinstance(err, PrologError) else err

    def is_builtin(self, name: str, arity: int) -> bool:
        """Whether `name/arity` is one of every engine's built-ins (so assert may not define it).
        An engine's own extra predicates (the workspace's relations) do not count: a clause
        asserted for one is kept, as in a file, though the relation answers first."""
        return is_builtin(name, arity)

    def call_goal(self, goal: Term, b: Bindings) -> Iterator[Bindings]:
        """Solve `goal` in a sub-machine sharing the bindings, keeping them after it: what
        setup_call_cleanup/3 runs its setup and goal in (the caller undoes)."""
        return self._run(body_term(goal, b), b)

    def sub_solve(self, goal: Term, b: Bindings) -> Iterator[Bindings]:
        """Solve `goal` in a sub-machine sharing the bindings (findall, forall)."""
        mark = b.mark()
        try:
            for _ in self._run(body_term(goal, b), b):
                yield b
        finally:
            b.undo(mark)


def _add_args(goal: Term, extra: tuple) -> Term:
    if isinstance(goal, Atom):
        return Struct(goal.name, tuple(extra))
    if isinstance(goal, Struct):
        return Struct(goal.name, goal.args + tuple(extra))
    if isinstance(goal, Var):
        raise instantiation_error()
    raise type_error("callable", goal)


# set_prolog_flag(unknown, fail | warning): an unknown procedure fails instead of raising.
_UNKNOWN_FAILS = (Atom("fail"), Atom("warning"))

# Control constructs the machine handles itself (so `is_builtin` knows them).
CONTROL = frozenset({(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1), ("not", 1), ("!", 0),
                     ("true", 0), ("fail", 0), ("false", 0), ("catch", 3)}
                    | {("call", n) for n in range(1, 9)})


# The tables every engine starts from: a nondeterministic version replaces a one-mode one.
NONDET_BUILTINS: dict[tuple[str, int], NondetBuiltin] = {**CORE_NONDET, **EXTRA_NONDET}
BUILTINS: dict[tuple[str, int], Builtin] = {key: fn for key, fn in {**CORE, **EXTRA, **ECLIPSE}.items()
                                            if key not in NONDET_BUILTINS}


# What the machine does with a goal of each name and arity that is not a user predicate:
# a control construct, a nondeterministic built-in, or the deterministic built-in itself.
_CONTROL_ENTRY, _NONDET_ENTRY = object(), object()


def _special_goals(builtins: dict, nondet: dict) -> dict:
    """The goals the machine handles itself, by (name, arity): a control construct, else a
    deterministic built-in, else a nondeterministic one (a key in two tables is the first)."""
    return {**{key: _NONDET_ENTRY for key in nondet}, **builtins, **{key: _CONTROL_ENTRY for key in CONTROL}}



def is_builtin(name: str, arity: int) -> bool:
    """Whether `name/arity` is built in (so it cannot be redefined)."""
    key = (name, arity)
    return key in BUILTINS or key in NONDET_BUILTINS or key in CONTROL
