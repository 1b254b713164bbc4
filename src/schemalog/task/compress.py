"""Definition 1 and Algorithm 1: merge sequential behaviours, keep provenance, undo it.

    Edge  = (i, j)           sibling i then sibling j: post(i) equals the entry releaser of j
    Path  = list[int]        a maximal chain of siblings through the edges; each becomes
                             one merged behaviour (a lone sibling stays as it is)

Sequentiality (Definition 1): two children of the same node, performed by the same
agent, acting on the same objects, where the post-condition of one equals the ENTRY
releaser of the other (its own releaser; for a merged behaviour, its first
constituent's). `kb/compression.pl` states the same rule in Prolog; `sequential_pairs`
is its indexed equivalent (siblings grouped by agent and objects, post matched to
entry by hash), and a property test keeps the two in agreement.

Algorithm 1, top down: at each node the maximal chains of its children are merged
(a chain a3 -> ... -> a7 becomes a3_a4_a5_a6_a7 whatever the visiting order; a
behaviour with N-1 successors gives N-1 merged behaviours). A merged behaviour's
pre-condition is the OR of its constituents', its post-condition the last one's, its
children the union of theirs. Before those children are merged in turn, each gets
its former parent's condition as context (`propagate`): `pre` is the paper's rule
(lines 12-17); `full` adds `not post` (the parent's whole activation condition,
needed because post-conditions such as hand.free toggle); `none` shows the
perceptual aliasing of Figure 2 (middle). Siblings whose releasers form a cycle are
left unmerged, and said so.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal

from .. import defaults
from . import conditions as cond
from .conditions import Condition, Simplifier
from ..errors import SchemalogError, shown_number
from ..logic.terms import Atom, Int, Float, Str, Struct, Term, term_to_text
from .tree import Behaviour, Origin, count_nodes, depth, map_tree, walk

Propagate = Literal["none", "pre", "full"]
PROPAGATE_MODES = defaults.PROPAGATE_MODES
MAX_PATHS_PER_GROUP = 10_000


@dataclass
class Compression:
    """The result of compressing a task tree, with the paper's figures."""

    original: Behaviour
    tree: Behaviour
    propagate: str
    simplifier: Simplifier
    notes: list[str] = field(default_factory=list)

    @property
    def nodes_before(self) -> int:
        return count_nodes(self.original)

    @property
    def nodes_after(self) -> int:
        return count_nodes(self.tree)

    @property
    def depth_before(self) -> int:
        return depth(self.original)

    @property
    def depth_after(self) -> int:
        return depth(self.tree)

    @property
    def reduction_degree(self) -> float:
        """RD = (Bi - Bm) / (Bi - D), equation (1); 0 when Bi = D (nothing can merge)."""
        b_i, b_m, d = self.nodes_before, self.nodes_after, self.depth_before
        return (b_i - b_m) / (b_i - d) if b_i > d else 0.0


# ---------------------------------------------------------------------------
# Definition 1

def _group_key(b: Behaviour) -> tuple:
    # Same agent, same objects, and the same kind: an action merges with actions and a
    # sub-task with sub-tasks. A merged behaviour runs its actions or its sub-behaviours;
    # one made of both would never command its action (the verifier found the dead end).
    return (b.agent, b.objects, bool(b.children))


def sequential_pairs(children: tuple[Behaviour, ...] | list[Behaviour],
                     protected: frozenset[Term] = frozenset()) -> list[tuple[int, int]]:
    """The pairs (i, j) of sequential siblings, i before j, found by hashing (no nested loop)."""
    by_entry: dict[tuple, list[int]] = {}
    canon_posts = []
    for j, b in enumerate(children):
        canon_posts.append(cond.canonical(b.post))
        if b.label in protected:
            continue
        by_entry.setdefault((_group_key(b), cond.canonical(b.entry)), []).append(j)
    pairs = []
    for i, b in enumerate(children):
        post = canon_posts[i]
        if b.label in protected or isinstance(post, cond.Const):
            continue  # a constant post-condition releases nothing in particular
        for j in by_entry.get((_group_key(b), post), ()):
            if j != i:
                pairs.append((i, j))
    return pairs


def maximal_paths(n: int, edges: list[tuple[int, int]]) -> tuple[list[list[int]], list[list[int]]]:
    """Maximal chains through the edges, and the cycles left out (as lists of indices).

    Every index appears in at least one returned path (alone if it has no edges)."""
    succ: dict[int, list[int]] = {i: [] for i in range(n)}
    for i, j in edges:
        succ[i].append(j)
    cyclic = _cyclic_nodes(n, succ)
    cycles = _group_cycles(cyclic, succ)
    succ = {i: [j for j in js if j not in cyclic] for i, js in succ.items() if i not in cyclic}
    indegree = {i: 0 for i in succ}
    for js in succ.values():
        for j in js:
            indegree[j] += 1
    paths: list[list[int]] = []
    for start in sorted(succ):
        if indegree[start]:
            continue
        # Depth-first over one path, extended and shortened in place (a copy only per
        # finished path), so a chain of n siblings costs O(n), not O(n^2).
        path, branches = [start], [iter(succ[start])]
        if not succ[start]:
            paths.append([start])
            continue
        while branches:
            nxt = next(branches[-1], None)
            if nxt is None:
                branches.pop()
                path.pop()
                continue
            path.append(nxt)
            if succ[nxt]:
                branches.append(iter(succ[nxt]))
                continue
            paths.append(list(path))
            path.pop()
            if len(paths) > MAX_PATHS_PER_GROUP:
                raise SchemalogError(
                    f"merging would create more than {MAX_PATHS_PER_GROUP:,} behaviours from "
                    f"{n} siblings (their releasers branch and join too often)")
    paths.extend([i] for i in sorted(cyclic))
    return sorted(paths), cycles


def _cyclic_nodes(n: int, succ: dict[int, list[int]]) -> set[int]:
    """Nodes on a cycle (Tarjan's strongly connected components, iteratively)."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on_stack: set[int] = set()
    stack: list[int] = []
    cyclic: set[int] = set()
    counter = 0
    for root in range(n):
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            v, child_i = work.pop()
            if child_i == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on_stack.add(v)
            recurse = False
            for k in range(child_i, len(succ[v])):
                w = succ[v][k]
                if w not in index:
                    work.append((v, k + 1))
                    work.append((w, 0))
                    recurse = True
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            if recurse:
                continue
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1 or v in succ[v]:
                    cyclic.update(component)
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[v])
    return cyclic


def _group_cycles(cyclic: set[int], succ: dict[int, list[int]]) -> list[list[int]]:
    groups, seen = [], set()
    for start in sorted(cyclic):
        if start in seen:
            continue
        group, todo = [], [start]
        while todo:
            v = todo.pop()
            if v in seen:
                continue
            seen.add(v)
            group.append(v)
            todo.extend(w for w in succ[v] if w in cyclic)
        groups.append(sorted(group))
    return groups


# ---------------------------------------------------------------------------
# Labels: createUniqueLabel

def _atomic_text(t: Term) -> str | None:
    if isinstance(t, Atom):
        return t.name
    if isinstance(t, (Int, Float)):
        return term_to_text(t)
    if isinstance(t, Str):
        return t.value
    return None


def merged_label(labels: list[Term]) -> Term:
    """The paper's labels: a1(spoon)+a2(spoon) -> a1_a2(spoon);
    subtask(take,spoon)+subtask(mix,spoon) -> subtask(take_mix,spoon)."""
    first = labels[0]
    same_shape = all(isinstance(lab, Struct) and isinstance(first, Struct) and lab.name == first.name
                     and len(lab.args) == len(first.args) for lab in labels)
    if same_shape and isinstance(first, Struct):
        args = []
        for position in range(len(first.args)):
            column = [lab.args[position] for lab in labels]
            if all(c == column[0] for c in column):
                args.append(column[0])
                continue
            texts = [_atomic_text(c) for c in column]
            if any(t is None for t in texts):
                break
            args.append(Atom("_".join(texts)))
        else:
            return Struct(first.name, tuple(args))
    names = [lab.name if isinstance(lab, (Atom, Struct)) else term_to_text(lab) for lab in labels]
    name = "_".join(names)
    if isinstance(first, Struct) and all(isinstance(lab, Struct) and lab.args == first.args for lab in labels):
        return Struct(name, first.args)
    return Atom(name) if not isinstance(first, Struct) else Struct(name, first.args)


def _unique(label: Term, taken: set[Term]) -> Term:
    """`label`, or `name_2(...)`, `name_3(...)` if a sibling already has it."""
    if label not in taken:
        return label
    n = 2
    while True:
        if isinstance(label, Struct):
            candidate: Term = Struct(f"{label.name}_{n}", label.args)
        else:
            candidate = Atom(f"{term_to_text(label)}_{n}")
        if candidate not in taken:
            return candidate
        n += 1


# ---------------------------------------------------------------------------
# Algorithm 1

def with_origins(root: Behaviour) -> Behaviour:
    """Give every behaviour of an original tree its own provenance record."""
    def stamp(b: Behaviour, position: int) -> Behaviour:
        origin = Origin(b.label, b.releaser, b.post, b.importance, position, 0)
        return replace(b, origins=(origin,))
    return map_tree(root, lambda b, pos: b if b.origins else stamp(b, pos))


def _grows(paths: list[list[int]], children: tuple[Behaviour, ...]) -> bool:
    """Whether the branching rule would make the tree larger: a behaviour with a sub-tree
    copied into several merged ones, or more merged behaviours than siblings (a lattice).

    Both tests are kept by compression itself (a leaf stays a leaf; merging a chain keeps
    the set of paths), so compressing twice decides the same way: idempotence."""
    seen: set[int] = set()
    copied: set[int] = set()
    for p in paths:
        for i in p:
            (copied if i in seen else seen).add(i)
    if not copied:
        return False  # no behaviour in two paths: merging only shrinks
    return len(paths) > len(children) or any(children[i].children for i in copied)


def _unbranched(paths: list[list[int]], n: int) -> list[list[int]]:
    """The chains through links that neither branch nor join, every sibling exactly once."""
    succ: dict[int, set[int]] = {}
    pred: dict[int, set[int]] = {}
    for p in paths:
        for i, j in zip(p, p[1:]):
            succ.setdefault(i, set()).add(j)
            pred.setdefault(j, set()).add(i)
    nxt = {i: next(iter(js)) for i, js in succ.items() if len(js) == 1 and len(pred.get(next(iter(js)), ())) == 1}
    has_prev = set(nxt.values())
    chains = []
    for start in range(n):
        if start in has_prev:
            continue
        chain = [start]
        while chain[-1] in nxt:
            chain.append(nxt[chain[-1]])
        chains.append(chain)
    return sorted(chains)


def _content_key(b: Behaviour) -> tuple:
    return (term_to_text(b.label), cond.to_text(cond.canonical(b.entry)), cond.to_text(cond.canonical(b.post)))


class Compressor:
    """Applies Algorithm 1 with one propagation mode and one simplifier."""

    def __init__(self, propagate: str = "full", protected: frozenset[Term] = frozenset(),
                 simplifier: Simplifier | None = None) -> None:
        if propagate not in PROPAGATE_MODES:
            raise SchemalogError(f"--propagate must be one of {', '.join(PROPAGATE_MODES)}")
        self.propagate = propagate
        self.protected = protected
        self.simplifier = simplifier or Simplifier()
        self.notes: list[str] = []

    def context_for(self, b: Behaviour) -> Condition:
        """What the children of a merged-away behaviour inherit (Alg. 1, lines 12-17)."""
        if self.propagate == "none":
            return cond.TRUE
        if self.propagate == "pre":
            return b.pre
        return self.simplifier.simplify(cond.conjoin([b.pre, cond.negate(b.post)]))

    def merge(self, parts: list[Behaviour], label: Term) -> Behaviour:
        """One behaviour standing for the chain `parts` (Alg. 1, lines 7-11)."""
        children: list[Behaviour] = []
        origins: list[Origin] = []
        for part in parts:
            inherited = self.context_for(part)
            offset = len(origins)
            for child in part.children:
                context = child.context if inherited == cond.TRUE else \
                    self.simplifier.simplify(cond.conjoin([inherited, child.context]))
                moved = tuple(replace(o, slot=o.slot + offset) for o in child.origins)
                children.append(replace(child, context=context, origins=moved))
            origins.extend(part.origins)
        contexts = {p.context for p in parts}
        if len(contexts) == 1:  # a shared context stays apart from the merged releaser
            context = parts[0].context
            releaser = self.simplifier.simplify(cond.disjoin([p.releaser for p in parts]))
        else:
            context = cond.TRUE
            releaser = self.simplifier.simplify(cond.disjoin([p.pre for p in parts]))
        first = parts[0]
        return Behaviour(label=label, agent=first.agent, objects=first.objects, releaser=releaser,
                         post=parts[-1].post, children=tuple(children), context=context,
                         importance=first.importance, origins=tuple(origins), source=first.source)

    def merge_siblings(self, parent: Behaviour) -> list[Behaviour]:
        """The children of `parent` after merging their maximal chains."""
        children = parent.children
        if len(children) < 2:
            return list(children)
        paths, cycles = maximal_paths(len(children), sequential_pairs(children, self.protected))
        for cycle in cycles:
            names = ", ".join(term_to_text(children[i].label) for i in cycle)
            self.notes.append(f"releasers form a cycle among the children of "
                              f"{term_to_text(parent.label)} ({names}): not merged")
        if _grows(paths, children):
            # Branching copies a behaviour (and its sub-tree) into every merged successor;
            # where that adds more than it removes, merge only the unbranched chains.
            self.notes.append(f"branching among the children of {term_to_text(parent.label)} would "
                              f"grow the tree ({len(paths):,} merged behaviours from {len(children):,}, "
                              f"or a sub-tree copied): merged only its unbranched chains")
            paths = _unbranched(paths, len(children))
        taken = {children[p[0]].label for p in paths if len(p) == 1}
        labels: dict[int, Term] = {}
        # Suffixes (_2, _3) go by content, not by sibling order, so a shuffled parent gets
        # the same labels for the same merged behaviours.
        merged = [k for k, p in enumerate(paths) if len(p) > 1]
        merged.sort(key=lambda k: [_content_key(children[i]) for i in paths[k]])
        for k in merged:
            labels[k] = _unique(merged_label([children[i].label for i in paths[k]]), taken)
            taken.add(labels[k])
        return [children[p[0]] if len(p) == 1 else self.merge([children[i] for i in p], labels[k])
                for k, p in enumerate(paths)]

    def compress(self, root: Behaviour) -> Behaviour:
        """Algorithm 1 over the whole tree, top down, iteratively."""
        root = with_origins(root)
        stack: list[tuple[Behaviour, list[Behaviour], list[Behaviour]]] = [
            (root, self.merge_siblings(root), [])]
        while True:
            node, pending, done = stack[-1]
            if len(done) < len(pending):
                child = pending[len(done)]
                stack.append((child, self.merge_siblings(child), []))
                continue
            stack.pop()
            rebuilt = replace(node, children=tuple(done))
            if not stack:
                return rebuilt
            stack[-1][2].append(rebuilt)


def compress(root: Behaviour, propagate: str = "full", protected: frozenset[Term] = frozenset(),
             simplifier: Simplifier | None = None) -> Compression:
    """Compress a task tree; the result carries the figures and any notes."""
    compressor = Compressor(propagate, protected, simplifier)
    tree = compressor.compress(root)
    notes = compressor.notes + compressor.simplifier.notes
    return Compression(root if not root.origins else decompress(root), tree, propagate,
                       compressor.simplifier, notes)


# ---------------------------------------------------------------------------
# Decompression

def decompress(root: Behaviour) -> Behaviour:
    """The original tree, rebuilt from provenance (a tree without provenance is returned as is)."""
    if not root.origins:
        return root
    originals = _expand(root)
    if len(originals) != 1:
        raise SchemalogError(f"the root {term_to_text(root.label)} stands for {len(originals)} "
                             f"behaviours: it cannot be decompressed to one tree")
    return originals[0][1]


def original_of(root: Behaviour) -> Behaviour:
    """The original tree of a tree read from knowledge: itself, or rebuilt from provenance.

    A sub-task of a compressed file (`--task preparecoffee`) has no provenance of its own
    but its children have: it stands for itself, unless its children name more than one
    original parent (then it is a merged behaviour, which is no single original tree)."""
    if root.origins:
        return decompress(root)
    if not any(c.origins for c in root.children):
        return root
    slots = {o.slot for c in root.children for o in c.origins}
    if slots != {0}:
        raise SchemalogError(f"{term_to_text(root.label)} is a merged behaviour (it stands for "
                             f"{max(slots) + 1} original behaviours), not one original task: run the "
                             f"task that contains it", root.source)
    return decompress(replace(root, origins=(Origin(root.label, root.releaser, root.post, root.importance),)))


def _expand(node: Behaviour) -> list[tuple[Origin, Behaviour]]:
    """The original behaviours `node` stands for, each with its rebuilt subtree."""
    if not node.origins:
        raise SchemalogError(f"{term_to_text(node.label)} has no provenance (origins/2) in a compressed "
                             f"tree: was the file edited? It cannot be decompressed", node.source)
    kids: list[dict[int, Behaviour]] = [{} for _ in node.origins]
    for child in node.children:
        for origin, original in _expand(child):
            if not 0 <= origin.slot < len(kids):
                raise SchemalogError(f"provenance of {term_to_text(child.label)} names parent slot "
                                     f"{shown_number(term_to_text(Int(origin.slot)))}, but "
                                     f"{term_to_text(node.label)} has {len(kids)} origins", child.source)
            kids[origin.slot].setdefault(origin.position, original)  # branching copies: keep one
    out = []
    for origin, children in zip(node.origins, kids):
        rebuilt = Behaviour(label=origin.label, agent=node.agent, objects=node.objects,
                            releaser=origin.releaser, post=origin.post,
                            children=tuple(children[p] for p in sorted(children)),
                            importance=origin.importance, source=node.source)
        out.append((origin, rebuilt))
    return out


def protected_labels(kb, root: Behaviour) -> frozenset[Term]:
    """The behaviours of `root` that the knowledge base protects with `no_merge/1`."""
    if not kb.clauses("no_merge", 1):
        return frozenset()
    from ..logic.engine import Engine

    engine = Engine(kb)
    return frozenset(b.label for b in walk(root) if engine.first(Struct("no_merge", (b.label,))) is not None)
