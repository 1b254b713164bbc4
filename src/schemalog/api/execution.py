"""A run of a task by the attentional executive against an emulated robot.

    Run      = (executive, task, kind of tree, initial state, notes)
    Decision = one winner-take-all choice: the behaviour, its emphasis, the runner-up, the
               actions it performed or skipped (run/execute.py)

A Run from Task.start() has not started: iterating it takes the decisions one by one (the
command line prints each as it is taken), finish() takes the rest; Task.run() returns one
already finished. Reading a run (its status, trace, decisions, text, repr, a notebook's
picture) never takes a decision: a run half iterated is shown as far as it has gone.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Iterator

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.terms import Term, term_to_text
from .arguments import checked, read_scene_for, state_atoms

if TYPE_CHECKING:
    from .task import Task
    from ..run.execute import Decision, Executive
    from ..task.tree import Behaviour


class Run:
    """One execution: its decisions, the actions the robot performed, and how it ended."""

    def __init__(self, executive: Executive, task: Task, initial: list[Term], notes: list[str]) -> None:
        self.executive = executive
        self.task = task
        self.initial = initial
        self.notes: tuple[str, ...] = tuple(notes)
        # A flag, not the executive's generator: a run, started or not, is pickled whole.
        self._started = False

    def __iter__(self) -> Iterator[Decision]:
        """The decisions still to come, as the executive takes them (a run is taken once:
        iterating again goes on where the last iteration stopped)."""
        self._started = True
        return self

    def __next__(self) -> Decision:
        self._started = True           # next(run) starts it too, without iter() first
        decision = self.executive.step()
        if decision is None:
            raise StopIteration
        return decision

    def finish(self) -> Run:
        """Run to the end (what is left of it)."""
        for _ in self:
            pass
        return self

    @property
    def ended(self) -> bool:
        """Whether the run has ended: no decision is left to take."""
        return self.executive.outcome.status.value != "running"

    @property
    def completed(self) -> bool:
        """Whether the task was completed; False while the run has not ended (finish() ends it)."""
        return self.executive.outcome.completed

    @property
    def status(self) -> str:
        """completed, stuck, livelock or decision limit once the run has ended; before, "not
        started" or "running" (reading it takes no decision: finish() runs the rest)."""
        if not self._started:
            return "not started"
        return self.executive.outcome.status.value

    @property
    def reason(self) -> str:
        if self.ended:
            return self.executive.outcome.reason
        taken = len(self.executive.decisions)
        return (f"{taken} decision{'' if taken == 1 else 's'} taken so far; iterate the run for the next, "
                f"or call finish() for the rest")

    @property
    def trace(self) -> list[str]:
        """The actions the robot performed, in order (so far, while the run goes on)."""
        return [term_to_text(a) for a in self.executive.trace]

    @property
    def decisions(self) -> list[Decision]:
        """The decisions taken (so far, while the run goes on)."""
        return list(self.executive.decisions)

    def header(self) -> list[str]:
        """The lines before the decisions: the tree, the selector, the scene, the initial state."""
        from ..run.scene import NO_SCENE

        ex = self.executive
        scene = "no scene (neutral distances)" if ex.scene == NO_SCENE else f"scene {ex.scene.name}"
        return [f"run {self.task.name}: {self.task.kind} tree of {len(self.task)} behaviours; "
                f"selector {ex.selector_name}; {scene}",
                f"initial state: {', '.join(term_to_text(a) for a in self.initial) or '(nothing true)'}"]

    def text(self) -> str:
        """What `schemalog run` prints (of a run that has not ended: as far as it has gone)."""
        from ..task.tree import walk

        width = min(40, max(len(n.name) for n in walk(self.task.tree)))
        lines = self.header()
        for d in self.executive.decisions:
            lines.extend(decision_lines(d, width))
        lines.extend(self.summary())
        return "\n".join(lines) + "\n"

    def summary(self) -> list[str]:
        """The end of the text: how the run ended, or how far it has gone."""
        if self.ended:
            return summary_lines(self.executive)
        return [f"{self.status}: {self.reason}"]

    def as_json(self) -> dict:
        """What `schemalog run --json` prints (of a run that has not ended: as far as it has gone,
        its status "not started" or "running")."""
        data = run_json(self.executive, self.task.label, self.task.kind, self.initial)
        if not self.ended:
            data.update(status=self.status, reason=self.reason)
        return data

    @checked
    def words(self, fmt: str) -> str:
        """What a run written to a file holds, for `wrote FILE: ...`."""
        ex = self.executive
        return f"the run of {self.task.name}, {len(ex.decisions)} decisions, {ex.outcome.status.value} ({fmt})"

    def __repr__(self) -> str:
        if not self._started:
            return f"<Run {self.task.name}: not started>"
        ex = self.executive
        actions = f"{len(ex.trace)} action{'' if len(ex.trace) == 1 else 's'}"
        if not self.ended:             # showing a run does not run it
            taken = len(ex.decisions)
            return f"<Run {self.task.name}: running, {taken} decision{'' if taken == 1 else 's'} so far, {actions}>"
        return f"<Run {self.task.name}: {self.status}, {actions}>"

    def _repr_html_(self) -> str:
        """How it ended (or how far it has gone), the tree with its decisions numbered (Graphviz)
        and a table of them."""
        import html

        from .notebook import run_html

        if not self._started:              # showing a run does not start it
            return f"<pre>{html.escape(repr(self))}</pre>"
        return run_html(self, self.summary())

    def _repr_svg_(self) -> str | None:
        """The tree that ran, each behaviour numbered by the decisions that took it; None without `dot`."""
        from .notebook import run_svg

        return run_svg(self) if self._started else None


def start_run(task: Task, scene, seed, jitter, state, selector: str, fail: tuple[str, ...], fail_times,
              retries: int, recovery: str, max_decisions) -> Run:
    """The executive for one run of `task`, not yet started (Task.start)."""
    from ..run.execute import Executive, RobotManager
    from ..run.scene import NO_SCENE
    from ..run.world import World, initial_state

    if selector not in defaults.SELECTORS:
        raise UsageError(f"selector {selector!r}: choose {' or '.join(defaults.SELECTORS)}")
    notes: list[str] = []
    found = read_scene_for(task, scene, seed, jitter, task.knowledge._max_bytes)
    world = World(task.original.tree)
    kb = task.knowledge._kb
    if state is not None:
        initial = state_atoms(state, "--state")
    else:
        initial = initial_state(kb)
        if not kb.clauses("initial", 1):
            notes.append(f"note: {', '.join(task.knowledge.files) or 'the knowledge'} declares no initial "
                         f"state (initial/1): every atom starts false; give one with --state")
    for atom in world.unknown(initial):
        notes.append(f"warning: {'--state' if state is not None else 'initial/1'} names "
                     f"{term_to_text(atom)}, which no condition of {task.name} reads or sets")
    world.reset(initial)
    failures = _failures(task, fail, fail_times, notes)
    executive = Executive(task.tree, world, found, robot=RobotManager(found, failures), selector=selector,
                          retries=retries, max_decisions=max_decisions, recovery=recovery)
    if found == NO_SCENE:
        notes.append("note: no --scene: every behaviour gets the neutral lambda, so emphasis follows "
                     "progress alone")
    if selector == "scan":
        # The paper's full traversal visits every behaviour at every decision: a cost that grows
        # with the square of a wide task (10,000 sub-tasks of one schema: over a minute)
        from ..task.tree import walk

        nodes = sum(1 for _ in walk(task.tree))
        leaves = sum(1 for n in walk(task.tree) if not n.children)
        if nodes * leaves > SCAN_NOTE_VISITS:
            notes.append(f"note: the scan selector visits all {nodes:,} behaviours at each decision, and a run "
                         f"here takes about {leaves:,} decisions (one per action): some {nodes * leaves:,} visits, "
                         f"which takes a while (the incremental selector takes the same decisions; "
                         f"--max-decisions bounds the run)")
    return Run(executive, task, initial, notes)


SCAN_NOTE_VISITS = 10**7        # about 10 s of the scan selector: past it a run says what it will cost


def _failures(task: Task, fail: tuple[str, ...], fail_times, notes: list[str]) -> dict:
    """The robot fails these actions' commands (fail_times each; None: every time)."""
    from ..logic.opread import parse_term
    from ..task.tree import walk

    actions = {n.label for n in walk(task.original.tree) if not n.children} | \
        {n.label for n in walk(task.tree) if not n.children}
    failures = {}
    for text in fail:
        try:
            label = parse_term(text, "--fail")
        except SchemalogError as err:
            raise UsageError(f"--fail {text!r} is not a term: {err.message}") from None
        if label not in actions:
            notes.append(f"warning: --fail {text}: no action (leaf behaviour) of the task is labelled "
                         f"{term_to_text(label)}, so no command will fail")
        failures[label] = fail_times
    return failures


def decision_width(tree) -> int:
    """The column a tree's decisions are printed in: its longest behaviour name, at most 40."""
    from ..task.tree import walk

    return min(40, max(len(n.name) for n in walk(tree)))


def decision_lines(d: Decision, width: int) -> list[str]:
    """One decision as text: the winner, its emphasis, the runner-up, merged actions beneath."""
    runner = f"{term_to_text(d.runner_up[0])} {d.runner_up[1]:.4g}" if d.runner_up else "-"
    status = f"  FAILED: the robot did not complete {term_to_text(d.failed)}" if d.failed is not None else ""
    lines = [f"{d.index:4d}  {term_to_text(d.behaviour):<{width}}  e {d.emphasis:<9.4g} "
             f"runner-up {runner:<{width + 8}} {d.enabled:3d} enabled{status}"]
    if d.apart:     # one behaviour used twice (add(water) in coffee and in tea): which is which
        lines.append(f"{'':6}(winner: {d.apart[0]}; runner-up: {d.apart[1]})")
    steps = [*d.skipped, *d.executed, *([d.failed] if d.failed is not None else [])]
    if len(steps) > 1 or (steps and steps[0] != d.behaviour):  # a merged behaviour: its actions
        lines.extend(f"{'':6}- {term_to_text(a)} (skipped: accomplished)" for a in d.skipped)
        lines.extend(f"{'':6}- {term_to_text(a)}" for a in d.executed)
        if d.failed is not None:
            lines.append(f"{'':6}- {term_to_text(d.failed)} (failed)")
    if d.decompressed:
        merged, *parts = (term_to_text(x) for x in d.decompressed)
        then = f"{term_to_text(d.failed)} is retried on its own" if d.inhibited is None else \
            f"{term_to_text(d.failed)} alone is inhibited"
        lines.append(f"{'':6}decompressed {merged} into {', '.join(parts)}: {then}")
    return lines


def _micro(seconds: float) -> str:
    return f"{seconds * 1e6:.0f} us" if seconds < 0.01 else f"{seconds * 1e3:.1f} ms"


def summary_lines(ex: Executive) -> list[str]:
    """The end of a run: status, reasons, decisions and time per decision."""
    from ..task.tree import count_nodes

    o = ex.outcome
    lines = [f"{o.status.value}: {o.reason}"]
    lines.extend(f"  {b}" for b in o.blocked)
    split = [d.decompressed[0] for d in ex.decisions if d.decompressed]
    if split:
        lines.append(f"decompressed {len(split)} merged behaviour{'s' if len(split) > 1 else ''} after failures "
                     f"({', '.join(term_to_text(x) for x in split)}): the tree went from "
                     f"{count_nodes(ex.given_tree)} to {count_nodes(ex.tree)} behaviours")
    times = sorted(d.seconds for d in ex.decisions)
    if times:
        mean = sum(times) / len(times)
        lines.append(f"{len(ex.decisions)} decisions, {len(ex.trace)} actions; time per decision "
                     f"({ex.selector_name}): mean {_micro(mean)}, median {_micro(times[len(times) // 2])}, "
                     f"max {_micro(times[-1])}")
    else:
        lines.append("no decision taken")
    return lines


def run_json(ex: Executive, task: Term, kind: str, initial: list[Term]) -> dict:
    """The run as data (docs/formats.md)."""
    from ..task.tree import count_nodes

    times = [d.seconds for d in ex.decisions]
    return {
        "task": term_to_text(task), "tree": kind, "behaviours": count_nodes(ex.given_tree),
        "final_behaviours": count_nodes(ex.tree), "recovery": ex.recovery,
        "selector": ex.selector_name, "scene": ex.scene.name,
        "initial_state": [term_to_text(a) for a in initial],
        "completed": ex.outcome.completed, "status": ex.outcome.status.value,
        "reason": ex.outcome.reason, "blocked": list(ex.outcome.blocked),
        "trace": [term_to_text(a) for a in ex.trace],
        "decisions": [{
            "index": d.index, "behaviour": term_to_text(d.behaviour), "emphasis": d.emphasis,
            "runner_up": None if d.runner_up is None else {
                "behaviour": term_to_text(d.runner_up[0]), "emphasis": d.runner_up[1],
                "where": d.apart[1] if d.apart else None},
            "where": d.apart[0] if d.apart else None,
            "enabled": d.enabled, "executed": [term_to_text(a) for a in d.executed],
            "skipped": [term_to_text(a) for a in d.skipped],
            "failed": None if d.failed is None else term_to_text(d.failed),
            "decompressed": None if not d.decompressed else {
                "behaviour": term_to_text(d.decompressed[0]),
                "into": [term_to_text(x) for x in d.decompressed[1:]]},
            "inhibited": None if d.inhibited is None else term_to_text(d.inhibited),
            "seconds": d.seconds, "hand": list(d.hand)} for d in ex.decisions],
        "decision_times": times,
        "final_state": sorted(term_to_text(a) for a in ex.world.atoms),
        "setup_seconds": ex.setup_seconds,
    }
