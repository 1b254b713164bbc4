"""Demonstration files: CSV and JSON read back what was written; bad rows are named."""

import json

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from schemalog.learn.demo import (Demonstration, GripperEvent, demonstration_csv, demonstration_from_csv,
                            demonstration_from_json, demonstration_json, read_demonstration)
from schemalog.errors import SchemalogError

HEADER = "t,x,y,z,gripper,cup_x,cup_y,cup_z"


def csv_text(*rows: str, header: str = HEADER) -> str:
    return "\n".join([header, *rows]) + "\n"


GOOD = ["0.0,0.4,0.0,0.3,,0.6,0.1,0.05", "0.1,0.5,0.05,0.2,,0.6,0.1,0.05",
        "0.2,0.6,0.1,0.1,close,0.6,0.1,0.05"]


def test_csv_reads_samples_events_and_objects():
    demo = demonstration_from_csv(csv_text(*GOOD), "d.csv")
    assert len(demo) == 3 and demo.orientations is None
    assert demo.gripper == (GripperEvent(2, "close", 4),)
    assert demo.positions[1].tolist() == [0.5, 0.05, 0.2]
    assert demo.objects["cup"].shape == (3, 3)
    assert demo.where(2) == "line 4"


def demos():
    """Random demonstrations: increasing times, finite positions, unit quaternions, some events."""
    @st.composite
    def build(draw):
        n = draw(st.integers(2, 12))
        steps = draw(st.lists(st.floats(0.4, 1.0), min_size=n, max_size=n))   # jumps under MAX_SPEED
        times = np.round(np.cumsum(steps), 4)
        coords = st.floats(-1, 1, allow_nan=False)
        positions = np.round(np.array(draw(st.lists(st.tuples(coords, coords, coords), min_size=n, max_size=n))), 6)
        q = np.array(draw(st.lists(st.tuples(*[st.floats(0.1, 1)] * 4), min_size=n, max_size=n)))
        q = np.round(q / np.linalg.norm(q, axis=1)[:, None], 6)
        q /= np.linalg.norm(q, axis=1)[:, None]
        indices = sorted(draw(st.sets(st.integers(0, n - 1), max_size=3)))
        events = tuple(GripperEvent(i, draw(st.sampled_from(["open", "close"])), 0) for i in indices)
        objects = {name: np.round(np.array(draw(st.lists(st.tuples(coords, coords, coords), min_size=n,
                                                                  max_size=n))), 6)
                   for name in draw(st.sets(st.sampled_from(["cup", "water", "spoon_2"]), min_size=1))}
        return Demonstration(times, positions, q, events, objects, np.arange(1, n + 1))
    return build()


def same(a: Demonstration, b: Demonstration) -> None:
    assert np.allclose(a.times, b.times, atol=1e-4)
    assert np.allclose(a.positions, b.positions, atol=1e-6)
    assert np.allclose(a.orientations, b.orientations, atol=1e-5)
    assert [(e.index, e.command) for e in a.gripper] == [(e.index, e.command) for e in b.gripper]
    assert sorted(a.objects) == sorted(b.objects)
    for name in a.objects:
        assert np.allclose(a.objects[name], b.objects[name], atol=1e-6)


@settings(max_examples=60, deadline=None)
@given(demos())
def test_csv_and_json_round_trip(demo):
    same(demo, demonstration_from_csv(demonstration_csv(demo, "a comment\nover two lines"), "d.csv"))
    same(demo, demonstration_from_json(demonstration_json(demo), "d.json"))


def error_of(text: str, reader=demonstration_from_csv) -> str:
    with pytest.raises(SchemalogError) as info:
        reader(text, "d.csv" if reader is demonstration_from_csv else "d.json")
    return str(info.value)


@pytest.mark.parametrize("header, expected", [
    ("t,x,y,gripper,cup_x,cup_y,cup_z", "d.csv:1:1: error: missing column z"),
    ("x,y,z,cup_x,cup_y,cup_z", "d.csv:1:1: error: missing column t"),
    ("t,x,y,z,gripper", "no object columns"),
    ("t,x,y,z,cup_x,cup_y", "missing column cup_z of object cup"),
    ("t,x,y,z,qx,qy,cup_x,cup_y,cup_z", "qz, qw missing"),
    ("t,x,y,z,speed,cup_x,cup_y,cup_z", "d.csv:1:9: error: unknown column 'speed'"),
    ("t,x,y,z,x,cup_x,cup_y,cup_z", "d.csv:1:9: error: column 'x' appears twice"),
])
def test_missing_and_unknown_columns_are_named_on_the_header(header, expected):
    rows = ["0,0,0,0" + ",0" * (header.count(",") - 3)] * 2
    assert expected in error_of(csv_text(*rows, header=header))


def test_time_that_does_not_increase_names_its_line_and_column():
    message = error_of(csv_text(GOOD[0], "0.0,0.5,0.05,0.2,,0.6,0.1,0.05", GOOD[2]))
    assert message.startswith("d.csv:3:1: error: time 0 s is not after the previous row's 0 s")
    assert "^" in message      # the line is shown with a caret


@pytest.mark.parametrize("bad, column, what", [("nan", 5, "x is NaN"), ("inf", 5, "x is infinite"),
                                                ("abc", 5, "x is not a number: 'abc'"), ("", 5, "x is empty")])
def test_bad_numbers_are_named_by_line_and_column(bad, column, what):
    message = error_of(csv_text(GOOD[0], f"0.1,{bad},0.05,0.2,,0.6,0.1,0.05", GOOD[2]))
    assert message.startswith(f"d.csv:3:{column}: error: {what}")


def test_other_row_errors():
    assert "d.csv:3:1: error: this row has 7 fields, the header 8" in error_of(
        csv_text(GOOD[0], "0.1,0.5,0.05,0.2,,0.6,0.1", GOOD[2]))
    assert "d.csv:3:18: error: gripper must be empty, open or close, not 'shut'" in error_of(
        csv_text(GOOD[0], "0.1,0.5,0.05,0.2,shut,0.6,0.1,0.05", GOOD[2]))
    assert "at least two samples" in error_of(csv_text(GOOD[0]))
    assert "is empty" in error_of("# only a comment\n")
    q = "t,x,y,z,qx,qy,qz,qw,cup_x,cup_y,cup_z"
    assert "not a unit quaternion" in error_of(csv_text("0,0,0,0,0,0,0,0.5,1,1,1", "1,0,0,0,0,0,0,1,1,1,1", header=q))


def json_text(**changes) -> str:
    data = {"time": [0.0, 0.1, 0.2], "position": [[0.4, 0, 0.3], [0.5, 0, 0.2], [0.6, 0.1, 0.1]],
            "gripper": [{"time": 0.2, "command": "close"}], "objects": {"cup": [0.6, 0.1, 0.05]}}
    data.update(changes)
    return json.dumps(data)


def test_json_reads_static_objects_and_timed_events():
    demo = demonstration_from_json(json_text(gripper=[{"time": 0.15, "command": "close"}]), "d.json")
    assert demo.objects["cup"].shape == (3, 3) and demo.gripper[0].index == 2   # the next sample
    assert demo.where(2) == "sample 3"


@pytest.mark.parametrize("changes, expected", [
    ({"gripper": [{"time": 0.5, "command": "close"}]},
     "gripper event 1 (close at t = 0.5 s) is outside any segment: the recording runs from 0 to 0.2 s"),
    ({"gripper": [{"time": -1, "command": "open"}]}, "outside any segment"),
    ({"time": [0.0, 0.2, 0.1]}, "sample 3: time 0.1 s is not after the previous sample's 0.2 s"),
    ({"position": [[0.4, 0, 0.3], [float("nan"), 0, 0.2], [0.6, 0.1, 0.1]]}, "sample 2: position is NaN"),
    ({"position": [[0.4, 0, 0.3]]}, "position has 1 sample, time has 3"),
    ({"objects": {}}, "objects maps each object"),
    ({"speed": 3}, "unknown key 'speed'"),
])
def test_json_errors(changes, expected):
    assert expected in error_of(json_text(**changes), demonstration_from_json)


def test_json_syntax_error_has_line_and_column(tmp_path):
    path = tmp_path / "d.json"
    path.write_text('{"time": [0, 1],\n "position": [[0,0,0] [1,1,1]]}')
    with pytest.raises(SchemalogError) as info:
        read_demonstration(path)
    assert f"{path}:2:" in str(info.value)


def test_implausible_positions_and_glitches_are_refused():
    far = error_of(csv_text(GOOD[0], "0.1,1e308,0.05,0.2,,0.6,0.1,0.05", GOOD[2]))
    assert far.startswith("d.csv:3:5: error: the end-effector is 1e+308 m from the base")
    glitch = error_of(csv_text(GOOD[0], "0.1,0.5,0.05,0.2,,5.6,0.1,0.05", GOOD[2]))
    assert glitch.startswith("d.csv:3:19: error: cup jumps 5 m in 0.1 s (50 m/s, more than 10 m/s)")


def test_noise_at_a_high_rate_is_not_a_glitch_but_a_glitch_still_is():
    # 1 mm of white noise at 10 kHz moves the hand about 2.4 mm between samples (24 m/s); over
    # 10 ms it is still 2.4 mm (0.24 m/s): speeds are measured over at least 10 ms.
    rng = np.random.default_rng(3)
    n = 2000
    times = np.arange(n) / 10_000
    hand = np.array([0.5, 0.0, 0.2]) + rng.normal(0.0, 0.001, (n, 3))
    lines = ["t,x,y,z,cup_x,cup_y,cup_z"] + [f"{t:.6f},{x:.6f},{y:.6f},{z:.6f},0.6,0.1,0.05"
                                             for t, (x, y, z) in zip(times, hand)]
    steps = np.linalg.norm(np.diff(hand, axis=0), axis=1) / np.diff(times)
    assert steps.max() > 10                                     # per sample, faster than MAX_SPEED
    assert len(demonstration_from_csv("\n".join(lines), "d.csv")) == n
    lines[1001] = lines[1001].replace(",0.6,0.1,0.05", ",0.9,0.1,0.05")     # the cup, 30 cm off for a sample
    message = error_of("\n".join(lines))
    assert message.startswith("d.csv:1002:") and "cup jumps 0.3 m in 0.01 s (30 m/s, more than 10 m/s)" in message
    lines[1001] = lines[1001].replace(",0.9,0.1,0.05", ",0.6,0.1,0.05")
    lines[3] = lines[3].replace(",0.6,0.1,0.05", ",0.9,0.1,0.05")           # within the first 10 ms
    assert "cup jumps 0.3 m in 0.0002 s (counted as 10 ms" in error_of("\n".join(lines))


def test_a_byte_order_mark_is_skipped(tmp_path):
    path = tmp_path / "bom.csv"
    path.write_bytes("\ufeff".encode() + csv_text(*GOOD).encode())
    assert len(read_demonstration(path)) == 3
    path = tmp_path / "bom.json"
    path.write_bytes("\ufeff".encode() + json_text().encode())
    assert len(read_demonstration(path)) == 3


def test_a_json_object_needs_three_coordinates():
    assert "objects.cup must be a position [x, y, z], or one per sample" in error_of(
        json_text(objects={"cup": [0.6, 0.1]}), demonstration_from_json)
