"""`schemalog compress F.xml` and `schemalog verify F.xml SMALL.xml` on real BT.CPP trees (the
corpus of tests/bt/corpus), as a Nav2 user runs them."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from conftest import ROOT

CORPUS = ROOT / "tests" / "bt" / "corpus"
NAV2 = CORPUS / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
REPLANNING = NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml"
ROUTING = NAV2 / "navigate_w_routing_global_planning_and_control_w_recovery.xml"
NAV2_TREES = sorted(p for p in NAV2.glob("*.xml") if p != NODES
                    and p.name != "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml")  # v3


def run(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


@pytest.mark.parametrize("tree", NAV2_TREES, ids=lambda p: p.stem)
def test_every_nav2_tree_compresses_and_the_result_is_proved(tree, tmp_path):
    out = tmp_path / "small.xml"
    r = run("compress", tree, "--nodes", NODES, "-o", out)
    assert r.returncode == 0, r.stderr
    # the README and docs/behaviour_trees.md: one Nav2 tree of the corpus compresses, the 13 others do not
    if tree == ROUTING:
        assert "proved equal to the original" in r.stderr
    else:
        assert "nothing to compress" in r.stderr
    v = run("verify", tree, out, "--nodes", NODES)
    assert v.returncode == 0 and v.stdout.startswith("proved equal"), v.stdout + v.stderr


def test_the_readmes_nav2_lines_do_what_they_say(tmp_path):
    """README, What you can do: its Nav2 line named no file and promised a compressed tree, which
    13 of the corpus's 14 Nav2 trees do not give."""
    import re

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    lines = [line for line in readme.splitlines() if "$N/nav2_tree_nodes.xml" in line]
    diff_line = next(line for line in lines if "schemalog diff" in line)
    lines.remove(diff_line)
    assert len(lines) == 3 and "44 nodes from 45" in lines[0] and "13 other Nav2 trees have nothing" in lines[0]
    script = "\n".join(line.split("   #", 1)[0].replace("small.xml", str(tmp_path / "small.xml")) for line in lines)
    script = re.sub(r"\bschemalog\b", f"{sys.executable} -m schemalog", script)
    r = subprocess.run(["bash", "-ec", script], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "wrote " in r.stderr and "44 nodes from 45 (1 rewrite), proved equal to the original" in r.stderr
    assert r.stdout.startswith("proved equal")
    assert "\nproved equal under BT.CPP 4 semantics with the nav2 profile: " in r.stdout     # --profile nav2
    # the diff line: an edit of a Nav2 tree, found by place (exit 1: behaviour changed)
    script = "N=tests/bt/corpus/nav2\n" + diff_line.split("   #", 1)[0].replace("edited.xml", str(tmp_path / "edited.xml"))
    r = subprocess.run(["bash", "-c", re.sub(r"\bschemalog\b", f"{sys.executable} -m schemalog", script)],
                       capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 1, r.stderr
    assert 'B retries PipelineSequence "NavigateWithReplanning" 5 times instead of 6' in r.stdout


def test_the_compressed_nav2_tree_keeps_every_node_and_port(tmp_path):
    out = tmp_path / "small.xml"
    r = run("compress", ROUTING, "--nodes", NODES, "-o", out)
    assert r.returncode == 0, r.stderr
    assert "44 nodes from 45 (1 rewrite)" in r.stderr and "by parts" in r.stderr
    written = out.read_text()
    for text in ('<ComputeRoute goal="{goal}" path="{route_path}"', 'main_tree_to_execute="NavigateWRoutingGlobalPlanningAndControlWRecovery"',
                 '<RecoveryNode number_of_retries="6" name="NavigateRecovery">', "<TreeNodesModel>"):
        assert text in written, text
    # Every node of the original but the one Fallback removed, with its type, form and attributes.
    from collections import Counter
    from schemalog.api.behaviour_trees import read_tree
    from schemalog.bt.model import walk

    def nodes(path):
        return Counter((n.type, n.form, n.attrs) for _, root in read_tree(path, [NODES]).trees for n in walk(root))
    assert nodes(ROUTING) - nodes(out) == Counter({("Fallback", "", ()): 1}) and not nodes(out) - nodes(ROUTING)


@pytest.mark.parametrize("name", ["routing", "routing.bt", "routing.XML"])
def test_a_tree_is_told_by_its_content_not_its_name(tmp_path, name):
    """A BT.CPP file without the .xml suffix was read as Prolog (`unexpected '<'`), even with --nodes."""
    tree = tmp_path / name
    tree.write_bytes(b"\xef\xbb\xbf\n" + ROUTING.read_bytes())        # a byte order mark and a blank line first
    out = tmp_path / "small.xml"
    r = run("compress", tree, "--nodes", NODES, "-o", out)
    assert r.returncode == 0, r.stderr
    assert "44 nodes from 45 (1 rewrite)" in r.stderr
    copy = tmp_path / "small"
    copy.write_bytes(out.read_bytes())
    v = run("verify", tree, copy, "--nodes", NODES)
    assert v.returncode == 0 and v.stdout.startswith("proved equal"), v.stdout + v.stderr


def test_a_recovery_node_with_its_children_swapped_is_refuted_tick_by_tick(tmp_path):
    text = REPLANNING.read_text()
    follow = '<FollowPath path="{path}" controller_id="FollowPath"/>\n'
    start = text.index('<RecoveryNode number_of_retries="1" name="FollowPath">')
    end = text.index("</RecoveryNode>", start)
    body = text[start:end]
    fallback = body[body.index("<ReactiveFallback"):body.index("</ReactiveFallback>") + len("</ReactiveFallback>")]
    swapped = body.replace(follow, "").replace(fallback, fallback + "\n          " + follow.strip())
    edited = tmp_path / "edited.xml"
    edited.write_text(text[:start] + swapped + text[end:])
    r = run("verify", REPLANNING, edited, "--nodes", NODES)
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout.startswith("refuted after")
    # each node by file:line:column (issue 48: two unnamed GoalUpdated leaves could not be told apart)
    assert (f'a: tick FollowPath path="{{path}}" controller_id="FollowPath" at {REPLANNING}:21:11   '
            f'<- the trees part here') in r.stdout
    assert f"b: tick GoalUpdated at {edited}:22:13   <- the trees part here" in r.stdout
    j = run("verify", REPLANNING, edited, "--nodes", NODES, "--json")
    assert j.returncode == 1 and json.loads(j.stdout)["proved"] is False


def test_a_wrapped_tree_is_compressed_and_a_limit_is_never_a_proof(tmp_path):
    # Wrapping a real tree's root in a Sequence inside a Sequence: the rewrite is proved by parts.
    text = REPLANNING.read_text()
    inner = text[text.index('<RecoveryNode number_of_retries="6"'):text.rindex("</RecoveryNode>") + len("</RecoveryNode>")]
    wrapped = tmp_path / "wrapped.xml"
    wrapped.write_text(text.replace(inner, f'<Sequence name="outer"><Sequence name="inner">{inner}'
                                           f'<Wait wait_duration="1"/></Sequence></Sequence>'))
    # named, both wrappers stay (issue 48, item 4), and the output says so
    named = run("compress", wrapped, "--nodes", NODES)
    assert named.returncode == 0 and "nothing to compress (25 nodes)" in named.stdout, named.stderr
    assert "kept 2 named nodes a rewrite would remove (--drop-names removes them): " in named.stdout
    assert 'wrapped.xml:9:28 Sequence "inner", ' in named.stdout and 'wrapped.xml:9:5 Sequence "outer"' in named.stdout
    r = run("compress", wrapped, "--nodes", NODES, "--drop-names")
    assert r.returncode == 0, r.stderr
    assert "flatten: removed Sequence 'inner'" in r.stdout and "proved equal" in r.stdout
    limited = run("compress", wrapped, "--nodes", NODES, "--max-states", "2", "--drop-names")
    assert limited.returncode == 3 and "NOT proved" in limited.stdout and "max_states" in limited.stdout
    out = tmp_path / "small.xml"
    unproved = run("compress", wrapped, "--nodes", NODES, "--max-states", "2", "-o", out, "--drop-names")
    assert unproved.returncode == 3 and "nothing written" in unproved.stderr and not out.exists()
    empty = run("compress", wrapped, "--nodes", wrapped)           # a tree, not a nodes file
    assert empty.returncode == 1 and "wrapped.xml:1:1: error: declares no node" in empty.stderr


T15 = CORPUS / "btcpp" / "tutorials" / "t15_nodes_mocking.xml"


def test_named_nodes_are_kept_and_said_in_text_json_xml_and_verify(tmp_path):
    """Issue 48, item 4: BT.CPP's t15 substitutes its Sequence "counting" by name; compress keeps
    it and says so, --drop-names flattens it as before."""
    where = f'{T15}:13:7 Sequence "counting"'
    said = f"kept 1 named node a rewrite would remove (--drop-names removes it): {where}\n"
    text = run("compress", T15, "--task", "MainTree")
    assert text.returncode == 0 and text.stderr == "", text.stderr
    assert text.stdout == (f"{T15}: nothing to compress (12 nodes): every rewrite of bt/compress.py that applies "
                           f"would remove a named node\n" + said)
    j = run("compress", T15, "--task", "MainTree", "--json")
    assert j.returncode == 0 and j.stderr == ""
    report = json.loads(j.stdout)
    assert report["rewrites"] == [] and report["nodes_after"] == 12 and report["kept_names"] == [
        {"rule": "flatten", "type": "Sequence", "name": "counting", "file": str(T15), "line": 13, "column": 7}]
    out = tmp_path / "small.xml"
    x = run("compress", T15, "--task", "MainTree", "-o", out)
    assert x.returncode == 0 and said in x.stderr and 'name="counting"' in out.read_text()
    dropped = run("compress", T15, "--task", "MainTree", "--drop-names", "--json")
    report = json.loads(dropped.stdout)
    assert dropped.returncode == 0 and report["kept_names"] == [] and report["proved"] is True
    assert [(r["rule"], r["name"]) for r in report["rewrites"]] == [("flatten", "counting")]
    assert report["nodes_after"] == 11
    # verify F.xml alone compresses: the same choice, the same words
    v = run("verify", T15, "--task", "MainTree")
    assert v.returncode == 3 and v.stdout == f"{T15}: nothing to compress, so nothing was proved (the tree is its own compression)\n" + said
    vj = json.loads(run("verify", T15, "--task", "MainTree", "--json").stdout)
    assert vj["proved"] is False and [k["name"] for k in vj["kept_names"]] == ["counting"]
    vd = run("verify", T15, "--task", "MainTree", "--drop-names")
    assert vd.returncode == 0 and vd.stdout.startswith("proved equal") and "kept" not in vd.stdout
    # a file with named and unnamed rewrites: the unnamed go, the named are said
    mixed = tmp_path / "mixed.xml"
    mixed.write_text(T15.read_text().replace('<SaySomething message="1"/>',
                                             '<Sequence><SaySomething message="1"/></Sequence>'))
    m = run("compress", mixed, "--task", "MainTree")
    assert m.returncode == 0 and "12 nodes from 13 (1 rewrite), proved equal" in m.stdout, m.stdout + m.stderr
    assert ":14:9: single: removed Sequence\n" in m.stdout and 'mixed.xml:13:7 Sequence "counting"\n' in m.stdout
    # --drop-names means nothing for two files, or for task knowledge: refused, not ignored
    two = run("verify", T15, T15, "--task", "MainTree", "--drop-names")
    assert two.returncode == 2 and "--drop-names applies when verify compresses one BT.CPP tree" in two.stderr
    task = run("compress", ROOT / "kb" / "tasks" / "mix_with_spoon.pl", "--drop-names")
    assert task.returncode == 2 and "--drop-names applies to BT.CPP trees" in task.stderr


def test_bt_cpp_examples_compress_and_bad_trees_are_refused_with_a_position(tmp_path):
    r = run("compress", CORPUS / "btcpp" / "tutorials" / "t09_scripting.xml")
    assert r.returncode == 0 and "nothing to compress (9 nodes)" in r.stdout, r.stderr
    several = run("compress", CORPUS / "btcpp" / "examples" / "test_files" / "log_test.xml")
    assert several.returncode == 1 and "main_tree_to_execute" in several.stderr
    chosen = run("compress", CORPUS / "btcpp" / "examples" / "test_files" / "log_test.xml", "--task", "Main")
    assert chosen.returncode == 0, chosen.stderr
    by_tag = run("compress", CORPUS / "btcpp" / "examples" / "test_files" / "subtree_test.xml", "--task", "BehaviorTree")
    assert by_tag.returncode == 1 and "subtree_test.xml:8:13: error: <CheckStatus> names the BehaviorTree" in by_tag.stderr
    v3 = run("compress", NAV2 / "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml", "--btcpp", "4")
    assert v3.returncode == 1 and ":21:15: error:" in v3.stderr and "BT.CPP 3" in v3.stderr
    bad = tmp_path / "bad.xml"
    bad.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><Inverter/></BehaviorTree></root>')
    r = run("compress", bad)
    assert r.returncode == 1 and "bad.xml:1:" in r.stderr and "Traceback" not in r.stderr
    picture = run("compress", REPLANNING, "-o", tmp_path / "x.png")
    assert picture.returncode == 2 and not (tmp_path / "x.png").exists()


def test_custom_nodes_get_the_semantics_a_user_gives_them(tmp_path):
    tree = tmp_path / "custom.xml"
    tree.write_text('<root BTCPP_format="4"><BehaviorTree ID="Main"><MyRecovery number_of_retries="1">'
                    '<Sequence><Sequence><IsBatteryOk/><Go/></Sequence></Sequence><Clear/>'
                    '</MyRecovery></BehaviorTree></root>')
    semantics = tmp_path / "semantics.yaml"
    semantics.write_text("MyRecovery: RecoveryNode\nIsBatteryOk: Condition\n")
    r = run("verify", tree, "--semantics", semantics)
    assert r.returncode == 0 and "proved equal" in r.stdout, r.stdout + r.stderr
    # Opaque, MyRecovery chooses what to tick first (an event); as a RecoveryNode it ticks its
    # first child, and IsBatteryOk as a Condition offers SUCCESS or FAILURE only.
    swapped = tmp_path / "swapped.xml"
    swapped.write_text(tree.read_text().replace("<Sequence><Sequence><IsBatteryOk/><Go/></Sequence></Sequence><Clear/>",
                                                "<Clear/><Sequence><Sequence><IsBatteryOk/><Go/></Sequence></Sequence>"))
    known = run("verify", tree, swapped, "--semantics", semantics)
    assert known.returncode == 1 and "environment's choices: none" in known.stdout
    opaque = run("verify", tree, swapped)
    assert opaque.returncode == 1 and "choice of MyRecovery" in opaque.stdout
    semantics.write_text("MyRecovery: Recovery\n")
    bad = run("verify", tree, "--semantics", semantics)
    assert bad.returncode == 1 and "semantics.yaml:1:13: error: 'Recovery' is not a node type" in bad.stderr
    out = run("compress", tree, "--semantics", semantics, "-o", semantics)
    assert out.returncode == 2 and semantics.read_text() == "MyRecovery: Recovery\n"


def test_verify_of_a_tree_with_nothing_to_compress_is_no_proof_in_text_and_json(tmp_path):
    # A check that covers nothing is not a proof: exit 3, and --json gives JSON (review of issue 33)
    tree = tmp_path / "tight.xml"
    tree.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><A/><B/></Sequence>'
                    '</BehaviorTree></root>\n')
    r = run("verify", tree)
    assert r.returncode == 3 and "nothing was proved" in r.stdout, r.stdout + r.stderr
    j = run("verify", tree, "--json")
    assert j.returncode == 3, j.stderr
    data = json.loads(j.stdout)
    assert data["proved"] is False and data["states"] == 0


def test_verify_tells_apart_identical_trees_whose_models_differ(tmp_path):
    # X a Condition in one file, an Action in the other: X may return RUNNING in one only
    body = '<BehaviorTree ID="M"><Sequence><X/><Y/></Sequence></BehaviorTree></root>\n'
    a, b = tmp_path / "a.xml", tmp_path / "b.xml"
    a.write_text('<root BTCPP_format="4"><TreeNodesModel><Condition ID="X"/></TreeNodesModel>' + body)
    b.write_text('<root BTCPP_format="4"><TreeNodesModel><Action ID="X"/></TreeNodesModel>' + body)
    r = run("verify", a, b)
    assert r.returncode == 1 and r.stdout.startswith("refuted"), r.stdout + r.stderr


def test_compress_does_not_remove_the_sequence_that_resets_a_guarded_condition(tmp_path):
    # WhileDoElse ticks its condition again without a reset; Sequence(X _skipIf) resets X, X does not
    tree = tmp_path / "w.xml"
    tree.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><WhileDoElse><Sequence>'
                    '<IsX _skipIf="c"/></Sequence><A/><B/></WhileDoElse></BehaviorTree></root>\n')
    r = run("compress", tree)
    assert r.returncode == 0 and "nothing to compress" in r.stdout, r.stdout + r.stderr
    small = tmp_path / "small.xml"
    small.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><WhileDoElse>'
                     '<IsX _skipIf="c"/><A/><B/></WhileDoElse></BehaviorTree></root>\n')
    v = run("verify", tree, small)
    assert v.returncode == 1 and "check _skipIf `c`" in v.stdout, v.stdout + v.stderr


def test_verify_of_compress_output_read_without_the_nodes_file_says_why_it_differs(tmp_path):
    """compress -o writes --nodes' models into its output; read without them, the original's
    GoalUpdated is an unknown leaf (may be RUNNING) and the output's a Condition: a real
    difference, and the refutation says where it comes from."""
    original = NAV2 / "navigate_w_routing_global_planning_and_control_w_recovery.xml"
    small = tmp_path / "small.xml"
    assert run("compress", original, "--nodes", NODES, "-o", small).returncode == 0
    differ = run("verify", original, small)
    assert differ.returncode == 1
    assert "GoalUpdated (a: an Action, b: a Condition); read both with the same --nodes file" in differ.stdout
    assert run("verify", original, small, "--nodes", NODES).returncode == 0


def test_xml_mistakes_a_user_makes_are_said_with_the_line_and_what_to_do(tmp_path):
    empty = tmp_path / "empty.xml"
    empty.write_text("")
    r = run("compress", empty)
    assert r.returncode == 1 and "empty.xml:1:1: error: the file is empty" in r.stderr
    broken = tmp_path / "broken.xml"
    broken.write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="M">\n    <Sequence>\n      <A x="1 && 2">\n'
                      '    </Sequence>\n  </BehaviorTree>\n</root>\n')
    r = run("compress", broken)
    assert r.returncode == 1 and "broken.xml:5:" in r.stderr and "\n        </Sequence>\n" in r.stderr
    assert r.stderr.rstrip().endswith("^") and "Traceback" not in r.stderr
    typo = tmp_path / "typo.xml"
    typo.write_text('<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence nmae="x"><A/></Sequence>'
                    '</BehaviorTree></root>')
    r = run("compress", typo)
    assert r.returncode == 1 and "port with name [nmae]" in r.stderr and "did you mean name?" in r.stderr
    r = run("compress", NODES)
    assert r.returncode == 1 and "a nodes file (give it with --nodes)" in r.stderr


def test_a_tree_too_deep_through_its_subtrees_is_refused_where_it_passes_the_limit(tmp_path):
    """A chain of 10,000 SubTrees was "error: the input nests too deeply to process", no place
    (issue 46): the tree BT.CPP would create is refused at the node that passes 256 levels."""
    trees = [f'<BehaviorTree ID="t{i}"><Inverter><SubTree ID="t{i + 1}"/></Inverter></BehaviorTree>'
             for i in range(10_000)]
    for leaf, name in (("a", "a.xml"), ("b", "b.xml")):
        (tmp_path / name).write_text('<root BTCPP_format="4" main_tree_to_execute="t0">\n' + "\n".join(trees) +
                                     f'\n<BehaviorTree ID="t10000"><Action ID="{leaf}"/></BehaviorTree></root>\n')
    for args in (("verify", "a.xml", "b.xml"), ("compress", "a.xml")):
        r = run(*args, cwd=tmp_path)
        assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr
        assert "a.xml:130:35: error: the tree BT.CPP creates nests deeper than 256 levels here, through t0 -> " \
               "t1 -> t2 -> ... -> t126 -> t127 -> t128 (128 SubTrees)" in r.stdout + r.stderr, r.stdout + r.stderr


@pytest.mark.parametrize("value, said", [("&#x1;", "U+0001"), ("&#xD800;", "U+D800 (a surrogate, no character)")])
def test_a_value_xml_cannot_hold_is_refused_at_its_node(tmp_path, value, said):
    """tinyxml2 reads p="&#x1;" as BT.CPP does; written back it has no XML 1.0 form: the refusal
    names the node's place and the character (a surrogate was named U+DCED, issue 46)."""
    (tmp_path / "t.xml").write_text('<root BTCPP_format="4">\n  <BehaviorTree ID="m">\n'
                                    f'    <Sequence><Action ID="a" p="{value}"/><Action ID="a"/></Sequence>\n'
                                    '  </BehaviorTree>\n</root>\n')
    r = run("compress", "t.xml", "-o", "out.xml", cwd=tmp_path)
    assert r.returncode == 1 and not (tmp_path / "out.xml").exists()
    assert r.stderr.strip() == (f't.xml:3:15: error: <Action ID="a"> cannot be written back: the value of p: '
                                f'{said} cannot be written in XML 1.0 (it has no character reference either)')


def test_semantics_files_read_as_one_and_builtins_refused(tmp_path):
    """--semantics twice kept one file silently; `Fallback: Sequence` proved Fallback(a, b) equal
    to Sequence(a, b), a program no robot can register (issue 46, issue 48)."""
    (tmp_path / "s1.yaml").write_text("MyRec: RecoveryNode\n")
    (tmp_path / "s2.yaml").write_text("Other: Condition\nMyRec: Sequence\n")
    (tmp_path / "bad.yaml").write_text("Fallback: Sequence\n")
    tree = NAV2 / "follow_point.xml"
    r = run("verify", tree, tree, "--semantics", "s1.yaml", "--semantics", "s2.yaml", cwd=tmp_path)
    assert r.returncode == 1 and r.stderr.startswith("s2.yaml:2:1: error: MyRec is given its semantics twice: "
                                                     "first at s1.yaml:1:1"), r.stderr
    r = run("verify", tree, tree, "--semantics", "bad.yaml", cwd=tmp_path)
    assert r.returncode == 1 and r.stderr.startswith("bad.yaml:1:1: error: Fallback is a node type of BT.CPP's "
                                                     "own"), r.stderr
    (tmp_path / "s3.yaml").write_text("Other: Condition\n")
    r = run("verify", tree, tree, "--semantics", "s1.yaml", "--semantics", "s3.yaml", cwd=tmp_path)
    assert r.returncode == 0, r.stderr


def test_nodes_and_semantics_for_task_knowledge_are_refused():
    r = run("compress", ROOT / "kb" / "tasks" / "mix_with_spoon.pl", "--nodes", NODES)
    assert r.returncode == 2 and "--nodes applies to BT.CPP trees" in r.stderr, r.stderr
    r = run("verify", ROOT / "kb" / "tasks" / "mix_with_spoon.pl", "--semantics", NODES)
    assert r.returncode == 2 and "--semantics applies to BT.CPP trees" in r.stderr, r.stderr


TWO_CHILDREN = """<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <{parent}>
      {first}
      <Action ID="{second}"/>
    </{parent}>
  </BehaviorTree>
</root>
"""


def two_children(parent: str, first: str, second: str) -> str:
    """A tree of one control node over `first` (XML) and an Action `second`; lines as above."""
    return TWO_CHILDREN.format(parent=parent, first=first, second=second)


def test_a_verdict_says_which_registrations_it_covers_and_a_counterexample_which_it_needs(tmp_path):
    """Issue 48: the XML does not say whether an Action is a SyncActionNode or a
    StatefulActionNode. PipelineSequence ticks its finished first child again unreset, where the
    two differ: wrapping that child in a SequenceWithMemory (which resets it) is refuted for a
    stateful one, and the counterexample names the registration and each node's place."""
    plain, wrapped = tmp_path / "plain.xml", tmp_path / "wrapped.xml"
    plain.write_text(two_children("PipelineSequence", '<Action ID="Plan"/>', "Follow"))
    wrapped.write_text(two_children("PipelineSequence", '<SequenceWithMemory><Action ID="Plan"/></SequenceWithMemory>',
                                    "Follow"))
    r = run("verify", plain, wrapped)
    assert r.returncode == 1, r.stdout + r.stderr
    first = r.stdout.splitlines()[0]
    assert first.endswith("(a run with Plan registered as a StatefulActionNode)"), first
    assert f"tick Follow at {plain}:5:7" in r.stdout and f"tick Plan at {wrapped}:4:27" in r.stdout
    sync = tmp_path / "sync.yaml"
    sync.write_text("Plan: ReTickedAction\n")
    r = run("verify", plain, wrapped, "--semantics", sync, "--json")
    out = json.loads(r.stdout)
    assert r.returncode == 0 and out["proved"], r.stdout + r.stderr
    assert "Follow, which the XML leaves open" in out["covers"] and "it takes the registration of Plan from --semantics or --profile" in out["covers"]
    r = run("verify", plain, plain)
    assert r.returncode == 0 and "It covers an executor that halts the tree (Tree::haltTree) between any two " \
        "ticks and ticks it anew for the next goal; it covers every registration of the 2 action types the XML " \
        "leaves open (Follow, Plan)" in r.stdout, r.stdout
    once = run("verify", plain, plain, "--run-once")
    assert once.returncode == 0 and "It assumes the tree is ticked until it finishes, once, and never halted " \
        "(--run-once)" in once.stdout, once.stdout


def test_a_proof_covers_an_executor_that_halts_the_tree_and_ticks_it_anew(tmp_path):
    """Issue 48: RunOnce(Calibrate) and Calibrate run alike until the tree first finishes; the next
    goal ticks the same tree again, and RunOnce remembers. A robot's executor does that (Nav2:
    haltTree after every goal, then the next one), so the default refutes; --run-once proves."""
    once, plain = tmp_path / "once.xml", tmp_path / "plain.xml"
    once.write_text(two_children("Sequence", '<RunOnce><Action ID="Calibrate"/></RunOnce>', "Work"))
    plain.write_text(two_children("Sequence", '<Action ID="Calibrate"/>', "Work"))
    r = run("verify", once, plain)
    assert r.returncode == 1 and "root tick 2 (the tree ticked anew, what its nodes keep kept):" in r.stdout, r.stdout
    assert f"a: tick Work at {once}:5:7   <- the trees part here" in r.stdout, r.stdout
    r = run("verify", once, plain, "--run-once")
    assert r.returncode == 0 and "(--run-once)" in r.stdout, r.stdout
    # a halt's own events: an `_onHalted` script runs when haltTree reaches its node, RUNNING or not
    halted = tmp_path / "halted.xml"
    halted.write_text(two_children("Sequence", '<Action ID="Calibrate" _onHalted="log()"/>', "Work"))
    r = run("verify", plain, halted)
    assert r.returncode == 1 and "tree halted (Tree::haltTree)" in r.stdout and "run script _onHalted `log()`" \
        in r.stdout, r.stdout
    assert run("verify", plain, halted, "--run-once").returncode == 0


def test_verify_with_the_nav2_profile(tmp_path):
    """`--profile nav2` (issue 48): Nav2's nodes under the rules of their source. A BtActionNode
    under a PipelineSequence returns its last result when ticked again unreset, a Sequence around
    it restarts it: equal when every Action re-ticks, refuted under the profile."""
    out = tmp_path / "small.xml"
    r = run("compress", ROUTING, "--nodes", NODES, "--profile", "nav2", "-o", out)
    assert r.returncode == 0 and "proved equal to the original under BT.CPP 4 semantics with the nav2 profile: " \
        in r.stderr, r.stderr
    v = run("verify", ROUTING, out, "--nodes", NODES, "--profile", "nav2")
    assert v.returncode == 0 and v.stdout.startswith("proved equal under BT.CPP 4 semantics with the nav2 profile: "), \
        v.stdout + v.stderr
    j = run("verify", ROUTING, out, "--nodes", NODES, "--profile", "nav2", "--json")
    assert j.returncode == 0 and json.loads(j.stdout)["profiles"] == ["nav2"], j.stdout + j.stderr
    text = (NAV2 / "navigate_w_replanning_time.xml").read_text()
    (tmp_path / "a.xml").write_text(text.replace('<RateController hz="1.0">', "<Sequence>")
                                    .replace("</RateController>", "</Sequence>"))
    (tmp_path / "b.xml").write_text(text.replace('<RateController hz="1.0">', "").replace("</RateController>", ""))
    # the default covers both registrations, so it refutes too, and names the one it needs
    plain = run("verify", "a.xml", "b.xml", "--nodes", NODES, cwd=tmp_path)
    assert plain.returncode == 1 and "ComputePathToPose" in plain.stdout.splitlines()[0].split(" (a run with ")[1], \
        plain.stdout + plain.stderr
    nav2 = run("verify", "a.xml", "b.xml", "--nodes", NODES, "--profile", "nav2", cwd=tmp_path)
    assert nav2.returncode == 1, nav2.stdout + nav2.stderr
    assert nav2.stdout.startswith("refuted after ") and " states under BT.CPP 4 semantics with the nav2 profile: the " \
        "next event differs: a tick ComputePathToPose" in nav2.stdout, nav2.stdout
    # a user's --semantics file overrides a profile entry, with a note
    (tmp_path / "mine.yaml").write_text("ComputePathToPose: SyncAction\n")
    mine = run("verify", "a.xml", "b.xml", "--nodes", NODES, "--profile", "nav2", "--semantics", "mine.yaml",
               cwd=tmp_path)
    assert mine.returncode == 0 and mine.stderr.startswith("note: mine.yaml:1:1: ComputePathToPose follows SyncAction "
                                                           "as this file says, not the nav2 profile's rule ("), \
        mine.stdout + mine.stderr


def test_an_unknown_profile_is_a_usage_error():
    r = run("verify", ROUTING, ROUTING, "--profile", "ros1")
    assert r.returncode == 2 and "argument --profile: unknown profile 'ros1'; the profiles schemalog ships: nav2" \
        in r.stderr and "Traceback" not in r.stderr, r.stderr
    r = run("verify", ROOT / "kb" / "tasks" / "mix_with_spoon.pl", "--profile", "nav2")
    assert r.returncode == 2 and "--profile applies to BT.CPP trees" in r.stderr, r.stderr


SUBTREE_WITH_DEFAULT = '''<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <SubTree ID="Sub"{call}/>
  </BehaviorTree>
  <BehaviorTree ID="Sub">
    <ScriptCondition code="v==42"/>
  </BehaviorTree>
  <TreeNodesModel>
    <SubTree ID="Sub">{ports}</SubTree>
  </TreeNodesModel>
</root>
'''


def test_verify_reads_a_subtree_models_defaults_as_the_calls_remapping(tmp_path):
    """Issue 48: two files that differ only in a SubTree model's default were "proved equal ...
    the documents' trees are identical", which BT.CPP runs SUCCESS and FAILURE; a remapping that
    spells out the default was refuted (tests/bt/test_btcpp_harness.py runs both in BT.CPP)."""
    files = {"a.xml": ("", '<input_port name="v" default="42"/>'),
             "b.xml": ("", '<input_port name="v" default="43"/>'),
             "c.xml": (' v="42"', '<input_port name="v"/>')}
    for name, (call, ports) in files.items():
        (tmp_path / name).write_text(SUBTREE_WITH_DEFAULT.format(call=call, ports=ports))
    r = run("verify", "a.xml", "b.xml", cwd=tmp_path)
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout.splitlines()[0] == ('refuted after 2 states: the next event differs: a check SubTree Sub v="42" > '
                                        'ScriptCondition code="v==42" at a.xml:6:5, b check SubTree Sub v="43" > '
                                        'ScriptCondition code="v==42" at b.xml:6:5')
    r = run("verify", "a.xml", "c.xml", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout.startswith("proved equal"), r.stdout + r.stderr


def test_a_nav2_tree_with_a_nodes_attributes_reordered_is_proved_equal(tmp_path):
    """Issue 48: all 21 attribute-order mutants of the Nav2 corpus were refuted; BT.CPP reads a
    node's ports by name (tests/bt/test_btcpp_harness.py runs this pair in BT.CPP)."""
    text = REPLANNING.read_text()
    written_so = 'goal="{goal}" path="{path}" planner_id="GridBased"'
    assert text.count(written_so) == 1
    edited = tmp_path / "reordered.xml"
    edited.write_text(text.replace(written_so, 'planner_id="GridBased" path="{path}" goal="{goal}"'))
    r = run("verify", REPLANNING, edited, "--nodes", NODES)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("proved equal: equal by parts: the documents' trees are the same to BT.CPP "
                               "(attributes by name"), r.stdout


def test_a_type_used_as_a_leaf_and_with_children_is_refused_and_nothing_is_written(tmp_path):
    """Issue 48: the shape of BT.CPP's ex03 (ManualSelector with children and as a leaf), which
    BT.CPP refuses however ManualSelector is registered, was imported, and `compress -o` wrote a
    file its own reader then refused."""
    (tmp_path / "ex03.xml").write_text(
        '<root BTCPP_format="4">\n  <BehaviorTree ID="MainTree">\n    <Sequence>\n      <Sequence>\n'
        '        <ManualSelector>\n          <Say/>\n          <Say/>\n          <ManualSelector/>\n'
        '        </ManualSelector>\n      </Sequence>\n    </Sequence>\n  </BehaviorTree>\n</root>\n')
    r = run("compress", "ex03.xml", "-o", "small.xml", cwd=tmp_path)
    assert r.returncode == 1 and not (tmp_path / "small.xml").exists()
    assert r.stderr.startswith("ex03.xml:8:11: error: <ManualSelector> has no child here and 3 children at "
                               "ex03.xml:5:9: BT.CPP registers a node type as a leaf or as a node with children"), \
        r.stderr
    assert "Traceback" not in r.stderr


def test_compress_never_writes_a_tree_its_own_reader_refuses():
    """tree_xml reads the XML back before it is written: a Document the reader would refuse (made
    by hand here: compress keeps what it read) is an error of ours, never an output."""
    from schemalog.api.behaviour_trees import tree_xml
    from schemalog.bt.model import Document, Node
    from schemalog.errors import SchemalogError

    root = Node("Sequence", (), (Node("Pick", (), (Node("A"),)), Node("Pick")))
    with pytest.raises(SchemalogError) as err:
        tree_xml(Document((("T", root),), "T"))
    # write_bt declares Pick an Action (infer_models), which its use with a child contradicts
    assert err.value.message.startswith("the tree to write would be refused when read back at line 5, column 7 "
                                        "(The node 'Pick' must not have any child"), err.value.message
    assert "nothing written" in err.value.message
    assert tree_xml(Document((("T", root.with_children(root.children[:1])),), "T")).startswith("<?xml")
