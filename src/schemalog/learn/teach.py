"""Teaching: connect segmented actions to a partially specified task structure (Sec. II-D).

    Structure  = schema knowledge whose lowest sub-tasks have no children yet
    Attachment = (segment, sub-task node, releaser, post)   a new learned action
    Recognised = (segment, action node)                     a known action, performed again
    Teaching   = attachments, recognitions, the learned schemas, and what was left untaught

The structure's task is instantiated in working memory and the demonstration is replayed
through it, one symbolic action at a time, with the hand and the objects where the
demonstration had them when the action ended:

- A known action (declared `action/1`, e.g. learned from an earlier demonstration) that is
  enabled and matches the segment (the same gripper command, or a motion on the same object)
  is recognised: performed, not taught again. Among several, the most emphasised.
- Otherwise the action is attached to the enabled sub-task with the highest activation
  (emphasis e = w mu / lambda, as the executive computes it). Its releaser is `true` when the
  sub-task has no action yet, else the previous action's post-condition (`a4.done`); its
  post-condition is `aN.done`, or the gripper schema's (`not hand.free`).
- A gripper command ends the sub-task it is attached to: the sub-task's post-condition from
  the structure is asserted (the grasp achieved `water.taken`), and composites whose
  sub-tasks are all accomplished complete as in the emulated world.

The sub-tasks to teach are the leaves of the task tree that are not declared actions.
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass, field

from ..task import conditions as cond
from ..task.conditions import Condition
from .demo import Demonstration
from ..logic.engine import Engine
from ..errors import SchemalogError, readable_name
from ..run.execute import Plan, activation, blocked_reasons, emphasis
from ..logic.kb import KnowledgeBase
from ..run.scene import Scene, object_name
from ..task.schema import Entry, SchemaDef, schema_term, write_clause
from .segment import Segment, motion_label
from ..logic.terms import Atom, Struct, Term, term_to_text
from ..task.tree import Behaviour, Instantiator, walk
from ..run.world import World, effect_of, initial_state

GRIPPER = "gripper"


@dataclass(frozen=True)
class Attachment:
    """A new action learned under a sub-task."""

    segment: Segment
    label: Term                 # a22(tea): numbered in teaching order, unique in the knowledge
    subtask: Term
    releaser: Condition
    post: Condition
    emphasis: float
    runner_up: tuple[Term, float] | None


@dataclass(frozen=True)
class Recognised:
    """A segment that performed an action the structure already knew."""

    segment: Segment
    action: Term
    emphasis: float


@dataclass
class Teaching:
    """What one demonstration taught."""

    task: Term
    steps: list[Attachment | Recognised] = field(default_factory=list)
    schemas: list[SchemaDef] = field(default_factory=list)        # taught sub-tasks, in teaching order
    actions: list[SchemaDef] = field(default_factory=list)        # new primitive behaviours
    untaught: list[Term] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)              # warnings for the report
    accomplished: bool = False
    post: Condition = cond.TRUE

    @property
    def attachments(self) -> list[Attachment]:
        return [s for s in self.steps if isinstance(s, Attachment)]


def done_atom(action: str) -> Condition:
    """`a3.done`, the post-condition of a learned motion."""
    return cond.Lit(Struct(".", (Atom(action), Atom("done"))))


def declared_actions(kb: KnowledgeBase, tree: Behaviour) -> set[Term]:
    """The leaves of `tree` that the knowledge declares as actions (`action/1`)."""
    if not kb.clauses("action", 1):
        return set()
    engine = Engine(kb)
    return {b.label for b in walk(tree) if not b.children
            and engine.first(Struct("action", (b.label,))) is not None}


def next_action_number(kb: KnowledgeBase) -> int:
    """One more than the highest `aN` the knowledge already names (labels stay unique)."""
    highest = 0
    for clause in kb.clauses("schema", 3):
        head = clause.head
        label = head.args[0] if isinstance(head, Struct) and head.args else None
        name = label.name if isinstance(label, (Atom, Struct)) else ""
        if re.fullmatch(r"a[1-9][0-9]*", name):
            highest = max(highest, int(name[1:]))
    return highest + 1


def teach(kb: KnowledgeBase, task: Term, demo: Demonstration, segments: list[Segment],
          first_label: int | None = None) -> Teaching:
    """Replay `segments` through the structure of `task`; return what they taught.

    New motions are numbered from `first_label` (default: after the knowledge's own aN), in
    the order they are attached; recognised segments take no number."""
    counter = next_action_number(kb) if first_label is None else first_label
    instantiator = Instantiator(kb)
    tree = instantiator.instantiate(task)
    known = declared_actions(kb, tree)
    plan = Plan.of(tree)
    teachable = [i for i in plan.leaves if plan.nodes[i].label not in known]
    if not teachable:
        raise SchemalogError(f"every leaf of {term_to_text(task)} is a declared action (action/1): nothing is "
                             f"left to teach; to teach it again, learn on the structure this knowledge was learned "
                             f"on (its first lines name it)")
    gripper_posts = {}
    for seg in segments:
        if seg.kind == "gripper" and seg.label not in gripper_posts:
            try:
                _, schema = instantiator.lookup(seg.label, None)
            except SchemalogError:
                raise SchemalogError(f"the structure has no schema for {term_to_text(seg.label)}, which the "
                                     f"demonstration commands: declare its post-condition, e.g. "
                                     f"schema(gripper(close), [], not hand.free)") from None
            gripper_posts[seg.label] = schema.post
    world = World(tree, initial_state(kb))
    teaching = Teaching(task, post=tree.post)
    taught: dict[int, list[Entry]] = {}
    ended: set[int] = set()
    last_post: dict[int, Condition] = {}
    teachable_set = set(teachable)

    used = {object_name(o) for b in walk(tree) for o in b.objects}
    untracked = sorted(used - set(demo.objects))
    if untracked:
        teaching.notes.append(f"the structure's {', '.join(untracked)} {'has' if len(untracked) == 1 else 'have'} no "
                              f"track in the demonstration: sub-tasks on {'it' if len(untracked) == 1 else 'them'} "
                              f"compete with a neutral lambda")
    for seg in segments:
        if world.holds(tree.post):
            # The task is accomplished: what the teacher does next (moving away) is not part of it.
            teaching.notes.append(f"{_describe(seg, demo)}: after {term_to_text(task)} was accomplished: ignored")
            continue
        hand = tuple(float(v) for v in demo.positions[seg.end])
        scene = Scene(objects={name: tuple(float(v) for v in track[seg.end])
                               for name, track in demo.objects.items()}, end_effector=hand)
        live, mu = activation(plan, world.atoms)

        def ranked(indices: list[int]) -> list[tuple[float, float, int]]:
            out = []
            for i in indices:
                wmu = plan.weight[i] * mu[i]
                out.append((emphasis(wmu, scene.lambda_at(plan.obj[i], hand)), wmu, -i))
            return sorted(out, reverse=True)

        matching = [i for i in plan.leaves if live[i] and i not in teachable_set and _matches(plan.nodes[i], seg)]
        if matching:
            best = ranked(matching)[0]
            i = -best[2]
            teaching.steps.append(Recognised(seg, plan.nodes[i].label, best[0]))
            world.perform(plan.post[i])
            continue
        open_subtasks = [i for i in teachable if live[i] and i not in ended]
        if not open_subtasks:
            reasons = blocked_reasons(plan, world, set(ended), Counter(), limit=6)
            why = "; ".join(reasons) if reasons else "every sub-task is accomplished"
            recent = [f"{term_to_text(a.label)} -> {term_to_text(a.subtask)}" for a in teaching.attachments[-3:]]
            before = f"; the actions before it: {', '.join(recent)}" if recent else ""
            raise demo.error(f"{_describe(seg, demo)}: no enabled sub-task of {term_to_text(task)} to attach "
                             f"it to ({why}){before}", seg.end)
        order = ranked(open_subtasks)
        e, _, minus = order[0]
        i = -minus
        runner_up = (plan.nodes[-order[1][2]].label, order[1][0]) if len(order) > 1 else None
        entries = taught.setdefault(i, [])
        releaser = cond.TRUE if not entries else last_post[i]
        if seg.kind == "gripper":
            label, post = seg.label, gripper_posts[seg.label]
            objects = {object_name(o) for o in plan.nodes[i].objects}
            if seg.label.args[0] == Atom("close") and objects and seg.obj not in objects:
                teaching.notes.append(f"{_describe(seg, demo)} at {seg.obj} is attached to "
                                      f"{term_to_text(plan.nodes[i].label)}, which acts on {', '.join(sorted(objects))}: "
                                      f"is a sub-task taught on the wrong object?")
        else:
            label, post = motion_label(counter, seg.obj), done_atom(f"a{counter}")
            counter += 1
            teaching.actions.append(SchemaDef(label, (), post))
        entries.append(Entry(label, releaser))
        last_post[i] = post
        teaching.steps.append(Attachment(seg, label, plan.nodes[i].label, releaser, post, e, runner_up))
        world.perform(post)
        if seg.kind == "gripper":
            # The teacher's command closes the sub-task: its goal is reached (docs/learning.md).
            ended.add(i)
            try:
                effect_of(plan.post[i])
            except SchemalogError:
                raise SchemalogError(f"{term_to_text(plan.nodes[i].label)} ends with {term_to_text(seg.label)}, "
                                     f"but its post-condition {cond.to_text(plan.post[i])} is not a conjunction "
                                     f"of literals that teaching could assert") from None
            world.perform(plan.post[i])
    seen: set[Term] = set()
    for i in teachable:
        label = plan.nodes[i].label
        if i in taught:
            if label in seen:
                continue
            seen.add(label)
            teaching.schemas.append(SchemaDef(label, tuple(taught[i]), plan.post[i], pos=plan.nodes[i].source))
        elif label not in seen:
            teaching.untaught.append(label)
    teaching.untaught = [t for t in dict.fromkeys(teaching.untaught) if t not in seen]
    teaching.accomplished = world.holds(tree.post)
    return teaching


def _matches(action: Behaviour, seg: Segment) -> bool:
    """Whether a known action is what the segment did: the same command, or a motion on its object."""
    if seg.kind == "gripper":
        return action.label == seg.label
    if action.agent == GRIPPER or (isinstance(action.label, Struct) and action.label.name == GRIPPER):
        return False
    return any(term_to_text(o) == seg.obj for o in action.objects)


def _describe(seg: Segment, demo: Demonstration) -> str:
    """`a5(cup) (line 212, t 2.10 s)`: a segment as messages name it."""
    return (f"{term_to_text(seg.label)} ({demo.where(seg.end)}, t {demo.times[seg.end]:.2f} s, "
            f"{seg.cause})")




# ---------------------------------------------------------------------------
# Writing what was learned

def learned_text(teaching: Teaching, kb: KnowledgeBase, structure_text: str, *, demo_file: str,
                 structure_files: list[str], rows: dict[Term, str], settings: str) -> str:
    """The learned knowledge: a header, the taught schemas and actions, then the structure as given.

    Learned schemas come first so they are found before the structure's leaf-less ones
    (`schema(subtask(take, O), [], O.taken)`); `rows` says where each action was demonstrated."""
    engine = Engine(kb)

    def known(goal: Struct) -> bool:
        return bool(kb.clauses(goal.name, len(goal.args))) and engine.first(goal) is not None

    attached = teaching.attachments
    motions = [a for a in attached if a.segment.kind == "motion"]
    recognised = [s for s in teaching.steps if isinstance(s, Recognised)]
    lines = [
        f"% Learned by `schemalog learn` from {readable_name(demo_file)} (task {term_to_text(teaching.task)}) on "
        f"the structure",
        f"% {', '.join(map(readable_name, structure_files))}: {len(motions)} motions and {len(attached) - len(motions)} gripper "
        f"commands attached to {len(teaching.schemas)} sub-tasks, {len(recognised)} known actions recognised.",
        f"% {settings}",
        "% The structure follows, unchanged, after the learned knowledge (which comes first, so that",
        "% its sub-tasks are found before the structure's leaf-less ones).",
        "",
    ]
    if not known(Struct("task", (teaching.task,))):
        lines += [f"task({term_to_text(teaching.task, 999, spaced=True)}).", ""]
    objects = sorted({a.segment.obj for a in motions})
    if kb.clauses("object", 1):
        missing = [o for o in objects if not known(Struct("object", (Atom(o),)))]
        lines += [f"object({term_to_text(Atom(o))})." for o in missing] + ([""] if missing else [])
    if teaching.schemas:
        lines.append("% Sub-tasks taught (Sec. II-D): each action attached to the enabled sub-task with the highest")
        lines.append("% activation, released by the previous one's post-condition (the first always).")
        for s in teaching.schemas:
            lines.append(write_clause(schema_term(s)))
        lines.append("")
    new_actions = list(dict.fromkeys(a.label for a in attached if not known(Struct("action", (a.label,)))))
    if new_actions:
        lines.append("% The learned actions, each a segment of the demonstration, and their post-conditions.")
        facts = [f"action({term_to_text(label, 999, spaced=True)})." for label in new_actions]
        width = max(map(len, facts)) + 2
        for fact, label in zip(facts, new_actions):
            where = rows.get(label)
            lines.append(f"{fact:<{width}}% {where}" if where else fact)
        lines.append("")
    for schema in teaching.actions:
        lines.append(f"schema({term_to_text(schema.task, 999, spaced=True)}, [], {cond.to_text(schema.post)}).")
    if teaching.actions:
        lines.append("")
    lines += ["% " + "-" * 94, f"% The structure, as given in {', '.join(structure_files)}", "",
              structure_text.rstrip("\n"), ""]
    return "\n".join(lines)

__all__ = ["teach", "next_action_number", "learned_text", "Teaching", "Attachment", "Recognised", "declared_actions", "done_atom"]
