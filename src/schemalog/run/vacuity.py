"""Whether a proof says anything: which covered initial states let the ORIGINAL task complete
at all. A compressed tree proved sound and complete against a task that can never complete is
proved vacuously; verify and compress --verify say so and exit 1, verify/2 and the REPL's
:verify answer no_proof(task_cannot_complete) (docs/semantics.md, docs/queries.md).

    Vacuity = (states, completes: tuple[bool | None], cause: lint Finding | None)
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import defaults
from ..logic.terms import Atom, Struct, Term, make_list


@dataclass(frozen=True)
class Vacuity:
    """Which covered initial states let the ORIGINAL task complete, and why not when none does.

    completes[i] is True (a run completes), False (none does: every run gets stuck or loops)
    or None (not decided within the state limit), for the report's initial state i."""

    states: tuple
    completes: tuple
    cause: "object | None" = None        # the lint Finding that explains it, when there is one

    @property
    def vacuous(self) -> bool:
        """No covered initial state completes: a proof about such a task says nothing."""
        return bool(self.completes) and all(c is False for c in self.completes)

    @property
    def undecided(self) -> bool:
        """No covered initial state is known to let the task complete, and the state limit
        stopped the search for at least one: whether the proof says anything is not known, so
        it is no proof (a limit must never buy one)."""
        return bool(self.completes) and True not in self.completes and None in self.completes

    @property
    def failing(self) -> list:
        return [s for s, c in zip(self.states, self.completes) if c is False]


def vacuity_of(original, world, states: list, max_states: int, known: bool | None = None) -> Vacuity:
    """Search, from each initial state, for a run of the original that completes the task (any
    choice of enabled behaviour, bounded by --max-states); explain with lint when none does.
    `known`: for one state, the answer a proof already found (Report.original_completes)."""
    from .lint import Facts, lint_tree, task_cannot_complete

    if known is not None and len(states) == 1:
        completes: tuple = (known,)
    else:
        completes = tuple(original_completes(original, world, s, max_states) for s in states)
    cause = None
    if completes and all(c is False for c in completes):
        always = frozenset.intersection(*map(frozenset, states))
        facts = Facts(always, frozenset().union(*states) - always)
        cause = task_cannot_complete(lint_tree(original, facts))
    return Vacuity(tuple(states), completes, cause)


def original_completes(original, world, start, max_states: int) -> bool | None:
    """Whether some run of the original tree from `start` accomplishes the task (depth first:
    a completing task is found in about one run), None when the state limit stops the search."""
    from .execute import Executive, Status
    from .verify import Meter, Model, OutOfWork

    # One winner-take-all run first: it completes a task that can in about one decision per
    # action, where the search below would test every enabled leaf of every state it passes.
    world.reset(start)
    if Executive(original, world).run().status is Status.COMPLETED:
        return True
    model = Model(original, world, Meter(max_states * defaults.WORK_PER_STATE))
    seen, stack = {start}, [start]
    cut = False
    try:
        while stack:
            state = stack.pop()
            if model.accomplished(state):
                return True
            for leaf in reversed(model.enabled(state)):
                after = model.step(state, leaf)[1]
                nxt = after[-1] if after else state
                if nxt in seen:
                    continue
                if len(seen) >= max_states:
                    cut = True
                    continue
                seen.add(nxt)
                stack.append(nxt)
    except OutOfWork:
        return None
    return None if cut else False


def verdict_term(report, vacuity: Vacuity | None = None) -> Term:
    """verify/2's answer: counterexample(Property, Steps) (Steps the compressed run), proved, or
    no_proof(Why) with Why task_cannot_complete (the original completes from no covered state:
    a proof would be vacuous), state_limit or unknown."""
    for name in ("soundness", "completion"):
        verdict = report.properties[name]
        if verdict.holds is False:
            ce = verdict.counterexample
            steps = [s.behaviour for s in ce.path] if ce is not None else []
            if ce is not None and ce.behaviour is not None:
                steps.append(ce.behaviour)
            return Struct("counterexample", (Atom(name), make_list(steps)))
    if vacuity is not None and vacuity.vacuous:
        return Struct("no_proof", (Atom("task_cannot_complete"),))
    if vacuity is not None and vacuity.undecided:
        return Struct("no_proof", (Atom("state_limit"),))
    if report.exhaustive and report.sound and report.complete:
        return Atom("proved")
    return Struct("no_proof", (Atom("state_limit" if not report.exhaustive else "unknown"),))
