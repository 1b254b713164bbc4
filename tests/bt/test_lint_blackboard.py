"""`schemalog lint` on BT.CPP trees, the blackboard rules (bt/lint.py, docs/lint.md "BT.CPP
trees"): each fixture of tests/bt/lint_fixtures (a real tree with one fault put in, see
SOURCES-blackboard.md) found at its file:line:col by its rule, the real corpus free of errors,
SARIF valid against the SARIF 2.1.0 schema, bad input refused with file:line:col."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
FIXTURES = HERE / "lint_fixtures"
NAV2_NODES = FIXTURES / "bb_nav2_tree_nodes.xml"       # Nav2's own, with port types (SOURCES-blackboard.md)
CORPUS = HERE / "corpus"
SCHEMA = HERE / "sarif" / "sarif-schema-2.1.0.json"


def cli(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=ROOT, timeout=600)


def findings(path: Path, *more) -> list[dict]:
    result = cli("lint", path, "--json", *more)
    assert "Traceback" not in result.stderr, result.stderr
    return json.loads(result.stdout)["findings"]


def nav2(name: str) -> list:
    return [FIXTURES / name, "--nodes", NAV2_NODES, "--profile", "nav2"]


@pytest.mark.parametrize("name, line, column, rule, says", [
    # FollowPath controller_id="{selected_controler}": ControllerSelector writes selected_controller
    ("bb_nav2_port_typo.xml", 13, 7, "never-written", "did you mean {selected_controller}?"),
    # ControllerSelector moved after FollowPath in the PipelineSequence: the first read comes first
    ("bb_nav2_output_after_reader.xml", 12, 7, "read-before-write", "on every run"),
    # a SubTree call remaps ComputePathToPose's path (nav_msgs::msg::Path) onto {goal} (a PoseStamped)
    ("bb_nav2_subtree_type_clash.xml", 17, 5, "type-clash", "geometry_msgs::msg::PoseStamped"),
])
def test_each_fixture_is_found_where_its_fault_is(name, line, column, rule, says):
    found = [f for f in findings(*nav2(name)) if f["severity"] == "error"]
    assert [(f["code"], f["line"], f["column"]) for f in found] == [(rule, line, column)]
    assert found[0]["file"].endswith(name)
    assert says in found[0]["message"] + found[0]["hint"]
    result = cli("lint", *nav2(name))
    assert result.returncode == 1
    assert f"{name}:{line}:{column}: error:" in result.stdout and f"[{rule}]" in result.stdout


def test_the_fixtures_original_is_clean():
    result = cli("lint", CORPUS / "nav2" / "navigate_w_replanning_time.xml", "--nodes", NAV2_NODES, "--profile", "nav2")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "[read-before-write]" not in result.stdout and "decided on every run" in result.stderr


def test_without_the_nav2_profile_the_goal_nav2_provides_is_never_written():
    found = findings(FIXTURES / "bb_nav2_port_typo.xml", "--nodes", NAV2_NODES)
    assert ("never-written", "{goal}") in {(f["code"], "{goal}") for f in found if "{goal}" in f["message"]}


def test_a_read_written_on_some_runs_only_is_a_warning_and_strict_fails_on_it(tmp_path):
    tree = tmp_path / "some.xml"
    tree.write_text("""<root BTCPP_format="4"><BehaviorTree ID="T"><Sequence>
  <Fallback><IsReady/><SetBlackboard value="1" output_key="x"/></Fallback>
  <Use in="{x}"/>
</Sequence></BehaviorTree>
<TreeNodesModel><Condition ID="IsReady"/><Action ID="Use"><input_port name="in"/></Action></TreeNodesModel></root>""")
    result = cli("lint", tree)
    assert result.returncode == 0
    assert "some.xml:3:3: warning: Use: in reads {x} before a node that may write it has ticked on some runs" \
        in result.stdout
    assert cli("lint", tree, "--strict").returncode == 1


def test_a_tree_without_blackboard_entries_says_there_was_nothing_to_check():
    result = cli("lint", CORPUS / "btcpp" / "examples" / "test_files" / "Check.xml")
    assert result.returncode == 0
    assert "no blackboard entry read or written: nothing to check" in result.stderr


NAV2_TREES = sorted(p for p in (CORPUS / "nav2").glob("*.xml") if p.name != "nav2_tree_nodes.xml")


@pytest.mark.parametrize("path", NAV2_TREES, ids=lambda p: p.name)
def test_no_error_on_the_nav2_trees_bt_cpp_runs(path):
    # Nav2's trees with Nav2's node models and the nav2 profile: no error (docs/lint.md lists the warnings)
    result = cli("lint", path, "--nodes", NAV2_NODES, "--profile", "nav2", "--json")
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert json.loads(result.stdout)["errors"] == 0


def test_sarif_output_validates_against_the_sarif_2_1_0_schema(tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    out = tmp_path / "lint.sarif"
    result = cli("lint", *nav2("bb_nav2_subtree_type_clash.xml"), "--format", "sarif", "-o", out)
    assert result.returncode == 1
    log = json.loads(out.read_text())
    jsonschema.validate(log, json.loads(SCHEMA.read_text()))
    results = log["runs"][0]["results"]
    clash = [r for r in results if r["ruleId"] == "type-clash"]
    assert clash[0]["level"] == "error"
    assert clash[0]["locations"][0]["physicalLocation"]["region"] == {"startLine": 17, "startColumn": 5}
    assert clash[0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == \
        "tests/bt/lint_fixtures/bb_nav2_subtree_type_clash.xml"


@pytest.mark.parametrize("name, text, where, says", [
    ("dup.xml", '<root BTCPP_format="4"><TreeNodesModel>\n<Action ID="Go"/>\n<Condition ID="Go"/>\n'
                "</TreeNodesModel></root>", "dup.xml:3:1", "declared twice with different kinds"),
    ("types.xml", '<root BTCPP_format="4"><TreeNodesModel>\n<Action ID="Go">\n<input_port name="x" type="int;x"/>'
                  "</Action></TreeNodesModel></root>", "types.xml:3:1", "is not a C++ type name"),
])
def test_nodes_files_that_no_program_can_be_are_refused(tmp_path, name, text, where, says):
    nodes = tmp_path / name
    nodes.write_text(text)
    result = cli("lint", FIXTURES / "bb_nav2_port_typo.xml", "--nodes", nodes)
    assert result.returncode == 1
    assert where in result.stderr and says in result.stderr and "Traceback" not in result.stderr


@pytest.mark.parametrize("text, where, says", [
    ("provides: [unclosed\n", ":2:1", "YAML syntax error"),
    ("provides:\n  goal: here\n  not a name: x\n", ":3:3", "is not a blackboard entry's name"),
    ("provided:\n  goal: here\n", ":1:1", "has `provides:`, `reads:` and `silence:` only"),
])
def test_a_provided_file_that_is_not_an_entry_list_is_refused(tmp_path, text, where, says):
    given = tmp_path / "entries.yaml"
    given.write_text(text)
    result = cli("lint", FIXTURES / "bb_nav2_port_typo.xml", "--provided", given)
    assert result.returncode == 1
    assert f"entries.yaml{where}" in result.stderr and says in result.stderr and "Traceback" not in result.stderr


def test_a_provided_file_makes_an_entry_the_program_sets_no_finding(tmp_path):
    given = tmp_path / "entries.yaml"
    given.write_text("provides:\n  selected_controler: set by our executor\n")
    found = findings(FIXTURES / "bb_nav2_port_typo.xml", "--nodes", NAV2_NODES, "--profile", "nav2",
                     "--provided", given)
    assert not [f for f in found if f["severity"] == "error"]


def test_one_edit_is_an_insertion_a_deletion_a_change_or_two_neighbours_swapped():
    from schemalog.bt.lint import _one_edit

    assert _one_edit("paht", "path") and _one_edit("remaning_path", "remaining_path")
    assert _one_edit("goal", "goals") and _one_edit("goal", "gaol") and _one_edit("goal", "coal")
    assert not _one_edit("goal", "goal") and not _one_edit("goal", "pose") and not _one_edit("ab", "bca")


# -- real BT.CPP shows what read-before-write and never-written find ------------------------------



def missing_in_btcpp(harness: str, tree: Path, seeds: int = 30) -> set[tuple[str, str]]:
    """The (node type, port) whose getInput BT.CPP 4.8.2 fails on (the entry not on the
    blackboard), over `seeds` runs of random draws, each leaf reading its inputs and writing its
    outputs when ticked (the harness's --blackboard)."""
    import random

    lines = "\n".join(f"s{k} " + " ".join(str(random.Random(k).randrange(6)) for _ in range(200))
                      for k in range(seeds))
    done = subprocess.run([harness, "--tree", str(tree), "--models", str(FIXTURES / "bb_nav2_tree_nodes.xml"),
                           "--blackboard", "--draws", "/dev/stdin", "--max-ticks", "8"], input=lines,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    events = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    assert sum(e["ev"] == "run" for e in events) == seeds
    return {(e["type"], e["port"]) for e in events if e["ev"] == "missing"}


def test_btcpp_fails_the_reads_lint_finds_and_no_other_but_what_nav2_provides(harness):
    """Where lint says a read comes before any write (bb_nav2_output_after_reader) or reads an
    entry nothing writes (bb_nav2_port_typo), BT.CPP's getInput fails on that port on a run; on
    the tree as Nav2 ships it, only the entries Nav2's navigator sets before the tree runs (`goal`,
    the nav2 profile's `provides:`) are missing, which the harness does not set."""
    provided = {("ComputePathToPose", "goal")}
    shipped = missing_in_btcpp(harness, CORPUS / "nav2" / "navigate_w_replanning_time.xml")
    assert shipped == provided
    assert missing_in_btcpp(harness, FIXTURES / "bb_nav2_output_after_reader.xml") - provided == \
        {("FollowPath", "controller_id")}
    assert missing_in_btcpp(harness, FIXTURES / "bb_nav2_port_typo.xml") - provided == {("FollowPath", "controller_id")}
