"""Artificial tasks in the shape of the paper's evaluation (Sec. IV-B).

    generate(depth, branching, reduction, seed) -> Behaviour

A full tree: one root, `branching` children per behaviour, `depth` levels (depth 4 and 2
children give 15 behaviours; depth 6 and 4 children, 1,365). The second level is released by
`true`, each of its behaviours on its own object. From the third level on, each sibling group
is cut into chains: a chain's first behaviour is released by `true`, each next one by the
previous one's `done`, and a chain acts on one object while the other chains of the group act
on others. Every behaviour's post-condition is `b<N>.done`. Each link of a chain is one pair
that Algorithm 1 merges, so the number of links sets the reduction degree
RD = links / (Bi - D) (capped at what the shape allows).
"""

from __future__ import annotations

import math
import random

from . import conditions as cond
from .scene import Scene
from .terms import Atom, Struct, Term
from .tree import Behaviour


def done(label: Term) -> cond.Lit:
    """`bN.done` for the behaviour labelled bN or bN(obj)."""
    name = label.name if isinstance(label, (Atom, Struct)) else str(label)
    return cond.Lit(Struct(".", (Atom(name), Atom("done"))))


def node_count(depth: int, branching: int) -> int:
    """Bi of a full tree: 1 + b + b^2 + ... + b^(depth-1)."""
    return sum(branching ** level for level in range(depth))


def max_links(depth: int, branching: int) -> int:
    """How many sequential pairs the shape allows: every adjacent pair below level 2."""
    return sum(branching ** (level - 2) * (branching - 1) for level in range(3, depth + 1))


def generate(depth: int, branching: int, reduction: float = 0.0, seed: int = 0) -> Behaviour:
    """A task tree of the paper's evaluation with about the requested reduction degree."""
    if depth < 1 or branching < 1:
        raise ValueError("depth and branching must be at least 1")
    if not 0.0 <= reduction <= 1.0:
        raise ValueError("the reduction degree is between 0 and 1")
    rng = random.Random(seed)
    total = node_count(depth, branching)
    slots = [(level, group, j) for level in range(3, depth + 1)
             for group in range(branching ** (level - 2)) for j in range(1, branching)]
    wanted = min(len(slots), round(reduction * (total - depth))) if total > depth else 0
    links = set(rng.sample(slots, wanted))
    counter = iter(range(1, total + 1))

    def build(level: int, group: int, releaser: cond.Condition, obj: str | None) -> Behaviour:
        number = next(counter)
        name = f"b{number}"
        label: Term = Struct(name, (Atom(obj),)) if obj else Atom(name)
        children: list[Behaviour] = []
        if level < depth:
            objects = _chain_objects(level + 1, group, branching, links)
            previous = None
            for j in range(branching):
                linked = (level + 1, group, j) in links
                pre = done(previous.label) if linked and previous is not None else cond.TRUE
                child = build(level + 1, group * branching + j, pre, objects[j])
                children.append(child)
                previous = child
        return Behaviour(label=label, objects=(Atom(obj),) if obj else (), releaser=releaser,
                         post=done(label), children=tuple(children))

    return build(1, 0, cond.TRUE, None)


def _chain_objects(level: int, group: int, branching: int, links: set) -> list[str]:
    """Objects of one sibling group: a chain shares one, different chains differ."""
    if level == 2:
        return [f"obj{j + 1}" for j in range(branching)]
    objects = []
    chain = 0
    for j in range(branching):
        if j > 0 and (level, group, j) not in links:
            chain += 1
        objects.append(f"obj{chain + 1}")
    return objects


def scene_for(branching: int, radius: float = 0.5, seed: int | None = None) -> Scene:
    """A scene for generated tasks: obj1..objN on a circle around the hand's start."""
    rng = random.Random(seed)
    objects = {}
    for j in range(branching):
        angle = 2 * math.pi * j / branching + (rng.uniform(-0.3, 0.3) if seed is not None else 0.0)
        objects[f"obj{j + 1}"] = (round(radius * math.cos(angle), 6), round(radius * math.sin(angle), 6), 0.0)
    return Scene(objects=objects, end_effector=(0.0, 0.0, 0.3), name=f"circle of {branching}")


__all__ = ["generate", "node_count", "max_links", "scene_for", "done"]
