"""Scene files: object positions and the bottom-up regulation lambda."""

import math

import pytest

from schemalog.errors import SchemalogError
from schemalog.run.scene import Scene, read_scene, scene_from_yaml

from conftest import ROOT


def test_shipped_scenes_read():
    kitchen = read_scene(ROOT / "kb" / "scenes" / "kitchen.yaml")
    assert set(kitchen.objects) == {"water", "coffee", "tea", "spoon", "cup"}
    assert kitchen.end_effector == (0.40, 0.00, 0.45)
    figure2 = read_scene(ROOT / "kb" / "scenes" / "mix_with_spoon.yaml")
    assert set(figure2.objects) == {"spoon", "cup"}


def test_lambda_is_proportional_to_distance_and_clamped():
    scene = Scene(objects={"cup": (0.3, 0.4, 0.0), "far": (3.0, 0.0, 0.0)}, end_effector=(0, 0, 0),
                  scale=1.0, min_lambda=0.05, neutral_lambda=0.8)
    assert scene.lambda_at("cup", (0.0, 0.0, 0.0)) == pytest.approx(0.5)
    assert scene.lambda_at("cup", (0.3, 0.4, 0.0)) == 0.05       # at the object: the floor
    assert scene.lambda_at("far", (0.0, 0.0, 0.0)) == 1.0        # beyond scale: the ceiling
    assert scene.lambda_at(None, (0.0, 0.0, 0.0)) == 0.8         # no object: neutral


def test_jitter_is_reproducible_and_bounded():
    scene = read_scene(ROOT / "kb" / "scenes" / "kitchen.yaml")
    a, b, other = scene.jittered(7, 0.05), scene.jittered(7, 0.05), scene.jittered(8, 0.05)
    assert a.objects == b.objects and a.objects != other.objects
    for name, pos in a.objects.items():
        assert all(abs(x - y) <= 0.05 + 1e-9 for x, y in zip(pos, scene.objects[name]))
    assert a.end_effector == scene.end_effector


@pytest.mark.parametrize("text, where, message", [
    ("end_effector: [0, 0]\nobjects:\n  cup: [1, x]\n", (3, 12), "must be a number, not 'x'"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1]\n", (3, 8), "a list of 2 or 3 numbers"),
    ("end_effector: [0, 0]\ncolour: red\n", (2, 1), "unknown key 'colour'"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1, 2]\n  cup: [2, 3]\n", (4, 3), "appears twice"),
    ("end_effector: [0, 0]\nscale: 0\n", (2, 8), "positive"),
    ("end_effector: [0, 0]\nmin_lambda: 2\n", (2, 13), "(0, 1]"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1, .nan]\n", (3, 12), "finite"),
    ("objects:\n  cup: [1, 2]\n", (1, 1), "no `end_effector`"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1234567890123456789, 2]\n", (3, 9), "is 1.23e+18 m: positions are in "
     "metres from the robot's base, within 1000 m"),
    ("end_effector: [0, -1001]\n", (1, 19), "within 1000 m"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1, -.inf]\n", (3, 12), "finite"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1e400, 0]\n", (3, 9), "finite"),
    ("end_effector: [0, 0, 0]\nobjects:\n  cup: [1, 2]\n", (3, 3), "mix 2-D and 3-D"),
    ("end_effector: [0, 0\n", (2, 1), "YAML syntax error"),
    ("- 1\n- 2\n", (1, 1), "a mapping"),
])
def test_bad_scenes_are_located(text, where, message):
    with pytest.raises(SchemalogError) as err:
        scene_from_yaml(text, "s.yaml")
    assert (err.value.pos.line, err.value.pos.column) == where
    assert message in err.value.message


def test_numbers_keep_yaml_semantics():
    scene = scene_from_yaml("end_effector: [0, 1e-1]\nobjects:\n  cup: [1_000, -2.5]\n")
    assert scene.end_effector == (0.0, 0.1) and scene.objects["cup"] == (1000.0, -2.5)
    assert math.isclose(scene.lambda_at("cup", (0.0, 0.0)), 1.0)


@pytest.mark.parametrize("text, where, message", [
    ("end_effector: [0, 0]\nname: [a, b]\n", (2, 7), "`name` is a line of text"),
    ("end_effector: [0, 0]\nobjects:\n  ? [spoon]\n  : [1, 2]\n", (3, 5), "an object's name"),
    ("end_effector: [0, 0]\nobjects:\n  cup: [1, 2]\n  pan: [1, 2, 3]\n", (4, 3), "positions mix 2-D and 3-D"),
])
def test_more_bad_scenes_are_located(text, where, message):
    with pytest.raises(SchemalogError) as err:
        scene_from_yaml(text, "s.yaml")
    assert (err.value.pos.line, err.value.pos.column) == where
    assert message in err.value.message


def test_a_scene_over_the_size_limit_is_refused(tmp_path):
    big = tmp_path / "big.yaml"
    big.write_text("end_effector: [0, 0]\n" + "# padding\n" * 500)
    with pytest.raises(SchemalogError, match="over the 1,000 bytes limit"):
        read_scene(big, max_bytes=1000)


def test_brackets_nested_past_the_limit_are_refused_at_their_place_before_pyyaml_reads_them():
    from schemalog.inputs import MAX_YAML_NESTING

    text = "objects:\n  spoon: " + "[" * 5000 + "\n"
    with pytest.raises(SchemalogError) as refused:
        scene_from_yaml(text, "deep.yaml")
    assert refused.value.pos.line == 2 and refused.value.pos.column == len("  spoon: ") + MAX_YAML_NESTING + 1
    assert "deeper than 100 levels" in str(refused.value)


def test_brackets_in_comments_and_quotes_do_not_count_as_nesting():
    text = ("name: '" + "{" * 200 + "'   # and " + "[" * 200 + "\n"
            "end_effector: [0.40, 0.00, 0.45]\n"
            "objects:\n  spoon: [0.35, 0.30, 0.02]\n")
    scene = scene_from_yaml(text, "fine.yaml")
    assert scene.name == "{" * 200 and "spoon" in scene.objects
