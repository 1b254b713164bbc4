"""schemalog.read_tree, compress_tree, verify_trees: BT.CPP trees from Python, whose results say
exactly what `schemalog compress` and `schemalog verify` print (api/trees.py)."""

from __future__ import annotations

import json
import pickle
import subprocess
import sys

import pytest

import schemalog
from conftest import ROOT

NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
ROUTING = NAV2 / "navigate_w_routing_global_planning_and_control_w_recovery.xml"   # 45 nodes, one rewrite
REPLANNING = NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml"               # nothing to compress
TIME, DISTANCE = NAV2 / "navigate_w_replanning_time.xml", NAV2 / "navigate_w_replanning_distance.xml"
T15 = ROOT / "tests" / "bt" / "corpus" / "btcpp" / "tutorials" / "t15_nodes_mocking.xml"   # named nodes


def cli(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=ROOT, timeout=300)


def wrapped(tmp_path):
    """REPLANNING with its root wrapped in two named Sequences: what --drop-names flattens."""
    text = REPLANNING.read_text()
    inner = text[text.index('<RecoveryNode number_of_retries="6"'):text.rindex("</RecoveryNode>") + len("</RecoveryNode>")]
    path = tmp_path / "wrapped.xml"
    path.write_text(text.replace(inner, f'<Sequence name="outer"><Sequence name="inner">{inner}'
                                        f'<Wait wait_duration="1"/></Sequence></Sequence>'))
    return path


# --- read_tree ---------------------------------------------------------------------------

def test_a_tree_is_read_with_its_nodes_files_and_semantics(tmp_path):
    tree = schemalog.read_tree(ROUTING, nodes=NODES)
    assert (tree.files, tree.nodes, tree.profiles, tree.rules) == ((str(ROUTING),), (str(NODES),), (), None)
    assert tree.name == "NavigateWRoutingGlobalPlanningAndControlWRecovery" and len(tree) == 45
    mine = tmp_path / "mine.yaml"
    mine.write_text("ComputePathToPose: SyncAction\n")
    tree = schemalog.read_tree([ROUTING], nodes=[NODES], semantics=mine, profile=["nav2", "nav2"])
    assert tree.profiles == ("nav2",) and "ComputePathToPose" in tree.rules
    # a profile's rule a file overrides is said, as the command line says it on standard error
    assert len(tree.notes) == 1 and tree.notes[0].startswith(f"note: {mine}:1:1: ComputePathToPose follows SyncAction")


@pytest.mark.parametrize("call, says", [
    (lambda: schemalog.read_tree(42), "read_tree(): paths is an int (42); pass a file name or a list of them"),
    (lambda: schemalog.read_tree([ROUTING, 7]), "read_tree(): paths holds an int (7); each of its items must be a file name"),
    (lambda: schemalog.read_tree(ROUTING, profile="nav3"), "read_tree(): unknown profile 'nav3'; the profiles schemalog ships: nav2"),
    (lambda: schemalog.read_tree([]), "read_tree(): paths is empty"),
    (lambda: schemalog.read_tree(ROUTING, nodez=NODES), "unexpected keyword argument 'nodez'"),
    (lambda: schemalog.verify_trees(schemalog.read_tree(ROUTING), ROUTING, nodes=NODES),
     "verify_trees(): original is a TreeDocument, read already; nodes applies to reading a file"),
    (lambda: schemalog.verify_trees(ROUTING, ROUTING, drop_names=True), "drop_names applies when verify_trees compresses one tree"),
    (lambda: schemalog.verify_trees(schemalog.read_tree(ROUTING), schemalog.read_tree(ROUTING, profile="nav2")),
     "the trees were read under different node semantics"),
    (lambda: schemalog.compress_tree(ROUTING, max_states=0), "compress_tree(): max_states is 0; pass an int of 1 or more"),
])
def test_what_a_call_cannot_take_is_a_usage_error(call, says):
    with pytest.raises(schemalog.UsageError) as err:
        call()
    assert says in err.value.message


def test_a_file_that_does_not_read_is_an_error_at_its_line_and_column(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <Sequence>\n    </Sequnce>\n'
                   '  </BehaviorTree>\n</root>\n')
    with pytest.raises(schemalog.SchemalogError) as err:
        schemalog.read_tree(bad)
    assert (err.value.file, err.value.line, err.value.column) == (str(bad), 4, 7)
    assert str(err.value) == cli("verify", bad, bad).stderr.rstrip("\n")


# --- the results are what the command line prints --------------------------------------------

@pytest.mark.parametrize("args, options", [
    ((ROUTING, "--nodes", NODES), dict(nodes=NODES)),
    ((ROUTING, "--nodes", NODES, "--profile", "nav2"), dict(nodes=NODES, profile="nav2")),
    ((ROUTING, "--nodes", NODES, "--max-states", "2"), dict(nodes=NODES, max_states=2)),
    ((REPLANNING,), {}),
    ((T15, "--task", "MainTree"), dict(main="MainTree")),
    ((T15, "--task", "MainTree", "--drop-names"), dict(main="MainTree", drop_names=True)),
], ids=["routing", "profile", "limit", "nothing", "named", "dropped"])
def test_compress_tree_says_what_schemalog_compress_prints(args, options):
    result = schemalog.compress_tree(args[0], **options)
    text, data = cli("compress", *args), cli("compress", *args, "--json")
    assert result.text() == text.stdout and result.exit_status == text.returncode
    assert json.dumps(result.as_json(), indent=2) + "\n" == data.stdout
    assert result.proved == json.loads(data.stdout)["proved"]


@pytest.mark.parametrize("args, options", [
    ((TIME, DISTANCE, "--nodes", NODES), dict(nodes=NODES)),                      # refuted
    ((TIME, DISTANCE, "--nodes", NODES, "--profile", "nav2"), dict(nodes=NODES, profile="nav2")),
    ((TIME, TIME, "--nodes", NODES, "--run-once"), dict(nodes=NODES, run_once=True)),   # proved
    ((ROUTING, "--nodes", NODES), dict(nodes=NODES)),                               # one tree, compressed
    ((ROUTING, "--nodes", NODES, "--max-states", "2"), dict(nodes=NODES, max_states=2)),   # a limit
    ((REPLANNING,), {}),                                                             # nothing compressed
    ((T15, "--task", "MainTree"), dict(main="MainTree")),                            # names kept
], ids=["refuted", "profile", "proved", "one", "limit", "nothing", "named"])
def test_verify_trees_says_what_schemalog_verify_prints(args, options):
    files = [a for a in args[:2] if a in (TIME, DISTANCE, ROUTING, REPLANNING, T15)]
    proof = schemalog.verify_trees(*files, **options)
    text, data = cli("verify", *args), cli("verify", *args, "--json")
    assert proof.text() == text.stdout and proof.exit_status == text.returncode
    assert json.dumps(proof.as_json(), indent=2) + "\n" == data.stdout
    assert proof.proved == (text.returncode == 0)


def test_a_refutation_carries_its_counterexample_tick_by_tick():
    proof = schemalog.verify_trees(TIME, DISTANCE, nodes=NODES)
    assert (proof.equal, proof.complete, proof.proved) == (False, True, False)
    assert proof.counterexample[:2] == ("environment's choices: SUCCESS, SUCCESS", "root tick 1:")
    assert proof.counterexample[-1].endswith("<- the trees part here")
    assert proof.text().splitlines()[1:] == list(proof.counterexample)


def test_a_limit_is_never_a_proof():
    for result in (schemalog.compress_tree(ROUTING, nodes=NODES, max_states=2),
                   schemalog.verify_trees(ROUTING, nodes=NODES, max_states=2)):
        assert (result.equal, result.complete, result.proved, result.exit_status) == (True, False, False, 3)
        assert "NOT proved" in result.text()


def test_nothing_to_compress_is_no_proof_for_verify():
    proof = schemalog.verify_trees(REPLANNING)
    assert (proof.equal, proof.proved, proof.states, proof.exit_status) == (True, False, 0, 3)
    assert proof.compression.rewrites == () and proof.compression.nodes_after == proof.compression.nodes_before


def test_named_nodes_are_kept_unless_dropped():
    kept = schemalog.compress_tree(T15, main="MainTree")
    assert kept.rewrites == () and [k.name for k in kept.kept_names] == ["counting"]
    dropped = schemalog.compress_tree(T15, main="MainTree", drop_names=True)
    assert [r.name for r in dropped.rewrites] == ["counting"] and dropped.kept_names == ()


def test_the_compressed_tree_is_written_read_back_and_proved(tmp_path):
    tree = schemalog.read_tree(ROUTING, nodes=NODES)
    compression = schemalog.compress_tree(tree)
    assert compression.xml() == compression.compressed.xml()
    out = tmp_path / "small.xml"
    written = cli("compress", ROUTING, "--nodes", NODES, "-o", out)
    assert written.returncode == 0 and out.read_text() == compression.xml()
    (tmp_path / "again.xml").write_text(compression.xml())
    again = schemalog.read_tree(tmp_path / "again.xml", nodes=NODES)
    assert len(again) == compression.nodes_after == 44
    assert schemalog.verify_trees(tree, again).proved and schemalog.verify_trees(tree, compression.compressed).proved


def test_a_timeout_stops_a_proof_with_limit_exceeded():
    with pytest.raises(schemalog.LimitExceeded) as err:
        schemalog.verify_trees(ROUTING, nodes=NODES, timeout=0.001)
    assert err.value.limit == "time"


def test_the_results_pickle_and_a_document_rereads_its_semantics():
    tree = schemalog.read_tree(ROUTING, nodes=NODES, profile="nav2")
    copy = pickle.loads(pickle.dumps(tree))
    assert copy.files == tree.files and len(copy) == 45 and copy.rules.keys() == tree.rules.keys()
    proof = schemalog.verify_trees(TIME, DISTANCE, nodes=NODES)
    assert pickle.loads(pickle.dumps(proof)).text() == proof.text()


def test_the_names_are_exported_lazily():
    names = {"read_tree", "compress_tree", "verify_trees", "TreeDocument", "TreeCompression", "TreeProof"}
    assert names <= set(schemalog.__all__) and names <= set(dir(schemalog))
    code = "import sys, schemalog; print('schemalog.api.trees' in sys.modules, 'schemalog.bt.prove' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert out.stdout.split() == ["False", "False"], out.stderr


def test_two_versions_are_two_readings_as_btcpp_3_4_gives_them():
    v3 = ROOT / "tests" / "bt" / "corpus" / "btcpp3" / "nav2_goal_patience_v3.xml"
    v4 = ROOT / "tests" / "bt" / "corpus" / "btcpp3" / "nav2_goal_patience_v4.xml"
    old, new = schemalog.read_tree(v3, nodes=NODES, version=3), schemalog.read_tree(v4, nodes=NODES, version=4)
    assert (old.version, old.document.version, new.document.version) == (3, 3, 4)
    proof = schemalog.verify_trees(old, new)
    args = (v3, v4, "--btcpp", "3:4", "--nodes", NODES)
    assert proof.text() == cli("verify", *args).stdout and proof.btcpp == "BT.CPP 3.8 (a) against BT.CPP 4 (b)"
    assert json.dumps(proof.as_json(), indent=2) + "\n" == cli("verify", *args, "--json").stdout
    with pytest.raises(schemalog.UsageError, match="version 5: 3"):
        schemalog.read_tree(v3, version=5)
