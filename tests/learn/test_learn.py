"""End to end: from a (simulated) demonstration to learned, compressed, verified knowledge,
as a user runs it; bad demonstrations leave nothing behind."""

import json
import subprocess
import sys

import pytest

from conftest import ROOT

STRUCTURE = ROOT / "kb" / "tasks" / "coffee_structure.pl"
KITCHEN = ROOT / "kb" / "scenes" / "kitchen.yaml"


def run(*args, cwd):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


@pytest.fixture(scope="module")
def coffee(tmp_path_factory):
    """The issue's commands: simulate the coffee task in the kitchen, learn it."""
    where = tmp_path_factory.mktemp("learn")
    r = run("simulate-demo", "--scene", KITCHEN, "--task", "preparecoffee", "-o", "demo.csv", cwd=where)
    assert r.returncode == 0, r.stderr
    assert r.stderr.startswith("wrote demo.csv: simulated preparecoffee in kitchen: ") and r.stdout == ""
    assert r.stderr.rstrip().endswith("6 gripper commands (CSV)")
    r = run("learn", "demo.csv", "--structure", STRUCTURE, "--task", "preparecoffee", "-o", "learned.pl", cwd=where)
    assert r.returncode == 0, r.stderr
    assert "wrote learned.pl: preparecoffee, 37 behaviours learned from demo.csv (schema text)" in r.stderr
    return where, r.stdout


def test_learn_reports_each_segment_and_where_it_went(coffee):
    _, report = coffee
    assert "27 segments: 21 motions, 6 gripper commands (radius 0.1 m)" in report
    first = next(line for line in report.splitlines() if line.lstrip().startswith("1 "))
    assert "a1(water)" in first and "enters water" in first and "-> subtask(take,water)" in first
    assert "preparecoffee is accomplished at the end of the demonstration (spoon.used)" in report
    assert "learned task: 37 behaviours; compressed: 19 behaviours" in report
    assert "wrote" not in report             # the report is the data of stdout; what was written, stderr


def test_the_learned_knowledge_is_accepted_by_check_show_compress_and_verify(coffee):
    where, _ = coffee
    r = run("check", "learned.pl", cwd=where)
    assert r.returncode == 0 and "preparecoffee (37 behaviours, depth 4)" in r.stdout, r.stderr
    assert "a1(water)  pre: true  post: a1.done" in run("show", "learned.pl", cwd=where).stdout
    r = run("compress", "learned.pl", "--verify", cwd=where)
    assert r.returncode == 0, r.stderr
    assert "Bi = 37, Bm = 19, D = 4" in r.stdout
    assert "result: the compressed tree is sound and complete (exit 0)" in r.stdout
    data = json.loads(run("compress", "learned.pl", "--verify", "--json", cwd=where).stdout)
    assert data["verification"]["sound"] is True and data["nodes_after"] == 19
    r = run("run", "learned.pl", "--scene", KITCHEN, "--compressed", cwd=where)
    assert r.returncode == 0 and "completed" in r.stdout


def test_learning_tea_on_the_coffee_knowledge_gives_the_63_behaviours(coffee):
    where, _ = coffee
    assert run("simulate-demo", "--scene", KITCHEN, "--task", "preparetea", "--seed", "3", "-o", "tea.json",
               cwd=where).returncode == 0
    r = run("learn", "tea.json", "--structure", "learned.pl", "--task", "preparetea", "-o", "both.pl", cwd=where)
    assert r.returncode == 0, r.stderr
    assert "recognised (known action)" in r.stdout
    data = json.loads(run("show", "both.pl", "--task", "prepareboth", "--json", cwd=where).stdout)
    assert (data["nodes"], data["depth"]) == (63, 5)
    r = run("compress", "both.pl", "--task", "prepareboth", cwd=where)
    assert "Bi = 63, Bm = 33, D = 5, RD = (Bi - Bm) / (Bi - D) = 0.52" in r.stdout


def test_learn_without_output_prints_the_knowledge(coffee):
    where, _ = coffee
    # Without --task, the structure's first task (prepareboth): the tea half is left untaught.
    r = run("learn", "demo.csv", "--structure", STRUCTURE, cwd=where)
    assert r.returncode == 0, r.stderr
    assert "warning: not demonstrated, still without actions: subtask(take,tea), subtask(pour,tea)" in r.stderr
    assert "prepareboth is NOT accomplished at the end of the demonstration" in r.stderr
    r = run("learn", "demo.csv", "--structure", STRUCTURE, "--task", "preparecoffee", cwd=where)
    assert r.returncode == 0 and r.stdout.startswith("% Learned by `schemalog learn` from demo.csv")
    assert "27 segments" in r.stderr


HEADER = "t,x,y,z,gripper,cup_x,cup_y,cup_z,spoon_x,spoon_y,spoon_z"


def rows(*lines):
    return "\n".join([HEADER, *lines]) + "\n"


BAD = {
    "missing.csv": (rows("0,0.6,0.1,0.3,,0.6,0.1,0.05,0.3,-0.3,0.02").replace(",z,", ",").replace(",0.3,,", ",,"),
                    "missing.csv:1:1: error: missing column z"),
    "backwards.csv": (rows("0,0.6,0.1,0.3,,0.6,0.1,0.05,0.3,-0.3,0.02", "0.2,0.6,0.1,0.2,,0.6,0.1,0.05,0.3,-0.3,0.02",
                           "0.1,0.6,0.1,0.1,,0.6,0.1,0.05,0.3,-0.3,0.02"),
                      "backwards.csv:4:1: error: time 0.1 s is not after the previous row's 0.2 s"),
    "nan.csv": (rows("0,0.6,0.1,0.3,,0.6,0.1,0.05,0.3,-0.3,0.02", "0.1,0.6,nan,0.2,,0.6,0.1,0.05,0.3,-0.3,0.02"),
                "nan.csv:3:9: error: y is NaN"),
    "far.csv": (rows("0,0.6,0.1,0.45,,0.6,0.1,0.05,0.3,-0.3,0.02", "0.1,0.6,0.1,0.30,,0.6,0.1,0.05,0.3,-0.3,0.02"),
                "far.csv:3:1: error: the end-effector never comes within 0.1 m of an object (nearest: cup, 0.250 m "
                "at line 3)"),
    "late.json": (json.dumps({"time": [0, 0.1], "position": [[0.6, 0.1, 0.3], [0.6, 0.1, 0.1]],
                              "gripper": [{"time": 2.0, "command": "close"}], "objects": {"cup": [0.6, 0.1, 0.05]}}),
                  "late.json: gripper event 1 (close at t = 2 s) is outside any segment"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_demonstrations_are_refused_with_their_row_and_nothing_is_written(tmp_path, name):
    text, expected = BAD[name]
    (tmp_path / name).write_text(text)
    (tmp_path / "learned.pl").write_text("% an earlier result\n")
    r = run("learn", name, "--structure", STRUCTURE, "--task", "preparecoffee", "-o", "learned.pl", cwd=tmp_path)
    assert r.returncode == 1
    assert expected in r.stderr
    assert "Traceback" not in r.stderr
    assert (tmp_path / "learned.pl").read_text() == "% an earlier result\n"
    assert (tmp_path / name).read_text() == text
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([name, "learned.pl"])


def test_learn_refuses_to_overwrite_its_inputs(coffee):
    where, _ = coffee
    r = run("learn", "demo.csv", "--structure", "learned.pl", "-o", "learned.pl", cwd=where)
    assert r.returncode == 2 and "would overwrite an input file" in r.stderr


def test_simulate_demo_needs_knowledge_when_the_scene_names_none(tmp_path):
    scene = tmp_path / "s.yaml"
    scene.write_text("end_effector: [0.4, 0, 0.45]\nobjects:\n  cup: [0.6, 0.1, 0.05]\n")
    r = run("simulate-demo", "--scene", scene, "--task", "x", cwd=tmp_path)
    assert r.returncode == 2 and "names none" in r.stderr


def test_plot_and_motion_primitives(coffee):
    where, report = coffee
    r = run("learn", "demo.csv", "--structure", STRUCTURE, "--task", "preparecoffee", "-o", "l2.pl",
            "--plot", "segments.png", "--motions", "motions.json", cwd=where)
    assert r.returncode == 0, r.stderr
    assert (where / "segments.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    data = json.loads((where / "motions.json").read_text())
    assert len(data["actions"]) == 21 and data["dimensions"] == ["x", "y", "z", "qx", "qy", "qz", "qw"]
    first = data["actions"][0]
    assert first["label"] == "a1(water)" and first["segment"]["ends"] == "enters water"
    merged = {m["label"]: m for m in data["merged"]}
    assert [p["action"] for p in merged["a3_a4_a5_a6_a7(cup)"]["parts"]] == ["a3(cup)", "a4(cup)", "a5(cup)",
                                                                           "a6(cup)", "a7(cup)"]
    for m in data["merged"]:
        assert m["error"]["final"] < 0.01                   # it ends where the demonstration ended
    assert "merged primitives, one per merged action of the compressed task" in r.stdout
    assert "a3_a4_a5_a6_a7(cup)       5 segments" in r.stdout


def test_plot_needs_a_known_format(coffee):
    where, _ = coffee
    r = run("learn", "demo.csv", "--structure", STRUCTURE, "--plot", "s.xyz", cwd=where)
    assert r.returncode == 2 and "name a .png, .svg or .pdf file" in r.stderr


def test_a_failed_write_leaves_no_output_behind(coffee):
    where, _ = coffee
    r = run("learn", "demo.csv", "--structure", STRUCTURE, "--task", "preparecoffee", "-o", "/proc/learned.pl",
            "--motions", "m2.json", "--plot", "p2.png", cwd=where)
    assert r.returncode == 1 and "cannot write /proc/learned.pl" in r.stderr and "nothing was written" in r.stderr
    assert not (where / "m2.json").exists() and not (where / "p2.png").exists()
    assert not [p for p in where.iterdir() if p.name.startswith(".")]      # no temporary files either


@pytest.mark.parametrize("args, expected", [
    (["--bases", "100000"], "argument --bases: must be from 0 to 1,000"),
    (["--radius", "0"], "argument --radius: must be more than 0"),
    (["--radius", "nan"], "argument --radius: must be a finite distance"),
])
def test_learn_option_ranges(coffee, args, expected):
    where, _ = coffee
    r = run("learn", "demo.csv", "--structure", STRUCTURE, *args, cwd=where)
    assert r.returncode == 2 and expected in r.stderr


def test_simulate_demo_option_ranges(tmp_path):
    r = run("simulate-demo", "--scene", KITCHEN, "--rate", "1e6", cwd=tmp_path)
    assert r.returncode == 2 and "argument --rate: must be from 1 to 10,000" in r.stderr
    r = run("simulate-demo", "--scene", KITCHEN, "--speed", "100", cwd=tmp_path)
    assert r.returncode == 2 and "argument --speed: must be from 0.01 to 2" in r.stderr


@pytest.mark.parametrize("args, expected", [
    (["--jitter", "1e308"], "argument --jitter: must be from 0 to 1"),
    (["--jitter", "nan"], "argument --jitter: must be from 0 to 1"),
    (["--seed", "-1"], "argument --seed: must be at least 0"),
    (["--noise", "inf"], "argument --noise: must be from 0 to 0.01"),
    (["--noise", "nan"], "argument --noise: must be from 0 to 0.01"),
])
def test_simulate_demo_refuses_bad_numbers_as_usage_errors(tmp_path, args, expected):
    r = run("simulate-demo", "--scene", KITCHEN, "-o", "d.csv", *args, cwd=tmp_path)
    assert r.returncode == 2 and expected in r.stderr and "internal error" not in r.stderr
    assert not (tmp_path / "d.csv").exists()


def test_a_scene_with_a_coordinate_out_of_range_is_located(tmp_path):
    scene = tmp_path / "far.yaml"
    scene.write_text(KITCHEN.read_text().replace("../tasks/", f"{KITCHEN.parent.parent}/tasks/")
                     .replace("[0.55, -0.30, 0.10]", "[1234567890123456789, -0.30, 0.10]"))
    r = run("simulate-demo", "--scene", scene, "-o", "d.csv", cwd=tmp_path)
    assert r.returncode == 1 and r.stderr.startswith(f"{scene}:13:12: error: a coordinate of the position of water")
    assert "internal error" not in r.stderr and not (tmp_path / "d.csv").exists()


def test_the_plot_fits_a_screen_and_no_two_labels_overlap(coffee, tmp_path):
    """Issue 45: learn --plot drew 2,806 px wide (three panels in a row), and the segment labels of
    the height panel piled up where short segments follow each other at the cup (a4, a5, a6)."""
    from matplotlib.image import imread
    from matplotlib.text import Text

    from schemalog.evaluate.figures import demonstration_figure, demonstration_plot, plt
    from schemalog.learn.learn import learn
    from schemalog.logic.parse import parse_term

    where, _ = coffee
    lesson = learn(str(where / "demo.csv"), str(STRUCTURE), parse_term("preparecoffee"))
    png = demonstration_figure(lesson, tmp_path / "segments.png")
    height, width = imread(str(png)).shape[:2]
    assert width <= 1920, (width, height)
    fig = demonstration_plot(lesson)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes[:2]:           # the path from above, the height over time
            texts = [t for t in ax.texts if t.get_text()]
            assert len(texts) >= 21
            boxes = [Text.get_window_extent(t, renderer) for t in texts]
            for i, a in enumerate(boxes):
                for j in range(i):
                    assert not a.overlaps(boxes[j]), (texts[i].get_text(), texts[j].get_text())
    finally:
        plt.close(fig)


def test_the_plots_labels_of_the_hands_path_do_not_overlap(coffee):
    from matplotlib.text import Text

    from schemalog.evaluate.figures import demonstration_plot, plt
    from schemalog.learn.learn import learn
    from schemalog.logic.parse import parse_term

    where, _ = coffee
    fig = demonstration_plot(learn(str(where / "demo.csv"), str(STRUCTURE), parse_term("preparecoffee")))
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        top = fig.axes[0]
        texts = [t for t in top.texts if t.get_text()]
        assert len(texts) == 21 + 5                     # a label per motion, a name per object
        boxes = [Text.get_window_extent(t, renderer) for t in texts]    # the text, not its leader line
        frame = top.get_window_extent(renderer)
        for i, a in enumerate(boxes):
            assert frame.x0 <= a.x0 and a.x1 <= frame.x1 and frame.y0 <= a.y0 and a.y1 <= frame.y1
            for j in range(i):
                assert not a.overlaps(boxes[j]), (texts[i].get_text(), texts[j].get_text())
    finally:
        plt.close(fig)
