"""Synthetic demonstrations segment back into the actions of the task they demonstrate."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conftest import COFFEE, MIX, ROOT
from schemalog.formats.documents import load_kb
from schemalog.errors import SchemalogError
from schemalog.logic.parse import parse_term
from schemalog.run.scene import Scene, read_scene
from schemalog.learn.segment import segment
from schemalog.learn.simulate import demonstrated_leaves, simulate
from schemalog.logic.terms import term_to_text

KITCHEN = ROOT / "kb" / "scenes" / "kitchen.yaml"


@settings(max_examples=12, deadline=None)
@given(st.sampled_from(["preparecoffee", "preparetea", "prepareboth"]), st.integers(0, 2**16),
       st.floats(0.0, 0.03))
def test_every_task_segments_into_its_actions_in_a_moved_kitchen(task, seed, jitter):
    kb = load_kb([COFFEE])
    scene = read_scene(KITCHEN).jittered(seed, jitter)
    demo = simulate(kb, parse_term(task), scene, seed=seed)
    leaves = demonstrated_leaves(kb, parse_term(task), scene)
    got = [(s.kind, s.obj if s.kind == "motion" else term_to_text(s.label)) for s in segment(demo)]
    wanted = [("gripper", term_to_text(leaf.label)) if leaf.command else ("motion", leaf.obj) for leaf in leaves]
    assert got == wanted
    assert np.all(np.diff(demo.times) > 0)
    speeds = np.linalg.norm(np.diff(demo.positions, axis=0), axis=1) / np.diff(demo.times)
    assert speeds.max() < 2.0        # smooth: no jumps (noise included)


def test_carried_objects_move_with_the_hand_and_stay_where_released():
    kb = load_kb([MIX])
    demo = simulate(kb, parse_term("use(spoon)"), read_scene(ROOT / "kb" / "scenes" / "mix_with_spoon.yaml"),
                    noise=0.0)
    close, release = demo.gripper[0].index, demo.gripper[1].index
    spoon = demo.objects["spoon"]
    assert np.allclose(spoon[:close + 1], spoon[0])                         # on the table until the grasp
    offset = spoon[close] - demo.positions[close]
    assert np.allclose(spoon[close:release + 1], demo.positions[close:release + 1] + offset)
    assert np.allclose(spoon[release:], spoon[release])                     # stays where it was let go


def test_objects_too_close_together_are_refused():
    kb = load_kb([MIX])
    scene = Scene(objects={"spoon": (0.5, 0.0, 0.02), "cup": (0.55, 0.0, 0.05)}, end_effector=(0.4, 0.0, 0.45),
                  name="cramped")
    with pytest.raises(SchemalogError, match="cramped would segment as"):
        simulate(kb, parse_term("use(spoon)"), scene)


def test_a_2d_scene_cannot_be_demonstrated():
    kb = load_kb([MIX])
    scene = Scene(objects={"spoon": (0.5, 0.0), "cup": (0.9, 0.0)}, end_effector=(0.4, 0.0), name="flat")
    with pytest.raises(SchemalogError, match="2-D"):
        simulate(kb, parse_term("use(spoon)"), scene)
