"""`schemalog diff A.xml B.xml` as a reviewer runs it on Nav2's trees and hand edits of them:
every place by both files' lines, the exit status a CI job reads, each output format, and bad
input refused with nothing written."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from conftest import ROOT

NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
REPLANNING = NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml"


def run(*args, cwd):
    """schemalog diff in `cwd`, where a.xml is Nav2's tree (the files named as a reviewer names them)."""
    return subprocess.run([sys.executable, "-m", "schemalog", "diff", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, timeout=300)


def edit(tmp_path, old: str, new: str, name: str = "b.xml"):
    """a.xml, Nav2's tree, and `name`, it with `old` replaced by `new`, in tmp_path."""
    text = REPLANNING.read_text(encoding="utf-8")
    assert old in text
    (tmp_path / "a.xml").write_text(text, encoding="utf-8")
    out = tmp_path / name
    out.write_text(text.replace(old, new, 1), encoding="utf-8")
    return out


def line_of(path, needle: str) -> int:
    return next(i for i, line in enumerate(path.read_text().splitlines(), 1) if needle in line)


def test_a_changed_retry_count_is_found_by_place_and_line_with_its_run(tmp_path):
    b = edit(tmp_path, 'number_of_retries="6"', 'number_of_retries="5"')
    r = run("a.xml", "b.xml", "--nodes", NODES, cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    out = r.stdout
    assert out.startswith("a.xml -> b.xml: behaviour changed: refuted after ")
    line = line_of(REPLANNING, 'number_of_retries="6"')
    assert f'1. RecoveryNode "NavigateRecovery" at a.xml:{line}:5 / b.xml:{line}:5' in out
    assert 'B retries PipelineSequence "NavigateWithReplanning" 5 times instead of 6' in out
    # the first divergence names each side's node by file:line:col
    first = out.split("first divergence", 1)[1].splitlines()
    assert re.fullmatch(r"  a: tick GoalUpdated at a\.xml:\d+:\d+", first[1]), first
    assert re.fullmatch(r"  b: tick ComputePathToPose .* at b\.xml:\d+:\d+ -> FAILURE, then the root tick ends "
                        r"FAILURE", first[2]), first
    assert "direction: neither" in out


def test_two_edits_are_two_places_and_a_reordering_of_attributes_is_no_place(tmp_path):
    b = edit(tmp_path, 'number_of_retries="6"', 'number_of_retries="4"')
    b.write_text(b.read_text().replace('<Wait wait_duration="5"/>', '<Wait wait_duration="2"/>', 1)
                 .replace('path="{path}" planner_id="GridBased"', 'planner_id="GridBased" path="{path}"', 1))
    r = run("a.xml", "b.xml", "--nodes", NODES, "--json", cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    report = json.loads(r.stdout)
    changes = sorted(c for p in report["places"] for c in p["changes"])
    assert changes == ['B retries PipelineSequence "NavigateWithReplanning" 4 times instead of 6',
                       'B sets wait_duration="2" on Wait (A: "5")']
    assert all(p["effect"] == "changes behaviour" and p["run"] for p in report["places"])
    assert {p["a"]["line"] for p in report["places"]} == {line_of(REPLANNING, 'number_of_retries="6"'),
                                                           line_of(REPLANNING, 'wait_duration="5"')}
    assert report["proved"] is False and report["complete"] is True and report["direction"] == "neither"


def test_a_pure_refactoring_is_listed_apart_and_the_exit_status_is_0(tmp_path):
    edit(tmp_path, '<Wait wait_duration="5"/>', '<Sequence><Wait wait_duration="5"/></Sequence>')
    r = run("a.xml", "b.xml", "--nodes", NODES, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert ": same behaviour: proved equal" in r.stdout.splitlines()[0]
    assert "1 structural change with no behavioural difference (a pure refactoring):" in r.stdout
    # under a RoundRobin, which may tick a finished Wait again unreset, the wrapper is the same here only
    assert "B wraps Wait in Sequence (in this program, not in every context)" in r.stdout
    assert "It covers an executor that halts the tree (Tree::haltTree)" in r.stdout


def test_the_markdown_is_a_pull_request_comment_with_a_table_and_the_run_folded(tmp_path):
    b = edit(tmp_path, 'number_of_retries="6"', 'number_of_retries="5"')
    r = run("a.xml", b, "--nodes", NODES, "--format", "markdown", cwd=tmp_path)
    assert r.returncode == 1
    md = r.stdout
    assert md.startswith("### schemalog diff: behaviour changed\n")
    row = next(line for line in md.splitlines() if line.startswith("| 1 |"))
    assert row.count(" | ") == 4 and "**changes behaviour**" in row
    assert 'RecoveryNode "NavigateRecovery"' in row and "5 times instead of 6" in row
    assert "<details><summary>Place 1: the shortest run that shows it</summary>" in md and "```text" in md


def test_a_picture_shows_both_trees_and_nothing_is_written_for_a_refused_suffix(tmp_path):
    b = edit(tmp_path, 'number_of_retries="6"', 'number_of_retries="5"')
    svg = tmp_path / "diff.svg"
    r = run("a.xml", b, "--nodes", NODES, "-o", svg, cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    assert r.stderr == f"wrote {svg}: an SVG picture; a.xml -> {b}: behaviour changed\n"
    text = svg.read_text()
    assert text.lstrip().startswith("<?xml") and "<svg" in text
    assert "A: " in text and "B: " in text and "NavigateRecovery" in text and "#f6b2b2" in text
    jpg = tmp_path / "diff.jpg"
    r = run("a.xml", b, "--nodes", NODES, "-o", jpg, cwd=tmp_path)
    assert r.returncode == 2 and "JPG" in r.stderr and not jpg.exists()


def test_a_limit_is_no_verdict_exit_3(tmp_path):
    b = edit(tmp_path, 'number_of_retries="6"', 'number_of_retries="5"')
    r = run("a.xml", b, "--nodes", NODES, "--max-states", "50", cwd=tmp_path)
    assert r.returncode == 3, r.stdout + r.stderr
    assert ": NOT decided: NOT proved: " in r.stdout.splitlines()[0]
    assert "not decided (a limit stopped the proof" in r.stdout


@pytest.mark.parametrize("case", ["missing", "malformed", "task", "output-over-input", "one-file"])
def test_bad_input_is_one_message_exit_2_and_nothing_written(tmp_path, case):
    b = edit(tmp_path, 'number_of_retries="6"', 'number_of_retries="5"')
    before = b.read_bytes()
    out = tmp_path / "out.md"
    args = {"missing": [REPLANNING, tmp_path / "nope.xml", "-o", out],
            "malformed": [REPLANNING, tmp_path / "bad.xml", "-o", out],
            "task": [REPLANNING, ROOT / "kb" / "tasks" / "mix_with_spoon.pl", "-o", out],
            "output-over-input": [REPLANNING, b, "-o", b],
            "one-file": [REPLANNING]}[case]
    (tmp_path / "bad.xml").write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <Sequence>\n'
                                      '  </BehaviorTree>\n</root>\n')
    r = run(*args, "--nodes", NODES, cwd=tmp_path)
    assert r.returncode == 2, (case, r.stdout, r.stderr)
    assert "Traceback" not in r.stderr and r.stderr.count("error") <= 1 and not r.stdout
    assert not out.exists() and b.read_bytes() == before
    expected = {"missing": "nope.xml: no such file", "malformed": "bad.xml:4:",
                "task": "is a BT.CPP tree and", "output-over-input": "b.xml",
                "one-file": "diff takes two versions"}[case]
    assert expected in r.stderr, r.stderr


def test_a_bt_cpp_3_tree_against_its_bt_cpp_4_conversion_answers_whether_the_upgrade_changed_it(tmp_path):
    """Nav2's goal-patience tree before and after its BT.CPP 4 migration (SequenceStar became
    SequenceWithMemory): under 3.8 the SequenceStar ticks Wait in the same tick; under 4 it returns
    RUNNING first and PathLongerOnApproach decides again (tests/bt/test_btcpp3.py)."""
    v3, v4 = ROOT / "tests/bt/corpus/btcpp3/nav2_goal_patience_v3.xml", ROOT / "tests/bt/corpus/btcpp3/nav2_goal_patience_v4.xml"
    r = run(v3, v4, "--btcpp", "3:4", "--nodes", NODES, "--profile", "nav2", "--json", cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    report = json.loads(r.stdout)
    assert report["first_divergence"]["a"].startswith('tick Wait wait_duration="5.0" at ')
    assert report["first_divergence"]["b"].startswith("choice of PathLongerOnApproach")
    (place,) = report["places"]
    assert (place["a"]["type"], place["b"]["type"]) == ("SequenceStar", "SequenceWithMemory")
    assert "two BT.CPP versions" in report["note"]


def test_two_folders_are_two_programs_and_an_edit_in_a_sibling_file_is_found_there(tmp_path):
    """The sentry robot's 11 files, read as one program on each side: a Delay changed in one of
    them is the place, by that file's line, and the first divergence is that Delay's time event."""
    import shutil

    folder = ROOT / "tests" / "bt" / "corpus" / "combat" / "behavior_trees"
    shutil.copytree(folder, tmp_path / "a")
    shutil.copytree(folder, tmp_path / "b")
    edited = tmp_path / "b" / "bump_traverse.xml"
    text = edited.read_text(encoding="utf-8")
    assert text.count('delay_msec="200"') == 1
    edited.write_text(text.replace('delay_msec="200"', 'delay_msec="300"'), encoding="utf-8")
    line = line_of(edited, 'delay_msec="300"')
    r = run("a", "b", "--task", "rmuc_2026", "--json", cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    report = json.loads(r.stdout)
    (place,) = report["places"]
    assert (place["b"]["file"], place["b"]["line"]) == ("b/bump_traverse.xml", line)
    assert place["changes"] == ["B waits 300 ms instead of 200 ms before ticking AlwaysSuccess"]
    assert report["first_divergence"]["b"].startswith("time at ") and "b/bump_traverse.xml" in \
        report["first_divergence"]["b"]
