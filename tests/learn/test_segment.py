"""Segmentation (Sec. II-C): a motion ends entering or leaving a proximity sphere, or at a
gripper command; the object in the hand does not segment."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from schemalog.learn.demo import Demonstration, GripperEvent
from schemalog.errors import SchemalogError
from schemalog.learn.segment import segment, smoothed
from schemalog.logic.terms import term_to_text

CUP = (0.6, 0.1, 0.05)
SPOON = (0.3, -0.3, 0.02)


def walk(*waypoints, commands=(), objects=None, per_leg=40, noise=0.0, seed=0, carry=None) -> Demonstration:
    """Straight legs through `waypoints`; commands = [(waypoint index, 'open'|'close')]."""
    points = [np.array(waypoints[0], float)]
    marks = {0: 0}
    for k in range(1, len(waypoints)):
        a, b = np.array(waypoints[k - 1], float), np.array(waypoints[k], float)
        points += [a + (b - a) * s for s in np.linspace(0, 1, per_leg + 1)[1:]]
        marks[k] = len(points) - 1
    positions = np.array(points)
    n = len(positions)
    objects = {name: np.repeat(np.array([p], float), n, axis=0)
               for name, p in (objects or {"cup": CUP, "spoon": SPOON}).items()}
    if carry:   # (name, from waypoint, to waypoint): the object moves with the hand
        name, first, last = carry
        offset = objects[name][0] - positions[marks[first]]
        objects[name][marks[first]:marks[last] + 1] = positions[marks[first]:marks[last] + 1] + offset
        objects[name][marks[last] + 1:] = objects[name][marks[last]]
    if noise:
        positions = positions + np.random.default_rng(seed).normal(0, noise, positions.shape)
    events = tuple(GripperEvent(marks[k], c, marks[k] + 2) for k, c in commands)
    return Demonstration(np.arange(n) * 0.01, positions, None, events, objects, np.arange(2, n + 2), "w.csv")


def labels(segments):
    return [(term_to_text(s.label), s.cause) for s in segments]


ABOVE_SPOON = (0.3, -0.3, 0.40)


def test_take_the_spoon_and_mix_as_in_figure_2():
    # approach the spoon (enter), grasp (close), carry it into the cup (enter), out (leave),
    # back in (enter), out (leave), beside the cup (open)
    demo = walk((0.3, -0.3, 0.40), (0.3, -0.3, 0.10), (0.3, -0.3, 0.03), (0.6, 0.1, 0.30), (0.6, 0.1, 0.12),
                (0.6, 0.1, 0.30), (0.6, 0.1, 0.12), (0.6, 0.1, 0.30), (0.78, 0.1, 0.30), (0.78, 0.1, 0.06),
                commands=[(2, "close"), (9, "open")], carry=("spoon", 2, 9))
    assert labels(segment(demo)) == [
        ("a1(spoon)", "enters spoon"), ("a2(spoon)", "gripper close"), ("gripper(close)", "gripper close"),
        ("a3(cup)", "enters cup"), ("a4(cup)", "leaves cup"), ("a5(cup)", "enters cup"),
        ("a6(cup)", "leaves cup"), ("a7(cup)", "gripper open"), ("gripper(open)", "gripper open")]


def test_without_carrying_the_spoon_would_cut_the_carry():
    # The same path with the spoon left on the table: leaving its sphere is an event then.
    demo = walk((0.3, -0.3, 0.40), (0.3, -0.3, 0.03), (0.6, 0.1, 0.30), commands=[(1, "close")],
                objects={"spoon": SPOON, "cup": CUP})
    demo_carried = walk((0.3, -0.3, 0.40), (0.3, -0.3, 0.03), (0.6, 0.1, 0.30), commands=[(1, "close")],
                        objects={"spoon": SPOON, "cup": CUP}, carry=("spoon", 1, 2))
    # Held, the spoon is excluded whether or not its track follows the hand.
    assert labels(segment(demo)) == labels(segment(demo_carried))
    assert [s.obj for s in segment(demo)][-1] == "cup"


def test_the_radius_is_configurable():
    demo = walk((0.6, 0.1, 0.45), (0.6, 0.1, 0.17), (0.6, 0.1, 0.45))
    with pytest.raises(SchemalogError):                             # never within 0.1 m ...
        segment(demo, radius=0.1)
    assert labels(segment(demo, radius=0.15)) == [("a1(cup)", "enters cup"), ("a2(cup)", "leaves cup"),
                                                  ("a3(cup)", "end")]


def test_a_demonstration_that_touches_no_object_is_refused():
    demo = walk((0.6, 0.1, 0.45), (0.6, 0.1, 0.20))
    with pytest.raises(SchemalogError) as info:
        segment(demo)
    message = str(info.value)
    assert message.startswith("w.csv:42:1: error: the end-effector never comes within 0.1 m of an object "
                              "(nearest: cup, 0.150 m at line 42)")


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.0, 0.002))
def test_noise_at_the_border_does_not_cut_slivers(seed, noise):
    # In, out, in again: three events whatever the noise, thanks to the hysteresis.
    demo = walk((0.6, 0.1, 0.40), (0.6, 0.1, 0.10), (0.6, 0.1, 0.30), (0.6, 0.1, 0.10), noise=noise, seed=seed,
                per_leg=80)
    assert [s.cause for s in segment(demo)] == ["enters cup", "leaves cup", "enters cup", "end"]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0.2, 0.8), st.floats(-0.4, 0.4), st.floats(0.0, 0.5)), min_size=2,
                max_size=8),
       st.lists(st.tuples(st.integers(0, 7), st.sampled_from(["open", "close"])), max_size=3))
def test_segments_partition_the_demonstration(points, commands):
    points = [(0.6, 0.1, 0.08), *points]          # starts in the cup: some object is touched
    commands = sorted({(k % len(points), c) for k, c in commands})
    demo = walk(*points, commands=commands)
    segments = segment(demo)
    motions = [s for s in segments if s.kind == "motion"]
    assert [term_to_text(s.label).split("(")[0] for s in motions] == [f"a{k}" for k in range(1, len(motions) + 1)]
    # Motions are consecutive: each starts where the previous stopped, none goes back.
    for a, b in zip(segments, segments[1:]):
        assert b.start >= a.end
    assert all(s.end > s.start for s in motions)
    # Only commands that change the gripper's state (it starts open) are actions.
    assert [term_to_text(s.label) for s in segments if s.kind == "gripper"] == \
        [f"gripper({c})" for c in _changes(sorted(commands))]
    hand = smoothed(demo.times, demo.positions, 0.05)
    for s in motions:
        moved = np.linalg.norm(hand[s.start:s.end + 1] - hand[s.start], axis=1).max()
        assert moved >= 0.01


def _changes(commands):
    state = "open"
    for _, command in commands:
        if command != state:
            yield command
        state = command


def test_repeated_gripper_commands_are_ignored_with_a_note():
    demo = walk((0.6, 0.1, 0.40), (0.6, 0.1, 0.03), (0.6, 0.1, 0.40),
                commands=[(0, "open"), (1, "close"), (2, "close")])
    notes = []
    assert labels(segment(demo, notes=notes)) == [("a1(cup)", "enters cup"), ("a2(cup)", "gripper close"),
                                                   ("gripper(close)", "gripper close"), ("a3(spoon)", "end")]
    assert notes[0] == "2 gripper commands that did not change its state ignored: line 2 (open), line 82 (close)"


def test_a_hand_that_never_moves_has_nothing_to_learn():
    demo = walk((0.6, 0.1, 0.05), (0.6, 0.1, 0.052))
    with pytest.raises(SchemalogError, match="no motion"):
        segment(demo)
