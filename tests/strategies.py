"""Hypothesis strategies shared by the test modules of several layers."""

from hypothesis import strategies as st

from schemalog.logic.parse import parse_term
from schemalog.task import conditions as cond
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
