"""Hypothesis strategies shared by the test modules of several layers."""

from hypothesis import strategies as st

from schemalog.logic.parse import parse_term
from schemalog.task import conditions as cond
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import Behaviour


@st.composite
def task_trees(draw, max_children=5, levels=3):
    """Trees whose siblings form chains, branches and cycles on shared objects and agents."""
    ids = iter(range(100_000))

    def node(level):
        n = next(ids)
        if level >= levels:
            kids = ()
        else:
            count = draw(st.integers(0, max_children))
            names = [f"b{next(ids)}" for _ in range(count)]
            kids = []
            for i, name in enumerate(names):
                child = node(level + 1)
                choice = draw(st.integers(0, 3))
                releaser = "true" if i == 0 or choice == 0 else f"{names[draw(st.integers(0, count - 1))]}.done"
                obj = draw(st.sampled_from(["cup", "cup", "spoon"]))
                agent = draw(st.sampled_from(["arm", "arm", "gripper"]))
                kids.append(Behaviour(label=parse_term(f"{name}({obj})"), agent=agent,
                                      objects=(parse_term(obj),),
                                      releaser=cond.from_term(parse_term(releaser)),
                                      post=cond.from_term(parse_term(f"{name}.done")),
                                      children=child.children))
            kids = tuple(kids)
        return Behaviour(label=parse_term(f"n{n}"), post=cond.from_term(parse_term(f"n{n}.done")), children=kids)
    return node(1)


@st.composite
def trees(draw, chains: int = 3, toggles: bool = True):
    """Depth 2-6, 1-4 children, at most ~40 behaviours: chains (a sibling's done), branches (two
    siblings released by one), toggling posts (hand.free) and releasers that read them.
    `chains` of 6 draws release a later sibling by an earlier one's done (3: half of them);
    without `toggles`, actions set only their own done (hand.free is still read)."""
    levels = draw(st.integers(2, 6))
    budget = [draw(st.integers(4, 40))]
    ids = iter(range(10_000))

    def node(level, releaser, n):
        name = f"b{n}"
        count = 0
        if level < levels and budget[0] > 0:
            count = min(draw(st.integers(0 if level > 1 else 1, 4)), budget[0])
            budget[0] -= count
        names = [next(ids) for _ in range(count)]
        kids = []
        for i in range(count):
            choice = draw(st.integers(0, chains + 2))
            if i and choice < chains:
                before = names[i - 1] if draw(st.booleans()) else draw(st.sampled_from(names[:i]))
                rel = f"b{before}.done"                                  # a chain, or a branch
            elif choice == chains:
                rel = "hand.free"
            elif choice == chains + 1:
                rel = "not hand.free"
            else:
                rel = "true"
            kids.append(node(level + 1, rel, names[i]))
        post = f"{name}.done"
        if not kids and toggles:
            post += draw(st.sampled_from(["", "", " and not hand.free", " and hand.free"]))
        obj = draw(st.sampled_from(["cup", "spoon"]))
        return Behaviour(label=parse_term(f"{name}({obj})" if level > 1 else name), objects=(parse_term(obj),),
                         releaser=_condition(releaser), post=_condition(post), children=tuple(kids))

    return node(1, "true", next(ids))


@st.composite
def starts(draw, tree):
    """One to three initial states: hand.free and a few done markers, some true."""
    leaves = sorted({lit.atom for n in _walk(tree) for lit in cond.literals(n.post)}, key=term_to_text)
    pool = [parse_term("hand.free"), *leaves[:6]]
    return draw(st.lists(st.lists(st.sampled_from(pool), max_size=3), min_size=1, max_size=3))


def _walk(tree):
    stack = [tree]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(n.children)


def _condition(text: str) -> cond.Condition:
    return cond.from_term(parse_term(text))
