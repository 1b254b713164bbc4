"""schemalog's own objects as Prolog relations: the workspace of `schemalog query` and the REPL.

    Workspace = the files' clauses + kb/compression.pl + the facts of every task's trees
    TaskView  = (task, original tree, compressed tree, first ids, reduction degree)
    Id        = an integer naming one behaviour, unique over every tree of the workspace
    Focus     = (task view, ORIGINAL | COMPRESSED): the tree enabled/1, emphasis/2 and
                next_action/1 look at
    State     = frozenset of true atoms: the world now (the files' initial/1 at first)

Relations that describe a tree are facts, added once and indexed like any clause (see
docs/queries.md for each). Relations that read the state or run something (holds/1,
enabled/1, emphasis/2, next_action/1, run/2, verify/2) are built-ins of the workspace's
engine, computed when called.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Callable, Iterator

from ..errors import SchemalogError
from ..formats.documents import load_kb
from ..logic.engine import DEFAULT_MAX_STEPS, Engine
from ..logic.exceptions import instantiation_error, iso_error, type_error
from ..logic.kb import KnowledgeBase
from ..logic.parse import MAX_BYTES
from ..logic.terms import Atom, Float, Int, Struct, Term, Var, is_ground, make_list, term_to_text
from ..logic.unify import Bindings
from ..run.execute import BASE_ACTIVATION, Executive, Plan, ScanSelector, emphasis, enabled_indices
from ..run.scene import NO_SCENE, Scene
from ..run.vacuity import vacuity_of, verdict_term
from ..run.verify import DEFAULT_MAX_STATES, prove
from ..run.world import World, initial_state
from ..shipped import shipped_text
from ..task import conditions as cond
from ..task.compress import compress, original_of, protected_labels
from ..task.conditions import DEFAULT_SYMPY_BUDGET, Simplifier
from ..task.facts import tree_facts
from ..task.schema import check_schemas
from ..task.tree import (DEFAULT_MAX_DEPTH, DEFAULT_MAX_NODES, Behaviour, Instantiator, count_nodes,
                          declared_tasks, depth)


ORIGINAL, COMPRESSED = "original", "compressed"


# The relations a workspace adds, name/arity -> one line for :help and the docs' table.
RELATIONS: dict[tuple[str, int], str] = {
    ("task", 1): "task(T): T is a task (the files' task/1, else every root schema)",
    ("original", 2): "original(T, B): B is the root of task T's tree as instantiated",
    ("compressed", 2): "compressed(T, B): B is the root of T's compressed tree (Algorithm 1)",
    ("in_tree", 3): "in_tree(B, T, Kind): behaviour B belongs to T's original or compressed tree",
    ("node", 2): "node(B, Label): behaviour B has this label",
    ("child", 2): "child(P, C): C is a child of P, children in order",
    ("parent", 2): "parent(C, P): P is the parent of C",
    ("depth", 2): "depth(B, D): B is on level D (the root is on level 1)",
    ("leaf", 1): "leaf(B): B is an action (it has no children)",
    ("kind", 2): "kind(B, K): K is action or subtask",
    ("pre", 2): "pre(B, C): C is B's pre-condition (context and releaser)",
    ("entry", 2): "entry(B, C): B's own releaser (a merged one: its first constituent's)",
    ("post", 2): "post(B, C): C is B's post-condition",
    ("agent", 2): "agent(B, A): B is performed by agent A",
    ("objects", 2): "objects(B, Os): B acts on the objects Os",
    ("k", 2): "k(B, K): B stands for K original behaviours",
    ("sequential", 2): "sequential(B1, B2): Definition 1 (kb/compression.pl), B1 first",
    ("merged", 3): "merged(T, B, Parts): B in T's compressed tree merges the labels Parts",
    ("reduction_degree", 2): "reduction_degree(T, RD): (Bi - Bm) / (Bi - D) of T's compression",
    ("holds", 1): "holds(C): condition C is true in the current state",
    ("enabled", 1): "enabled(B): action B of the focus tree is enabled now",
    ("emphasis", 2): "emphasis(B, E): E = w * mu / lambda of behaviour B of the focus tree now",
    ("next_action", 1): "next_action(B): the action the executive would select now",
    ("run", 2): "run(T, Outcome): run T (a task, or a root) from now: completed(Trace), stuck(Trace), ...",
    ("verify", 2): "verify(T, Result): proved, counterexample(Property, Steps) or no_proof(Why)",
}


# The relations computed when called (built-ins of the workspace's engine); the rest are facts.
_COMPUTED = frozenset({("holds", 1), ("enabled", 1), ("emphasis", 2), ("next_action", 1), ("run", 2),
                       ("verify", 2), ("sequential", 2)})


@dataclass
class TaskView:
    """One task of the workspace: its trees and where their ids start."""

    task: Term
    original: Behaviour
    compressed: Behaviour
    original_first: int
    compressed_first: int
    reduction_degree: float
    world: World

    def tree(self, kind: str) -> Behaviour:
        return self.compressed if kind == COMPRESSED else self.original

    def first(self, kind: str) -> int:
        return self.compressed_first if kind == COMPRESSED else self.original_first


@dataclass(frozen=True)
class Options:
    """How the workspace reads and compresses its files."""

    propagate: str = "full"
    max_bytes: int = MAX_BYTES
    max_depth: int = DEFAULT_MAX_DEPTH
    max_nodes: int = DEFAULT_MAX_NODES
    max_steps: int = DEFAULT_MAX_STEPS
    sympy_budget: int = DEFAULT_SYMPY_BUDGET
    scene: Scene = NO_SCENE


class Workspace:
    """Knowledge files with their tasks instantiated and compressed, and a current state."""

    def __init__(self, files: list[str], options: Options = Options(),
                 read: Callable[[], KnowledgeBase] | None = None) -> None:
        self.files = list(files)
        self.options = options
        self._read = read           # the files' knowledge base, when not read from `files` (a text)
        self.notes: list[str] = []
        self.kb = KnowledgeBase()
        self.views: list[TaskView] = []
        self._build()

    # -- building ---------------------------------------------------------------
    def _build(self) -> None:
        kb = self._read() if self._read is not None else \
            load_kb(self.files, self.options.max_bytes, self.options.max_steps)
        self.notes = list(kb.warnings)
        user_defined = {key for key, p in kb.predicates.items() if any(not c.library for c in p.clauses)}
        views: list[TaskView] = []
        next_id = 0
        for task in _tasks(kb, self.notes):
            instantiator = Instantiator(kb, max_depth=self.options.max_depth, max_nodes=self.options.max_nodes)
            tree = instantiator.instantiate(task)
            self.notes.extend(w for w in instantiator.warnings if w not in self.notes)
            original = original_of(tree)
            if original is not tree:             # a file written by `schemalog compress`
                compressed, before, after = tree, count_nodes(original), count_nodes(tree)
            else:
                result = compress(original, self.options.propagate, protected_labels(kb, original),
                                  Simplifier(sympy_budget=self.options.sympy_budget))
                compressed, before, after = result.tree, result.nodes_before, result.nodes_after
            levels = depth(original)
            rd = (before - after) / (before - levels) if before > levels else 0.0
            view = TaskView(task, original, compressed, next_id, next_id + before, rd, World(original))
            next_id += before + after
            views.append(view)
        kb.consult_text(shipped_text("kb/compression.pl"), "kb/compression.pl")
        facts: list[Term] = []
        for view in views:
            facts.extend(_view_facts(view, declare_task=("task", 1) not in user_defined))
        clashes = sorted(f"{name}/{arity}" for name, arity in user_defined
                         if (name, arity) in RELATIONS and (name, arity) not in _COMPUTED
                         and (name, arity) != ("task", 1) and views)
        hidden = sorted(f"{name}/{arity}" for name, arity in user_defined
                        if (name, arity) in _COMPUTED and (name, arity) != ("sequential", 2) and views)
        # Said once at the REPL's start; `schemalog query` stays quiet (docs/queries.md says it).
        self.clashes = "\n".join([*(_clash_note(c, kb) for c in clashes)] +
                                  ([f"note: your files' clauses for {', '.join(hidden)} are not called: "
                                    f"{'these are' if len(hidden) > 1 else 'it is'} schemalog's relation{'s' if len(hidden) > 1 else ''} "
                                    f"here (docs/queries.md); rename yours to call "
                                    f"{'them' if len(hidden) > 1 else 'it'}"] if hidden else []))
        kb.add_facts(facts)
        if views:      # a relation without facts (no merge: merged/3) fails rather than raising
            for name, arity in RELATIONS:
                if (name, arity) not in _COMPUTED:
                    kb.declare_dynamic(name, arity)
        self.kb = kb
        self.views = views
        self.initial = initial_state(kb)
        self.focus: TaskView | None = views[0] if views else None
        self.kind = ORIGINAL
        self._plans: dict[tuple[int, str], Plan] = {}
        self.reset()

    def load(self, path: str) -> None:
        """Add a file, or read one loaded already again in its place; rebuild everything."""
        before, new = self.files, os.path.realpath(path) not in map(os.path.realpath, self.files)
        self.files = [*self.files, path] if new else self.files
        self._read = None
        try:
            self._build()
        except BaseException:
            self.files = before
            raise

    def reset(self) -> None:
        """Put the world back in the initial state (the files' initial/1), settled."""
        self.set_state(self.initial)

    def set_state(self, atoms: list[Term]) -> None:
        """Make exactly `atoms` true (settled by the focus task's world)."""
        if self.focus is None:
            self.state = frozenset(atoms)
            return
        self.focus.world.reset(atoms)
        self.state = self.focus.world.atoms

    # -- focus --------------------------------------------------------------------
    def tree_of(self, term: Term) -> tuple[TaskView, str] | None:
        """The tree `term` names: a task (its original tree) or the root id of a tree."""
        for view in self.views:
            if term == view.task or term == Int(view.original_first):
                return view, ORIGINAL
            if term == Int(view.compressed_first):
                return view, COMPRESSED
        return None

    def find_tree(self, term: Term) -> tuple[TaskView, str]:
        """`tree_of`, or a message naming the tasks there are."""
        if isinstance(term, Var):
            raise SchemalogError("name a task or a root id, not a variable")
        found = self.tree_of(term)
        if found is None:
            known = ", ".join(term_to_text(v.task) for v in self.views) or "none"
            raise SchemalogError(f"no task {term_to_text(term)} here (tasks: {known})")
        return found

    def set_focus(self, view: TaskView, kind: str) -> None:
        if view is not self.focus:
            self.focus = view
            self.reset()
        self.kind = kind

    def plan(self, view: TaskView, kind: str) -> Plan:
        key = (view.original_first, kind)
        if key not in self._plans:
            self._plans[key] = Plan.of(view.tree(kind))
        return self._plans[key]

    # -- asking -------------------------------------------------------------------
    def engine(self, output: Callable[[str], None] | None = None, max_steps: int | None = None) -> Engine:
        """An engine over the workspace, with its relations built in (when it has tasks: a
        plain Prolog program keeps its own run/2 or holds/1)."""
        if not self.views:
            return Engine(self.kb, max_steps or self.options.max_steps, output)
        return Engine(self.kb, max_steps or self.options.max_steps, output,
                      builtins={("holds", 1): self._holds, ("next_action", 1): self._next_action,
                                ("run", 2): self._run, ("verify", 2): self._verify},
                      nondet={("enabled", 1): self._enabled, ("emphasis", 2): self._emphasis})

    def _focus_plan(self) -> tuple[Plan, int] | None:
        if self.focus is None:
            return None
        return self.plan(self.focus, self.kind), self.focus.first(self.kind)

    def _holds(self, e: Engine, a: tuple, b: Bindings) -> bool:
        """holds(+Condition)"""
        c = _condition(b.resolve(a[0]))
        return cond.holds(c, self.state)

    def _enabled(self, e: Engine, a: tuple, b: Bindings) -> Iterator[None]:
        """enabled(?B)"""
        found = self._focus_plan()
        if found is None:
            return
        plan, first = found
        yield from _each(b, a[0], [Int(first + i) for i in enabled_indices(plan, self.state)])

    def _emphasis(self, e: Engine, a: tuple, b: Bindings) -> Iterator[None]:
        """emphasis(?B, ?E)"""
        found = self._focus_plan()
        if found is None:
            return
        plan, first = found
        values = emphases(plan, self.state, self.options.scene)
        target = Struct("-", (a[0], a[1]))
        yield from _each(b, target, [Struct("-", (Int(first + i), Float(float(v)))) for i, v in enumerate(values)])

    def _next_action(self, e: Engine, a: tuple, b: Bindings) -> bool:
        """next_action(?B)"""
        found = self._focus_plan()
        if found is None:
            return False
        plan, first = found
        world = self.focus.world
        world.load(self.state)
        best, _ = ScanSelector(plan, world, self.options.scene).select(self.options.scene.end_effector)
        return bool(best) and b.unify(a[0], Int(first - best[0][2]))

    def _tree_arg(self, t: Term) -> tuple[TaskView, str]:
        if isinstance(t, Var):
            raise instantiation_error()
        found = self.tree_of(t)
        if found is None:
            raise iso_error(Struct("existence_error", (Atom("task"), t)))
        return found

    def _run(self, e: Engine, a: tuple, b: Bindings) -> bool:
        """run(+Task or +Root, ?Outcome): the executive from the current state; the state stays."""
        view, kind = self._tree_arg(b.walk(a[0]))
        executive = self.execute(view, kind, self.state)
        outcome = Struct(executive.outcome.status.name.lower(), (make_list(executive.trace),))
        return b.unify(a[1], outcome)

    def execute(self, view: TaskView, kind: str, state: frozenset, max_decisions: int | None = None) -> Executive:
        """Run one of `view`'s trees from `state` to its end, in a world of its own."""
        world = World(view.original, state)
        executive = Executive(view.tree(kind), world, self.options.scene, max_decisions=max_decisions)
        executive.run()
        return executive

    def _verify(self, e: Engine, a: tuple, b: Bindings) -> bool:
        """verify(+Task, ?Result): the compressed tree against the original, from initial/1."""
        view, _ = self._tree_arg(b.walk(a[0]))
        return b.unify(a[1], verdict_term(*self.verify(view)))

    def verify(self, view: TaskView) -> tuple:
        """The verifier's report on `view`'s compression from the files' initial state, and the
        Vacuity that says whether the original itself can complete from it."""
        world = World(view.original, self.initial)
        report = prove(view.original, view.compressed, world, [world.atoms], None, view.task)
        return report, vacuity_of(view.original, World(view.original), report.initial_states, DEFAULT_MAX_STATES,
                                  report.original_completes)


def emphases(plan: Plan, atoms: frozenset, scene: Scene) -> list[float]:
    """e = w * mu / lambda of every behaviour of `plan` in the state `atoms`, in pre-order
    (the scan selector's mu: the root's parent counts BASE_ACTIVATION, each behaviour adds
    its accomplished original children)."""
    mu: list[int] = []
    out: list[float] = []
    for i in range(len(plan)):
        seen: set = set()
        for c in plan.children[i]:
            if cond.holds(plan.post[c], atoms):
                seen.update(plan.keys[c])
        up = plan.parent[i]
        mu.append((mu[up] if up >= 0 else BASE_ACTIVATION) + len(seen))
        out.append(emphasis(plan.weight[i] * mu[i], scene.lambda_at(plan.obj[i], scene.end_effector)))
    return out


def _condition(term: Term) -> cond.Condition:
    if not is_ground(term):
        raise instantiation_error()
    try:
        return cond.from_term(term)
    except cond.NotACondition:
        raise type_error("condition", term) from None


def _each(b: Bindings, target: Term, values: list[Term]) -> Iterator[None]:
    """Unify `target` with each value in turn (a nondeterministic built-in's answers)."""
    for value in values:
        mark = b.mark()
        if b.unify(target, value):
            yield
        b.undo(mark)


def _tasks(kb: KnowledgeBase, notes: list[str]) -> list[Term]:
    """The files' task/1, else every schema never used as a sub-task that instantiates."""
    declared = list(dict.fromkeys(declared_tasks(kb)))     # task(t) twice is one task
    if declared:
        return declared
    schemas = check_schemas(kb)
    used = {e.behaviour for s in schemas for e in s.entries}
    roots = [s.task for s in schemas if s.entries and s.task not in used and is_ground(s.task)]
    if roots:
        notes.append(f"note: no task/1: taking {', '.join(term_to_text(r) for r in roots[:6])}"
                     f"{' ...' if len(roots) > 6 else ''} (schemas no other schema uses)")
    return roots


def _clash_note(indicator: str, kb: KnowledgeBase) -> str:
    """What a relation the files define too means at the prompt, in words a newcomer follows:
    whose clauses it has, in which order a query gets them, and how to ask for schemalog's alone."""
    from ..logic.terms import variable_names

    name, arity = indicator.rsplit("/", 1)
    template, _, meaning = RELATIONS[(name, int(arity))].partition(": ")
    first = template[len(name) + 1:].split(",")[0].rstrip(")")
    clauses = [c for c in kb.clauses(name, int(arity)) if not c.library]
    head = clauses[0].head
    shown = term_to_text(head, names=variable_names([head]), next_argument=True)
    where = f" ({clauses[0].pos.file}:{clauses[0].pos.line})" if clauses[0].pos else ""
    more = f" and {len(clauses) - 1} more" if len(clauses) > 1 else ""
    lines = [f"note: {indicator} means two things here:",
             f"  your files' {shown}{where}{more}, and"]
    if first in ("B", "P", "C"):       # a behaviour: node/2 holds for behaviours only
        lines += [f"  schemalog's {template}: {meaning} ({first} a behaviour's id, as :tree numbers them).",
                  f"  ?- {template}. gives your clauses' answers first, then one per behaviour;",
                  f"  ?- node({first}, _), {template}. gives the behaviours only (docs/queries.md, Relations)."]
    else:
        lines += [f"  schemalog's {template}: {meaning}.",
                  f"  ?- {template}. gives your clauses' answers first, then schemalog's (docs/queries.md, Relations)."]
    return "\n".join(lines)


def _view_facts(view: TaskView, declare_task: bool) -> list[Term]:
    task = view.task
    facts: list[Term] = [Struct("task", (task,))] if declare_task else []
    facts.append(Struct("original", (task, Int(view.original_first))))
    facts.append(Struct("compressed", (task, Int(view.compressed_first))))
    facts.append(Struct("reduction_degree", (task, Float(view.reduction_degree))))
    for kind in (ORIGINAL, COMPRESSED):
        tree_part = tree_facts(view.tree(kind), view.first(kind))
        facts.extend(tree_part)
        facts.extend(Struct("in_tree", (f.args[0], task, Atom(kind))) for f in tree_part if f.name == "node")
    order = view.compressed_first
    stack = [view.compressed]
    while stack:                      # the same pre-order as tree_facts numbers them
        node = stack.pop()
        if node.merged_from:
            facts.append(Struct("merged", (task, Int(order), make_list(node.merged_from))))
        order += 1
        stack.extend(reversed(node.children))
    return facts


__all__ = ["Workspace", "TaskView", "Options", "RELATIONS", "ORIGINAL", "COMPRESSED", "emphases", "verdict_term"]
