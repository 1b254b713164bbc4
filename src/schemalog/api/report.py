"""Proving a compressed task against its original, and the report a person or a program reads.

    Report         = (the verifier's report, vacuity, what was compressed how, sizes, notes)
    Counterexample = (property, initial state, steps: the compressed tree's behaviours, state)

verify() is `schemalog verify`: report.text() is what that command prints, report.as_json()
what `--json` prints, report.exit_status its exit status. A report never calls a proof what
covered nothing: `proved` needs every state explored, both properties, and a task that can
complete (not `vacuous`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Iterable

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.terms import Term, term_to_text
from .limits import DEFAULT, within
from .arguments import Count, Path, Seconds, Size, checked, read_scene_for, state_atoms

if TYPE_CHECKING:
    from .task import Task
    from ..run.vacuity import Vacuity
    from ..run.world import World

INCONCLUSIVE = 3    # no counterexample, but no proof either (state limit, sampling)


@dataclass(frozen=True)
class Counterexample:
    """A run of the compressed tree that breaks a property, in behaviours' names."""

    property: str                     # "soundness" or "completion"
    initial: tuple[str, ...]          # the initial state's true atoms
    steps: tuple[str, ...]            # the compressed tree's behaviours, in the order taken
    actions: tuple[tuple[str, ...], ...]   # the actions each step performed
    state: tuple[str, ...]            # the state where the property fails
    lines: tuple[str, ...]            # as `schemalog verify` prints it
    behaviour: str | None = None      # soundness: the compressed tree's next behaviour, which the
    action: str | None = None         # ... original does not allow: its action the original would not take

    def text(self) -> str:
        return "\n".join(self.lines)

    def __str__(self) -> str:
        return self.text()


class Report:
    """The verdict of one proof: soundness, completion, the diagnostics, and whether it says anything."""

    def __init__(self, raw, vacuity: Vacuity | None, how: str, before: int, after: int,
                 states_option: str = "default", notes: Iterable[str] = (),
                 tasks: tuple[Task, Task] | None = None) -> None:
        self.raw = raw                  # run.verify.Report: every figure of the exploration
        self.vacuity = vacuity
        self.how = how
        self.nodes_before = before
        self.nodes_after = after
        self.states_option = states_option
        self.notes: tuple[str, ...] = tuple(notes)
        self.tasks = tasks              # (original, compressed) as verified, for the picture

    @property
    def task(self) -> str:
        return term_to_text(self.raw.task)

    @property
    def sound(self) -> bool:
        """No perceptual aliasing: every step the compressed tree takes, the original allows."""
        return self.raw.properties["soundness"].holds is True

    @property
    def complete(self) -> bool:
        """Every run of the compressed tree can still accomplish the task."""
        return self.raw.properties["completion"].holds is True

    @property
    def exhaustive(self) -> bool:
        """Every reachable state was explored (no limit stopped it, no sampling)."""
        return self.raw.exhaustive and not self.raw.sampled

    @property
    def vacuous(self) -> bool:
        """The original task cannot complete from any covered state: a proof would say nothing."""
        return self.vacuity is not None and self.vacuity.vacuous

    @property
    def proved(self) -> bool:
        return self.exit_status == 0

    @property
    def verdict(self) -> str:
        """proved, refuted (a counterexample), vacuous, or inconclusive (a limit, sampling)."""
        if self.raw.violated:
            return "refuted"
        if self.vacuous:
            return "vacuous"
        return "proved" if self.exit_status == 0 else "inconclusive"

    @property
    def exit_status(self) -> int:
        return exit_status(self.raw, self.vacuity)

    @property
    def counterexample(self) -> Counterexample | None:
        """The first counterexample, to soundness or else to completion."""
        for name in ("soundness", "completion"):
            ce = self.raw.properties[name].counterexample
            if ce is not None:
                return Counterexample(
                    name, tuple(sorted(term_to_text(a) for a in ce.initial)),
                    tuple(term_to_text(s.behaviour) for s in ce.path),
                    tuple(tuple(term_to_text(a) for a in s.actions) for s in ce.path),
                    tuple(sorted(term_to_text(a) for a in ce.state)), tuple(counterexample_lines(ce)),
                    None if ce.behaviour is None else term_to_text(ce.behaviour),
                    None if ce.action is None else term_to_text(ce.action))
        return None

    def text(self) -> str:
        """What `schemalog verify` prints."""
        return "\n".join(self.lines()) + "\n"

    def lines(self) -> list[str]:
        return verify_lines(self.raw, self.how, self.nodes_before, self.nodes_after, self.states_option,
                            self.vacuity)

    def as_json(self) -> dict:
        """What `schemalog verify --json` prints."""
        return verify_json(self.raw, self.how, self.nodes_before, self.nodes_after, self.vacuity)

    @checked
    def words(self, fmt: str) -> str:
        """What a verification written to a file says, for `wrote FILE: ...`."""
        return verdict_words(self.raw, fmt, self.vacuity)

    def __repr__(self) -> str:
        return f"<Report {self.task}: {self.verdict}>"

    def _repr_html_(self) -> str:
        """The verdict, the counterexample's picture (Graphviz) and the report as verify prints it."""
        from .notebook import report_html

        return report_html(self)

    def _repr_svg_(self) -> str | None:
        """The compressed tree with the counterexample's steps numbered; None without one or `dot`."""
        from .notebook import report_svg

        return report_svg(self)


@checked
def verify(original: Task, compressed: Task, *, states: str | Iterable[str] = "default", method: str = "auto",
           max_states: Count = defaults.MAX_STATES, max_bdd_nodes: Count = 5_000_000, split: bool = True,
           scene: Path | None = None, sample: Count | None = None, seed: int = 0,
           progress: Callable[[int, int], None] | None = None, timeout: Seconds | None = None,
           max_memory: Size | None = DEFAULT) -> Report:
    """Prove `compressed` against `original` from the covered initial states: "default"
    (initial/1), "all" (every assignment of the free atoms allowed by constraint/1), or one
    state, 'hand.free, spoon.taken'. sample=RUNS checks random runs instead (no proof).
    timeout (seconds) and max_memory (bytes, '2G', None) stop the proof with LimitExceeded."""
    with within(timeout, max_memory):
        return _verify(original, compressed, states, method, max_states, max_bdd_nodes, split, scene, sample,
                       seed, progress)


def _verify(original: Task, compressed: Task, states, method: str, max_states: int, max_bdd_nodes: int,
            split: bool, scene, sample: int | None, seed: int, progress) -> Report:
    from ..run.vacuity import vacuity_of
    from ..run.verify import Verifier, prove
    from ..run.world import World
    from ..task import conditions as cond
    from ..task.compress import original_of

    if method not in ("auto", "symbolic", "explicit"):
        raise UsageError(f"method {method!r}: choose auto, symbolic or explicit")
    if sample is not None and not 1 <= sample <= defaults.MAX_SAMPLE:
        raise UsageError(f"sample: from 1 to {defaults.MAX_SAMPLE:,} runs, not {sample:,}")
    notes: list[str] = []
    if original.compressed:
        # A compressed task's tree runs merged leaves, so its actions and its world are not the
        # original's: the proof is against the tree it was compressed from (its provenance).
        notes.append(f"note: {original.name} is itself compressed; the proof is against the original it "
                     f"was compressed from ({len(original.original)} behaviours, rebuilt from its provenance)")
        original = original.original
    first, second = original.tree, compressed.tree
    if compressed.knowledge is not original.knowledge and compressed.provenance:
        if (second.label, second.post) != (first.label, first.post):
            raise SchemalogError(
                f"{', '.join(compressed.knowledge.files)} compresses {compressed.name} (post-condition "
                f"{cond.to_text(second.post)}), not {original.name} of {', '.join(original.knowledge.files)} "
                f"({cond.to_text(first.post)}): name the task (--task)")
        if original_of(second) != first:
            notes.append(f"note: the provenance of {', '.join(compressed.knowledge.files)} does not rebuild "
                         f"{', '.join(original.knowledge.files)}'s {original.name} exactly; the world is "
                         f"the original file's")
    world = World(first)
    states_option = states if isinstance(states, str) and states in ("default", "all") else "state"
    initial = initial_states(original, world, states, notes)
    found = read_scene_for(original, scene, None, None)
    if sample:
        raw = Verifier(first, second, world, max_states=max_states).sample(initial, sample, seed, found,
                                                                           first.label, progress=progress)
    else:
        raw = prove(first, second, world, initial, found, first.label, method, max_states, max_bdd_nodes,
                    split=split)
    vacuity = vacuity_of(first, World(first), raw.initial_states, max_states, raw.original_completes)
    return Report(raw, vacuity, how_compressed(original, compressed), len(original), len(compressed),
                  states_option, notes, tasks=(original, compressed))


def how_compressed(original: Task, compressed: Task) -> str:
    """`propagate full`, a compressed file's name, or `the compressed file`."""
    if compressed.compression is not None:
        return f"propagate {compressed.compression.propagate}"
    if compressed.knowledge is not original.knowledge:
        return ", ".join(compressed.knowledge.files)
    return "the compressed file"


def initial_states(original: Task, world: World, states, notes: list[str]) -> list:
    """The initial states to cover, settled: default, all, or one state's atoms."""
    from ..run.verify import all_states, constraints, free_atoms
    from ..run.world import initial_state

    kb = original.knowledge._kb
    if isinstance(states, str) and states == "all":
        found = all_states(world, free_atoms(kb, world.original), constraints(kb))
        if not found:
            raise SchemalogError("no assignment of the free atoms satisfies the constraints (constraint/1)")
        return found
    atoms = initial_state(kb) if isinstance(states, str) and states == "default" else state_atoms(states, "--states")
    for atom in world.unknown(atoms):
        notes.append(f"warning: {term_to_text(atom)} is read or set by no condition of {original.name}")
    world.reset(atoms)
    return [world.atoms]


def exit_status(report, vacuity: "Vacuity | None" = None) -> int:
    """1 on a counterexample or when the task itself never completes (a vacuous proof), 0 for a
    proof, INCONCLUSIVE otherwise."""
    if report.violated or (vacuity is not None and vacuity.vacuous):
        return 1
    if vacuity is not None and vacuity.undecided:
        return INCONCLUSIVE
    return 0 if report.exhaustive and report.sound and report.complete else INCONCLUSIVE


def vacuity_lines(vacuity: "Vacuity | None") -> list[str]:
    """What the report says about the original task's own completion."""
    from ..run.verify import state_text

    if vacuity is None:
        return []
    if vacuity.vacuous:
        n = len(vacuity.states)
        where = "from the covered initial state" if n == 1 else f"from any of the {n} covered initial states"
        lines = [f"the task itself cannot complete: no run of the original accomplishes it {where}, so the "
                 f"properties above hold vacuously"]
        if vacuity.cause is not None:
            lines.append(f"  why (schemalog lint): {vacuity.cause.text()}")
        else:
            lines.append("  (lint finds no single cause: every run of the original gets stuck or loops)")
        return lines
    if vacuity.undecided:
        return ["whether the task itself can complete is not known: the search for a run of the original "
                "that accomplishes it stopped at the state limit (--max-states) and found none, so the "
                "properties above may hold vacuously"]
    failing = vacuity.failing
    if not failing:
        return []
    shown = "; ".join(state_text(s) for s in failing[:5]) + ("; ..." if len(failing) > 5 else "")
    return [f"the original task cannot complete from {len(failing)} of {len(vacuity.states)} covered initial "
            f"states (the proof says nothing about those): {shown}"]


def verify_lines(report, how: str, before: int, after: int, states_option: str,
                 vacuity: Vacuity | None = None) -> list[str]:
    """The report as a person reads it: each property, and a counterexample where one fails."""
    from ..run.verify import state_text

    n = len(report.initial_states)
    which = "default: " + state_text(report.initial_states[0]) if states_option == "default" else \
        ("all that satisfy the constraints" if states_option == "all" else state_text(report.initial_states[0]))
    lines = [f"verify {term_to_text(report.task)}: original {before} behaviours, compressed {after} ({how}); "
             f"{n} initial state{'s' if n != 1 else ''} ({which})",
             (f"sampled: visited {report.compressed_states:,} states of the compressed tree in "
              f"{report.seconds:.2f} s (NOT a proof)" if report.sampled else
              (f"explored {report.compressed_states:,} states of the compressed tree as sets (at most "
               f"{report.nodes:,} decision-diagram nodes) in {report.seconds:.2f} s" if report.method == "symbolic" else
               f"explored {report.compressed_states:,} states of the compressed tree and "
               f"{report.original_states:,} of the original in {report.seconds:.2f} s")
              + (f", in {report.parts} parts" if report.parts > 1 else "")
              + ("" if report.exhaustive else f" (stopped at the limit of {report.limit}: NOT a proof)")),
             *([f"note: {report.note}"] if report.note else []), ""]
    titles = {"soundness": "soundness (no perceptual aliasing)", "completion": "completion",
              "flexibility": "flexibility (diagnostic)", "traces": "trace equivalence (diagnostic)",
              "selection": "selection under emphasis (diagnostic)"}
    for name, verdict in report.properties.items():
        sound = report.properties["soundness"].holds is True
        removed = _interleavings_removed(verdict) if name == "traces" and sound else None
        if removed is not None:
            lines.append(f"{titles[name]}: {removed}")
            lines.append("")
            continue
        status = {True: "holds", False: "FAILS", None: "unknown"}[verdict.holds]
        lines.append(f"{titles[name]}: {status}: {verdict.summary}")
        if verdict.counterexample is not None:
            lines.extend(counterexample_lines(verdict.counterexample))
        lines.append("")
    said = vacuity_lines(vacuity)
    if said:
        lines.extend([*said, ""])
    if report.violated:
        verdict = "the compressed tree is " + ("not sound" if report.properties["soundness"].holds is False
                                               else "not complete") + " (exit 1)"
    elif vacuity is not None and vacuity.vacuous:
        verdict = "vacuous: the task itself cannot complete, so nothing is proved about it (exit 1)"
    elif vacuity is not None and vacuity.undecided:
        verdict = ("no proof: whether the task itself can complete was not decided within the state limit "
                   "(raise --max-states) (exit 3)")
    elif report.exhaustive:
        verdict = "the compressed tree is sound and complete (exit 0)"
    elif report.limit and not report.sampled:
        verdict = f"no proof: stopped at the limit of {report.limit}; no counterexample before it (exit 3)"
    else:
        verdict = "no counterexample found, but this is not a proof (exit 3)"
    lines.append(f"result: {verdict}")
    return lines


def verdict_words(report, fmt: str, vacuity: "Vacuity | None" = None) -> str:
    """What a verification written to a file says, for `wrote FILE: ...`."""
    verdict = ("not sound" if report.properties["soundness"].holds is False else "not complete") \
        if report.violated else "vacuous (the task itself cannot complete)" if vacuity is not None and vacuity.vacuous \
        else "sound and complete" if exit_status(report, vacuity) == 0 else "no proof"
    return f"the verification of {term_to_text(report.task)}: {verdict} ({fmt})"


def _interleavings_removed(verdict) -> str | None:
    """Fewer complete traces in a sound compressed tree (each of its runs is one of the
    original's), as what merging does: it runs a merged sequence as one behaviour, so the orders
    its actions could interleave in are gone by design. None when the counts are not that
    (equal, unknown, infinite, or more traces)."""
    rows = verdict.details.get("states") if verdict.holds is False else None
    try:
        original = sum(r["original"] for r in rows)
        compressed = sum(r["compressed"] for r in rows)
    except (TypeError, KeyError):          # not counted, or infinitely many
        return None
    if compressed >= original:
        return None
    text = (f"{original - compressed:,} interleaving{'s' if original - compressed != 1 else ''} removed "
            f"by merging (by design: a merged behaviour runs its actions as one): the original has "
            f"{original:,} complete trace{'s' if original != 1 else ''}, the compressed tree {compressed:,}")
    lost = verdict.details.get("lost_example")
    if lost:
        text += "; e.g. this original trace is no longer produced: " + ", ".join(lost["trace"])
    return text


def counterexample_lines(ce) -> list[str]:
    from ..run.verify import state_text

    lines = [f"  counterexample, from the initial state {state_text(ce.initial)}:"]
    if not ce.path:
        lines.append("    (at the start)")
    for k, step in enumerate(ce.path, 1):
        actions = ", ".join(term_to_text(a) for a in step.actions)
        label = term_to_text(step.behaviour)
        lines.append(f"    {k:3d}  {label}" + (f"   [{actions}]" if actions != label else ""))
    if ce.action is not None:
        done = "".join(f"{term_to_text(a)}, " for a in ce.done_first)
        own = "" if ce.behaviour == ce.action and not done else f": {done}{term_to_text(ce.action)}"
        lines.append(f"    then the compressed tree takes {term_to_text(ce.behaviour)}{own}")
        lines.append(f"      ({ce.where})")
        lines.append(f"    the original would not take {term_to_text(ce.action)} there "
                     f"(state: {state_text(ce.state)}):")
    else:
        lines.append(f"    state: {state_text(ce.state)}")
    lines.extend(f"      {r}" for r in ce.reasons)
    return lines


def verify_json(report, how: str, before: int, after: int, vacuity: Vacuity | None = None) -> dict:
    """The report as data (docs/formats.md)."""
    def ce_json(ce):
        if ce is None:
            return None
        return {"initial": sorted(term_to_text(a) for a in ce.initial),
                "run": [{"behaviour": term_to_text(s.behaviour), "actions": [term_to_text(a) for a in s.actions]}
                        for s in ce.path],
                "state": sorted(term_to_text(a) for a in ce.state),
                "behaviour": None if ce.behaviour is None else term_to_text(ce.behaviour),
                "behaviour_path": ce.where or None,
                "actions_before": [term_to_text(a) for a in ce.done_first],
                "action": None if ce.action is None else term_to_text(ce.action),
                "reasons": list(ce.reasons)}
    return {
        "task": term_to_text(report.task), "compressed": how, "behaviours": {"original": before, "compressed": after},
        "sound": report.properties["soundness"].holds, "complete": report.properties["completion"].holds,
        "exhaustive": report.exhaustive,
        "states": len(report.initial_states),
        "initial_states": [sorted(term_to_text(a) for a in s) for s in report.initial_states],
        "explored": {"compressed": report.compressed_states, "original": report.original_states,
                     "seconds": report.seconds, "parts": report.parts, "sampled": report.sampled,
                     "stopped_at": report.limit or None, "method": report.method,
                     "bdd_nodes": report.nodes if report.method == "symbolic" else None,
                     "note": report.note or None},
        "counterexample": ce_json(report.properties["soundness"].counterexample
                                  or report.properties["completion"].counterexample),
        "properties": {name: {"holds": v.holds, "summary": v.summary, "counterexample": ce_json(v.counterexample),
                              **v.details} for name, v in report.properties.items()},
        **({} if vacuity is None else vacuity_json(vacuity)),
    }


def vacuity_json(vacuity: Vacuity) -> dict:
    """completing_states, not_completing_states, undecided_states, vacuous, and the lint cause."""
    def listed(flag):
        return [sorted(term_to_text(a) for a in s) for s, c in zip(vacuity.states, vacuity.completes) if c is flag]
    return {"completing_states": listed(True), "not_completing_states": listed(False),
            "undecided_states": listed(None), "vacuous": vacuity.vacuous,
            "vacuous_because": None if vacuity.cause is None else vacuity.cause.as_json()}
