"""Congruence: a subtree identical in two programs taken, on both sides, as one opaque node whose
events are its ticks and halts (docs/semantics.md, "Congruence").

    abstract(pa, pb) -> Abstraction | None   both programs with their maximal common subtrees
                                              replaced, or None when there is none to replace
    key of a subtree = its expanded structure  node type, form, attributes, rule key, decorator
                                              flag, SubTree calls above it, its children's keys
    label of an instance = (key's number, occurrence in pre-order among the chosen instances of
                                              that key): a bijection between a's and b's instances

The abstract node's tick is an event whose identity carries its status before the tick (a parent
may reset a finished child silently, or tick it again unreset: the subtree behaves differently);
its outcome is any status the subtree's root may return (SKIPPED only where the subtree can skip,
then with the status the root is left in). Its halt is an event too. Equal abstract programs have
equal concrete ones: an instance's memory is a function of the events of its label, and its
events, statuses and errors are a function of that memory, the run's history and the
environment, the same in both. Only a proof may come from here; bt/prove.py falls back to the
concrete programs when the abstract ones are told apart (the difference may be spurious).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace
from types import MappingProxyType

from schemalog.bt import semantics
from schemalog.bt.model import Node
from schemalog.bt.semantics import (ACTION_OUTCOMES, IDLE, RULES, RUNNING, SKIPPED, PNode, Program,
                                    Rule, Status, _Run)

TYPE = "\0congruent"                 # no XML document can name a type so (NUL)


def _identity(n: PNode, status: Status) -> tuple:
    return (TYPE, n.node.ports + (("status", status.value),))


def _tick(run: _Run, n: PNode) -> Status:
    """The abstract tick: an event (its label and the status before it); the environment says
    what the subtree returns and, for a SKIPPED (which executeTick does not store), the status
    its root is left in: as it was, IDLE (a `_while` or the rule halted it), or RUNNING where
    the root's rule sets it before ticking its children (the table's rules set no other)."""
    prev = run.status(n)
    skips = n.node.attr("skips")
    left = () if skips is None else (IDLE, RUNNING) if skips == "yes" else (IDLE,)
    options = ACTION_OUTCOMES + tuple((SKIPPED, s) for s in left + ((prev,) if prev not in left else ()) if left)
    outcome = run.event("tick", n, options, _identity(n, prev))
    if isinstance(outcome, tuple):
        run.set_status(n, outcome[1])
        return SKIPPED
    return outcome


def _halt(run: _Run, n: PNode) -> None:
    """The abstract halt (haltNode): an event; every halt in the table leaves the root IDLE. One
    case is no event: a root that is not RUNNING, of a rule of the table, without `_onHalted`
    (`quiet`). Only Tree::haltTree's own haltNode on the tree's root halts such a node; it halts
    no child (haltChild halts RUNNING ones only), and what it puts back the visitor's haltNode
    right after puts back again before any tick reads it: nothing a run can see."""
    if run.status(n) is not RUNNING and n.node.attr("quiet") == "yes":
        run.set_status(n, IDLE)
        return
    run.event("halt", n, (None,), _identity(n, run.status(n)))
    run.set_status(n, IDLE)


def _visited(run: _Run, n: PNode) -> None:
    """Tree::haltTree's visit of the subtree: an event (its label, its status): inside, it puts
    back what its nodes keep and runs their `_onHalted` scripts, as its history decides."""
    run.event("visit", n, (None,), _identity(n, run.status(n)))
    run.set_status(n, IDLE)


CONGRUENT = Rule(_tick, _halt, visit=_visited)
RULE_KEY = "\0congruent"


@dataclass(frozen=True)
class Abstraction:
    """Both programs with their common subtrees as opaque nodes; how many and how big they were."""

    a: Program
    b: Program
    subtrees: int                    # instances replaced in each program
    nodes: int                       # nodes they held, in a


# Rules whose tick returns SKIPPED only when a child returned it (leaves never): with no
# `_skipIf`/`_while` in it, a subtree of these never returns SKIPPED. RunOnce (then_skip),
# Precondition (`else`), an opaque node with children and a user's rule may originate one.
_PASSING = frozenset(id(RULES[t]) for t in RULES if t not in ("RunOnce", "Precondition"))
# Rules that never return SKIPPED, whatever their child returns (SKIPPED becomes FAILURE,
# RUNNING): Nav2's RateController, KeepRunningUntilFailure
_BLOCKING = frozenset(id(RULES[t]) for t in ("RateController", "KeepRunningUntilFailure") if t in RULES)
# Rules that return SKIPPED only when every child did (all_skipped, skipped == count)
_ALL = frozenset(id(RULES[t]) for t in ("Sequence", "Fallback", "AsyncSequence", "AsyncFallback", "SequenceWithMemory",
                                         "ReactiveSequence", "ReactiveFallback", "Parallel", "ParallelAll",
                                         "PipelineSequence") if t in RULES)
# Rules that never set their node's own status (executeTick does, after them)
_KEEPING = frozenset(id(RULES[t]) for t in RULES if t == "PipelineSequence" or t.startswith("Switch")) | {id(semantics.OPAQUE)}
_LEAVES = frozenset(id(getattr(semantics, name)) for name in ("ACTION", "SYNC_ACTION", "STATEFUL_ACTION", "CONDITION")
                    if hasattr(semantics, name))


def _ours(rule: Rule | None) -> bool:
    """Whether the rule is one of the table's (semantics.py's functions): it reads and writes only
    its node's memory and its children's statuses, and every halt leaves the node IDLE."""
    return rule is not None and all(f is None or getattr(f, "__module__", None) == semantics.__name__
                                    for f in (rule.tick, rule.halt))


class _Index:
    """Every node of a program with its key's number, size, eligibility and whether it may skip."""

    def __init__(self, prog: Program, other: Program, table: dict) -> None:
        self.nodes: list[tuple[PNode, int]] = []
        self.size: dict[int, int] = {}
        self.eligible: dict[int, bool] = {}
        self.skips: dict[int, str | None] = {}
        self.prog = prog
        self._visit(prog.root, other, table)

    def _visit(self, n: PNode, other: Program, table: dict) -> int:
        slot = len(self.nodes)
        self.nodes.append((n, -1))
        kids = tuple(self._visit(c, other, table) for c in n.kids)
        node = n.node
        key = table.setdefault((node.type, node.form, tuple(sorted(node.attrs)), n.rule, n.decorator, n.context, kids), len(table))
        self.nodes[slot] = (n, key)
        if key not in self.size:
            rule = self.prog.rules.get(n.rule)
            self.size[key] = 1 + sum(self.size[k] for k in kids)
            self.eligible[key] = (_ours(rule) and other.rules.get(n.rule) is rule
                                  and all(self.eligible[k] for k in kids))
            if node.attr("_skipIf") is not None or node.attr("_while") is not None:
                skips = True
            elif not n.kids:
                skips = id(rule) not in _LEAVES | _PASSING and rule is not semantics.OPAQUE
            elif id(rule) in _BLOCKING:
                skips = False
            else:
                kid_skips = [self.skips[k] is not None for k in kids]
                skips = id(rule) not in _PASSING or (all(kid_skips) if id(rule) in _ALL else any(kid_skips))
            self.skips[key] = ("keeps" if id(rule) in _KEEPING else "yes") if skips else None
        return key


def _choose(index: _Index, allowed: set[int]) -> dict[tuple, int]:
    """The maximal subtrees (top-down, pre-order) whose key is allowed: path -> key."""
    chosen: dict[tuple, int] = {}
    for n, key in index.nodes:
        if key in allowed and not any(n.path[:i] in chosen for i in range(len(n.path))):
            chosen[n.path] = key
    return chosen


def _rebuild(n: PNode, chosen: dict[tuple, int], labels: dict[tuple, str], skips: dict[int, str | None]) -> PNode:
    if n.path in chosen:
        skip = skips[chosen[n.path]]
        quiet = n.node.attr("_onHalted") is None and n.rule != "<opaque>"
        attrs = ((("name", n.node.name), ("subtree", labels[n.path])) + ((("skips", skip),) if skip else ())
                 + ((("quiet", "yes"),) if quiet else ()))
        return PNode(Node(TYPE, attrs, (), "", n.node.line, n.node.column, n.node.file), RULE_KEY, (),
                     n.context, n.path, False)
    if not any(p[:len(n.path)] == n.path for p in chosen):
        return n
    return replace(n, kids=tuple(_rebuild(c, chosen, labels, skips) for c in n.kids))


def _labels(chosen: dict[tuple, int]) -> dict[tuple, str]:
    seen: Counter = Counter()
    labels = {}
    for path, key in chosen.items():                 # pre-order: dicts keep insertion order
        labels[path] = f"{key}.{seen[key]}"
        seen[key] += 1
    return labels


def abstract(pa: Program, pb: Program, *, min_size: int = 2) -> Abstraction | None:
    """Replace, in both programs, the maximal subtrees that both hold (same key, the same rules)
    by opaque nodes, instance for instance; None when there is no such subtree of `min_size`
    nodes or more. A key whose chosen instances are not as many in a as in b is not replaced
    (its subtrees' own common parts may be)."""
    table: dict = {}
    ia, ib = _Index(pa, pb, table), _Index(pb, pa, table)
    in_a, in_b = {k for _, k in ia.nodes}, {k for _, k in ib.nodes}
    allowed = {k for k in in_a & in_b if ia.eligible[k] and ib.eligible[k] and ia.size[k] >= min_size}
    while True:
        ca, cb = _choose(ia, allowed), _choose(ib, allowed)
        count_a, count_b = Counter(ca.values()), Counter(cb.values())
        unequal = {k for k in count_a.keys() | count_b.keys() if count_a[k] != count_b[k]}
        if not unequal:
            break
        allowed -= unequal
    if not ca:
        return None
    table_rules = MappingProxyType({**pa.rules, RULE_KEY: CONGRUENT})
    qa = replace(pa, root=_rebuild(pa.root, ca, _labels(ca), ia.skips), rules=table_rules)
    qb = replace(pb, root=_rebuild(pb.root, cb, _labels(cb), ib.skips), rules=MappingProxyType({**pb.rules, RULE_KEY: CONGRUENT}))
    return Abstraction(qa, qb, len(ca), sum(ia.size[k] for k in ca.values()))
