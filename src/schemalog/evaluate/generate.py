"""Artificial tasks in the shape of the paper's evaluation (Sec. IV-B).

    generate(depth, branching, reduction, seed) -> Behaviour

A full tree: one root, `branching` children per behaviour, `depth` levels (depth 4 and 2
children give 15 behaviours; depth 6 and 4 children, 1,365). The second level is released by
`true`, each of its behaviours on its own object. From the third level on, each sibling group
is cut into chains: a chain's first behaviour is released by `true`, each next one by the
previous one's `done`, and a chain acts on one object while the other chains of the group act
on others. Every behaviour's post-condition is `b<N>.done`.

Each link of a chain is one pair that Algorithm 1 merges, so the number of links sets the
reduction degree RD = links / (Bi - D). Sibling links alone cap RD at about 0.53 for binary
trees, below the paper's 0.7; the paper allows any other behaviour's `done` ("b_j.done, active
if another behavior b_j is executed"), so beyond the sibling links a group's first behaviour
may be released by the previous group's last one, where their parents are linked (a cousin
link): once the parents merge, the two are siblings in one chain. That reaches every cell of
the paper's grid within TOLERANCE.
"""

from __future__ import annotations

import math
import random

from .. import defaults
from ..task import conditions as cond
from ..run.scene import Scene
from ..logic.terms import Atom, Struct, Term
from ..task.tree import Behaviour


def done(label: Term) -> cond.Lit:
    """`bN.done` for the behaviour labelled bN or bN(obj)."""
    name = label.name if isinstance(label, (Atom, Struct)) else str(label)
    return cond.Lit(Struct(".", (Atom(name), Atom("done"))))


def node_count(depth: int, branching: int) -> int:
    """Bi of a full tree: 1 + b + b^2 + ... + b^(depth-1)."""
    return sum(branching ** level for level in range(depth))


def max_links(depth: int, branching: int, cousins: bool = True) -> int:
    """How many merges the shape allows: every level from the third down to one behaviour
    per second-level sub-tree (`cousins`), or only sibling chains (not `cousins`)."""
    siblings = sum(branching ** (level - 2) * (branching - 1) for level in range(3, depth + 1))
    if not cousins:
        return siblings
    return siblings + sum(branching ** (level - 2) - branching for level in range(4, depth + 1))


def max_reduction(depth: int, branching: int, cousins: bool = True) -> float:
    """The largest reduction degree the shape allows (RD of `max_links`)."""
    total = node_count(depth, branching)
    return max_links(depth, branching, cousins) / (total - depth) if total > depth else 0.0


Slot = tuple[int, int, int]   # (level, group, j): the j-th child of the group-th behaviour one level up


def choose_links(depth: int, branching: int, wanted: int, rng: random.Random,
                 cousins: bool = True) -> set[Slot]:
    """`wanted` links: sibling slots first, at random; then, if more are wanted, cousin slots.

    A sibling link (j >= 1) releases the j-th child by its predecessor's `done`. A cousin link
    (j = 0, level >= 4) releases a group's first child by the previous group's last child,
    and is taken only where the two parents are linked themselves: once Algorithm 1 has merged
    the parents, the two children are siblings in a chain.
    """
    siblings = [(level, group, j) for level in range(3, depth + 1)
                for group in range(branching ** (level - 2)) for j in range(1, branching)]
    if wanted <= len(siblings):
        return set(rng.sample(siblings, wanted))
    links = set(siblings)
    if not cousins:
        return links
    for level in range(4, depth + 1):   # parents a level up are all linked before a level is used
        open_slots = [(level, group, 0) for group in range(branching ** (level - 2))
                      if group % branching or (level - 1, group // branching, 0) in links]
        take = min(wanted - len(links), len(open_slots))
        links.update(rng.sample(open_slots, take))
        if len(links) == wanted:
            break
    return links


def generate(depth: int, branching: int, reduction: float = 0.0, seed: int = 0,
             cousins: bool = True) -> Behaviour:
    """A task tree of the paper's evaluation with about the requested reduction degree."""
    if depth < 1 or branching < 1:
        raise ValueError("depth and branching must be at least 1")
    if not 0.0 <= reduction <= 1.0:
        raise ValueError("the reduction degree is between 0 and 1")
    rng = random.Random(seed)
    total = node_count(depth, branching)
    wanted = min(max_links(depth, branching, cousins), round(reduction * (total - depth))) \
        if total > depth else 0
    links = choose_links(depth, branching, wanted, rng, cousins)
    counter = iter(range(1, total + 1))
    latest: dict[int, Term] = {}     # level -> the label built last on it (DFS: the previous group's last)
    chain_of: dict[int, int] = {}    # level -> the chain number of that behaviour

    def build(level: int, index: int, releaser: cond.Condition, obj: str | None) -> Behaviour:
        name = f"b{next(counter)}"
        label: Term = Struct(name, (Atom(obj),)) if obj else Atom(name)
        latest[level] = label
        children: list[Behaviour] = []
        if level < depth:
            below = level + 1
            previous: Term | None = latest.get(below) if (below, index, 0) in links else None
            chain = chain_of.get(below, 0) if previous is not None else 0
            for j in range(branching):
                if j and (below, index, j) not in links:
                    chain += 1
                    previous = None
                pre = done(previous) if previous is not None else cond.TRUE
                obj_below = f"obj{j + 1}" if below == 2 else f"obj{chain % branching + 1}"
                chain_of[below] = chain
                child = build(below, index * branching + j, pre, obj_below)
                children.append(child)
                previous = child.label
        return Behaviour(label=label, objects=(Atom(obj),) if obj else (), releaser=releaser,
                         post=done(label), children=tuple(children))

    return build(1, 0, cond.TRUE, None)


TOLERANCE = defaults.RD_TOLERANCE


def shortfall(depth: int, branching: int, asked: float, got: float, cousins: bool = True) -> str | None:
    """Why the achieved reduction degree misses the request by more than TOLERANCE (None if it
    does not): the shape's ceiling, or the step of one merge in a small tree."""
    if abs(got - asked) <= TOLERANCE:
        return None
    total = node_count(depth, branching)
    if total <= depth:
        return f"a tree of {total} behaviours and depth {depth} has nothing to merge (Bi = D)"
    ceiling = max_reduction(depth, branching, cousins)
    if asked > ceiling:
        limit = ("a level below merges at most down to one behaviour per second-level sub-tree" if cousins
                 else "a sibling group merges at most into one behaviour (--siblings-only)")
        return (f"depth {depth} with {branching} children allows RD at most {ceiling:.2f}: "
                f"the second level is never merged and {limit}")
    return (f"one merge moves RD by 1/(Bi - D) = 1/{total - depth} = {1 / (total - depth):.2f}, "
            f"so {asked:.2f} falls between two reachable values")


def scene_for(branching: int, radius: float = 0.5, seed: int | None = None) -> Scene:
    """A scene for generated tasks: obj1..objN on a circle around the hand's start."""
    rng = random.Random(seed)
    objects = {}
    for j in range(branching):
        angle = 2 * math.pi * j / branching + (rng.uniform(-0.3, 0.3) if seed is not None else 0.0)
        objects[f"obj{j + 1}"] = (round(radius * math.cos(angle), 6), round(radius * math.sin(angle), 6), 0.0)
    return Scene(objects=objects, end_effector=(0.0, 0.0, 0.3), name=f"circle of {branching}")


__all__ = ["generate", "node_count", "max_links", "max_reduction", "choose_links", "shortfall", "TOLERANCE", "scene_for", "done"]
