"""Several BT.CPP files, or a folder of them, read as one program (api/behaviour_trees.read_tree,
formats/btxml.read_bt's (text, file) pairs), as BT.CPP's registerBehaviorTreeFromFile reads file
after file into one factory and as Nav2 (bt_search_directories) and BehaviorTree.ROS2
(behavior_trees) load a folder: a real robot's folder whose trees call SubTrees across files,
BT.CPP's own partner files, and every way a folder can be wrong."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from schemalog.api.behaviour_trees import compress_tree, prove_trees, read_tree, tree_xml
from schemalog.bt.model import Node, size, walk
from schemalog.errors import SchemalogError
from schemalog.formats.btxml import read_bt, write_bt

CORPUS = Path(__file__).resolve().parent / "corpus"
COMBAT = CORPUS / "combat" / "behavior_trees"
MAIN = "rmuc_2026"                  # the tree its client runs (params/sentry_behavior.yaml: target_tree)
T14 = [CORPUS / "btcpp" / "tutorials" / "t14_subtree_model_1.xml", CORPUS / "btcpp" / "tutorials" / "t14_subtree_model_2.xml"]


def tree(tree_id: str, body: str, main: str | None = None, extra: str = "") -> str:
    """A BT.CPP 4 document of one tree."""
    head = f' main_tree_to_execute="{main}"' if main else ""
    return f'<root BTCPP_format="4"{head}>\n{extra}  <BehaviorTree ID="{tree_id}">\n    {body}\n  </BehaviorTree>\n</root>\n'


def folder(path: Path, files: dict[str, str]) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (path / name).write_text(text, encoding="utf-8")
    return path


def message(err) -> str:
    return str(err.value)


# ---------------------------------------------------------------------------
# A real folder: a RoboMaster sentry's 11 files, SubTrees called across them

def test_a_sentry_robots_folder_reads_as_one_program():
    document = read_tree(COMBAT, main=MAIN)
    assert len(document.trees) == 65 and size(document) == 596 and document.main == MAIN
    assert len({Path(root.file).name for _, root in document.trees}) == 11
    # every file is listed as read, in name order (a folder's files), for -o's check
    assert [Path(f).name for f in document.includes] == sorted(p.name for p in COMBAT.glob("*.xml"))
    # the main tree's file alone cannot be read: its SubTrees are defined in sibling files
    with pytest.raises(SchemalogError) as err:
        read_tree(COMBAT / "rmuc_2026.xml", main=MAIN)
    assert "rmuc_2026.xml:" in message(err) and "names no BehaviorTree" in message(err)
    # the SubTree calls across files resolve: the main tree reaches trees of seven other files
    trees = dict(document.trees)
    reached, todo = set(), [MAIN]
    while todo:
        t = todo.pop()
        if t not in reached:
            reached.add(t)
            todo += [n.attr("ID") for n in walk(trees[t]) if n.type == "SubTree" and not n.form]
    assert len({Path(trees[t].file).name for t in reached}) == 8


def test_a_folder_without_main_tree_to_execute_asks_for_the_tree_to_run():
    with pytest.raises(SchemalogError) as err:
        read_tree(COMBAT)
    said = message(err)
    assert "no file read names main_tree_to_execute" in said and "define 65 BehaviorTrees" in said
    assert "intra_team_match" in said and "--task" in said         # the candidates: trees no SubTree calls
    assert f", {MAIN}," not in said                                 # test.xml calls rmuc_2026: no candidate


def test_the_sentry_folder_compresses_and_proves_and_an_edit_is_refuted():
    document = read_tree(COMBAT, main=MAIN)
    result = compress_tree(document)
    assert result.rewrites and result.verdict.equal and result.verdict.complete
    assert result.nodes_after == result.nodes_before - len(result.rewrites)
    # the compressed program, written as one document, reads back as the same program
    back = read_bt(tree_xml(result.compressed), "small.xml")
    assert back.main == MAIN and [k for k, _ in back.trees] == [k for k, _ in document.trees]
    assert prove_trees(document, back).equal
    # an edit in a tree of another file than the main tree's: refuted
    trees = dict(document.trees)
    target = "rmuc_2026_recover_under_highland"
    assert Path(trees[target].file).name == "rmuc_2026_recovery.xml"
    edited = document.with_trees(tuple((k, Node("Inverter", (), (r,)) if k == target else r)
                                       for k, r in document.trees))
    verdict = prove_trees(document, edited)
    assert not verdict.equal and verdict.counterexample is not None


# ---------------------------------------------------------------------------
# BT.CPP's partner files t14_subtree_model_1/2: a SubTree model's defaults from the other file

@pytest.mark.parametrize("order", [T14, T14[::-1]], ids=["model-first", "model-last"])
def test_t14s_partner_files_read_as_one_program_in_either_order(order):
    document = read_tree(order, main="MainTree")
    assert sorted(k for k, _ in document.trees) == ["MainTree", "MySub"] and size(document) == 7
    # MySub's model (in t14_subtree_model_1.xml) gives the ports MainTree's call leaves unremapped
    assert document.subtree_model("MySub").ports[0].default == "42"
    # without the partner the call is refused
    with pytest.raises(SchemalogError) as err:
        read_tree(T14[1], main="MainTree")
    assert "t14_subtree_model_2.xml:7:7: error: <SubTree ID=\"MySub\"> names no BehaviorTree" in message(err) and "MySub" in message(err)


def test_t14s_files_in_a_folder_read_as_the_two_paths(tmp_path):
    for f in T14:
        shutil.copy(f, tmp_path / f.name)
    assert read_tree(tmp_path, main="MainTree").trees == read_tree(T14, main="MainTree").trees
    # neither names main_tree_to_execute and there are two trees: the folder asks for --task
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert "the trees no <SubTree> calls: MainTree: name the one to run with --task" in message(err)


# ---------------------------------------------------------------------------
# What BT.CPP does with several files, followed

def test_read_bt_reads_texts_as_one_program_with_every_check_across_them():
    main, sub = tree("Main", '<SubTree ID="Sub"/>', main="Main"), tree("Sub", "<AlwaysSuccess/>")
    document = read_bt([(main, "main.xml"), (sub, "sub.xml")])
    assert document.main == "Main" and [k for k, _ in document.trees] == ["Main", "Sub"]
    # texts no file holds are never taken for one another, whatever their names
    with pytest.raises(SchemalogError) as err:
        read_bt([(sub, "<xml>"), (sub, "<xml>")], main="Sub")
    assert "BehaviorTree Sub is defined twice" in message(err)
    # a node type used as a leaf in one file and with children in another: BT.CPP refuses one use
    with pytest.raises(SchemalogError) as err:
        read_bt([(tree("Main", '<Sequence><Go/><SubTree ID="Sub"/></Sequence>', main="Main"), "main.xml"),
                 (tree("Sub", "<Go><AlwaysSuccess/></Go>"), "sub.xml")])
    assert message(err).startswith("sub.xml:3:5: error: <Go> has 1 child here and no child at main.xml:3:15")


def test_a_models_only_file_gives_its_subtree_defaults_to_the_program(tmp_path):
    main = tree("Main", '<SubTree ID="Sub"/>', main="Main")
    sub = tree("Sub", '<Script code="x := goal"/>')
    models = ('<root BTCPP_format="4">\n  <TreeNodesModel>\n    <SubTree ID="Sub">\n'
              '      <input_port name="goal" default="7"/>\n    </SubTree>\n  </TreeNodesModel>\n</root>\n')
    folder(tmp_path / "with", {"main.xml": main, "sub.xml": sub, "models.xml": models.replace("default", "DEFAULT")})
    with pytest.raises(SchemalogError) as err:       # a mandatory port the call does not remap
        read_tree(tmp_path / "with")
    assert "main.xml:3:5: error: " in message(err) and "mandatory port called [goal]" in message(err)
    folder(tmp_path / "with", {"models.xml": models})
    document = read_tree(tmp_path / "with")
    assert document.main == "Main" and document.subtree_model("Sub").ports[0].default == "7"


def test_a_tree_defined_in_two_files_is_refused_with_both_places(tmp_path):
    folder(tmp_path, {"a.xml": tree("Main", '<SubTree ID="Sub"/>', main="Main"),
                      "b.xml": tree("Sub", "<AlwaysSuccess/>"), "c.xml": tree("Sub", "<AlwaysFailure/>")})
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert message(err).startswith(f"{tmp_path / 'c.xml'}:2:3: error: BehaviorTree Sub is defined twice "
                                   f"(first at {tmp_path / 'b.xml'}:2:3)")


def test_a_file_a_sibling_includes_is_read_once(tmp_path):
    """BT.CPP loads it twice (the folder's, then the include's) and registers the same trees
    anew; read once, it is the same program, not a tree defined twice."""
    folder(tmp_path, {"a_main.xml": tree("Main", '<SubTree ID="Sub"/>', main="Main", extra='  <include path="z_sub.xml"/>\n'),
                      "z_sub.xml": tree("Sub", "<AlwaysSuccess/>")})
    document = read_tree(tmp_path)
    assert [k for k, _ in document.trees] == ["Sub", "Main"]
    assert [Path(f).name for f in document.includes] == ["a_main.xml", "z_sub.xml"]
    # the same file named twice, or as a file and in its folder, is read once too
    assert read_tree([tmp_path / "z_sub.xml", tmp_path, tmp_path / "z_sub.xml"], main="Main").trees == document.trees


def test_a_diamond_of_includes_reads_each_file_once(tmp_path):
    folder(tmp_path, {"top.xml": tree("Main", '<Sequence><SubTree ID="L"/><SubTree ID="R"/></Sequence>', main="Main",
                                      extra='  <include path="l.xml"/>\n  <include path="r.xml"/>\n'),
                      "l.xml": tree("L", '<SubTree ID="Base"/>', extra='  <include path="base.xml"/>\n'),
                      "r.xml": tree("R", '<SubTree ID="Base"/>', extra='  <include path="base.xml"/>\n'),
                      "base.xml": tree("Base", "<AlwaysSuccess/>")})
    document = read_tree(tmp_path / "top.xml")
    assert sorted(k for k, _ in document.trees) == ["Base", "L", "Main", "R"]


def test_the_main_tree_is_the_first_files_and_a_folders_agreed_one(tmp_path):
    a, b = tree("A", '<SubTree ID="B"/>', main="A"), tree("B", "<AlwaysSuccess/>", main="B")
    folder(tmp_path, {"a.xml": a, "b.xml": b})
    # several files: the first one named is the main file (BT.CPP: the first document opened)
    assert read_tree([tmp_path / "b.xml", tmp_path / "a.xml"]).main == "B"
    assert read_tree([tmp_path / "a.xml", tmp_path / "b.xml"]).main == "A"
    # a folder and a file: the file named is the main file, wherever it stands
    other = folder(tmp_path / "sub", {"c.xml": tree("C", '<SubTree ID="A"/>', main="C")})
    assert read_tree([tmp_path, other / "c.xml"]).main == "C"
    # a folder alone: two different main_tree_to_execute are refused, both places named
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert (f"{tmp_path / 'a.xml'}:1:1: main_tree_to_execute=\"A\"; {tmp_path / 'b.xml'}:1:1: "
            f"main_tree_to_execute=\"B\"") in message(err) and "--task" in message(err)
    assert read_tree(tmp_path, main="B").main == "B"
    # ... and the one they agree on is taken
    folder(tmp_path, {"b.xml": tree("B", "<AlwaysSuccess/>", main="A")})
    assert read_tree(tmp_path).main == "A"
    # the subfolder was not read (folders are read as Nav2 and BehaviorTree.ROS2 read them: flat)
    assert "C" not in dict(read_tree(tmp_path).trees)


def test_a_folder_member_that_is_no_btcpp_document_is_refused_with_its_place(tmp_path):
    folder(tmp_path, {"a.xml": tree("A", "<AlwaysSuccess/>"), "package.xml": "<package format=\"3\">\n</package>\n"})
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert message(err).startswith(f"{tmp_path / 'package.xml'}:1:1: error: a BT.CPP document starts with <root")


@pytest.mark.parametrize("case", ["empty", "no xml", "models only", "missing"])
def test_a_folder_with_no_tree_is_refused(tmp_path, case):
    files = {"empty": {}, "no xml": {"notes.txt": "x", "Tree.XML": tree("A", "<AlwaysSuccess/>")},
             "models only": {"m.xml": '<root BTCPP_format="4"><TreeNodesModel/></root>',
                             "n.xml": '<root BTCPP_format="4"/>'}, "missing": None}[case]
    target = tmp_path / "trees"
    if files is not None:
        folder(target, files)
    with pytest.raises(SchemalogError) as err:
        read_tree(target)
    expected = {"empty": "no *.xml file in this folder", "no xml": "no *.xml file in this folder",
                "models only": "the 2 files read", "missing": "no such file"}[case]
    assert expected in message(err)


def test_links_are_followed_to_files_and_never_into_folders(tmp_path):
    real = folder(tmp_path / "share", {"sub.xml": tree("Sub", "<AlwaysSuccess/>")})
    trees = folder(tmp_path / "trees", {"main.xml": tree("Main", '<SubTree ID="Sub"/>', main="Main")})
    os.symlink(real / "sub.xml", trees / "sub.xml")             # colcon --symlink-install's way
    os.symlink(tmp_path, trees / "up")                           # a cycle: a link to a parent folder
    document = read_tree(trees)
    assert sorted(k for k, _ in document.trees) == ["Main", "Sub"]
    os.symlink(tmp_path, trees / "loop.xml")                     # a link to a folder, named *.xml
    with pytest.raises(SchemalogError) as err:
        read_tree(trees)
    assert message(err).startswith(f"error: {trees / 'loop.xml'}: a directory named *.xml in the folder {trees}")


def test_a_fifo_in_a_folder_is_refused_unopened(tmp_path):
    folder(tmp_path, {"main.xml": tree("Main", "<AlwaysSuccess/>")})
    os.mkfifo(tmp_path / "pipe.xml")            # opened, the read would wait for a writer for ever
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert message(err).startswith(f"error: {tmp_path / 'pipe.xml'}: a FIFO named *.xml in the folder")


def test_a_folder_that_cannot_be_listed_is_one_message(tmp_path, monkeypatch):
    folder(tmp_path, {"main.xml": tree("Main", "<AlwaysSuccess/>")})

    def refused(path):
        raise PermissionError(13, "Permission denied", str(path))
    monkeypatch.setattr(os, "listdir", refused)      # as root, chmod 000 does not keep a reader out
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert message(err) == f"error: {tmp_path}: cannot read the folder: Permission denied"


# ---------------------------------------------------------------------------
# Any program split across files reads as the program

@st.composite
def programs(draw):
    """Trees T0..Tn, each calling later ones (no cycle), and a split of them into files."""
    n = draw(st.integers(2, 6))
    bodies = []
    for i in range(n):
        calls = draw(st.lists(st.integers(i + 1, n - 1), max_size=2)) if i < n - 1 else []
        leaves = [f'<SubTree ID="T{c}"/>' for c in calls] + [draw(st.sampled_from(
            ["<AlwaysSuccess/>", "<AlwaysFailure/>", '<Action ID="Go" to="{goal}"/>', "<Condition ID=\"Ok\"/>"]))]
        kind = draw(st.sampled_from(["Sequence", "Fallback", "ReactiveFallback"]))
        bodies.append(f"<{kind}>{''.join(leaves)}</{kind}>")
    files = draw(st.lists(st.integers(0, n - 1), min_size=n, max_size=n))    # the file of each tree
    return bodies, files


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(programs())
def test_a_program_split_across_files_reads_as_the_program_in_one(tmp_path_factory, program):
    bodies, split = program
    whole = "".join(f'  <BehaviorTree ID="T{i}">{b}</BehaviorTree>\n' for i, b in enumerate(bodies))
    one = read_bt(f'<root BTCPP_format="4" main_tree_to_execute="T0">\n{whole}</root>\n', "one.xml")
    where = tmp_path_factory.mktemp("split")
    for f in sorted(set(split)):
        inside = "".join(f'  <BehaviorTree ID="T{i}">{b}</BehaviorTree>\n' for i, b in enumerate(bodies) if split[i] == f)
        (where / f"part{f}.xml").write_text(f'<root BTCPP_format="4">\n{inside}</root>\n')
    parts = read_tree(where, main="T0")
    assert dict(parts.trees) == dict(one.trees) and parts.main == one.main
    # written back as one document, it reads as the same program again
    assert dict(read_bt(write_bt(parts), "again.xml").trees) == dict(one.trees)


# ---------------------------------------------------------------------------
# BT.CPP 4.8.2 loads the folder as one program, and runs it as compress -o's one document

from test_btcpp_harness import SEEDS, completed_models, load, models_xml, run  # noqa: E402


def test_btcpp_loads_the_sentry_folder_as_one_program_and_only_whole(harness, tmp_path):  # noqa: F811
    document = read_tree(COMBAT, main=MAIN)
    supplement = tmp_path / "models.xml"        # the robot's node types, as its plugins register them
    supplement.write_text(models_xml(completed_models(document)))
    files = sorted(COMBAT.glob("*.xml"))
    ok, said = load(harness, files, [supplement], MAIN)
    assert ok and said == MAIN, said
    # without the file that defines the recovery trees, BT.CPP refuses as schemalog does
    partial = [f for f in files if f.name != "rmuc_2026_recovery.xml"]
    ok, said = load(harness, partial, [supplement], MAIN)
    with pytest.raises(SchemalogError) as err:
        read_tree(partial, main=MAIN)
    assert not ok and "Can't find a tree with name: rmuc_2026_recover_" in said
    assert "Can't find a tree with name: rmuc_2026_recover_" in message(err)
    # and without the tree to run: no file names main_tree_to_execute, as schemalog says
    ok, said = load(harness, files, [supplement])
    assert not ok and "[main_tree_to_execute] was not specified correctly" in said


@pytest.mark.parametrize("stateful", [False, True], ids=["actions", "stateful-actions"])
def test_the_compressed_sentry_program_runs_in_btcpp_as_its_folder(harness, stateful, tmp_path):  # noqa: F811
    """compress -o writes one document holding every tree: BT.CPP runs it as it runs the folder."""
    from test_btcpp_harness import stateful_rules
    from schemalog.bt.model import Document

    read = read_tree(COMBAT, main=MAIN)
    document = Document(read.trees, read.main, completed_models(read), read.includes)
    small = compress_tree(document, rules=stateful_rules(document, stateful))
    assert small.rewrites and small.verdict.equal and small.verdict.complete
    supplement = tmp_path / "models.xml"
    supplement.write_text(models_xml(document.models))
    one = tmp_path / "small.xml"
    one.write_text(tree_xml(small.compressed))
    runs_a = run(harness, sorted(COMBAT.glob("*.xml")), [supplement], tmp_path, stateful=stateful, main=MAIN)
    runs_b = run(harness, one, [supplement], tmp_path, stateful=stateful)      # its main_tree_to_execute
    assert len(runs_a) == SEEDS
    assert sum(e["ev"] == "tick" for events in runs_a.values() for e in events) > SEEDS
    for seed, events in runs_a.items():
        assert runs_b[seed] == events, f"seed {seed}: the compressed program differs in BT.CPP"


def test_btcpp_loads_a_file_twice_and_a_tree_twice_where_schemalog_reads_once_and_refuses(harness, tmp_path):  # noqa: F811
    """What the docs say of BT.CPP: a file a folder holds and a sibling includes is loaded twice,
    without complaint (schemalog reads it once: the same program); a tree defined in two files is
    kept as read last (schemalog refuses it: which runs would hang on the order)."""
    folder(tmp_path, {"a_main.xml": tree("Main", '<SubTree ID="Sub"/>', main="Main", extra='  <include path="z_sub.xml"/>\n'),
                      "z_sub.xml": tree("Sub", "<AlwaysSuccess/>")})
    files = sorted(tmp_path.glob("*.xml"))
    ok, said = load(harness, files, [])
    assert ok and said == "Main" and read_tree(tmp_path).main == "Main"
    folder(tmp_path, {"y_sub.xml": tree("Sub", "<AlwaysFailure/>")})
    ok, said = load(harness, sorted(tmp_path.glob("*.xml")), [])
    assert ok and said == "Main"
    with pytest.raises(SchemalogError) as err:
        read_tree(tmp_path)
    assert "BehaviorTree Sub is defined twice" in message(err)
