"""Behaviours and task trees: the paper's working memory, instantiated from long-term memory.

    Behaviour = (label, agent, objects, releaser, post, children, context, k,
                 merged_from, importance)
    TaskTree  = the root Behaviour

`instantiate(kb, label)` is the paper's loadTaskFromLTM: it looks up
`schema(label, Subtasks, Post)` (by resolution, so parameterised and rule schemas
work), then each sub-task in turn. Two uses of the same sub-task (add(water) under
coffee and under tea) become two distinct nodes. The walk is iterative with
explicit depth and size limits, measured before anything is built (each distinct sub-task
counted once); a schema that reaches itself is a cycle error.

A sub-task no schema applies to is an error, except under a schema imported from SEED
(`kb.seed_files`): SEED says "no semantic for ..." and leaves the node out, and so does
the walk, with a warning at the parent schema's clause (`Instantiator.warnings`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field, replace
from typing import Iterator

from .. import defaults
from . import conditions as cond
from .conditions import Condition
from ..logic.engine import Engine
from ..logic.exceptions import PrologError, StepLimitExceeded
from ..errors import SchemalogError, SourcePos, shown_number
from ..logic.kb import KnowledgeBase
from .schema import DEFAULT_AGENT, DEFAULT_IMPORTANCE, Entry, SchemaDef, importance_problem, read_schema
from ..logic.terms import NIL, TRUE, Atom, Float, Int, Str, Struct, Term, Var, is_ground, list_items, term_to_text
from ..logic.unify import Bindings, variant

DEFAULT_MAX_DEPTH = defaults.MAX_DEPTH
DEFAULT_MAX_NODES = defaults.MAX_NODES


@dataclass(frozen=True, slots=True)
class Origin:
    """An original behaviour that a compressed one stands for (provenance).

    `position` is its index among its original siblings; `slot` is which origin of the
    compressed parent was its original parent. Both are relative, so two identical
    subtrees keep identical provenance, and decompression rebuilds the original exactly.
    """

    label: Term
    releaser: Condition
    post: Condition
    importance: int | float = DEFAULT_IMPORTANCE
    position: int = 0
    slot: int = 0


@dataclass(frozen=True, slots=True)
class Behaviour:
    """A node of a task tree: a running behaviour with its conditions."""

    label: Term
    agent: str = DEFAULT_AGENT
    objects: tuple[Term, ...] = ()
    releaser: Condition = cond.TRUE
    post: Condition = cond.TRUE
    children: tuple["Behaviour", ...] = ()
    context: Condition = cond.TRUE        # inherited from merged-away ancestors (compression)
    importance: int | float = DEFAULT_IMPORTANCE
    origins: tuple[Origin, ...] = ()      # provenance; empty in a tree read from knowledge
    source: SourcePos | None = field(default=None, compare=False)

    @property
    def pre(self) -> Condition:
        """The pre-condition: propagated context AND own releaser."""
        releaser = self.releaser
        if self.context is cond.TRUE and (releaser is cond.TRUE or type(releaser) is cond.Lit):
            return releaser      # what conjoin gives, without its list and comparisons
        return cond.conjoin([self.context, releaser])

    @property
    def k(self) -> int:
        """How many original behaviours this one stands for (Sec. III-D)."""
        return max(1, len(self.origins))

    @property
    def merged_from(self) -> tuple[Term, ...]:
        """The original behaviours a merged behaviour replaces, in order (empty if not merged)."""
        return tuple(o.label for o in self.origins) if len(self.origins) > 1 else ()

    @property
    def entry(self) -> Condition:
        """The entry releaser: its own releaser, or for a merged one its first constituent's
        original releaser (what Definition 1 compares with a post-condition)."""
        return self.origins[0].releaser if self.origins else self.releaser

    @property
    def is_leaf(self) -> bool:
        return not self.children

    @property
    def name(self) -> str:
        return term_to_text(self.label)


TaskTree = Behaviour


def walk(root: Behaviour) -> Iterator[Behaviour]:
    """Every behaviour of the tree, pre-order, iteratively."""
    stack = [root]
    while stack:
        node = stack.pop()
        yield node
        stack.extend(reversed(node.children))


def walk_with_depth(root: Behaviour) -> Iterator[tuple[Behaviour, int]]:
    """Every behaviour with its level (the root is level 1), pre-order."""
    stack = [(root, 1)]
    while stack:
        node, level = stack.pop()
        yield node, level
        stack.extend((c, level + 1) for c in reversed(node.children))


def count_nodes(root: Behaviour) -> int:
    """B in the paper: the number of behaviours."""
    return sum(1 for _ in walk(root))


def depth(root: Behaviour) -> int:
    """D in the paper: the number of levels (a lone root has depth 1)."""
    return max(level for _, level in walk_with_depth(root))


def map_tree(root: Behaviour, fn) -> Behaviour:
    """Rebuild the tree bottom-up: fn(node with its rebuilt children, position among siblings)."""
    stack: list[tuple[Behaviour, int, list[Behaviour]]] = [(root, 0, [])]
    while True:
        node, position, done = stack[-1]
        if len(done) < len(node.children):
            stack.append((node.children[len(done)], len(done), []))
            continue
        stack.pop()
        rebuilt = fn(replace(node, children=tuple(done)) if done else node, position)
        if not stack:
            return rebuilt
        stack[-1][2].append(rebuilt)


# ---------------------------------------------------------------------------
# Instantiation

@dataclass
class _Frame:
    label: Term
    releaser: Condition
    importance: int | float
    schema: SchemaDef
    level: int
    pending: list[Entry]      # its entries; the next to build is number len(built)
    origins: tuple[Origin, ...] = ()
    built: list[Behaviour] = field(default_factory=list)


_UNSEEN = object()   # not looked up yet (None: looked up, no schema)


class Instantiator:
    """Looks behaviours up in one knowledge base (schemas, agents, objects)."""

    def __init__(self, kb: KnowledgeBase, max_depth: int = DEFAULT_MAX_DEPTH,
                 max_nodes: int = DEFAULT_MAX_NODES, read: dict[int, SchemaDef] | None = None) -> None:
        self.kb = kb
        # check_schemas's schemas by id of their clause (`schemalog check` has read them all
        # once already): a ground fact's is taken from here instead of being read again
        self._read = read or {}
        # A rule schema's body, and each look-up of agent/2, object/1 ..., runs under the
        # knowledge base's step limit (--max-steps), as its directives do.
        self.engine = Engine(kb, max_steps=kb.max_steps)
        self.max_depth = max_depth
        self.max_nodes = max_nodes
        self._has = {name: bool(kb.clauses(name, arity))
                     for name, arity in (("agent", 2), ("object", 1), ("objects", 2), ("behaviour", 1),
                                         ("origins", 2), ("task_origins", 2))}
        self._origins_cache: dict[Term, list[tuple[Origin, ...]]] = {}
        self._agent_cache: dict[Term, str] = {}
        self._objects_cache: dict[Term, tuple[Term, ...]] = {}
        self._object_cache: dict[Term, bool] = {}
        self._object_tuples: dict[tuple[Term, ...], tuple[Term, ...]] = {}
        # The sub-tasks the last instantiation left out, as SEED does: (parent's clause, parent, sub-task).
        self.left_out: list[tuple[SourcePos, Term, Term]] = []

    # -- look-ups -------------------------------------------------------------
    def lookup(self, label: Term, used_at: SourcePos | None) -> tuple[Term, SchemaDef]:
        """Find the schema of `label`; return the (possibly more bound) label and the schema."""
        found = self._find(label, used_at)
        if found is None:
            raise _no_schema(label, used_at)
        return found

    def _find(self, label: Term, used_at: SourcePos | None) -> tuple[Term, SchemaDef] | None:
        """The schema of `label`, or None when no clause applies (a body that raises is an error)."""
        goal_list = goal_post = None     # made for the first clause that needs them
        ground = is_ground(label)
        for clause in self.kb.candidates("schema", 3, label) or []:
            if clause.library:
                continue
            if ground and (clause.body is TRUE or clause.body == TRUE) and is_ground(clause.head):
                # A ground fact matches a ground label when equal, and is its own answer:
                # no copy to rename, unify and resolve.
                if clause.head.args[0] == label:
                    known = self._read.get(id(clause))
                    return label, known or read_schema(clause.head, pos=clause.pos, allow_unbound=False)
                continue
            if goal_list is None:
                goal_list, goal_post = Var("L"), Var("P")
            b = Bindings()
            head, body = clause.renamed()
            if not b.unify(head, Struct("schema", (label, goal_list, goal_post))):
                continue
            if body != Atom("true"):
                try:
                    if self.engine.first(body, b) is None:
                        continue
                except PrologError as err:
                    missing = _missing_procedure(err.ball)
                    if missing is not None:
                        raise SchemalogError(f"while instantiating {term_to_text(label)}, the schema's body "
                                             f"calls {missing}, which neither the file nor schemalog defines",
                                             clause.pos) from None
                    raise SchemalogError(f"while instantiating {term_to_text(label)}, the schema's "
                                         f"body raised {err}", clause.pos) from None
                except StepLimitExceeded:
                    raise SchemalogError(f"while instantiating {term_to_text(label)}, the schema's body "
                                         f"exceeded the step limit of {self.engine.max_steps:,} steps "
                                         f"(raise it with --max-steps N)", clause.pos) from None
            resolved = Struct("schema", (b.resolve(label), b.resolve(goal_list), b.resolve(goal_post)))
            return resolved.args[0], read_schema(resolved, pos=clause.pos, allow_unbound=False)
        if self._has["behaviour"] and self._succeeds(Struct("behaviour", (label,))):
            post = cond.Lit(Struct(".", (label, Atom("done"))))
            return label, SchemaDef(label, (), post, pos=used_at)
        return None

    def _first(self, goal: Term, shown: str | None = None) -> Bindings | None:
        """The first answer of a look-up (agent/2, objects/2, object/1, origins/2), or an error
        that names it (`shown`, else the goal): an exception it raised, or the step limit."""
        try:
            return self.engine.first(goal)
        except PrologError as err:
            raise SchemalogError(f"{shown or term_to_text(goal)} raised {err}") from None
        except StepLimitExceeded:
            raise SchemalogError(f"{shown or term_to_text(goal)} exceeded the step limit of "
                                 f"{self.engine.max_steps:,} steps (raise it with --max-steps N)") from None

    def _succeeds(self, goal: Term) -> bool:
        return self._first(goal) is not None

    def agent(self, label: Term) -> str:
        """Who performs `label`: the first `agent(Label, A)` answer, else `arm`."""
        cached = self._agent_cache.get(label)
        if cached is not None:
            return cached
        agent = DEFAULT_AGENT
        if self._has["agent"]:
            a = Var("A")
            b = self._first(Struct("agent", (label, a)), f"agent({term_to_text(label)}, A)")
            if b is not None:
                value = b.resolve(a)
                if not isinstance(value, Atom):
                    raise SchemalogError(f"agent({term_to_text(label)}, A) gave A = {term_to_text(value)}, "
                                         f"not an agent name")
                agent = value.name
        self._agent_cache[label] = agent
        return agent

    def objects(self, label: Term) -> tuple[Term, ...]:
        """What `label` acts on: `objects/2` if it answers, else the arguments declared
        with `object/1`, else every atomic argument."""
        cached = self._objects_cache.get(label)
        if cached is not None:
            return cached
        result: tuple[Term, ...] | None = None
        if self._has["objects"]:
            v = Var("Os")
            b = self._first(Struct("objects", (label, v)), f"objects({term_to_text(label)}, Os)")
            if b is not None:
                items, tail = list_items(b.resolve(v))
                if tail != NIL:
                    raise SchemalogError(f"objects({term_to_text(label)}, Os) must give a list")
                result = tuple(items)
        if result is None:
            args = label.args if isinstance(label, Struct) else ()
            if self._has["object"]:
                result = tuple(a for a in args if self._is_object(a))
            else:
                result = tuple(a for a in args if isinstance(a, (Atom, Int, Float, Str)))
        # one tuple for each distinct list of objects: (obj1,) stands for thousands of behaviours
        result = self._objects_cache[label] = self._object_tuples.setdefault(result, result)
        return result

    def _is_object(self, arg: Term) -> bool:
        """Whether `object(arg)` succeeds, asked once per argument (a file of 100,000 schemas
        names each of its few objects tens of thousands of times)."""
        known = self._object_cache.get(arg)
        if known is None:
            known = self._object_cache[arg] = self._succeeds(Struct("object", (arg,)))
        return known

    # -- provenance of a compressed tree (written by schemalog compress) ------
    def child_origins(self, parent: Term, index: int, pos: SourcePos | None) -> tuple[Origin, ...]:
        """The origins of the `index`-th sub-task of `parent`, from origins(Parent, [...])."""
        if not self._has["origins"]:
            return ()
        table = self._origins_cache.get(parent)
        if table is None:
            table = self._origins_cache[parent] = self._read_origins(
                Struct("origins", (parent, Var("L"))), pos, many=True)
        return table[index] if index < len(table) else ()

    def root_origins(self, root: Term) -> tuple[Origin, ...]:
        if not self._has["task_origins"]:
            return ()
        found = self._read_origins(Struct("task_origins", (root, Var("L"))), None, many=False)
        return found[0] if found else ()

    def _read_origins(self, goal: Struct, pos: SourcePos | None, many: bool) -> list[tuple[Origin, ...]]:
        b = self._first(goal)
        if b is None:
            return []
        value = b.resolve(goal.args[1])
        groups = list_items(value)[0] if many else [value]
        try:
            return [tuple(_origin(t) for t in list_items(group)[0]) for group in groups]
        except (ValueError, cond.NotACondition) as err:
            raise SchemalogError(f"malformed provenance in {term_to_text(goal.args[0])}: {err}",
                                 self._fact_at(goal) or pos) from None

    def _fact_at(self, goal: Struct) -> SourcePos | None:
        """Where the first clause that answers `goal` (an origins/2 fact) was written, if known."""
        for clause in self.kb.candidates(goal.name, len(goal.args), goal.args[0]) or []:
            if Bindings().unify(clause.head, goal):
                return clause.pos
        return None

    # -- the walk -------------------------------------------------------------
    def _lookup_once(self, label: Term, used_at: SourcePos | None) -> tuple[Term, SchemaDef] | None:
        """`_find`, once per distinct sub-task of one instantiation (a rule's body runs once)."""
        found = self._lookups.get(label, _UNSEEN)    # one look-up: a term's hash is Python code
        if found is _UNSEEN:
            found = self._lookups[label] = self._find(label, used_at)
        return found

    def _sub_schema(self, parent: Term, schema: SchemaDef, entry: Entry) -> tuple[Term, SchemaDef] | None:
        """The schema of one sub-task of `parent`; None for one SEED leaves out (a warning says so)."""
        found = self._lookup_once(entry.behaviour, schema.pos)
        if found is not None:
            return found
        if schema.pos is None or schema.pos.file not in self.kb.seed_files:
            raise _no_schema(entry.behaviour, schema.pos)   # schema text promises every sub-task a schema
        if (schema.pos, parent, entry.behaviour) not in self.left_out:
            self.left_out.append((schema.pos, parent, entry.behaviour))
        return None

    @property
    def warnings(self) -> list[str]:
        """What the last instantiation left out, as SEED says it, at the parent schema's clause."""
        return [f"{pos}: warning: {left_out_message(parent, sub)}" for pos, parent, sub in self.left_out]

    def _present(self, parent: Term, schema: SchemaDef) -> list[Entry]:
        """The entries of `parent`'s schema that are built: those with a schema."""
        return [e for e in schema.entries if self._sub_schema(parent, schema, e) is not None]

    def _measure(self, label: Term, schema: SchemaDef) -> int:
        """Count the behaviours and levels the tree will have before building it, by a walk over
        schemas that counts each distinct sub-task once; raise at a cycle or a limit.

        A chain 100,000 deep stops at --max-depth after that many look-ups, and 40 levels of
        two uses of one sub-task (2^40 behaviours) are refused after 40, not after building
        --max-nodes behaviours."""
        size: dict[Term, int] = {}       # behaviours in the tree of a sub-task
        height: dict[Term, int] = {}     # its levels
        on_path = {label}
        # (label, schema, next entry, behaviours so far, levels below so far)
        stack: list[list] = [[label, schema, 0, 1, 0]]
        while True:
            frame = stack[-1]
            here, here_schema, k = frame[0], frame[1], frame[2]
            if k < len(here_schema.entries):
                frame[2] = k + 1
                entry = here_schema.entries[k]
                level = len(stack) + 1
                if level > self.max_depth:
                    self._too_deep(entry.behaviour, here_schema.pos)
                if not is_ground(entry.behaviour):
                    # Each look-up would bind the variable on its own, so siblings sharing it
                    # could disagree: the schema must bind it.
                    raise SchemalogError(
                        f"the sub-task {term_to_text(entry.behaviour)} of {term_to_text(here)} has "
                        f"variables the schema does not bind", here_schema.pos)
                found = self._sub_schema(here, here_schema, entry)
                if found is None:
                    continue
                sub, sub_schema = found
                if sub in on_path:
                    cycle = [f[0] for f in stack] + [sub]
                    raise SchemalogError(f"recursive schema: {' -> '.join(term_to_text(p) for p in cycle)}",
                                         here_schema.pos)
                known = size.get(sub)
                if known is None:
                    on_path.add(sub)
                    stack.append([sub, sub_schema, 0, 1, 0])
                    continue
                if level - 1 + height[sub] > self.max_depth:
                    self._too_deep(sub, here_schema.pos)
                frame[3] += known
                frame[4] = max(frame[4], height[sub])
                if frame[3] > self.max_nodes:
                    self._too_many(frame[3], here_schema.pos)
                continue
            stack.pop()
            on_path.discard(here)
            size[here], height[here] = frame[3], frame[4] + 1
            if not stack:
                return frame[3]
            up = stack[-1]
            up[3] += frame[3]
            up[4] = max(up[4], frame[4] + 1)
            if up[3] > self.max_nodes:
                self._too_many(up[3], up[1].pos)

    def _too_deep(self, at: Term, pos: SourcePos | None):
        raise SchemalogError(f"the task is deeper than {self.max_depth} levels at {term_to_text(at)} "
                             f"(raise the limit with --max-depth)", pos)

    def _too_many(self, counted: int, pos: SourcePos | None):
        raise SchemalogError(f"the task has more than {self.max_nodes:,} behaviours (at least {counted:,}, "
                             f"counted before building it; raise the limit with --max-nodes)", pos)

    def _declared_at(self, label: Term) -> SourcePos | None:
        """Where the task/1 fact that declares `label` was written (None: the command line named it)."""
        return next((c.pos for c in self.kb.clauses("task", 1) if not c.library and variant(c.head.args[0], label)),
                    None)

    def instantiate(self, label: Term) -> Behaviour:
        """Build the task tree rooted at `label` (a ground term)."""
        if not is_ground(label):
            raise SchemalogError(f"the task {term_to_text(label)} has variables: name a ground task "
                                 f"(its objects filled in, e.g. add(water) rather than add(X))",
                                 self._declared_at(label))
        self._lookups: dict[Term, tuple[Term, SchemaDef] | None] = {}
        self.left_out = []
        label, schema = self.lookup(label, None)
        self._measure(label, schema)   # within the limits and acyclic: the build below cannot fail on them
        root = _Frame(label, cond.TRUE, DEFAULT_IMPORTANCE, schema, 1, self._present(label, schema),
                      self.root_origins(label))
        stack = [root]
        while True:
            frame = stack[-1]
            if len(frame.built) < len(frame.pending):
                entry = frame.pending[len(frame.built)]
                sub, sub_schema = self._lookup_once(entry.behaviour, frame.schema.pos)
                # The sibling being built now is entry number len(frame.built).
                origins = self.child_origins(frame.label, len(frame.built), frame.schema.pos)
                stack.append(_Frame(sub, entry.releaser, entry.importance, sub_schema, frame.level + 1,
                                    self._present(sub, sub_schema), origins))
                continue
            stack.pop()
            node = Behaviour(
                label=frame.label, agent=self.agent(frame.label), objects=self.objects(frame.label),
                releaser=frame.releaser, post=frame.schema.post, children=tuple(frame.built),
                importance=frame.importance, origins=frame.origins, source=frame.schema.pos)
            if not stack:
                return node
            stack[-1].built.append(node)


def left_out_message(parent: Term, sub: Term) -> str:
    """SEED's word for a sub-task no schema applies to."""
    return (f"no semantic for {term_to_text(sub)} (a sub-task of {term_to_text(parent)}): "
            f"no schema applies to it; left out, as SEED does")


def _no_schema(label: Term, used_at: SourcePos | None) -> SchemalogError:
    where = f" (a sub-task in the schema at {used_at})" if used_at else ""
    return SchemalogError(
        f"no schema for {term_to_text(label)}{where}; define schema({term_to_text(label)}, Subtasks, Post), "
        f"or declare a primitive behaviour with schema({term_to_text(label)}, [], Post) or "
        f"behaviour({term_to_text(label)})", used_at)


def _missing_procedure(ball: Term) -> str | None:
    """`name/arity` of error(existence_error(procedure, PI), _), else None."""
    if isinstance(ball, Struct) and ball.name == "error" and len(ball.args) == 2:
        formal = ball.args[0]
        if (isinstance(formal, Struct) and formal.name == "existence_error" and len(formal.args) == 2
                and formal.args[0] == Atom("procedure")):
            return term_to_text(formal.args[1])
    return None


def _origin(t: Term) -> Origin:
    """Read origin(Label, Releaser, Post, Importance, Position, Slot)."""
    if not (isinstance(t, Struct) and t.name == "origin" and len(t.args) == 6):
        raise ValueError(f"expected origin(Label, Releaser, Post, Importance, Position, Slot), "
                         f"not {term_to_text(t)}")
    label, releaser, post, weight, position, slot = t.args
    if not (isinstance(weight, (Int, Float)) and isinstance(position, Int) and isinstance(slot, Int)):
        raise ValueError(f"importance, position and slot must be numbers in {term_to_text(t)}")
    problem = importance_problem(weight)
    if problem is not None:      # as a schema's weight: emphasis is computed in floats
        raise ValueError(f"the importance of {term_to_text(label)} {problem}")
    for name, index in (("position", position), ("slot", slot)):
        if not 0 <= index.value <= sys.maxsize:     # no list has more places
            raise ValueError(f"the {name} of {term_to_text(label)} is an index, from 0, "
                             f"not {shown_number(term_to_text(index))}")
    return Origin(label, cond.from_term(releaser), cond.from_term(post), weight.value,
                  position.value, slot.value)


def instantiate(kb: KnowledgeBase, label: Term, max_depth: int = DEFAULT_MAX_DEPTH,
                max_nodes: int = DEFAULT_MAX_NODES) -> Behaviour:
    """The paper's loadTaskFromLTM: the task tree of `label` in working memory."""
    return Instantiator(kb, max_depth, max_nodes).instantiate(label)


def declared_tasks(kb: KnowledgeBase) -> list[Term]:
    """The tasks a file declares with `task/1`, in order."""
    return [c.head.args[0] for c in kb.clauses("task", 1) if not c.library]


__all__ = ["Behaviour", "Origin", "TaskTree", "instantiate", "declared_tasks", "walk", "walk_with_depth",
           "count_nodes", "depth", "Instantiator", "left_out_message"]
