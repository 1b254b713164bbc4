"""The attentional executive: enabling, emphasis and winner-take-all against an emulated robot.

    Decision = (behaviour, emphasis, runner-up, enabled, executed, skipped, failed, seconds,
                hand, decompressed, inhibited, apart)   apart: where the winner and a runner-up
                                                        of the same label are in the tree
    Outcome  = (status, reason, blocked)
    Run      = an iterator of Decisions: `for d in Executive(tree, world, scene): ...`

A leaf is enabled when it and each of its ancestors is *active*: its pre-condition holds and
its post-condition does not (Sec. II-B: a behaviour is active when its releaser is true and
its goal is not yet achieved). Among enabled leaves the one with the highest emphasis wins
(winner-take-all):

    e_b  = w_b * mu_b / lambda_b                 (Sec. II-B; w_b the SEED importance, default 1)
    mu_b = mu_parent + n_b,   mu_root = 1 + n_root
    n_b  = the original sub-behaviours of b that are accomplished (Sec. III-D: a merged child
           counts k; a constituent shared by branching merges counts once)
    lambda_b = clamp(distance(hand, b's object) / scale, min_lambda, 1); neutral without object

Ties go to the higher `w * mu` (closer to completion), then to the earlier behaviour in the
tree. A merged leaf executes its constituents in order, skipping those already accomplished.

A failed command is retried, then its leaf is inhibited. When the robot fails a constituent
of a merged leaf, the `decompress` recovery (the default) replaces just that leaf in the
running tree by its constituents, one leaf per original action with its own releaser and
retry count, so only the failed action is replanned (the paper's Sec. V); `resume` keeps the
merged leaf, which resumes at the failed action.

Two selectors give the same decisions: `scan` visits every behaviour at every decision (the
paper's cost model: one periodic check per behaviour), `incremental` re-evaluates only the
conditions that read an atom the last action changed and keeps enabled leaves in one
priority queue per object.
"""

from __future__ import annotations

import enum
import heapq
import itertools
import time
from collections import Counter
from dataclasses import dataclass, field, replace
from typing import Iterator

from .. import defaults
from ..task import conditions as cond
from ..task.conditions import Condition
from ..errors import SchemalogError
from .scene import NO_SCENE, Position, Scene, object_name
from ..logic.terms import Term, term_to_text
from ..task.tree import Behaviour, walk
from .world import Change, World

SELECTORS = defaults.SELECTORS
RECOVERIES = defaults.RECOVERIES
BASE_ACTIVATION = 1          # mu of the root's (absent) parent
DEFAULT_RETRIES = defaults.RETRIES


class Status(enum.Enum):
    """How a run stands."""

    RUNNING = "running"
    """Decisions remain to be taken."""
    COMPLETED = "completed"
    """The task's post-condition holds."""
    STUCK = "stuck"
    """Nothing is enabled and the task is not accomplished."""
    LIMIT = "decision limit"
    """The run reached its decision limit without completing."""
    LIVELOCK = "livelock"
    """The executive came back to a configuration it had been in: it would loop forever."""


@dataclass(frozen=True, slots=True)    # one per decision: 100,000 in a run of 111,111 behaviours
class Decision:
    """One winner-take-all decision and what the robot made of it."""

    index: int
    behaviour: Term
    emphasis: float
    runner_up: tuple[Term, float] | None
    enabled: int
    executed: tuple[Term, ...]
    skipped: tuple[Term, ...]
    failed: Term | None
    seconds: float
    hand: Position
    decompressed: tuple[Term, ...] = ()   # after a failure: the merged leaf split, then its constituents
    inhibited: Term | None = None         # the leaf inhibited after this decision's failure
    apart: tuple[str, str] | None = None  # a runner-up with the winner's label: where each is


@dataclass(frozen=True)
class Outcome:
    """The end of a run: its status, why, and (when stuck) what blocks progress."""

    status: Status
    reason: str = ""
    blocked: tuple[str, ...] = ()

    @property
    def completed(self) -> bool:
        return self.status is Status.COMPLETED


# ---------------------------------------------------------------------------
# The emulated robot manager

class RobotManager:
    """Acknowledges each command and moves the hand to the action's object (Sec. II-A, IV-C).

    `failures` maps an action label to how many times its command fails (None: always)."""

    def __init__(self, scene: Scene = NO_SCENE, failures: dict[Term, int | None] | None = None) -> None:
        self.scene = scene
        self.hand: Position = scene.end_effector
        self.failures = dict(failures or {})

    def command(self, action: Term, obj: str | None, within: Term | None = None) -> bool:
        """Execute one learned action (the first one of merged behaviour `within`, if given);
        whether it succeeded. A failure asked for the merged behaviour is spent first."""
        for label in (within, action):
            left = self.failures.get(label, 0) if label is not None else 0
            if left is None or left > 0:
                if left is not None:
                    self.failures[label] = left - 1
                return False
        if obj is not None and obj in self.scene.objects:
            self.hand = self.scene.objects[obj]
        return True

    def state_key(self) -> tuple:
        if not self.failures:         # the usual case: one key per hand position, not one per call
            key = self.__dict__.get("_plain_key")
            if key is None or key[0] != self.hand:
                key = self._plain_key = (self.hand, ())
            return key
        return self.hand, tuple(sorted((term_to_text(k), v if v is not None else -1)
                                       for k, v in self.failures.items()))


# ---------------------------------------------------------------------------
# The tree, flattened once for both selectors

@dataclass
class Plan:
    """A task tree as arrays in pre-order (index 0 is the root)."""

    nodes: list[Behaviour]
    parent: list[int]
    children: list[list[int]]
    pre: list[Condition]
    post: list[Condition]
    weight: list[float]
    obj: list[str | None]
    keys: list[tuple]              # what each node counts for in its parent's n
    disjoint: list[bool]           # the children's keys never overlap: n is a plain sum
    steps: list[tuple[tuple[Term, Condition], ...]]   # a leaf's constituents, in order
    leaves: list[int]
    pre_check: list[cond.Check] = field(default_factory=list)    # compiled pre and post (set tests)
    post_check: list[cond.Check] = field(default_factory=list)

    @classmethod
    def of(cls, root: Behaviour, compiled: dict | None = None) -> "Plan":
        """`root`'s plan; `compiled`: condition -> check, shared with other plans of the same
        task (an original and its compressed tree share most conditions)."""
        nodes: list[Behaviour] = []
        parent: list[int] = []
        children: list[list[int]] = []
        keys: list[tuple] = []
        interned: dict[tuple, tuple] = {}
        stack: list[tuple[Behaviour, int, int]] = [(root, -1, 0)]
        while stack:
            node, up, position = stack.pop()
            i = len(nodes)
            nodes.append(node)
            parent.append(up)
            children.append([])
            if up >= 0:
                children[up].append(i)
            key = tuple((o.slot, o.position) for o in node.origins) or ((-1, position),)
            keys.append(interned.setdefault(key, key))   # a few dozen distinct keys in 100,000 nodes
            stack.extend((c, i, p) for p, c in reversed(list(enumerate(node.children))))
        disjoint = []
        for kids in children:
            seen: set = set()
            ok = True
            for c in kids:
                if seen.intersection(keys[c]):
                    ok = False
                    break
                seen.update(keys[c])
            disjoint.append(ok)
        steps = [tuple((o.label, o.post) for o in n.origins) if len(n.origins) > 1 else ((
            n.origins[0].label if n.origins else n.label, n.post),) for n in nodes]
        # A behaviour with no object of its own (gripper(close)) attends to the object of the
        # sub-task it serves (subtask(take, spoon)): pre-order puts the parent first.
        obj: list[str | None] = []
        for i, n in enumerate(nodes):
            obj.append(object_name(n.objects[0]) if n.objects else obj[parent[i]] if parent[i] >= 0 else None)
        if compiled is None:
            compiled = {}                            # siblings share conditions: compile each once

        def check(c: Condition) -> cond.Check:
            found = compiled.get(c)
            if found is None:
                found = compiled[c] = cond.compile_check(c)
            return found

        return cls(nodes, parent, children, [n.pre for n in nodes], [n.post for n in nodes],
                   [n.importance for n in nodes], obj, keys, disjoint, steps,
                   [i for i, n in enumerate(nodes) if not n.children],
                   [check(n.pre) for n in nodes], [check(n.post) for n in nodes])

    def __len__(self) -> int:
        return len(self.nodes)


def emphasis(weighted_mu: float, lam: float) -> float:
    """e = w * mu / lambda; both selectors compute it here, so their ties agree."""
    return weighted_mu / lam


def activation(plan: Plan, atoms: set | frozenset) -> tuple[list[bool], list[int]]:
    """Every behaviour's liveness (it and its ancestors active) and mu, the selectors' rule in
    plain form, for callers that rank inner behaviours too (teaching ranks sub-tasks)."""
    post_ok = [cond.holds(c, atoms) for c in plan.post]
    live = [False] * len(plan)
    mu = [0] * len(plan)
    for i in range(len(plan)):
        up = plan.parent[i]
        n = len({k for c in plan.children[i] if post_ok[c] for k in plan.keys[c]})
        mu[i] = (mu[up] if up >= 0 else BASE_ACTIVATION) + n
        live[i] = (up < 0 or live[up]) and cond.holds(plan.pre[i], atoms) and not post_ok[i]
    return live, mu


Candidate = tuple[float, float, int]      # (emphasis, w * mu, -order): the larger wins


# ---------------------------------------------------------------------------
# Selectors

class ScanSelector:
    """Visit every behaviour at every decision: the paper's periodic check of each node."""

    def __init__(self, plan: Plan, world: World, scene: Scene) -> None:
        self.plan, self.world, self.scene = plan, world, scene
        self.inhibited: set[int] = set()

    def update(self, change: Change) -> None:
        """Nothing to maintain: the next selection looks at everything."""

    def inhibit(self, leaf: int) -> None:
        self.inhibited.add(leaf)

    def select(self, hand: Position) -> tuple[list[Candidate], int]:
        """The two best enabled leaves (best first) and how many are enabled."""
        p = self.plan
        atoms = self.world._atoms
        post_ok = [check(atoms) for check in p.post_check]
        pre_ok = [check(atoms) for check in p.pre_check]
        n_total = len(p.nodes)
        mu = [0] * n_total
        live = [False] * n_total
        best: list[Candidate] = []
        enabled = 0
        lambdas: dict[str | None, float] = {}
        parent, children = p.parent, p.children
        for i in range(n_total):
            up = parent[i]
            # Every behaviour is visited and tested (the paper's cost model); only a live one's
            # emphasis is computed, which nothing below a behaviour that is not live reads.
            if not ((up < 0 or live[up]) and pre_ok[i] and not post_ok[i]):
                continue
            live[i] = True
            kids = children[i]
            if not kids:
                mu[i] = mu[up] if up >= 0 else BASE_ACTIVATION
            elif p.disjoint[i]:
                mu[i] = (mu[up] if up >= 0 else BASE_ACTIVATION) + sum(len(p.keys[c]) for c in kids if post_ok[c])
            else:
                mu[i] = (mu[up] if up >= 0 else BASE_ACTIVATION) + len({k for c in kids if post_ok[c] for k in p.keys[c]})
            if not kids and i not in self.inhibited:
                enabled += 1
                obj = p.obj[i]
                lam = lambdas.get(obj)
                if lam is None:
                    lam = lambdas[obj] = self.scene.lambda_at(obj, hand)
                wmu = p.weight[i] * mu[i]
                best.append((emphasis(wmu, lam), wmu, -i))
                if len(best) > 2:
                    best.sort(reverse=True)
                    best.pop()
        best.sort(reverse=True)
        return best, enabled


class IncrementalSelector:
    """Re-evaluate only what an action touched; enabled leaves in a priority queue per object.

    A leaf's w * mu is its weight times its parent's mu, which changes for every sibling at
    once when one of them is accomplished. So the live leaves of one parent acting on one object
    form a group, ordered by (-w, order) within it (the same order as (-w * mu, order): mu > 0
    is shared), and each object's queue holds one entry per group, keyed by its best leaf's
    w * mu: a completion under a parent of 10,000 leaves re-keys one entry, not 10,000."""

    def __init__(self, plan: Plan, world: World, scene: Scene) -> None:
        self.plan, self.world, self.scene = plan, world, scene
        size = len(plan)
        self.reads: dict[Term, list[int]] = {}
        for i in range(size):
            for atom in {lit.atom for c in (plan.pre[i], plan.post[i]) for lit in cond.literals(c)}:
                self.reads.setdefault(atom, []).append(i)
        atoms = world._atoms
        self.pre_ok = [cond.holds(c, atoms) for c in plan.pre]
        self.post_ok = [cond.holds(c, atoms) for c in plan.post]
        self.counts: list[Counter | None] = [None if plan.disjoint[i] else Counter() for i in range(size)]
        self.n = [0] * size
        for i in range(1, size):
            if self.post_ok[i]:
                self._count(plan.parent[i], i, +1)
        self.inhibited: set[int] = set()
        self.live = [False] * size
        self.live_kids: dict[int, set[int]] = {}   # the live composite children (made when first live)
        self.mu = [0] * size                                             # of composites; a leaf's is its parent's
        self.version = [0] * size
        # group (parent, obj) -> heap of (-w, order, version) of its live leaves, and how many
        self.groups: dict[tuple[int, str | None], list[tuple[float, int, int]]] = {}
        self.group_size: dict[tuple[int, str | None], int] = {}
        self.group_version: dict[tuple[int, str | None], int] = {}
        self.groups_of: list[set[tuple[int, str | None]] | None] = [None] * size   # a parent's groups
        # obj -> heap of (-(w * mu), order, group, group version): each group's best leaf
        self.heaps: dict[str | None, list[tuple[float, int, tuple[int, str | None], int]]] = {}
        self.enabled: dict[str | None, int] = {}
        self._refresh([0])

    # -- maintenance ----------------------------------------------------------
    def _count(self, parent: int, child: int, sign: int) -> None:
        """Child `child` of `parent` became accomplished (+1) or not (-1): update n."""
        keys = self.plan.keys[child]
        counter = self.counts[parent]
        if counter is None:
            self.n[parent] += sign * len(keys)
            return
        for k in keys:
            counter[k] += sign
            if counter[k] == 0:
                del counter[k]
        self.n[parent] = len(counter)

    def update(self, change: Change) -> None:
        """Re-evaluate the conditions that read a changed atom, then liveness and mu below them."""
        p = self.plan
        atoms = self.world._atoms
        dirty = {i for atom in change.atoms for i in self.reads.get(atom, ())}
        refresh = set()
        for i in dirty:
            pre = p.pre_check[i](atoms)
            post = p.post_check[i](atoms)
            if post != self.post_ok[i] and i > 0:
                self._count(p.parent[i], i, +1 if post else -1)
                refresh.add(p.parent[i])
            if pre != self.pre_ok[i] or post != self.post_ok[i]:
                self.pre_ok[i], self.post_ok[i] = pre, post
                refresh.add(i)
        if refresh:
            self._refresh(sorted(refresh))

    def inhibit(self, leaf: int) -> None:
        self.inhibited.add(leaf)
        self._refresh([leaf])

    def _refresh(self, starts: list[int]) -> None:
        """Recompute liveness and mu from each start down, as far as something changes."""
        p = self.plan
        live, mu, pre_ok, post_ok, n = self.live, self.mu, self.pre_ok, self.post_ok, self.n
        touched: set[tuple[int, str | None]] = set()
        for start in starts:
            stack = [start]
            while stack:
                i = stack.pop()
                up = p.parent[i]
                now = (up < 0 or live[up]) and pre_ok[i] and not post_ok[i]
                kids = p.children[i]
                if not kids:
                    if i in self.inhibited:
                        now = False
                    if now != live[i]:
                        live[i] = now
                        self._leaf_moved(i, now, touched)
                    continue
                new_mu = ((mu[up] if up >= 0 else BASE_ACTIVATION) + n[i]) if now else 0
                if now == live[i] and new_mu == mu[i]:
                    continue
                was = live[i]
                live[i], mu[i] = now, new_mu
                if was != now and up >= 0:
                    if now:
                        self.live_kids.setdefault(up, set()).add(i)
                    else:
                        self.live_kids[up].discard(i)      # made when i became live
                if was != now:
                    stack.extend(kids)            # every child may become live, or stop being so
                else:
                    # Liveness unchanged: a child that is not live stays so (its own condition
                    # changes start their own refresh), so only the live composites move, and
                    # the live leaves move as groups: 10,000 siblings cost O(1) per decision.
                    stack.extend(self.live_kids.get(i, ()))
                    touched.update(self.groups_of[i] or ())
        for group in touched:
            self._rekey(group)

    def _leaf_moved(self, i: int, now: bool, touched: set) -> None:
        """Leaf i became live (enter its group) or stopped being so (leave it, lazily)."""
        p = self.plan
        up, obj = p.parent[i], p.obj[i]
        group = (up, obj)
        self.version[i] += 1
        if now:
            heap = self.groups.get(group)
            if heap is None:
                heap = self.groups[group] = []
                self.group_size[group] = 0
                if self.groups_of[up] is None:
                    self.groups_of[up] = set()
                self.groups_of[up].add(group)
            heapq.heappush(heap, (-p.weight[i], i, self.version[i]))
            self.group_size[group] += 1
            self.enabled[obj] = self.enabled.get(obj, 0) + 1
        else:
            self.group_size[group] -= 1
            self.enabled[obj] -= 1
        touched.add(group)

    def _group_head(self, group: tuple[int, str | None]) -> tuple[float, int] | None:
        """The best live leaf of a group, as (-w, order), stale entries dropped."""
        heap = self.groups.get(group)
        if not heap:
            return None
        version, live = self.version, self.live
        while heap and (heap[0][2] != version[heap[0][1]] or not live[heap[0][1]]):
            heapq.heappop(heap)
        if len(heap) > 2 * self.group_size[group] + 64:   # drop stale entries now and then
            heap[:] = [e for e in heap if e[2] == version[e[1]] and live[e[1]]]
            heapq.heapify(heap)
        return (heap[0][0], heap[0][1]) if heap else None

    def _rekey(self, group: tuple[int, str | None]) -> None:
        """Put a group's best leaf in its object's queue, with its w * mu now (the old entry goes stale)."""
        self.group_version[group] = version = self.group_version.get(group, 0) + 1
        head = self._group_head(group)
        if head is None:
            return
        up, obj = group
        key = -(-head[0] * self.mu[up]) if up >= 0 else -(-head[0] * BASE_ACTIVATION)
        queue = self.heaps.setdefault(obj, [])
        heapq.heappush(queue, (key, head[1], group, version))
        if len(queue) > 2 * len(self.group_version) + 64:
            queue[:] = [e for e in queue if e[3] == self.group_version[e[2]]]
            heapq.heapify(queue)

    # -- selection ------------------------------------------------------------
    def _top(self, obj: str | None, skip: int = -1) -> tuple[float, int] | None:
        """The best live leaf of one object, as (w * mu, order) (optionally the best but `skip`)."""
        queue = self.heaps.get(obj)
        if not queue:
            return None
        current = self.group_version
        while queue and queue[0][3] != current[queue[0][2]]:
            heapq.heappop(queue)
        if not queue:
            return None
        key, order, group, _ = queue[0]
        if order != skip:
            return -key, order
        # The runner-up: the best of the next group and this group's second leaf.
        first = heapq.heappop(queue)
        found = self._top(obj)
        heapq.heappush(queue, first)
        heap = self.groups[group]
        taken = heapq.heappop(heap)                  # the skipped leaf, live and current
        second = self._group_head(group)
        heapq.heappush(heap, taken)
        if second is not None:
            up = group[0]
            wmu = -second[0] * (self.mu[up] if up >= 0 else BASE_ACTIVATION)
            if found is None or (wmu, -second[1]) > (found[0], -found[1]):
                found = (wmu, second[1])
        return found

    def select(self, hand: Position) -> tuple[list[Candidate], int]:
        """The two best enabled leaves (best first) and how many are enabled."""
        tops: list[tuple[Candidate, str | None, float]] = []
        total = 0
        for obj, count in self.enabled.items():
            if count <= 0:
                continue
            total += count
            top = self._top(obj)
            if top is not None:
                lam = self.scene.lambda_at(obj, hand)
                tops.append(((emphasis(top[0], lam), top[0], -top[1]), obj, lam))
        if not tops:
            return [], total
        tops.sort(reverse=True)
        best, obj, lam = tops[0]
        candidates = [best] + [t[0] for t in tops[1:2]]
        # The runner-up is the next object's head or the winner's own second, whichever is better.
        if self.enabled[obj] > 1:
            second = self._top(obj, skip=-best[2])
            if second is not None:
                candidates.append((emphasis(second[0], lam), second[0], -second[1]))
        candidates.sort(reverse=True)
        return candidates[:2], total


def tell_apart(plan: Plan, a: int, b: int) -> tuple[str, str]:
    """Where two nodes of one label are: the sub-trees their paths enter below their lowest
    common ancestor ("in preparecoffee", "in preparetea"), or their pre-order ids when those
    sub-trees have one label too."""
    def up(i: int) -> list[int]:
        path = [i]
        while plan.parent[path[-1]] >= 0:
            path.append(plan.parent[path[-1]])
        return path[::-1]               # the root first

    pa, pb = up(a), up(b)
    k = next(k for k in range(min(len(pa), len(pb))) if pa[k] != pb[k])
    x, y = plan.nodes[pa[k]].label, plan.nodes[pb[k]].label
    if x != y:
        return f"in {term_to_text(x)}", f"in {term_to_text(y)}"
    return f"node {a}", f"node {b}"


def make_selector(name: str, plan: Plan, world: World, scene: Scene):
    if name == "scan":
        return ScanSelector(plan, world, scene)
    if name == "incremental":
        return IncrementalSelector(plan, world, scene)
    raise SchemalogError(f"unknown selector {name!r} (choose {' or '.join(SELECTORS)})")


# ---------------------------------------------------------------------------
# Failure-local decompression

def constituents(leaf: Behaviour) -> tuple[Behaviour, ...]:
    """Split a merged leaf into one leaf per original action it stands for, in order."""
    # Each keeps its own releaser, post-condition, importance and provenance (so it counts for
    # its parent's n as before) under the context the merged-away ancestors propagated. When
    # the constituents came from different original parents, their contexts differed and the
    # merged leaf kept them only inside its releaser: each then inherits its whole pre-condition.
    one_parent = len({o.slot for o in leaf.origins}) == 1
    context = leaf.context if one_parent else leaf.pre
    return tuple(Behaviour(label=o.label, agent=leaf.agent, objects=leaf.objects, releaser=o.releaser,
                           post=o.post, context=context, importance=o.importance, origins=(o,),
                           source=leaf.source) for o in leaf.origins)


def splice(root: Behaviour, path: list[int], parts: tuple[Behaviour, ...]) -> Behaviour:
    """Put `parts` in place of the behaviour at `path` (child positions from the root)."""
    spine = [root]
    for position in path[:-1]:
        spine.append(spine[-1].children[position])
    kids = spine[-1].children
    rebuilt = replace(spine[-1], children=kids[:path[-1]] + parts + kids[path[-1] + 1:])
    for node, position in zip(reversed(spine[:-1]), reversed(path[:-1])):
        rebuilt = replace(node, children=node.children[:position] + (rebuilt,) + node.children[position + 1:])
    return rebuilt


# ---------------------------------------------------------------------------
# The executive

_NONE: frozenset = frozenset()      # shared by the loop detector's configurations


class Executive:
    """Runs a task tree (original or compressed) against the world of its original task."""

    def __init__(self, tree: Behaviour, world: World, scene: Scene = NO_SCENE, *,
                 robot: RobotManager | None = None, selector: str = "incremental",
                 retries: int = DEFAULT_RETRIES, max_decisions: int | None = None,
                 detect_loops: bool = True, recovery: str = RECOVERIES[0], plan: Plan | None = None) -> None:
        if recovery not in RECOVERIES:
            raise SchemalogError(f"unknown recovery {recovery!r} (choose {' or '.join(RECOVERIES)})")
        self.tree, self.world, self.scene = tree, world, scene
        self.given_tree = tree                   # self.tree changes when a merged leaf is decompressed
        self.recovery = recovery
        self.robot = robot or RobotManager(scene)
        self.plan = plan if plan is not None and plan.nodes[0] is tree else Plan.of(tree)   # `plan`: of `tree`, made
        started = time.perf_counter()                                                       # once by the caller
        self.selector = make_selector(selector, self.plan, world, scene)
        self.selector_name = selector
        self.setup_seconds = time.perf_counter() - started
        self.retries = retries
        leaves = sum(1 for n in walk(world.original) if not n.children)
        self.max_decisions = max_decisions if max_decisions is not None else max(100, 4 * leaves)
        self.detect_loops = detect_loops
        self.decisions: list[Decision] = []
        self.trace: list[Term] = []
        self.failures: Counter = Counter()       # consecutive failures per leaf
        self.outcome = Outcome(Status.RUNNING)
        self._pending = Change()
        self._journal: list[tuple[Term, ...]] = []      # the atoms each decision changed
        self._seen: dict[tuple, int] = {}
        self._remember()

    def __iter__(self) -> Iterator[Decision]:
        while True:
            decision = self.step()
            if decision is None:
                return
            yield decision

    def run(self) -> Outcome:
        """Take decisions until the run ends; return how it ended."""
        for _ in self:
            pass
        return self.outcome

    def step(self) -> Decision | None:
        """Take one decision and command the robot; None once the run has ended (see `outcome`)."""
        if self.outcome.status is not Status.RUNNING:
            return None
        if self.world.holds(self.plan.post[0]):
            self.outcome = Outcome(Status.COMPLETED, f"{term_to_text(self.tree.label)} is accomplished "
                                                     f"({cond.to_text(self.plan.post[0])})")
            return None
        if len(self.decisions) >= self.max_decisions:
            self.outcome = Outcome(Status.LIMIT, f"no completion after {self.max_decisions:,} decisions "
                                                 f"(raise the limit with --max-decisions)",
                                   self._last_cycle())
            return None
        started = time.perf_counter()
        self.selector.update(self._pending)
        best, enabled = self.selector.select(self.robot.hand)
        seconds = time.perf_counter() - started
        if not best:
            self.outcome = Outcome(Status.STUCK, f"nothing is enabled and {term_to_text(self.tree.label)} "
                                                 f"is not accomplished ({cond.to_text(self.plan.post[0])} "
                                                 f"is false)", tuple(self.blocked()))
            return None
        e, _, order = best[0]
        leaf = -order
        label = self.plan.nodes[leaf].label
        runner_up = (self.plan.nodes[-best[1][2]].label, best[1][0]) if len(best) > 1 else None
        apart = tell_apart(self.plan, leaf, -best[1][2]) if runner_up and runner_up[0] == label else None
        executed, skipped, failed, step = self._execute(leaf)
        decompressed: tuple[Term, ...] = ()
        inhibited = None
        if failed is not None:
            self.failures[leaf] += 1
            if self.recovery == "decompress" and len(self.plan.steps[leaf]) > 1:
                decompressed = (label, *(action for action, _ in self.plan.steps[leaf]))
                leaf = self._decompress(leaf, step)
            if self.failures[leaf] > self.retries:
                self.selector.inhibit(leaf)
                inhibited = self.plan.nodes[leaf].label
        else:
            self.failures.pop(leaf, None)
        decision = Decision(len(self.decisions) + 1, label, e, runner_up, enabled, tuple(executed),
                            tuple(skipped), failed, seconds, self.robot.hand, decompressed, inhibited,
                            apart)
        self.decisions.append(decision)
        self._check_loop()
        return decision

    def _execute(self, leaf: int) -> tuple[list[Term], list[Term], Term | None, int]:
        """Command the robot through the leaf's constituents, skipping accomplished ones."""
        # Returns the actions executed and skipped, and the failed one with its position (or -1).
        executed: list[Term] = []
        skipped: list[Term] = []
        before: dict[Term, bool] = {}       # each changed atom's value before the decision
        obj = self.plan.obj[leaf]
        steps = self.plan.steps[leaf]
        merged_label = self.plan.nodes[leaf].label if len(steps) > 1 else None
        failed = None
        failed_step = -1
        for position, (action, post) in enumerate(steps):
            if self.world.holds(post):
                skipped.append(action)
                continue
            if not self.robot.command(action, obj, merged_label if not executed else None):
                failed, failed_step = action, position
                break
            change = self.world.perform(post)
            for atom in change.added:
                before.setdefault(atom, False)
            for atom in change.removed:
                before.setdefault(atom, True)
            executed.append(action)
            self.trace.append(action)
        # The net change: an atom set and cleared again within the decision did not change.
        change = Change(frozenset(a for a, was in before.items() if not was and a in self.world),
                        frozenset(a for a, was in before.items() if was and a not in self.world))
        self._pending = change
        self._journal.append((*change.added, *change.removed))     # what loop detection reads, compactly
        return executed, skipped, failed, failed_step

    def _decompress(self, leaf: int, step: int) -> int:
        """Replace merged leaf `leaf` by its constituents; return the failed one's (`step`) index."""
        # The failed constituent takes over the leaf's failure count.
        plan = self.plan
        path = []
        i = leaf
        while plan.parent[i] >= 0:
            path.append(plan.children[plan.parent[i]].index(i))
            i = plan.parent[i]
        parts = constituents(plan.nodes[leaf])
        self.tree = splice(self.tree, path[::-1], parts)
        # Pre-order: the parts take the leaf's place, everything after it moves by len(parts) - 1.
        shift = len(parts) - 1

        def moved(i: int) -> int:
            return i if i < leaf else i + shift

        failed = leaf + step
        failures = Counter({moved(i): n for i, n in self.failures.items() if i != leaf})
        failures[failed] = self.failures[leaf]
        inhibited = [moved(i) for i in self.selector.inhibited]
        self.plan = Plan.of(self.tree)
        self.selector = make_selector(self.selector_name, self.plan, self.world, self.scene)
        for i in inhibited:
            self.selector.inhibit(i)
        self.failures = failures
        self._pending = Change()             # the new selector read the world as it is
        self._seen.clear()                   # configurations of another tree are incomparable
        return failed

    # -- loops ----------------------------------------------------------------
    def _config(self) -> tuple:
        inhibited = self.selector.inhibited      # one empty set for every configuration without any
        return (self.world.hash, self.robot.state_key(), frozenset(inhibited) if inhibited else _NONE,
                tuple(sorted(self.failures.items())))

    def _remember(self) -> None:
        if self.detect_loops:
            self._seen.setdefault(self._config(), len(self._journal))

    def _check_loop(self) -> None:
        """Stop when the executive is back where it was: deterministic, so it would loop forever."""
        if not self.detect_loops:
            return
        config = self._config()
        earlier = self._seen.get(config)
        if earlier is not None and self._same_state_since(earlier):
            loop = [term_to_text(d.behaviour) for d in self.decisions[earlier:]]
            self.outcome = Outcome(
                Status.LIVELOCK, f"decisions {earlier + 1}-{len(self.decisions)} brought the world back "
                                 f"to the state before decision {earlier + 1}: it would repeat them forever",
                (f"loop: {' -> '.join(loop)}",))
            return
        self._seen.setdefault(config, len(self._journal))

    def _same_state_since(self, index: int) -> bool:
        """Whether every atom changed an even number of times since decision `index` (exact)."""
        flips: Counter = Counter()
        for atoms in itertools.islice(self._journal, index, None):
            flips.update(atoms)
        return all(v % 2 == 0 for v in flips.values())

    def _last_cycle(self) -> tuple[str, ...]:
        tail = [term_to_text(d.behaviour) for d in self.decisions[-8:]]
        return (f"last decisions: {', '.join(tail)}",) if tail else ()

    # -- explanations ---------------------------------------------------------
    def blocked(self, limit: int = 12) -> list[str]:
        """Why nothing is enabled: the false conditions on the way down from the root."""
        return blocked_reasons(self.plan, self.world, self.selector.inhibited, self.failures, limit)


def blocked_reasons(plan: Plan, world: World, inhibited: set[int], failures: Counter,
                    limit: int = 12) -> list[str]:
    """The first behaviours, top down, whose conditions stop progress, each with why."""
    reasons: list[str] = []
    stack = [0]
    while stack:
        i = stack.pop()
        node = plan.nodes[i]
        if world.holds(plan.post[i]):
            continue
        if not world.holds(plan.pre[i]):
            false = [cond.to_text(lit) for lit in cond.literals(cond.canonical(plan.pre[i]))
                     if not world.holds(lit)]
            why = f" (false: {', '.join(dict.fromkeys(false))})" if false else ""
            reasons.append(f"{node.name}: pre-condition {cond.to_text(plan.pre[i])} is false{why}")
            continue
        if not plan.children[i]:
            if i in inhibited:
                reasons.append(f"{node.name}: its command failed {failures[i]} times; inhibited")
            continue
        if all(world.holds(plan.post[c]) for c in plan.children[i]):
            reasons.append(f"{node.name}: every sub-behaviour is accomplished, but its post-condition "
                           f"{cond.to_text(plan.post[i])} is false")
            continue
        stack.extend(reversed(plan.children[i]))
    if len(reasons) > limit:
        reasons = reasons[:limit] + [f"... and {len(reasons) - limit} more"]
    return reasons


# ---------------------------------------------------------------------------
# Checking a trace against the original task

def enabled_indices(plan: Plan, atoms: set | frozenset) -> list[int]:
    """The leaves of `plan` enabled when exactly `atoms` are true, in tree order."""
    live = [False] * len(plan)
    out = []
    for i in range(len(plan)):
        up = plan.parent[i]
        live[i] = (up < 0 or live[up]) and plan.pre_check[i](atoms) and not plan.post_check[i](atoms)
        if live[i] and not plan.children[i]:
            out.append(i)
    return out


def enabled_leaves(tree: Behaviour, world: World) -> list[Behaviour]:
    """The leaves of `tree` enabled in the world's current state, in tree order."""
    plan = Plan.of(tree)
    return [plan.nodes[i] for i in enabled_indices(plan, world._atoms)]


@dataclass(frozen=True)
class Replay:
    """Whether a trace is a run of a tree: the first action that is not, and why."""

    valid: bool
    index: int = -1
    reason: str = ""


def replay(original: Behaviour, initial, trace: list[Term]) -> Replay:
    """Replay `trace` through `original`: each action must be an enabled leaf when it runs."""
    world = World(original, initial)
    for index, action in enumerate(trace):
        enabled = enabled_leaves(original, world)
        match = next((leaf for leaf in enabled if leaf.label == action), None)
        if match is None:
            names = ", ".join(leaf.name for leaf in enabled) or "nothing"
            return Replay(False, index, f"action {index + 1}, {term_to_text(action)}, is not enabled "
                                        f"in the original task (enabled: {names})")
        world.perform(match.post)
    return Replay(True)


__all__ = ["Executive", "Decision", "Outcome", "Status", "RobotManager", "Plan", "SELECTORS", "RECOVERIES",
           "constituents", "splice",
           "ScanSelector", "IncrementalSelector", "activation", "enabled_leaves", "enabled_indices", "replay", "Replay", "emphasis",
           "blocked_reasons"]
