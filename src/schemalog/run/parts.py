"""Where verifying a task splits exactly: independent parts and sequential phases.

    Fixed  = {atom: bool}: atoms that keep one value while a piece runs (an ancestor's
             conditions, the other phases' post-conditions)
    Part   = an original and a compressed subtree, explored as they are
    Group  = sub-pieces on disjoint atoms that run interleaved (independent parts)
    Chain  = sub-pieces that run one after the other (sequential phases)
    Piece  = Part | Group | Chain

`decompose` is pure syntax: it reads the two trees' conditions and provenance, never a state
space. run/verify.py explores each Part and combines what it found up the Groups and Chains.
Why each split is exact is argued in docs/semantics.md ("Independent parts", "Sequential
phases"); the checks below are that argument's premises, each tested where it is used.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..logic.terms import Term
from ..task import conditions as cond
from ..task.conditions import Condition
from ..task.tree import Behaviour

State = frozenset
Fixed = dict


@dataclass(frozen=True)
class Part:
    """An original subtree and its compressed counterpart, explored as they are.

    `atoms` are the atoms its steps may change; `start` is its start state (its own atoms'
    start values and the fixed atoms that are true). Its root's post-condition says when it
    has ended."""

    label: Term
    original: Behaviour
    compressed: Behaviour
    atoms: frozenset
    start: State


@dataclass(frozen=True)
class Group:
    """Pieces on disjoint atoms, run interleaved; it has ended when every one has."""

    label: Term
    pieces: tuple
    atoms: frozenset
    start: State


@dataclass(frozen=True)
class Chain:
    """Pieces run one after the other: phase i+1 starts when phase i's post-condition
    `ends[i]` becomes true, and nothing of the others runs meanwhile."""

    label: Term
    phases: tuple
    ends: tuple
    atoms: frozenset
    start: State


Piece = Part | Group | Chain


def parts_of(piece: Piece) -> list[Part]:
    """The Parts a piece is made of, in order."""
    if isinstance(piece, Part):
        return [piece]
    found: list[Part] = []
    for p in (piece.pieces if isinstance(piece, Group) else piece.phases):
        found.extend(parts_of(p))
    return found


def decompose(original: Behaviour, compressed: Behaviour, start: State, phases: bool = True) -> Piece | None:
    """The task split into pieces from the initial state `start`, or None where it does not
    split (or splitting would not be exact); without `phases`, into independent parts only."""
    try:
        piece = _at(original, compressed, start, {}, top=True, phases=phases)
    except _NotExact:
        return None
    return None if piece is None or isinstance(piece, Part) else piece


class _NotExact(Exception):
    """A part would read or write an atom it does not own: the whole is not split."""


# ---------------------------------------------------------------------------
# Atoms

def atoms_of(node: Behaviour) -> set[Term]:
    """Every atom a condition of `node`'s subtree reads or sets."""
    found: set[Term] = set()
    stack = [node]
    while stack:
        n = stack.pop()
        for c in (n.pre, n.post):
            found.update(lit.atom for lit in cond.literals(c))
        stack.extend(n.children)
    return found


def _atoms(c: Condition) -> set[Term]:
    return {lit.atom for lit in cond.literals(c)}


def _written_inside(node: Behaviour) -> set[Term]:
    """The atoms the post-conditions below `node` set (its own post excluded)."""
    found: set[Term] = set()
    stack = list(node.children)
    while stack:
        n = stack.pop()
        found.update(_atoms(n.post))
        stack.extend(n.children)
    return found


def _read_inside(node: Behaviour) -> set[Term]:
    found: set[Term] = set()
    for child in node.children:
        found |= atoms_of(child)
    return found


def _same(a: Condition, b: Condition, fixed: Fixed) -> bool:
    """`a` and `b` agree wherever the fixed atoms have their values (compared canonically)."""
    if fixed:
        a, b = cond.assign(a, fixed), cond.assign(b, fixed)
    return a == b or cond.canonical(a) == cond.canonical(b)


def _owned(part: Part) -> None:
    """Check that the compressed side of a part reads and writes only the part's own atoms:
    otherwise what it does would depend on, or change, another piece."""
    own = part.atoms
    stack = [part.compressed]
    while stack:
        n = stack.pop()
        for c in (n.pre, n.post):
            for lit in cond.literals(c):
                if lit.atom not in own:
                    raise _NotExact
        if not n.children:
            for origin in n.origins:
                for lit in cond.literals(origin.post):
                    if lit.atom not in own:
                        raise _NotExact
        stack.extend(n.children)


def _part(label: Term, original: Behaviour, compressed: Behaviour, atoms: frozenset, start: State,
          fixed: Fixed) -> Part:
    """A part with the fixed atoms' values written into its conditions (they keep them while
    it runs): what is left reads and sets only its own atoms, which is checked."""
    fixed = {a: v for a, v in fixed.items() if a not in _atoms(original.post)}
    original, compressed = _fix(original, fixed), _fix(compressed, fixed)
    own = frozenset(a for a in atoms if a not in fixed)
    part = Part(label, original, compressed, own, frozenset(a for a in start if a in own))
    _owned(part)
    return part


def _fix(node: Behaviour, fixed: Fixed) -> Behaviour:
    """`node`'s subtree with the fixed atoms' values in every condition."""
    if not fixed:
        return node
    return replace(node, releaser=cond.assign(node.releaser, fixed), context=cond.assign(node.context, fixed),
                   post=cond.assign(node.post, fixed), children=tuple(_fix(k, fixed) for k in node.children))


def _start(start: State, atoms: frozenset, fixed: Fixed) -> State:
    """A piece's start: the whole's start on its atoms, and the true fixed atoms."""
    return frozenset(a for a in start if a in atoms) | frozenset(a for a, v in fixed.items() if v)


# ---------------------------------------------------------------------------
# Independent parts: the children of a behaviour X grouped by shared atoms

def _at(o: Behaviour, c: Behaviour, start: State, fixed: Fixed, top: bool = False,
        phases: bool = True) -> Piece | None:
    """The pieces of X = (o, c) from `start`, or None where X does not split.

    X splits when it stands for itself in both trees (the same pre- and post-condition where
    the fixed atoms hold), its pre-condition holds and its post-condition does not in `start`,
    no descendant sets its conditions' atoms and none reads its post-condition's. Then X stays
    active until all its children are accomplished, and its conditions' atoms keep their
    values meanwhile: they are fixed for the pieces below."""
    if not o.children or not c.children:
        return None
    if not _same(o.pre, c.pre, fixed) or not _same(o.post, c.post, fixed):
        return None
    if not cond.holds(o.pre, start) or cond.holds(o.post, start):
        return None
    post_atoms, pre_atoms = _atoms(o.post), _atoms(o.pre)
    if post_atoms & _read_inside(o) or (pre_atoms | post_atoms) & _written_inside(o):
        return None
    below = {**fixed, **{a: a in start for a in pre_atoms | post_atoms}}
    atoms = [atoms_of(child) for child in o.children]
    group = list(range(len(o.children)))

    def find(i: int) -> int:
        while group[i] != i:
            group[i] = group[group[i]]
            i = group[i]
        return i

    owner: dict[Term, int] = {}
    for i, found in enumerate(atoms):
        for atom in found:
            if atom in below:
                continue            # read by several children, set by none: shared, not a link
            if atom in owner:
                group[find(i)] = find(owner[atom])
            else:
                owner[atom] = i
    members: dict[int, list[int]] = {}
    for i in range(len(o.children)):
        members.setdefault(find(i), []).append(i)
    mapped: dict[int, list[Behaviour]] = {}
    for child in c.children:
        positions = {origin.position for origin in child.origins if origin.slot == 0}
        if not child.origins or len(positions) != len(child.origins):
            return None
        roots = {find(p) for p in positions if p < len(o.children)}
        if len(roots) != 1:
            return None
        mapped.setdefault(roots.pop(), []).append(child)
    pieces: list[Piece] = []
    for root, indices in members.items():
        o_kids = tuple(o.children[i] for i in indices)
        c_kids = tuple(mapped.get(root, ()))
        group_atoms = frozenset().union(*(atoms[i] for i in indices))
        group_start = _start(start, group_atoms, below)
        piece = None
        if len(o_kids) == 1 and len(c_kids) == 1 and len(c_kids[0].origins) == 1:
            piece = _at(o_kids[0], c_kids[0], group_start, below, phases=phases)
        elif len(o_kids) > 1 and phases:
            piece = _chain(o, indices, c_kids, group_start, below)
        if piece is None:
            post = cond.conjoin([k.post for k in o_kids])
            piece = _part(o.label, Behaviour(o.label, post=post, children=o_kids),
                          Behaviour(o.label, post=post, children=c_kids, origins=c.origins[:1]),
                          group_atoms, group_start, below)
        pieces.append(piece)
    if len(pieces) == 1:
        return None if isinstance(pieces[0], Part) and not top else pieces[0]
    all_atoms = frozenset().union(*(p.atoms for p in pieces))
    return Group(o.label, tuple(pieces), all_atoms, _start(start, all_atoms, below))


# ---------------------------------------------------------------------------
# Sequential phases: a group of siblings released one by one

def _chain(x: Behaviour, indices: list[int], c_kids: tuple[Behaviour, ...], start: State,
           fixed: Fixed) -> Chain | None:
    """The phases of a group of X's children that form a chain, or None.

    A chain: c1 is released by a condition no behaviour of the group sets and c(k+1) by
    exactly `ck.post`, a single positive atom set only by ck's completion (the world's rule)
    and read by nothing else; the atoms below each ck are its own; none of the posts holds
    at the start. Then c1 runs alone until it is accomplished, then c2, ... In the compressed
    tree, in phase i (the posts before ci true, the others false) every compressed child of
    X but one must be inactive whatever the other atoms, and that one must contain ci and
    only ci's children may be active in it: it then runs exactly ci's compressed subtree."""
    kids = [x.children[i] for i in indices]
    posts: dict[Term, int] = {}
    for k, kid in enumerate(kids):
        post = cond.canonical(kid.post)
        if not isinstance(post, cond.Lit) or not post.positive or post.atom in posts:
            return None
        posts[post.atom] = k
    after: dict[int, int] = {}
    head = None
    for k, kid in enumerate(kids):
        pre = cond.canonical(kid.pre)
        if isinstance(pre, cond.Lit) and pre.positive and pre.atom in posts and posts[pre.atom] != k:
            before = posts[pre.atom]
            if before in after:
                return None                    # a branch: two behaviours released by one post
            after[before] = k
        elif head is None:
            head = k
        else:
            return None
    order = []
    k = head
    while k is not None and len(order) <= len(kids):
        order.append(k)
        k = after.get(k)
    if head is None or len(order) != len(kids):
        return None
    ends = [cond.canonical(kids[k].post).atom for k in order]
    if any(d in start for d in ends):
        return None
    head_atoms = _atoms(kids[order[0]].pre)
    written: set[Term] = set(ends)
    inner: list[set[Term]] = []
    for k in order:
        below = _read_inside(kids[k])
        written |= _written_inside(kids[k])
        inner.append(below)
    if head_atoms & written or not cond.holds(kids[order[0]].pre, start):
        return None
    seen: set[Term] = set(head_atoms)
    for d, own in zip(ends, inner):
        if d in own:
            return None                       # read or set below: not only by the completion
        mine = (own - fixed.keys()) | {d}     # fixed atoms are read by many, set by none
        if mine & seen:
            return None
        seen |= mine
    phases = []
    for i, k in enumerate(order):
        phase_fixed = {**fixed, **{a: a in start for a in head_atoms},
                       **{d: j < i for j, d in enumerate(ends) if j != i}}
        deciding = {**phase_fixed, ends[i]: False}        # at a decision in phase i, ends[i] is false
        compressed = _phase_tree(x, indices[k], kids[k], c_kids, deciding)
        if compressed is None:
            return None
        atoms = frozenset(inner[i] | {ends[i]} | _atoms(kids[k].pre))
        phase_start = _start(start, atoms, phase_fixed)
        piece = _at(kids[k], compressed, phase_start, phase_fixed) if kids[k].children else None
        if piece is None:
            if kids[k].children:
                piece = _part(kids[k].label, kids[k], compressed, atoms, phase_start, phase_fixed)
            else:                              # a leaf: its part is rooted at X, ended by its post
                post = kids[k].post
                piece = _part(x.label, Behaviour(x.label, post=post, children=(kids[k],)),
                              Behaviour(x.label, post=post, children=(compressed,), origins=x.origins[:1]),
                              atoms, phase_start, phase_fixed)
        phases.append(piece)
    all_atoms = frozenset().union(*(p.atoms for p in phases))
    return Chain(x.label, tuple(phases), tuple(ends), all_atoms, start)


def _active_can_be(node: Behaviour, values: Fixed) -> bool:
    """Whether `node` can be active (pre-condition true, post-condition false) where the
    atoms of `values` have those values."""
    return cond.assign(cond.conjoin([node.pre, cond.negate(node.post)]), values) != cond.FALSE


def _phase_tree(x: Behaviour, position: int, kid: Behaviour, c_kids: tuple[Behaviour, ...],
                deciding: Fixed) -> Behaviour | None:
    """The compressed tree that runs in the phase of X's child `kid` (at `position`): the one
    compressed child that can be active, with only `kid`'s children, under `kid`'s own
    conditions; None when that is not what the compressed tree does."""
    live = [y for y in c_kids if _active_can_be(y, deciding)]
    if len(live) != 1:
        return None
    y = live[0]
    slot = next((j for j, origin in enumerate(y.origins) if origin.position == position), None)
    if slot is None or cond.assign(cond.conjoin([y.pre, cond.negate(y.post)]), deciding) != cond.TRUE:
        return None
    if not kid.children:                        # an action: the compressed one must be it alone
        if y.children or len(y.origins) != 1:
            return None
        return y
    if not y.children:
        return None
    children = []
    for z in y.children:
        if not _active_can_be(z, deciding):
            continue
        if any(origin.slot != slot for origin in z.origins) or not z.origins:
            return None
        children.append(replace(z, origins=tuple(replace(origin, slot=0) for origin in z.origins)))
    if not children:
        return None
    return replace(y, releaser=kid.releaser, context=cond.TRUE, post=kid.post, children=tuple(children),
                   origins=(replace(y.origins[slot], slot=0),))


# ---------------------------------------------------------------------------
# Shapes: parts that are one another up to names

Shape = tuple     # a part with its atoms and behaviour labels numbered in order of appearance


def shape_of(part: Part) -> tuple[Shape, list[Term], list[Term]]:
    """The part's shape, and its atoms and labels in the order the shape numbers them.

    Two parts with the same shape are the same verification problem up to a one-to-one
    renaming of atoms and of labels: both trees (every condition, every child in order, every
    constituent's label, post-condition and place) and the start state correspond under it,
    and verifying reads nothing else (a constituent's releaser is provenance only)."""
    atoms: dict[Term, int] = {}
    labels: dict[Term, int] = {}

    def atom(a: Term) -> int:
        found = atoms.get(a)
        if found is None:
            found = atoms[a] = len(atoms)
        return found

    def label(t: Term) -> int:
        found = labels.get(t)
        if found is None:
            found = labels[t] = len(labels)
        return found

    def condition(c: Condition) -> tuple | int | bool:
        kind = type(c)
        if kind is cond.Lit:
            return atom(c.atom) if c.positive else -1 - atom(c.atom)
        if kind is cond.Const:
            return c.value
        if kind is cond.Not:
            return ("not", condition(c.item))
        return ("and" if kind is cond.And else "or", *(condition(i) for i in c.items))

    def tree(root: Behaviour) -> tuple:
        out: list = []
        stack = [root]
        while stack:
            n = stack.pop()
            out.append((label(n.label), condition(n.pre), condition(n.post), len(n.children),
                        tuple((label(o.label), condition(o.post), o.position, o.slot) for o in n.origins)))
            stack.extend(reversed(n.children))
        return tuple(out)

    shape = (tree(part.original), tree(part.compressed),
             tuple(sorted(atom(a) for a in part.start)))
    return shape, list(atoms), list(labels)


__all__ = ["Part", "Group", "Chain", "Piece", "decompose", "parts_of", "atoms_of", "shape_of"]
