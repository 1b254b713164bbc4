"""Lint: diagnostics that catch task knowledge which loads but cannot work.

    Finding = (pos, severity, code, message, hint)     severity: "error" | "warning"
    Facts   = (initial, free)    the atoms true at the start (initial/1), and those that may be
                                 either (free/1)

The diagnostics read a knowledge base's schema/3 and task/1 clauses (positions from the
clauses, refined to the spot where an atom is written) and the ORIGINAL trees of its tasks.
Whether an atom can ever become true is decided by a relaxation of the executive: a behaviour
may run when its parent may run and its pre-condition can hold with every literal that can
ever hold (nothing is ever undone), a leaf that may run makes its post-condition possible, and a
composite's post-condition is possible once all its children's are (the world's completion).
What the relaxation calls impossible is impossible in every run; it may miss a dead end, never
invent one. Every pass is linear in the tree and the clauses (docs/lint.md).
"""

from __future__ import annotations

import bisect
import difflib
import functools
import os
import re
from array import array
from collections import deque
from dataclasses import dataclass

from ..errors import SchemalogError, SourcePos
from ..logic.kb import KnowledgeBase
from ..logic.terms import Atom, Float, Int, Str, Struct, Term, Var, iter_vars, term_to_text
from ..logic.unify import Bindings, rename, variant
from ..task import conditions as cond
from ..task.compress import original_of
from ..task.schema import schema_clauses
from ..task.tree import Behaviour, Instantiator, left_out_message

ERROR = "error"
WARNING = "warning"


@dataclass(frozen=True)
class Finding:
    """One diagnostic: where, how bad, which check, what is wrong, what to do."""

    pos: SourcePos | None
    severity: str
    code: str
    message: str
    hint: str = ""

    @property
    def file(self) -> str | None:
        return self.pos.file if self.pos else None

    @property
    def line(self) -> int | None:
        return self.pos.line if self.pos else None

    @property
    def column(self) -> int | None:
        return self.pos.column if self.pos else None

    @property
    def fix(self) -> str:
        """What to do about it ("" when lint has no advice)."""
        return self.hint

    def text(self, severity: str | None = None) -> str:
        """The finding as a compiler prints it, `severity` overriding its own (check warns)."""
        where = f"{self.pos}: " if self.pos else ""
        head = f"{where}{severity or self.severity}: {self.message} [{self.code}]"
        return head + (f"\n    fix: {self.hint}" if self.hint else "")

    def as_json(self) -> dict:
        return {"file": self.pos.file if self.pos else None, "line": self.pos.line if self.pos else None,
                "column": self.pos.column if self.pos else None, "severity": self.severity,
                "code": self.code, "message": self.message, "hint": self.hint}


@dataclass(frozen=True)
class Facts:
    """What holds at the start: initial/1's atoms, and free/1's, which may hold or not."""

    initial: frozenset = frozenset()
    free: frozenset = frozenset()


def error_finding(err: SchemalogError) -> Finding:
    """A load or instantiation error as an error finding."""
    return Finding(err.pos, ERROR, "load", err.message, "correct the file where the message points")


# ---------------------------------------------------------------------------
# The whole lint of a knowledge base

def lint_kb(kb: KnowledgeBase, max_depth: int, max_nodes: int,
            tasks: list[tuple[Term, SourcePos | None]] | None = None) -> tuple[Finding, ...]:
    """Every finding about a loaded knowledge base: its tasks (default: task/1's) instantiated,
    then linted."""
    findings: list[Finding] = []
    trees = []
    for task, pos in task_declarations(kb) if tasks is None else tasks:
        try:
            # A compressed file runs against its original's world: the original is what can work.
            instantiator = Instantiator(kb, max_depth, max_nodes)
            trees.append(original_of(instantiator.instantiate(task)))
            findings.extend(Finding(pos, WARNING, "no-semantic", left_out_message(parent, sub),
                                    f"define a schema for {term_to_text(sub)}, or remove it from "
                                    f"{term_to_text(parent)}'s schema")
                            for pos, parent, sub in instantiator.left_out)
        except SchemalogError as err:
            findings.append(Finding(err.pos or pos, ERROR, "load", f"task {term_to_text(task)}: {err.message}",
                                    "correct the schema the message names"))
    try:
        facts = facts_of(kb)
    except SchemalogError as err:
        return (*findings, error_finding(err))
    # Unused schemas are judged against the declared tasks, not one named on the command line.
    return (*findings, *lint_knowledge(kb, trees, facts, unused=tasks is None))


def task_declarations(kb: KnowledgeBase) -> list[tuple[Term, SourcePos | None]]:
    """The distinct tasks task/1 declares, each with its first declaration's place."""
    seen: dict[str, tuple[Term, SourcePos | None]] = {}
    for c in kb.clauses("task", 1):
        if not c.library:
            seen.setdefault(_key_text(c.head.args[0]), (c.head.args[0], c.pos))
    return list(seen.values())


def facts_of(kb: KnowledgeBase) -> Facts:
    """initial/1 and free/1 of the knowledge base (SchemalogError when they cannot be read)."""
    from ..logic.exceptions import PrologError, StepLimitExceeded
    from .verify import free_atoms
    from .world import initial_state

    try:
        free = frozenset(free_atoms(kb, Behaviour(Atom("none")))) if kb.clauses("free", 1) else frozenset()
    except (PrologError, StepLimitExceeded) as err:
        pos = kb.clauses("free", 1)[0].pos
        raise SchemalogError(f"asking free/1 failed: {err}", pos) from None
    return Facts(frozenset(initial_state(kb)), free)


def lint_knowledge(kb: KnowledgeBase, trees: list[Behaviour], facts: Facts,
                   unused: bool = True) -> tuple[Finding, ...]:
    """The findings about the clauses of `kb` and the original trees of its tasks (with `unused`,
    also the schemas none of those trees uses)."""
    found: list[Finding] = []
    found += duplicate_tasks(kb)
    found += shadowed_schemas(kb)
    if trees and unused:
        shadowed = {f.pos for f in found if f.code == "shadowed-schema"}
        found += [f for f in unused_schemas(kb, trees) if f.pos not in shadowed]
    for tree in trees:
        found += lint_tree(tree, facts, bool(kb.clauses("object", 1)))
    return _distinct(found)


def lint_tree(tree: Behaviour, facts: Facts, declares_objects: bool = False) -> list[Finding]:
    """The findings about one original task tree."""
    flat = _Flat(tree)
    reach = _Reachability(flat, facts)
    found: list[Finding] = []
    cycles, explained = releaser_cycles(flat, reach)
    found += cycles
    found += unreachable_releasers(flat, reach, facts, explained)
    found += undone_posts(flat)
    found += posts_not_produced(flat)
    found += shared_posts(flat)
    found += dead_behaviours(flat, reach)
    found += missing_gripper_commands(flat)
    if declares_objects:
        found += undeclared_objects(flat)
    if not any(f.severity == ERROR for f in found) and not reach.accomplishable(0):
        found.append(Finding(tree.source, ERROR, "task-cannot-complete",
                             f"the task {tree.name} can never be accomplished from the initial state: "
                             f"{cond.to_text(tree.post)} is never made true",
                             "declare the initial state with initial/1, or check the post-conditions"))
    return found


def task_cannot_complete(findings: tuple[Finding, ...] | list[Finding]) -> Finding | None:
    """The error that best explains why a task cannot complete (the first error), if any."""
    return next((f for f in findings if f.severity == ERROR), None)


# ---------------------------------------------------------------------------
# The tree, flat

class _Flat:
    """A tree in pre-order: each node's parent, children and subtree end (nesting in O(1))."""

    def __init__(self, tree: Behaviour) -> None:
        self.nodes: list[Behaviour] = []
        # Machine integers, and one empty tuple for every leaf: on a task of 100,000
        # behaviours a list per leaf and an int object per index cost tens of MB.
        self.parent = array("l")
        self.children: list[list[int] | tuple[()]] = []
        self.end = array("l")
        stack: list[tuple[Behaviour, int, bool]] = [(tree, -1, False)]
        open_: list[int] = []
        while stack:
            node, parent, closing = stack.pop()
            if closing:
                self.end[open_.pop()] = len(self.nodes)
                continue
            i = len(self.nodes)
            self.nodes.append(node)
            self.parent.append(parent)
            self.children.append([] if node.children else ())
            self.end.append(i + 1)
            if parent >= 0:
                self.children[parent].append(i)
            if node.children:
                open_.append(i)
                stack.append((node, -1, True))
                stack.extend((c, i, False) for c in reversed(node.children))
        self.post_lits = [_literal_keys(n.post) for n in self.nodes]

    def __len__(self) -> int:
        return len(self.nodes)

    def nested(self, i: int, j: int) -> bool:
        """Whether one of i, j is an ancestor of the other (or they are the same node)."""
        return i <= j < self.end[i] or j <= i < self.end[j]

    def releaser_pos(self, i: int) -> SourcePos | None:
        """Where node i's releaser is written: its parent's schema (the task's own, for the root)."""
        p = self.parent[i]
        return self.nodes[p].source if p >= 0 else self.nodes[i].source


_NO_LITERALS: tuple = ()


def _literal_keys(c: cond.Condition) -> tuple[tuple[Term, bool], ...]:
    """The distinct (atom, positive) of the literals of `c`, left to right; without a
    generator and a dict for the common conditions, one literal or none."""
    kind = type(c)
    if kind is cond.Lit:
        return ((c.atom, c.positive),)
    if kind is cond.Const:
        return _NO_LITERALS
    return tuple(dict.fromkeys((lit.atom, lit.positive) for lit in cond.literals(c)))


class _Reachability:
    """The relaxed executive (the module's docstring): which behaviours may ever run and which
    literals may ever hold, by a worklist over the literals each condition reads (linear)."""

    def __init__(self, flat: _Flat, facts: Facts) -> None:
        self.flat = flat
        self.can_true: set[Term] = set(facts.initial) | set(facts.free)
        self.stuck_true: set[Term] = set(facts.initial) - set(facts.free)   # true, never made false (yet)
        n = len(flat)
        self.runnable = [False] * n
        nnf_of: dict = {}
        self.pre = pres = []
        for node in flat.nodes:
            pre = node.pre         # made anew by each call: once per node, and NNF once per distinct one
            if type(pre) is cond.Lit or type(pre) is cond.Const:
                pres.append(pre)   # its own NNF
                continue
            found = nnf_of.get(pre)
            if found is None:
                found = nnf_of[pre] = cond.nnf(pre)
            pres.append(found)
        watch_pre: dict[tuple, list[int]] = {}
        watch_post: dict[tuple, list[int]] = {}
        for i, c in enumerate(self.pre):
            for lit in _literal_keys(c):
                watching = watch_pre.get(lit)
                if watching is None:
                    watch_pre[lit] = [i]
                else:
                    watching.append(i)
        self.missing = [0] * n
        for i, lits in enumerate(flat.post_lits):
            for lit in lits:
                watching = watch_post.get(lit)
                if watching is None:
                    watch_post[lit] = [i]
                else:
                    watching.append(i)
                if not self.possible(lit):
                    self.missing[i] += 1
        self.done_children = [0] * n
        events: deque = deque()
        ready: list[int] = []

        def make_possible(lit: tuple) -> None:
            atom, positive = lit
            if positive and atom not in self.can_true:
                self.can_true.add(atom)
                events.append(lit)
            elif not positive and atom in self.stuck_true:
                self.stuck_true.discard(atom)
                events.append(lit)

        def child_done(j: int) -> None:
            p = flat.parent[j]
            if p >= 0:
                self.done_children[p] += 1
                if self.done_children[p] == len(flat.children[p]):
                    for lit in flat.post_lits[p]:     # the world completes p
                        make_possible(lit)

        def try_run(i: int) -> None:
            p = flat.parent[i]
            if not self.runnable[i] and (p < 0 or self.runnable[p]) and self.may_hold(self.pre[i]):
                self.runnable[i] = True
                ready.append(i)

        for i in range(n):
            if self.missing[i] == 0:
                child_done(i)
        try_run(0)
        while ready or events:
            while ready:
                i = ready.pop()
                if not flat.children[i]:
                    for lit in flat.post_lits[i]:
                        make_possible(lit)
                for k in flat.children[i]:
                    try_run(k)
            if events:
                lit = events.popleft()
                for i in watch_pre.get(lit, ()):
                    try_run(i)
                for j in watch_post.get(lit, ()):
                    self.missing[j] -= 1
                    if self.missing[j] == 0:
                        child_done(j)

    def possible(self, lit: tuple) -> bool:
        atom, positive = lit
        return atom in self.can_true if positive else atom not in self.stuck_true

    def may_hold(self, c: cond.Condition) -> bool:
        """Whether an NNF condition can hold when every possible literal is taken as true."""
        if isinstance(c, cond.Const):
            return c.value
        if isinstance(c, cond.Lit):
            return self.possible((c.atom, c.positive))
        if isinstance(c, cond.And):
            return all(self.may_hold(i) for i in c.items)
        if isinstance(c, cond.Or):
            return any(self.may_hold(i) for i in c.items)
        return True    # not in NNF: cannot happen after cond.nnf; never claim impossible

    def accomplishable(self, i: int) -> bool:
        return self.missing[i] == 0

    def blocked(self) -> list[int]:
        """The behaviours that never run although their parent may (the topmost ones)."""
        flat = self.flat
        return [i for i in range(len(flat)) if not self.runnable[i]
                and (flat.parent[i] < 0 or self.runnable[flat.parent[i]])]


# ---------------------------------------------------------------------------
# Tree diagnostics

def unreachable_releasers(flat: _Flat, reach: _Reachability, facts: Facts, explained: set[int]) -> list[Finding]:
    """An atom a releaser reads that can never become true (or false, for `not atom`)."""
    producers: dict[tuple, list[int]] = {}
    for i, lits in enumerate(flat.post_lits):
        for lit in lits:
            producers.setdefault(lit, []).append(i)
    known: list[str] | None = None
    found: list[tuple[str, Finding]] = []     # (kind of cause, finding)
    for i in reach.blocked():
        if i in explained:
            continue
        node = flat.nodes[i]
        for lit in dict.fromkeys((x.atom, x.positive) for x in cond.literals(reach.pre[i])):
            if reach.possible(lit):
                continue
            atom, positive = lit
            text = term_to_text(atom)
            written = text if positive else f"not {text}"
            makers = producers.get((atom, positive), [])
            if makers:
                kind = "derived" if any(flat.children[m] for m in makers) else "chained"
                distinct = list(dict.fromkeys(flat.nodes[m].name for m in makers))
                one = len(distinct) == 1
                names = ", ".join(distinct[:4]) + (", ..." if len(distinct) > 4 else "")
                why = f"only {names} make{'s' if one else ''} it {'true' if positive else 'false'}, " \
                      f"and {'it' if one else 'they'} can never run"
                hint = "release those behaviours first, or declare the atom's initial value"
                if not facts.initial and not facts.free:
                    hint += " (no initial/1 declares an initial state: nothing is true at the start)"
            elif positive:
                kind = "root"
                why = "no post-condition, initial/1, free/1 or completion ever makes it true"
                if known is None:
                    known = sorted({term_to_text(a) for a in reach.can_true})
                close = difflib.get_close_matches(text, known, n=1, cutoff=0.75)
                hint = (f"did you mean {close[0]}? " if close else "") + \
                    f"correct the atom, declare initial({text}) or free({text}), or give a behaviour " \
                    f"the post-condition {text}"
            else:
                kind = "root"
                why = "it holds initially (initial/1) and no post-condition ever makes it false"
                hint = f"give a behaviour the post-condition not {text}, or declare free({text})"
            pos = _locate(flat.releaser_pos(i), text)
            found.append((kind, Finding(pos, ERROR, "unreachable-releaser",
                                        f"{node.name} can never be released: {written} never holds ({why})", hint)))
    # Report the causes, not their consequences: an atom nothing makes true explains the rest;
    # failing that (a deadlock), the atoms only primitive behaviours make true (kukahand.free),
    # not the sub-tasks' posts that follow from them.
    for kind in ("root", "chained", "derived"):
        chosen = [f for k, f in found if k == kind]
        if chosen:
            return chosen
    return []


def undone_posts(flat: _Flat) -> list[Finding]:
    """Siblings whose post-conditions contradict: the later one undoes the earlier one's, which
    is then enabled again (a livelock), and their parent never has them all accomplished."""
    found = []
    for p in range(len(flat)):
        seen: dict[tuple, int] = {}
        for k in flat.children[p]:
            for atom, positive in flat.post_lits[k]:
                earlier = seen.get((atom, not positive))
                if earlier is not None:
                    a, b = flat.nodes[earlier], flat.nodes[k]
                    was = term_to_text(atom) if not positive else f"not {term_to_text(atom)}"
                    found.append(Finding(
                        _locate(flat.nodes[p].source, b.name), ERROR, "undone-post",
                        f"{b.name} undoes {was}, the post-condition of {a.name}, an earlier behaviour of "
                        f"{flat.nodes[p].name}: {a.name} is enabled again (a livelock) and "
                        f"{flat.nodes[p].name} can never complete",
                        f"end {flat.nodes[p].name} with one gripper command and give the other to its own "
                        f"sub-task (docs/lint.md)"))
                seen.setdefault((atom, positive), k)
    return found


def posts_not_produced(flat: _Flat) -> list[Finding]:
    """A sub-task whose post-condition its own behaviours undo: the last of its behaviours that
    sets the atom sets it the other way, so completing it contradicts what it just did."""
    found = []
    for p in range(len(flat)):
        if not flat.children[p]:
            continue
        last: dict[Term, tuple[bool, int]] = {}
        for k in flat.children[p]:
            for atom, positive in flat.post_lits[k]:
                last[atom] = (positive, k)
        for atom, positive in flat.post_lits[p]:
            if atom in last and last[atom][0] != positive:
                k = last[atom][1]
                text = term_to_text(atom) if positive else f"not {term_to_text(atom)}"
                found.append(Finding(
                    _locate(flat.nodes[p].source, term_to_text(atom)), WARNING, "post-not-produced",
                    f"the post-condition {text} of {flat.nodes[p].name} is not what its behaviours produce: "
                    f"{flat.nodes[k].name}, the last that sets {term_to_text(atom)}, sets it the other way",
                    "write the post-condition its behaviours leave true, or reorder them"))
    return found


def dead_behaviours(flat: _Flat, reach: _Reachability) -> list[Finding]:
    """A behaviour whose post-condition holds from the start and can never be undone: it is
    accomplished whenever it could be released, so it never runs (the topmost such one)."""
    found = []
    i = 0
    while i < len(flat):
        lits = flat.post_lits[i]
        forever = lits and reach.runnable[i] and all(
            atom in reach.stuck_true if positive else atom not in reach.can_true for atom, positive in lits)
        if not forever:
            i += 1
            continue
        node = flat.nodes[i]
        post = cond.to_text(node.post)
        if flat.parent[i] < 0:
            found.append(Finding(node.source, WARNING, "dead-behaviour",
                                 f"the task {node.name} is accomplished from the start: {post} holds initially "
                                 f"and nothing makes it false, so nothing runs",
                                 "check initial/1 against the task's post-condition"))
        else:
            parent = flat.nodes[flat.parent[i]]
            found.append(Finding(
                _locate(parent.source, node.name), WARNING, "dead-behaviour",
                f"{node.name} never runs: its post-condition {post} holds from the start and nothing before or "
                f"after it makes it false, so it is accomplished whenever it could be released",
                f"a behaviour of {parent.name} should undo {post} first (a take ends with gripper(close)), "
                f"or the initial state is wrong"))
        i = flat.end[i]            # what is inside a behaviour that never runs never runs either
    return found


def missing_gripper_commands(flat: _Flat) -> list[Finding]:
    """A learned sub-task (its actions in a chain, docs/syntax.md) that commands no gripper, in a
    task whose other learned sub-tasks do: its actions leave the gripper as they found it."""
    from ..task.schema import DEFAULT_AGENT

    learned = [p for p in range(len(flat)) if _is_learned_chain(flat, p)]
    commanding = {p for p in learned if any(flat.nodes[k].agent != DEFAULT_AGENT for k in flat.children[p])}
    if not commanding:
        return []            # a task with no gripper commands at all is not learned the paper's way
    agents = sorted({flat.nodes[k].agent for p in commanding for k in flat.children[p]} - {DEFAULT_AGENT})
    found = []
    for p in learned:
        if p in commanding:
            continue
        node = flat.nodes[p]
        found.append(Finding(
            _locate(node.source, node.name), WARNING, "no-gripper-command",
            f"the learned sub-task {node.name} commands no {' or '.join(agents)}: its {len(flat.children[p])} "
            f"actions leave the gripper as they found it, unlike the task's other learned sub-tasks",
            "end a take with gripper(close) and a pour or a mix with gripper(open) (docs/syntax.md, "
            "Learned sub-tasks)"))
    return found


def _is_learned_chain(flat: _Flat, p: int) -> bool:
    """Whether node p is a learned sub-task: two or more actions, the first released by `true`,
    each next one by the post-condition of the one before."""
    kids = flat.children[p]
    if len(kids) < 2 or any(flat.children[k] for k in kids):
        return False
    nodes = [flat.nodes[k] for k in kids]
    return nodes[0].releaser == cond.TRUE and all(b.releaser == a.post for a, b in zip(nodes, nodes[1:]))


def shared_posts(flat: _Flat) -> list[Finding]:
    """Two different behaviours (neither inside the other) with the same post-condition literal
    that nothing undoes: whichever completes first accomplishes the other, which never runs."""
    undone = {(atom, not positive) for lits in flat.post_lits for atom, positive in lits}
    reps: dict[tuple, list[int]] = {}
    for i, lits in enumerate(flat.post_lits):
        p = flat.parent[i]
        for lit in lits:
            if lit not in undone and (p < 0 or lit not in flat.post_lits[p]):
                reps.setdefault(lit, []).append(i)    # the topmost of a chain that shares it
    found = []
    for (atom, positive), owners in reps.items():
        if len(owners) < 2:
            continue
        pair = _unnested_pair(flat, owners)
        if pair is None:
            continue
        a, b = (flat.nodes[i] for i in pair)
        text = term_to_text(atom) if positive else f"not {term_to_text(atom)}"
        found.append(Finding(
            _locate(b.source, term_to_text(atom)), ERROR, "shared-post",
            f"{a.name} and {b.name} have the same post-condition {text}, which nothing undoes: whichever "
            f"completes first accomplishes the other, which then never runs",
            "give each behaviour its own post-condition (a unique aN.done, or one that names its object)"))
    return found


def _unnested_pair(flat: _Flat, owners: list[int], most: int = 2000) -> tuple[int, int] | None:
    """Two owners with different labels, neither inside the other (bounded search)."""
    tried = 0
    for x, i in enumerate(owners):
        for j in owners[x + 1:]:
            tried += 1
            if tried > most:
                return None
            if flat.nodes[i].label != flat.nodes[j].label and not flat.nested(i, j):
                return i, j
    return None


def releaser_cycles(flat: _Flat, reach: _Reachability) -> tuple[list[Finding], set[int]]:
    """Siblings each waiting for another's post-condition: none can start first. An error when
    none of them can ever run (then the cycle explains their releasers), else a warning."""
    found: list[Finding] = []
    explained: set[int] = set()
    for p in range(len(flat)):
        kids = flat.children[p]
        if len(kids) < 2:
            continue
        makers: dict[Term, list[int]] = {}
        for x, k in enumerate(kids):
            for atom, positive in flat.post_lits[k]:
                if positive:
                    makers.setdefault(atom, []).append(x)
        succ: list[list[int]] = [[] for _ in kids]
        for y, k in enumerate(kids):
            for lit in cond.literals(reach.pre[k]):
                if lit.positive:
                    for x in makers.get(lit.atom, ()):
                        succ[x].append(y)
        for component in _cycles(succ):
            members = [kids[x] for x in component]
            names = ", ".join(flat.nodes[m].name for m in members)
            stuck = not any(reach.runnable[m] for m in members)
            if stuck:
                explained.update(members)
            found.append(Finding(
                _locate(flat.nodes[p].source, flat.nodes[members[0]].name), ERROR if stuck else WARNING,
                "releaser-cycle",
                f"the releasers of {names} (under {flat.nodes[p].name}) form a cycle: each waits for "
                f"another's post-condition" + (", so none can ever start" if stuck else
                                               "; compress leaves them unmerged"),
                "release one of them without the others (true, or an atom of the initial state)"))
    return found, explained


def _cycles(succ: list[list[int]]) -> list[list[int]]:
    """The strongly connected components with a cycle (Tarjan's, iteratively), in index order."""
    n = len(succ)
    index = [-1] * n
    low = [0] * n
    on_stack = [False] * n
    stack: list[int] = []
    found: list[list[int]] = []
    counter = 0
    for root in range(n):
        if index[root] >= 0 or not succ[root]:
            continue
        work = [(root, 0)]
        while work:
            v, k = work.pop()
            if k == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on_stack[v] = True
            if k < len(succ[v]):
                work.append((v, k + 1))
                w = succ[v][k]
                if index[w] < 0:
                    work.append((w, 0))
                elif on_stack[w]:
                    low[v] = min(low[v], index[w])
                continue
            if work:
                u = work[-1][0]
                low[u] = min(low[u], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack[w] = False
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1 or v in succ[v]:
                    found.append(sorted(component))
    return sorted(found)


def undeclared_objects(flat: _Flat) -> list[Finding]:
    """An argument of a behaviour that its conditions treat as an object (`O.prop`) but that
    object/1 does not declare: the behaviour acts on nothing, and --scene does not place it."""
    objects = {o for node in flat.nodes for o in node.objects}
    owners: set[Term] = set()
    for node in flat.nodes:
        for c in (node.releaser, node.post):
            for lit in cond.literals(c):
                a = lit.atom
                if isinstance(a, Struct) and a.name == "." and len(a.args) == 2:
                    owners.add(a.args[0])
    found, seen = [], set()
    for node in flat.nodes:
        for arg in node.label.args if isinstance(node.label, Struct) else ():
            if isinstance(arg, (Atom, Int, Float, Str)) and arg in owners and arg not in objects and arg not in seen:
                seen.add(arg)
                text = term_to_text(arg)
                found.append(Finding(_locate(node.source, node.name), WARNING, "undeclared-object",
                                     f"{text} is an argument of {node.name} and the owner of a condition "
                                     f"({text}.…), but object/1 does not declare it: {node.name} acts on "
                                     f"nothing", f"declare object({text})"))
    return found


# ---------------------------------------------------------------------------
# Clause diagnostics

def duplicate_tasks(kb: KnowledgeBase) -> list[Finding]:
    """A task that task/1 declares more than once."""
    first: dict[str, SourcePos | None] = {}
    found = []
    for c in kb.clauses("task", 1):
        if c.library:
            continue
        key = _key_text(c.head.args[0])
        if key in first:
            where = f" (first at {first[key]})" if first[key] else ""
            found.append(Finding(c.pos, WARNING, "duplicate-task", f"the task {key} is declared twice{where}",
                                 "keep one task/1 declaration"))
        else:
            first[key] = c.pos
    return found


def shadowed_schemas(kb: KnowledgeBase) -> list[Finding]:
    """A schema no look-up can reach: an earlier schema fact covers every sub-task it names (two
    schemas for one sub-task; instantiation always takes the first)."""
    groups: dict[tuple, list] = {}
    for c in schema_clauses(kb):
        task = c.head.args[0]
        key = (task.name, len(task.args)) if isinstance(task, Struct) else (term_to_text(task), 0)
        groups.setdefault(key, []).append(c)
    found = []
    for clauses in groups.values():
        if len(clauses) < 2:
            continue
        exact: dict[Term, object] = {}
        general = []       # earlier facts whose task has variables: they may cover later ones
        for c in clauses:
            task = c.head.args[0]
            ground = not any(True for _ in iter_vars(task))
            earlier = exact.get(task) if ground else None
            if earlier is None:
                earlier = next((g for g in general if _subsumes(g.head.args[0], task)), None)
            if earlier is not None:
                where = f"the schema at {earlier.pos}" if earlier.pos else "an earlier schema"
                if variant(c.head, earlier.head) and variant(c.body, earlier.body):
                    found.append(Finding(c.pos, WARNING, "shadowed-schema",
                                         f"the schema of {term_to_text(task)} repeats {where} word for word",
                                         "delete one of the two"))
                else:
                    found.append(Finding(c.pos, ERROR, "shadowed-schema",
                                         f"the schema of {term_to_text(task)} is never used: {where} "
                                         f"({term_to_text(earlier.head.args[0])}) answers every look-up of it "
                                         f"first", "delete one of the two schemas, or make the earlier one "
                                                   "more specific"))
            if c.body == Atom("true"):
                if ground:
                    exact.setdefault(task, c)
                elif len(general) < 200:
                    general.append(c)
    return found


def _subsumes(general: Term, specific: Term) -> bool:
    """Whether every instance of `specific` is an instance of `general` (subsumes_term/2)."""
    frozen = _frozen(rename(specific))
    return Bindings().unify(rename(general), frozen)


def _frozen(term: Term) -> Term:
    """`term` with each variable replaced by its own fresh constant."""
    names: dict[Var, Atom] = {}
    for v in iter_vars(term):
        names.setdefault(v, Atom(f"$frozen{len(names)}"))
    if not names:
        return term
    b = Bindings()
    for v, a in names.items():
        b.unify(v, a)
    return b.resolve(term)


def unused_schemas(kb: KnowledgeBase, trees: list[Behaviour]) -> list[Finding]:
    """A schema with sub-tasks that no declared task uses (primitives are a vocabulary: not listed)."""
    used = {node.source for tree in trees for node in _walk(tree)}
    tasks = ", ".join(tree.name for tree in trees)
    found = []
    for c in schema_clauses(kb):
        items = c.head.args[1]
        if c.pos is None or c.pos in used or (isinstance(items, Atom) and items.name == "[]"):
            continue
        if isinstance(items, Var) and c.body == Atom("true"):
            continue
        found.append(Finding(c.pos, WARNING, "unused-schema",
                             f"the schema of {term_to_text(c.head.args[0])} is used by no declared task ({tasks})",
                             "delete it, or use it as a sub-task; declare its task with task/1 if it is one"))
    return found


def _walk(tree: Behaviour):
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node
        stack.extend(node.children)


# ---------------------------------------------------------------------------
# Helpers

def _key_text(term: Term) -> str:
    return term_to_text(term, names={v: "_" for v in iter_vars(term)})


def _locate(pos: SourcePos | None, needle: str, span: int = 400) -> SourcePos | None:
    """The place of `needle` within the clause that starts at `pos`, else `pos`."""
    if pos is None:
        return None
    try:
        stat = os.stat(pos.file)
    except (OSError, ValueError):
        return pos
    name = os.path.abspath(pos.file)
    lines = _source_lines(name, stat.st_mtime_ns, stat.st_size)
    if not lines:
        return pos
    # A word or dotted word (`a7.done`, the commonest needle) is looked up in its line's index,
    # not searched for: a releaser of 100,000 literals has 100,000 findings on one line, and a
    # search from the clause's start for each was quadratic (issue 32).
    word = _WORDS.fullmatch(needle) is not None
    for k in range(pos.line - 1, min(len(lines), pos.line - 1 + span)):
        start = pos.column - 1 if k == pos.line - 1 else 0
        at = -1
        if word:
            columns = _words_of(name, stat.st_mtime_ns, stat.st_size, k).get(needle, ())
            j = bisect.bisect_left(columns, start)
            if j < len(columns):
                at = columns[j]
        if at < 0:                     # inside a longer word, or no word: the first occurrence
            at = lines[k].find(needle, start)
        if at >= 0:
            return SourcePos(pos.file, k + 1, at + 1)
    return pos


_WORDS = re.compile(r"[A-Za-z0-9_]+(?:\.[A-Za-z0-9_]+)*")


@functools.lru_cache(maxsize=16)
def _words_of(name: str, mtime_ns: int, size: int, k: int) -> dict[str, list[int]]:
    """The columns (0-based, ascending) where each whole word or dotted word of line `k` starts."""
    found: dict[str, list[int]] = {}
    for m in _WORDS.finditer(_source_lines(name, mtime_ns, size)[k]):
        found.setdefault(m.group(), []).append(m.start())
    return found


@functools.lru_cache(maxsize=8)     # a few files, read once per lint; a changed file is read again
def _source_lines(name: str, mtime_ns: int, size: int) -> list[str] | None:
    """A regular file's lines, or None: a FIFO, a device or a missing file is not reread."""
    try:
        if os.path.isfile(name) and size <= 64 << 20:
            with open(name, encoding="utf-8", errors="replace") as handle:
                return handle.read().splitlines()
    except OSError:
        pass
    return None


def _distinct(found: list[Finding]) -> tuple[Finding, ...]:
    """Each finding once (two uses of one sub-task give the same finding twice), by place."""
    unique = list(dict.fromkeys(found))
    return tuple(sorted(unique, key=lambda f: ((f.pos.file, f.pos.line, f.pos.column) if f.pos else ("", 0, 0))))


__all__ = ["Finding", "Facts", "lint_kb", "lint_knowledge", "lint_tree", "facts_of", "error_finding",
           "task_cannot_complete", "ERROR", "WARNING"]
