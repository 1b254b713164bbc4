"""Rendering: the JSON shape later commands reuse, DOT, the terminal, and tree -> knowledge."""

import json

from hypothesis import given, settings
from hypothesis import strategies as st
from rich.console import Console

from schemalog.task import conditions as cond
from schemalog.formats.documents import document_from_text, read_document, to_pl
from schemalog.logic.parse import parse_term
from schemalog.formats.render import rich_tree, show_json, to_dot, tree_document
from schemalog.task.tree import Behaviour, instantiate

from conftest import COFFEE, MIX

NODE_KEYS = {"label", "agent", "objects", "pre", "releaser", "post", "importance", "k", "merged_from",
             "children"}


def mix_tree():
    return instantiate(read_document(MIX).to_kb(), parse_term("use(spoon)"))


def test_show_json_shape():
    data = show_json(parse_term("use(spoon)"), mix_tree())
    assert (data["task"], data["nodes"], data["depth"]) == ("use(spoon)", 12, 3)
    take = data["tree"]["children"][0]
    assert set(take) == NODE_KEYS
    assert take["label"] == "subtask(take,spoon)" and take["pre"] == "hand.free"
    assert take["post"] == "spoon.taken" and take["objects"] == ["spoon"] and take["agent"] == "arm"
    assert take["children"][2]["agent"] == "gripper" and take["children"][2]["post"] == "not hand.free"
    json.dumps(data)  # serialisable as is


def test_dot_has_every_behaviour_and_edge_with_coloured_conditions():
    dot = to_dot(mix_tree(), "use(spoon)")
    assert dot.startswith('digraph "use(spoon)"')
    assert dot.count("[label=<") == 12 and dot.count(" -> ") == 11
    assert '<font color="darkgreen">hand.free</font>' in dot
    assert '<font color="blue" point-size="9">not hand.free</font>' in dot


def test_terminal_tree_shows_conditions():
    console = Console(width=200, record=True, no_color=True)
    console.print(rich_tree(mix_tree(), "use(spoon)"))
    text = console.export_text()
    assert "subtask(take,spoon)  pre: hand.free  post: spoon.taken" in text
    assert "gripper(close) [gripper]" in text


def roundtrip(task, tree):
    doc = tree_document(tree)
    again = instantiate(document_from_text(to_pl(doc), "tree.pl").to_kb(), task)
    return again


def test_shipped_trees_written_as_knowledge_instantiate_to_themselves():
    for path, task in ((MIX, "use(spoon)"), (COFFEE, "prepareboth")):
        t = parse_term(task)
        tree = instantiate(read_document(path).to_kb(), t)
        assert roundtrip(t, tree) == tree


@st.composite
def trees(draw):
    counter = iter(range(10_000))
    objects = ["cup", "spoon", "water"]

    def node(level):
        n = next(counter)
        obj = draw(st.sampled_from(objects))
        label = parse_term(f"b{n}({obj})")
        kids = () if level >= 3 else tuple(node(level + 1) for _ in range(draw(st.integers(0, 3))))
        rel = draw(st.sampled_from(["true", f"b{max(n - 1, 0)}.done", "hand.free", "not hand.free"]))
        return Behaviour(label=label, agent=draw(st.sampled_from(["arm", "gripper"])),
                         objects=(parse_term(obj),), releaser=cond.from_term(parse_term(rel)),
                         post=cond.from_term(parse_term(f"b{n}.done")), children=kids,
                         importance=draw(st.sampled_from([1, 2, 0.5])))
    root = node(1)
    return Behaviour(label=root.label, agent=root.agent, objects=root.objects, post=root.post,
                     children=root.children)


@settings(max_examples=100, deadline=None)
@given(trees())
def test_any_tree_written_as_knowledge_instantiates_to_itself(tree):
    assert roundtrip(tree.label, tree) == tree


def test_a_tree_too_wide_for_the_paper_layout_is_drawn_compact_and_fits_a_screen():
    from schemalog.formats.graphviz import drawing_size, readable_on_screen, screen_scale

    assert screen_scale(1440, 810) == 1.0 and screen_scale(2880, 810) == 0.5
    assert readable_on_screen(1440, 810, 9) and not readable_on_screen(1441, 810, 9)
    small = to_dot(mix_tree(), "use(spoon)")
    assert "shape=ellipse" in small and readable_on_screen(*drawing_size(small), 9)   # the paper's drawing
    kb = document_from_text(COFFEE.read_text(), str(COFFEE)).to_kb()
    big = to_dot(instantiate(kb, parse_term("prepareboth")), "prepareboth")
    assert "shape=box, style=rounded" in big and "shape=point" in big                 # leaves in columns
    assert readable_on_screen(*drawing_size(big), 9)
