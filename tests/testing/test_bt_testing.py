"""schemalog.testing for BT.CPP trees: assert_bt_equal, assert_bt_compresses, and the plugin's
`pytest --schemalog-trees DIR` (docs/testing.md, "BT.CPP trees")."""

from __future__ import annotations

import os
import pickle
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import schemalog
from schemalog.testing import NotProved, TreesNotProved, assert_bt_compresses, assert_bt_equal

from test_testing import PLUGIN, environ

ROOT = Path(__file__).resolve().parents[2]
NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
ROUTING = NAV2 / "navigate_w_routing_global_planning_and_control_w_recovery.xml"
REPLANNING = NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml"
TIME, DISTANCE = NAV2 / "navigate_w_replanning_time.xml", NAV2 / "navigate_w_replanning_distance.xml"


def verify_prints(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "schemalog", "verify", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=300, env=environ())


def swapped(text: str) -> str:
    """REPLANNING with the two children of its FollowPath RecoveryNode swapped: refuted."""
    follow = '<FollowPath path="{path}" controller_id="FollowPath"/>\n'
    start = text.index('<RecoveryNode number_of_retries="1" name="FollowPath">')
    end = text.index("</RecoveryNode>", start)
    body = text[start:end]
    fallback = body[body.index("<ReactiveFallback"):body.index("</ReactiveFallback>") + len("</ReactiveFallback>")]
    return text[:start] + body.replace(follow, "").replace(fallback, fallback + "\n          " + follow.strip()) + text[end:]


# --- the assertions ----------------------------------------------------------------

def test_equal_trees_return_the_proof():
    proof = assert_bt_equal(TIME, TIME, nodes=NODES)
    assert proof.proved and proof.exit_status == 0
    tree = schemalog.read_tree(ROUTING, nodes=NODES)
    proof = assert_bt_compresses(tree)
    assert proof.proved and proof.compression.nodes_after == 44 and proof.compression.xml().startswith("<?xml")


def test_a_refutation_fails_with_what_schemalog_verify_prints():
    with pytest.raises(AssertionError) as failure:
        assert_bt_equal(TIME, DISTANCE, nodes=NODES)
    assert isinstance(failure.value, TreesNotProved) and isinstance(failure.value, NotProved)
    printed = verify_prints(TIME, DISTANCE, "--nodes", NODES)
    assert printed.returncode == 1 and str(failure.value) == printed.stdout
    assert "<- the trees part here" in str(failure.value)
    assert failure.value.report.counterexample is not None and failure.value.report.exit_status == 1


def test_a_limit_or_nothing_compressed_fails_saying_so():
    with pytest.raises(TreesNotProved) as failure:
        assert_bt_compresses(ROUTING, nodes=NODES, max_states=2)
    assert str(failure.value) == verify_prints(ROUTING, "--nodes", NODES, "--max-states", "2").stdout
    assert str(failure.value).startswith("NOT proved: ") and failure.value.report.exit_status == 3
    with pytest.raises(TreesNotProved, match="nothing to compress, so nothing was proved"):
        assert_bt_compresses(REPLANNING)


def test_a_failure_pickles_with_its_proof():
    with pytest.raises(TreesNotProved) as failure:
        assert_bt_equal(TIME, DISTANCE, nodes=NODES)
    copy = pickle.loads(pickle.dumps(failure.value))
    assert type(copy) is TreesNotProved and str(copy) == str(failure.value)
    assert copy.report.text() == failure.value.report.text()


# --- the plugin ----------------------------------------------------------------------

def pytest_in(folder: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pytest", *PLUGIN, "-p", "no:cacheprovider", *args],
                          cwd=folder, capture_output=True, text=True, timeout=300, env=environ())


@pytest.fixture
def project(tmp_path):
    """A robotics team's folder: trees/ with a compressed tree and an approved one that a change
    broke, the nodes file beside it, one ordinary test."""
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_plain.py").write_text("def test_plain():\n    pass\n")
    trees = tmp_path / "trees"
    trees.mkdir()
    shutil.copy(NODES, tmp_path)
    shutil.copy(ROUTING, trees / "routing.xml")
    compressed = subprocess.run([sys.executable, "-m", "schemalog", "compress", "trees/routing.xml", "--nodes",
                                 "nav2_tree_nodes.xml", "-o", "trees/routing.compressed.xml"], cwd=tmp_path,
                                capture_output=True, text=True, timeout=300, env=environ())
    assert compressed.returncode == 0, compressed.stderr
    shutil.copy(REPLANNING, trees / "navigate.approved.xml")
    (trees / "navigate.xml").write_text(swapped(REPLANNING.read_text()))
    shutil.copy(TIME, trees / "lone.xml")                       # no recorded version: no item
    return tmp_path


def test_without_the_option_no_tree_is_collected(project):
    out = pytest_in(project, "-v")
    assert out.returncode == 0 and "1 passed" in out.stdout, out.stdout + out.stderr
    assert ".xml::" not in out.stdout and "schemalog: proving" not in out.stdout


def test_each_recorded_version_is_an_item_and_a_broken_one_fails_with_the_counterexample(project):
    out = pytest_in(project, "-v", "--schemalog-trees", "trees", "--schemalog-nodes", "nav2_tree_nodes.xml")
    assert out.returncode == 1, out.stdout + out.stderr
    assert ("schemalog: proving the trees under trees equal to their recorded versions (X.compressed.xml, "
            "X.approved.xml); nodes nav2_tree_nodes.xml") in out.stdout
    assert "trees/routing.xml::routing.compressed.xml PASSED" in out.stdout
    assert "trees/navigate.xml::navigate.approved.xml FAILED" in out.stdout
    assert "_ navigate.approved.xml against trees/navigate.xml _" in out.stdout
    printed = subprocess.run([sys.executable, "-m", "schemalog", "verify", "trees/navigate.xml",
                              "trees/navigate.approved.xml", "--nodes", "nav2_tree_nodes.xml"], cwd=project,
                             capture_output=True, text=True, timeout=300, env=environ())
    assert printed.returncode == 1 and printed.stdout.rstrip("\n") in out.stdout     # verify's words, whole
    assert "Traceback" not in out.stdout and "plugin.py" not in out.stdout
    assert "lone.xml" not in out.stdout and "1 failed, 2 passed" in out.stdout      # the plain test too


def test_the_ini_options_prove_the_trees_with_a_plain_pytest(project):
    (project / "trees" / "navigate.approved.xml").unlink()
    (project / "pytest.ini").write_text("[pytest]\nschemalog_trees = trees\nschemalog_nodes = nav2_tree_nodes.xml\n"
                                        "schemalog_profile = nav2\nschemalog_run_once = true\n")
    out = pytest_in(project, "-v")
    assert out.returncode == 0 and "2 passed" in out.stdout, out.stdout + out.stderr
    assert "; nodes nav2_tree_nodes.xml; profile nav2; run once" in out.stdout
    out = pytest_in(project, "-v", "test_plain.py")         # test paths named: the ini's trees are not collected
    assert out.returncode == 0 and "1 passed" in out.stdout and ".xml::" not in out.stdout


def test_the_options_reach_the_proof(project):
    """Without the nodes file the compressed tree (written with a TreeNodesModel) is refuted: the
    models differ (docs/behaviour_trees.md); a limit is no proof and fails saying so."""
    out = pytest_in(project, "-q", "--schemalog-trees", "trees/routing.xml")
    assert out.returncode == 1 and "FAILED trees/routing.xml::routing.compressed.xml" in out.stdout, out.stdout
    out = pytest_in(project, "-q", "--schemalog-trees", "trees/routing.xml", "--schemalog-nodes",
                    "nav2_tree_nodes.xml", "--schemalog-max-states", "1")
    assert out.returncode == 1 and "NOT proved: " in out.stdout, out.stdout + out.stderr


def test_the_printed_node_id_reruns_its_item(project):
    out = pytest_in(project, "--schemalog-trees", "trees", "--schemalog-nodes", "nav2_tree_nodes.xml")
    failed = re.search(r"^FAILED (\S+) - ", out.stdout, re.M).group(1)
    assert failed == "trees/navigate.xml::navigate.approved.xml"
    out = pytest_in(project, "-v", "--schemalog-trees", "trees", "--schemalog-nodes", "nav2_tree_nodes.xml", failed)
    assert out.returncode == 1 and "1 failed" in out.stdout and "passed" not in out.stdout, out.stdout
    out = pytest_in(project, "-v", "--schemalog-trees", "trees", "--schemalog-nodes", "nav2_tree_nodes.xml", "-k",
                    "routing")
    assert out.returncode == 0 and "trees/routing.xml::routing.compressed.xml PASSED" in out.stdout


def test_a_file_that_does_not_read_fails_its_item_with_its_position(project):
    bad = project / "trees" / "bad.xml"
    bad.write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <Sequence>\n      <AlwaysSuccess/>\n'
                   '    </Sequnce>\n  </BehaviorTree>\n</root>\n')
    shutil.copy(bad, project / "trees" / "bad.compressed.xml")
    out = pytest_in(project, "-q", "--schemalog-trees", "trees", "--schemalog-nodes", "nav2_tree_nodes.xml",
                    "-k", "bad or routing")
    assert out.returncode == 1, out.stdout + out.stderr
    assert "trees/bad.xml:5:7: error: malformed XML: mismatched tag" in out.stdout
    assert "1 failed, 1 passed" in out.stdout and "Traceback" not in out.stdout


@pytest.mark.parametrize("args, expected", [
    (["--schemalog-trees", "nowhere"], "--schemalog-trees: nowhere: no such folder or file"),
    (["--schemalog-trees", "trees", "--schemalog-profile", "nav3"],
     "--schemalog-profile: unknown profile 'nav3'; the profiles schemalog ships: nav2"),
    (["--schemalog-trees", "trees", "--schemalog-nodes", "missing.xml"], "--schemalog-nodes: missing.xml: no such file"),
    (["--schemalog-trees", "empty"], "--schemalog-trees: empty: no tree with a recorded version in this folder"),
])
def test_a_wrong_option_is_a_usage_error(project, args, expected):
    (project / "empty").mkdir()
    shutil.copy(TIME, project / "empty" / "lone.xml")
    out = pytest_in(project, *args)
    assert out.returncode == 4 and expected in out.stderr, out.stdout + out.stderr


def test_collecting_reads_no_tree(project):
    (project / "conftest.py").write_text(
        "import schemalog.api.trees as trees\n\ndef refused(*a, **k):\n    raise RuntimeError('read at collection')\n\n"
        "trees.read_tree = refused\n")
    out = pytest_in(project, "--collect-only", "-q", "--schemalog-trees", "trees")
    assert out.returncode == 0, out.stdout + out.stderr
    assert [line for line in out.stdout.splitlines() if "::" in line and ".xml" in line] == \
        ["trees/navigate.xml::navigate.approved.xml", "trees/routing.xml::routing.compressed.xml"]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")
def test_a_fifo_or_an_orphan_recorded_version_is_named_and_never_read(project):
    trees = project / "trees"
    os.mkfifo(trees / "pipe.compressed.xml")
    (trees / "pipe.xml").write_text(ROUTING.read_text())
    shutil.copy(ROUTING, trees / "gone.compressed.xml")
    out = pytest_in(project, "-q", "--schemalog-trees", "trees", "--schemalog-nodes", "nav2_tree_nodes.xml",
                    "-k", "routing")
    assert out.returncode == 0 and "1 passed" in out.stdout, out.stdout + out.stderr
    lines = out.stdout.splitlines()
    assert "schemalog: trees/pipe.compressed.xml: a FIFO (reading it would wait for a writer): skipped" in lines
    assert "schemalog: trees/gone.compressed.xml: a recorded version with no gone.xml beside it: skipped" in lines
    (project / "pipes").mkdir()
    os.mkfifo(project / "pipes" / "only.compressed.xml")
    (project / "pipes" / "only.xml").write_text(ROUTING.read_text())
    out = pytest_in(project, "--schemalog-trees", "pipes")
    assert out.returncode == 2 and "schemalog: no tree to prove under pipes:" in out.stdout, out.stdout + out.stderr
    assert "pipes/only.compressed.xml: a FIFO" in out.stdout
