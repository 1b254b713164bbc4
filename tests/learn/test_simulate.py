"""Synthetic demonstrations segment back into the actions of the task they demonstrate."""

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from conftest import COFFEE, MIX, ROOT
from schemalog.formats.documents import load_kb
from schemalog.errors import SchemalogError
from schemalog.logic.parse import parse_term
from schemalog.run.scene import Scene, read_scene
from schemalog.learn.demo import demonstration_csv, demonstration_from_csv
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


@settings(max_examples=8, deadline=None)
@given(rate=st.sampled_from([1.0, 7.0, 100.0, 1000.0, 10_000.0]), seed=st.integers(0, 2 ** 16),
       noise=st.sampled_from([0.0, 0.001, 0.01]))
def test_what_simulate_demo_writes_learn_reads_at_every_rate(rate, seed, noise):
    # The mismatch this guards against: at 10 kHz, 1 mm of noise per sample read as 21.8 m/s jumps.
    kb = load_kb([MIX])
    scene = read_scene(ROOT / "kb" / "scenes" / "mix_with_spoon.yaml")
    try:
        demo = simulate(kb, parse_term("use(spoon)"), scene, seed=seed, noise=noise, rate=rate, speed=2.0)
    except SchemalogError as error:       # the simulation may refuse (too few samples to segment as planned)
        assert "would segment as" in str(error) or "segments into" in str(error)
        assume(False)
    text = demonstration_csv(demo, "a comment")
    back = demonstration_from_csv(text, "demo.csv")            # raises if learn would refuse it
    assert len(back) == len(demo)
    assert [s.label for s in segment(back)] == [s.label for s in segment(demo)]


def test_a_demonstration_over_the_sample_budget_is_refused_before_it_is_built():
    kb = load_kb([MIX])
    scene = read_scene(ROOT / "kb" / "scenes" / "mix_with_spoon.yaml")
    with pytest.raises(SchemalogError, match=r"more than 1,000 samples at 100 Hz and 0.25 m/s: lower --rate"):
        simulate(kb, parse_term("use(spoon)"), scene, max_samples=1000)


def test_a_demonstration_learn_would_refuse_is_not_simulated():
    # --noise is bounded to 1 cm on the command line; the library refuses what learn would
    kb = load_kb([MIX])
    scene = read_scene(ROOT / "kb" / "scenes" / "mix_with_spoon.yaml")
    with pytest.raises(SchemalogError, match=r"would be refused by learn: the end-effector jumps .* lower --noise"):
        simulate(kb, parse_term("use(spoon)"), scene, noise=0.2)
