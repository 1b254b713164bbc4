"""formats/btxml.py: BT.CPP 4 XML in and out, on public trees (tests/bt/corpus) and generated ones.

Every corpus tree reads (Nav2's with nav2_tree_nodes.xml's models) and comes back equal from
write_bt; what BT.CPP refuses is refused with file:line:column.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from schemalog.bt.model import Document, Node, NodeModel, Port, size, walk
from schemalog.errors import SchemalogError
from schemalog.formats.quoting import xml_attribute
from schemalog.formats.btxml import BUILTIN, MAX_INCLUDE_DEPTH, infer_models, read_bt, read_models, write_bt

CORPUS = Path(__file__).resolve().parent / "corpus"
NAV2 = CORPUS / "nav2"
BTCPP = CORPUS / "btcpp"
V3_NAV2 = NAV2 / "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml"
# Files that are not a whole program on their own: the tree to run is named, as BT.CPP's
# createTree(name) names it, or the file is read together with its partner.
MAIN_OF = {"log_test.xml": "Main", "t15_nodes_mocking.xml": "MainTree"}
PARTS = {"t14_subtree_model_2.xml"}
# Folders whose files are one program (SubTrees called across files): read whole, as a robot
# loads the folder (tests/bt/test_folders.py), never file by file.
FOLDERS = (CORPUS / "combat" / "behavior_trees",)
# Files BT.CPP 4.8.2 refuses, and schemalog with them (tests/bt/test_btcpp_harness.py shows BT.CPP's
# refusal): a tree called by its ID as a tag, <CheckStatus/>, where BT.CPP 4 needs <SubTree>.
CORPUS_REFUSED = {BTCPP / "examples" / "test_files" / "subtree_test.xml":
           "subtree_test.xml:8:13: error: <CheckStatus> names the BehaviorTree CheckStatus"}


def _read_file(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        return f.read()


def nav2_models() -> tuple[NodeModel, ...]:
    return read_models(_read_file(str(NAV2 / "nav2_tree_nodes.xml")), "nav2_tree_nodes.xml")


def corpus_files() -> list[Path]:
    out = []
    for path in sorted(CORPUS.rglob("*.xml")):
        if path.name == "nav2_tree_nodes.xml" or path == V3_NAV2 or path.name in PARTS or path in CORPUS_REFUSED \
                or path.parent in FOLDERS:
            continue
        out.append(path)
    return out


def read_corpus(path: Path) -> Document:
    models = nav2_models() if NAV2 in path.parents else ()
    return read_bt(_read_file(str(path)), str(path), read=_read_file, models=models, main=MAIN_OF.get(path.name))


def _ids(paths):
    return [str(p.relative_to(CORPUS)) for p in paths]


# ---------------------------------------------------------------------------
# The corpus

def test_the_corpus_holds_the_navigator_trees_and_btcpp_examples():
    files = corpus_files()
    assert len([p for p in files if NAV2 in p.parents]) == 14
    assert len([p for p in files if BTCPP in p.parents]) == 16 and len(CORPUS_REFUSED) == 1
    assert (CORPUS / "SOURCES.md").is_file() and (CORPUS / "LICENSE.Apache-2.0").is_file()
    assert (CORPUS / "LICENSE.MIT").is_file()
    sources = (CORPUS / "SOURCES.md").read_text(encoding="utf-8")
    for path in CORPUS.rglob("*.xml"):
        assert str(path.relative_to(CORPUS)) in sources, path


@pytest.mark.parametrize("path", sorted(CORPUS_REFUSED), ids=_ids(sorted(CORPUS_REFUSED)))
def test_what_btcpp_refuses_is_refused_with_its_position(path):
    with pytest.raises(SchemalogError) as err:
        read_corpus(path)
    assert CORPUS_REFUSED[path] in str(err.value)


@pytest.mark.parametrize("path", corpus_files(), ids=_ids(corpus_files()))
def test_every_corpus_file_reads(path):
    document = read_corpus(path)
    assert document.tree(document.main) is not None
    assert size(document) >= 1


@pytest.mark.parametrize("path", corpus_files(), ids=_ids(corpus_files()))
def test_every_corpus_file_comes_back_from_write_bt(path):
    document = read_corpus(path)
    text = write_bt(document)
    back = read_bt(text, "written.xml")
    assert back.trees == document.trees
    assert back.main == document.main
    assert back.models == document.models + infer_models(document)
    assert read_bt(write_bt(back), "again.xml") == back          # a fixed point once the models are complete
    assert f'BTCPP_format="{document.version}"' in text and "<TreeNodesModel" in text    # 3: read under 3.8


# Counted by hand from the files.
HAND_COUNTS = {
    "nav2/follow_point.xml": 8,            # PipelineSequence RateController Sequence GoalUpdater
                                           # ComputePathToPose TruncatePath KeepRunningUntilFailure FollowPath
    "nav2/odometry_calibration.xml": 10,   # Repeat Sequence, 4 x (DriveOnHeading Spin)
    "nav2/navigate_to_pose_w_replanning_and_recovery.xml": 22,
    "nav2/navigate_w_replanning_speed.xml": 4,   # PipelineSequence SpeedController ComputePathToPose FollowPath
    "btcpp/tutorials/t09_scripting.xml": 9,      # Sequence Script Script Precondition Sequence 4 x SaySomething
    "btcpp/tests/trees/parent_include_child_include_child.xml": 7,
}


@pytest.mark.parametrize("name,count", sorted(HAND_COUNTS.items()))
def test_node_counts_checked_by_hand(name, count):
    assert size(read_corpus(CORPUS / name)) == count


def test_a_nav2_tree_keeps_types_ports_names_and_positions():
    document = read_corpus(NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml")
    root = document.root
    assert document.main == "MainTree"
    assert (root.type, root.attrs) == ("RecoveryNode", (("number_of_retries", "6"), ("name", "NavigateRecovery")))
    compute = next(n for n in walk(root) if n.type == "ComputePathToPose")
    assert compute.attrs == (("goal", "{goal}"), ("path", "{path}"), ("planner_id", "GridBased"))
    assert (compute.line, compute.column) == (13, 13)
    assert document.model("RecoveryNode").kind == "Control"
    assert document.model("FollowPath").ports[0] == Port("input", "controller_id", "FollowPath")
    assert document.model("BackUp").ports[0].description == "Distance to backup"


def test_t09_scripting_reads_its_ampersands_as_bt_cpp_does():
    """The old importer called it malformed XML: `if="A>B && color != BLUE"` is not XML, but
    tinyxml2 (BT.CPP's parser) takes a bare & in a value literally."""
    document = read_corpus(BTCPP / "tutorials" / "t09_scripting.xml")
    assert document.main == "BehaviorTree_0"                    # one tree without an ID
    pre = next(n for n in walk(document.root) if n.type == "Precondition")
    assert pre.attrs == (("if", "A>B && color != BLUE"), ("else", "FAILURE"))
    assert "&amp;&amp;" in write_bt(document)


def test_t14_subtree_model_reads_with_its_main_tree():
    """t14_subtree_model_1 (its `&&` made it "malformed XML" too) holds a SubTree model whose
    defaults cover the ports t14_subtree_model_2's SubTree leaves unremapped."""
    one = read_corpus(BTCPP / "tutorials" / "t14_subtree_model_1.xml")
    assert one.model("MySub") == NodeModel("MySub", "SubTree", (
        Port("input", "sub_in_value", "42"), Port("input", "sub_in_name"),
        Port("output", "sub_out_result", "{out_result}"), Port("output", "sub_out_state")))
    top = ('<root BTCPP_format="4" main_tree_to_execute="MainTree">\n'
           '  <include path="t14_subtree_model_1.xml"/>\n  <include path="t14_subtree_model_2.xml"/>\n</root>\n')
    both = read_bt(top, str(BTCPP / "tutorials" / "t14.xml"), read=_read_file)
    assert [k for k, _ in both.trees] == ["MySub", "MainTree"] and size(both) == 7
    sub = next(n for n in walk(both.root) if n.type == "SubTree")
    assert sub.attrs == (("ID", "MySub"), ("sub_in_name", "{in_name}"), ("sub_out_state", "{out_state}"))
    assert read_bt(write_bt(both)).trees == both.trees


def test_includes_are_read_relative_to_the_including_file():
    path = BTCPP / "tests" / "trees" / "parent_include_child_include_child.xml"
    document = read_corpus(path)
    assert [os.path.relpath(p, BTCPP / "tests" / "trees") for p in document.includes] == [
        "child/child_include_child.xml", "child/child/child_child_no_include.xml"]
    assert [k for k, _ in document.trees] == ["ChildChildNoInclude", "ChildIncludeChild", "ParentIncludeChildIncludeChild"]


def test_a_nav2_version_3_file_is_read_under_3_8_and_refused_under_4():
    assert read_corpus(V3_NAV2).version == 3            # <SequenceStar>, no BTCPP_format: a 3.8 file
    with pytest.raises(SchemalogError) as err:
        read_bt(V3_NAV2.read_text(), str(V3_NAV2), models=nav2_models(), version=4)
    assert "BT.CPP 3" in err.value.message and "SequenceStar" in err.value.message
    assert (err.value.line, err.value.column) == (21, 15)


def test_unknown_node_types_are_opaque_custom_nodes():
    document = read_bt('<root BTCPP_format="4"><BehaviorTree ID="T"><MyRobotDoesThis x="{y}">'
                       '<AndThat/><AndThat/></MyRobotDoesThis></BehaviorTree></root>')
    assert document.root == Node("MyRobotDoesThis", (("x", "{y}"),), (Node("AndThat"), Node("AndThat")))
    assert infer_models(document) == (NodeModel("MyRobotDoesThis", "Control", (Port("inout", "x"),)),
                                      NodeModel("AndThat", "Action"))


# ---------------------------------------------------------------------------
# Refusals, each where it is

def _tree(body: str, extra: str = "", root: str = '<root BTCPP_format="4">') -> str:
    return f'{root}\n  <BehaviorTree ID="T">\n    {body}\n  </BehaviorTree>{extra}\n</root>\n'


REFUSED = [
    ("wrong root", "<tree>\n</tree>", (1, 1), "<root"),
    ("version 5", '<root BTCPP_format="5">\n  <BehaviorTree ID="T"><A/></BehaviorTree>\n</root>', (1, 1),
     "--btcpp"),
    ("v3 node without format calling no tree", '<root>\n  <BehaviorTree ID="T">\n    <SubTreePlus ID="X"/>\n'
     '  </BehaviorTree>\n</root>', (3, 5), "BT.CPP 3.8: Can't find a tree"),
    ("subtree naming no tree", _tree('<Sequence>\n      <SubTree ID="Nowhere"/>\n    </Sequence>'), (4, 7),
     "names no BehaviorTree"),
    ("decorator with two children", _tree("<Inverter>\n      <A/>\n      <B/>\n    </Inverter>"), (3, 5),
     "exactly 1 child"),
    ("generic decorator without child", _tree('<Decorator ID="Retry7"/>'), (3, 5), "exactly 1 child"),
    ("builtin leaf with a child", _tree("<AlwaysSuccess>\n      <A/>\n    </AlwaysSuccess>"), (3, 5),
     "must not have any child"),
    ("generic action with a child", _tree('<Sequence><Action ID="Say">\n      <A/>\n    </Action></Sequence>'),
     (3, 15), "must not have any child"),
    ("control without children", _tree("<Sequence/>"), (3, 5), "1 or more children"),
    ("generic form without ID", _tree('<Action name="x"/>'), (3, 5), "[ID]"),
    ("ID on a custom node", _tree('<Sequence>\n      <Foo ID="x"/>\n    </Sequence>'), (4, 7), "not allowed"),
    ("tree with two nodes", _tree("<A/>\n    <B/>"), (2, 3), "exactly 1 child"),
    ("unnamed tree beside another element", '<root BTCPP_format="4">\n  <BehaviorTree><A/></BehaviorTree>\n'
     '  <TreeNodesModel/>\n</root>', (2, 3), "[ID]"),
    ("tree named after a node", '<root BTCPP_format="4">\n  <BehaviorTree ID="Sequence"><A/></BehaviorTree>\n'
     '</root>', (2, 3), "registered"),
    ("main naming no tree", _tree("<A/>", root='<root BTCPP_format="4" main_tree_to_execute="Main">'), (1, 1),
     "names no BehaviorTree"),
    ("two trees without main", '<root BTCPP_format="4">\n  <BehaviorTree ID="A"><X/></BehaviorTree>\n'
     '  <BehaviorTree ID="B"><X/></BehaviorTree>\n</root>', (1, 1), "main_tree_to_execute"),
    ("a tree defined twice", '<root BTCPP_format="4" main_tree_to_execute="A">\n  <BehaviorTree ID="A"><X/>'
     '</BehaviorTree>\n  <BehaviorTree ID="A"><X/></BehaviorTree>\n</root>', (3, 3), "defined twice"),
    ("two TreeNodesModel", _tree("<A/>", "\n  <TreeNodesModel/>\n  <TreeNodesModel/>"), (6, 3), "single"),
    ("include without path", _tree("<A/>", '\n  <include file="x.xml"/>'), (5, 3), "path"),
    ("autoremap not a boolean", '<root BTCPP_format="4" main_tree_to_execute="T">\n  <BehaviorTree ID="T">\n'
     '    <SubTree ID="S" _autoremap="yes"/>\n  </BehaviorTree>\n  <BehaviorTree ID="S"><A/></BehaviorTree>\n</root>',
     (3, 5), "boolean"),
    ("subtree model port unremapped", '<root BTCPP_format="4" main_tree_to_execute="T">\n  <BehaviorTree ID="T">\n'
     '    <SubTree ID="S" a="1"/>\n  </BehaviorTree>\n  <BehaviorTree ID="S"><A/></BehaviorTree>\n'
     '  <TreeNodesModel><SubTree ID="S"><input_port name="a"/><input_port name="b"/></SubTree></TreeNodesModel>\n'
     '</root>', (3, 5), "[b]"),
    ("subtree containing itself", '<root BTCPP_format="4" main_tree_to_execute="T">\n  <BehaviorTree ID="T">\n'
     '    <Sequence><A/><SubTree ID="T"/></Sequence>\n  </BehaviorTree>\n</root>', (3, 19), "contains itself"),
    ("a model's decorator with two children", _tree("<Gate>\n      <A/>\n      <B/>\n    </Gate>",
                                                    '\n  <TreeNodesModel><Decorator ID="Gate"/></TreeNodesModel>'),
     (3, 5), "exactly 1 child"),
    ("a BehaviorTree inside a tree", _tree("<Sequence>\n      <BehaviorTree ID='U'><A/></BehaviorTree>\n"
                                           "    </Sequence>"), (4, 7), "inside a tree"),
    ("a port a node does not declare", _tree('<Sequence foo="1">\n      <A/>\n    </Sequence>'), (3, 5),
     "providedPorts"),
    ("a literal that does not convert", _tree('<Repeat num_cycles="x3">\n      <A/>\n    </Repeat>'), (3, 5),
     "can not be converted to int"),
    ("a negative duration", _tree('<Sequence>\n      <Sleep msec="-1"/>\n    </Sequence>'), (4, 7),
     "unsigned int"),
    ("a script node without its script", _tree('<Action ID="Script"/>'), (3, 5), "Missing port [code]"),
    ("a tree called by its ID as a tag", '<root BTCPP_format="4" main_tree_to_execute="T">\n  <BehaviorTree ID="T">\n'
     '    <Sequence><A/><S/></Sequence>\n  </BehaviorTree>\n  <BehaviorTree ID="S"><A/></BehaviorTree>\n</root>',
     (3, 19), "names the BehaviorTree S"),
    ("a generic form under a ReactiveSequence", _tree('<ReactiveSequence>\n      <Action ID="A"/>\n'
                                                       '    </ReactiveSequence>'), (4, 7), "Unknown node type: Action"),
    ("two async children of a ReactiveSequence", _tree('<ReactiveSequence>\n      <AsyncSequence><A/></AsyncSequence>'
                                                        '<AsyncSequence><A/></AsyncSequence>\n    </ReactiveSequence>'),
     (3, 5), "more than one async child"),
    ("a generic form naming SubTree", _tree('<Sequence>\n      <Action ID="SubTree"/>\n    </Sequence>'), (4, 7),
     "Can't find a tree with name: SubTree"),
    ("a BT.CPP 3 spelling", '<root>\n  <BehaviorTree ID="T">\n    <RetryUntilSuccesful num_attempts="2"><A/>'
     '</RetryUntilSuccesful>\n  </BehaviorTree>\n</root>', (3, 5), "BT.CPP 3"),
    ("a generic element under root without ID beside a TreeNodesModel",
     _tree("<A/>", "\n  <TreeNodesModel/>\n  <Action/>"), (6, 3), "The attribute [ID] is mandatory"),
    ("a subtree model port no attribute can remap", '<root BTCPP_format="4" main_tree_to_execute="T">\n'
     '  <BehaviorTree ID="T">\n    <SubTree ID="S" name="x"/>\n  </BehaviorTree>\n  <BehaviorTree ID="S"><A/>'
     '</BehaviorTree>\n  <TreeNodesModel><SubTree ID="S"><input_port name="name"/></SubTree></TreeNodesModel>\n'
     '</root>', (3, 5), "[name]"),
    ("a port of a second model of a subtree unremapped", '<root BTCPP_format="4" main_tree_to_execute="T">\n'
     '  <BehaviorTree ID="T">\n    <SubTree ID="S" a="1"/>\n  </BehaviorTree>\n  <BehaviorTree ID="S"><A/>'
     '</BehaviorTree>\n  <TreeNodesModel><SubTree ID="S"><input_port name="a"/></SubTree><SubTree ID="S">'
     '<input_port name="b"/></SubTree></TreeNodesModel>\n</root>', (3, 5), "[b]"),
    # issue 48: BT.CPP's ex03 uses ManualSelector with five children and as a leaf; a type is
    # registered as one kind, so BT.CPP refuses one of the two uses, whatever it is registered as
    ("a custom type as a leaf and with children", _tree("<Sequence>\n      <Foo>\n        <A/>\n      </Foo>\n"
                                                       "      <Foo/>\n    </Sequence>"), (7, 7),
     "<Foo> has no child here and 1 child at bad.xml:4:7"),
    ("a custom type in generic forms with and without children",
     _tree('<Sequence>\n      <Action ID="Foo"/>\n      <Control ID="Foo">\n        <A/>\n      </Control>\n'
           '    </Sequence>'), (5, 7), "<Control ID='Foo'> has 1 child here and no child at bad.xml:4:7"),
    ("malformed XML", _tree('<Sequence>\n      <A x="1">\n    </Sequence>'), (5, 7), "malformed XML"),
    ("an entity", '<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY e "x">]>\n<root/>', None, "entit"),
]


@pytest.mark.parametrize("name,text,where,words", REFUSED, ids=[r[0] for r in REFUSED])
def test_what_bt_cpp_refuses_is_refused_where_it_is(name, text, where, words):
    with pytest.raises(SchemalogError) as err:
        read_bt(text, "bad.xml", read=lambda p: "<root/>")
    assert words in err.value.message
    assert err.value.file == "bad.xml"
    if where is not None:
        assert (err.value.line, err.value.column) == where


# Refused here although BT.CPP 4.x loads them (or crashes on them), each on purpose.
BEYOND_BT_CPP = {
    "version 3": "BT.CPP only warns when BTCPP_format is missing and ignores its value",
    "version 5": "BT.CPP only warns when BTCPP_format is missing and ignores its value",
    "a tree defined twice": "BT.CPP keeps the last tree of an ID silently",
    "subtree containing itself": "BT.CPP recurses until its stack overflows",
}


@pytest.mark.parametrize("name,text", [(r[0], r[1]) for r in REFUSED if r[0] not in BEYOND_BT_CPP],
                         ids=[r[0] for r in REFUSED if r[0] not in BEYOND_BT_CPP])
def test_bt_cpp_refuses_them_too(name, text):
    """BT.CPP itself (behaviortreepy), with the leaves the text uses registered, refuses each."""
    bt = pytest.importorskip("behaviortreepy")
    factory = bt.BehaviorTreeFactory()
    trees = set(re.findall(r'<BehaviorTree ID="([^"]*)"', text))
    for leaf in {"A", "B", "X", "Say", "Foo"} - trees:
        factory.register_simple_action(leaf, lambda node: bt.NodeStatus.SUCCESS)
    with pytest.raises(Exception):
        factory.create_tree_from_text(text)


def test_a_tree_named_after_a_node_of_the_nodes_file_is_refused_and_of_its_own_model_read():
    """A nodes file stands for what the program registers (BT.CPP then refuses the tree's ID); a
    document's own TreeNodesModel registers nothing in BT.CPP, which loads the document."""
    text = ('<root BTCPP_format="4">\n  <BehaviorTree ID="Say"><A/></BehaviorTree>\n'
            '  <TreeNodesModel><Action ID="Say"/></TreeNodesModel>\n</root>')
    assert read_bt(text, "own.xml").main == "Say"
    with pytest.raises(SchemalogError) as err:
        read_bt(text, "own.xml", models=(NodeModel("Say", "Action"),))
    assert "registered Node" in err.value.message and (err.value.line, err.value.column) == (2, 3)


def test_bt_cpp_checks_ports_only_in_the_trees_it_creates():
    """createNodeFromXML checks ports; a tree the main tree does not reach is never created."""
    unused = ('<root BTCPP_format="4" main_tree_to_execute="M">\n  <BehaviorTree ID="M"><AlwaysSuccess/>'
              '</BehaviorTree>\n  <BehaviorTree ID="U"><Sleep msec="x"/></BehaviorTree>\n</root>')
    assert read_bt(unused, "u.xml").main == "M"
    reached = unused.replace("<AlwaysSuccess/>", '<SubTree ID="U"/>')
    with pytest.raises(SchemalogError) as err:
        read_bt(reached, "u.xml")
    assert "can not be converted to unsigned int" in err.value.message and (err.value.line, err.value.column) == (3, 24)


# Checked by createNodeFromXML or recursivelyCreateSubtree, so only in the trees BT.CPP creates
# (found by tests/bt/test_btcpp_harness.py's generated documents: BT.CPP 4.8.2 loads each in a
# tree the main tree does not reach).
CREATED_ONLY = [
    ('<AlwaysSuccess ID="x"/>', "Attribute [ID] is not allowed in <AlwaysSuccess>"),
    ('<Sequence ID="x"><AlwaysSuccess/></Sequence>', "Attribute [ID] is not allowed in <Sequence>"),
    ('<Foo ID="Foo"/>', "Attribute [ID] is not allowed in <Foo>"),
    ('<SubTree ID="M" _autoremap="yes"/>', "not a boolean"),
    ('<Action ID="SubTree"/>', "Can't find a tree with name: SubTree"),
]


@pytest.mark.parametrize("body,words", CREATED_ONLY, ids=[w for _, w in CREATED_ONLY])
def test_bt_cpp_checks_ids_autoremap_and_subtree_forms_only_in_the_trees_it_creates(body, words):
    unused = ('<root BTCPP_format="4" main_tree_to_execute="M">\n  <BehaviorTree ID="M"><AlwaysSuccess/>'
              f'</BehaviorTree>\n  <BehaviorTree ID="U">{body}</BehaviorTree>\n</root>')
    assert read_bt(unused, "u.xml").main == "M"
    reached = unused.replace("<AlwaysSuccess/>", '<SubTree ID="U"/>', 1)
    with pytest.raises(SchemalogError) as err:
        read_bt(reached, "u.xml")
    assert words in err.value.message and (err.value.line, err.value.column) == (3, 24)


def test_a_node_types_kind_is_the_nodes_files_not_the_documents_own_model():
    """BT.CPP goes by the registered kind; a document's own TreeNodesModel registers nothing, so
    its entry of another kind changes nothing (found by the harness's generated documents)."""
    text = _tree("<Sequence>\n      <Act/>\n    </Sequence>", '\n  <TreeNodesModel><Control ID="Act"/></TreeNodesModel>')
    registered = (NodeModel("Act", "Action", (Port("input", "p"),)),)
    with pytest.raises(SchemalogError) as err:
        read_bt(text, "k.xml")                          # unregistered: the document's model says Control
    assert "1 or more children" in err.value.message and (err.value.line, err.value.column) == (4, 7)
    document = read_bt(text, "k.xml", models=registered)
    assert document.model("Act") == NodeModel("Act", "Action")
    with pytest.raises(SchemalogError) as err:
        read_bt(text.replace("<Act/>", "<Act><Act/></Act>"), "k.xml", models=registered)
    assert "must not have any child" in err.value.message


def test_a_tree_with_an_empty_id_is_named_the_empty_string_as_bt_cpp_names_it():
    """BT.CPP names a tree BehaviorTree_N only without the attribute; ID="" is the tree "", which
    main_tree_to_execute="" names (found by the harness's generated documents)."""
    text = '<root BTCPP_format="4">\n  <BehaviorTree ID="">\n    <A/>\n  </BehaviorTree>\n</root>'
    assert read_bt(text, "e.xml").main == ""
    assert read_bt(text.replace('"4"', '"4" main_tree_to_execute=""'), "e.xml").main == ""
    assert read_bt(text.replace(' ID=""', ""), "e.xml").main == "BehaviorTree_0"
    with pytest.raises(SchemalogError):     # main="" is no main asked for, as createTree("") is
        read_bt(text.replace('"4"', '"4" main_tree_to_execute="M"'), "e.xml", main="")
    with pytest.raises(SchemalogError) as err:
        read_bt(text.replace("</root>", "<TreeNodesModel/></root>"), "e.xml")
    assert "[ID]" in err.value.message


def test_subtree_model_ports_are_read_as_bt_cpp_reads_them():
    """loadSubtreeModel: name="" is a port named "" (mandatory, no attribute remaps it), the last
    port of a name wins, inout after output after input; _autoremap remaps every port. A stray
    <Foo/> or <SubTree ID=""/> under <root> is ignored (found by the harness's documents)."""
    def doc(call: str, ports: str, extra: str = "") -> str:
        return ('<root BTCPP_format="4" main_tree_to_execute="T">\n  <BehaviorTree ID="T">\n    '
                f'{call}\n  </BehaviorTree>\n  <BehaviorTree ID="S"><A/></BehaviorTree>\n  <TreeNodesModel>'
                f'<SubTree ID="S">{ports}</SubTree></TreeNodesModel>{extra}\n</root>')
    with pytest.raises(SchemalogError) as err:
        read_bt(doc('<SubTree ID="S"/>', '<input_port name=""/>'), "s.xml")
    assert "called [], but" in err.value.message
    assert read_bt(doc('<SubTree ID="S" _autoremap="1"/>', '<input_port name=""/>'), "s.xml").main == "T"
    assert read_bt(doc('<SubTree ID="S"/>', '<output_port name="b" default="1"/><input_port name="b"/>'),
                   "s.xml").main == "T"
    with pytest.raises(SchemalogError):
        read_bt(doc('<SubTree ID="S"/>', '<output_port name="b"/><input_port name="b" default="1"/>'), "s.xml")
    with pytest.raises(SchemalogError):
        read_bt(doc('<SubTree ID="S"/>', '<input_port name="b" default="1"/><inout_port name="b"/>'), "s.xml")
    assert read_bt(doc('<SubTree ID="S" b="1"/>', '<input_port name="b"/>', '<Foo/><SubTree ID=""/>'),
                   "s.xml").main == "T"


def test_autoremap_is_read_on_a_subtree_only():
    assert read_bt(_tree('<Sleep msec="1" _autoremap="maybe"/>'), "a.xml").root.attr("_autoremap") == "maybe"


def _files(files: dict[str, str]):
    def read(path: str) -> str:
        try:
            return files[path]
        except KeyError:
            raise SchemalogError(f"no such file: {path}") from None
    return read


def test_an_include_cycle_is_refused():
    files = {"a.xml": '<root BTCPP_format="4" main_tree_to_execute="A">\n  <include path="b.xml"/>\n'
                      '  <BehaviorTree ID="A"><SubTree ID="B"/></BehaviorTree>\n</root>',
             "b.xml": '<root BTCPP_format="4">\n  <BehaviorTree ID="B"><X/></BehaviorTree>\n'
                      '  <include path="./a.xml"/>\n</root>'}
    with pytest.raises(SchemalogError) as err:
        read_bt(files["a.xml"], "a.xml", read=_files(files))
    assert "recursive include: a.xml -> b.xml -> a.xml" in err.value.message
    assert (err.value.file, err.value.line, err.value.column) == ("b.xml", 3, 3)


def test_includes_deeper_than_the_limit_are_refused():
    files = {f"f{k}.xml": f'<root BTCPP_format="4">\n  <include path="f{k + 1}.xml"/>\n'
                          f'  <BehaviorTree ID="T{k}"><X/></BehaviorTree>\n</root>' for k in range(MAX_INCLUDE_DEPTH + 5)}
    with pytest.raises(SchemalogError) as err:
        read_bt(files["f0.xml"], "f0.xml", read=_files(files), main="T0")
    assert "deeper" in err.value.message


def test_an_include_without_a_reader_or_through_ros_pkg_is_refused():
    with pytest.raises(SchemalogError, match="only from files"):
        read_bt(_tree("<A/>", '\n  <include path="x.xml"/>'), "bad.xml")
    with pytest.raises(SchemalogError, match="ROS"):
        read_bt(_tree("<A/>", '\n  <include ros_pkg="nav2" path="x.xml"/>'), "bad.xml", read=_read_file)
    with pytest.raises(SchemalogError, match="no such file") as err:
        read_bt(_tree("<A/>", '\n  <include path="x.xml"/>'), "bad.xml", read=_files({}))
    assert (err.value.line, err.value.column) == (5, 3)


def test_a_separate_nodes_file_gives_kinds_and_the_document_wins():
    models = nav2_models()
    assert len(models) == 31
    assert {m.type for m in models if m.kind == "Control"} == {"PipelineSequence", "RecoveryNode", "RoundRobin"}
    own = _tree("<Spin/>", '\n  <TreeNodesModel><Action ID="Spin"><input_port name="turn"/></Action></TreeNodesModel>')
    document = read_bt(own, "own.xml", models=models)
    assert document.model("Spin").ports == (Port("input", "turn"),)
    with pytest.raises(SchemalogError, match="exactly 1 child"):      # RateController is a decorator
        read_bt(_tree("<RateController hz='1'><A/><B/></RateController>"), "x.xml", models=models)


# ---------------------------------------------------------------------------
# Round trip over generated documents

XML_CHARS = st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00\ufffe\uffff").filter(
    lambda c: c in "\t\n\r" or ord(c) >= 0x20)
AWKWARD = st.one_of(
    st.text(XML_CHARS, max_size=12),
    st.sampled_from(['"', "'", "<", "&", "&&", "&amp;", "&#10;", "]]>", "a\nb", "\r\n", "\t", "{goal}", "ü€😀",
                     '<a href="x">', "&unknown;", "-->", " lead and trail "]))
NAMES = st.from_regex(r"[a-z][a-z0-9_]{0,6}", fullmatch=True).filter(lambda n: n not in ("name",))
CUSTOM = {"Act0": "Action", "Act1": "Action", "Cond0": "Condition", "Ctrl0": "Control", "Deco0": "Decorator",
          'Say "hi" <&>\n ü': "Action"}
PLAIN_NAME = [t for t in CUSTOM if t.isidentifier()]


@st.composite
def attrs(draw, reserved=()):
    keys = draw(st.lists(NAMES, max_size=3, unique=True).map(lambda ks: [k for k in ks if k not in reserved]))
    if draw(st.booleans()):
        keys.append("name")
    return tuple((k, draw(AWKWARD)) for k in keys)


@st.composite
def builtin_attrs(draw):
    """Attributes BT.CPP's portless nodes accept: `name` and `_`-attributes (no port: bt/ports.py)."""
    keys = draw(st.lists(st.sampled_from(["name", "_description", "_uid"]), max_size=2, unique=True))
    return tuple((k, draw(AWKWARD)) for k in keys)


@st.composite
def node(draw, depth, later_trees):
    kinds = ["leaf"] + (["sequence", "inverter", "control", "decorator"] if depth < 3 else [])
    choice = draw(st.sampled_from(kinds))
    if choice == "leaf":
        options = ["custom", "builtin"] + (["subtree"] if later_trees else [])
        what = draw(st.sampled_from(options))
        if what == "subtree":
            target = draw(st.sampled_from(later_trees))
            extra = (("_autoremap", draw(st.sampled_from(["true", "false", "1"]))),) if draw(st.booleans()) else ()
            return Node("SubTree", (("ID", target), *draw(attrs(reserved=("id",))), *extra))
        if what == "builtin":
            return Node("AlwaysSuccess", draw(builtin_attrs()))
        node_type = draw(st.sampled_from(["Act0", "Act1", "Cond0", 'Say "hi" <&>\n ü']))
        form = CUSTOM[node_type] if node_type not in PLAIN_NAME or draw(st.booleans()) else ""
        return Node(node_type, draw(attrs()), (), form)
    if choice in ("inverter", "decorator"):
        child = draw(node(depth + 1, later_trees))
        if choice == "inverter":
            return Node("Inverter", draw(builtin_attrs()), (child,))
        return Node("Deco0", draw(attrs()), (child,), draw(st.sampled_from(["", "Decorator"])))
    children = tuple(draw(st.lists(node(depth + 1, later_trees), min_size=1, max_size=3)))
    if choice == "sequence":
        return Node("Sequence", draw(builtin_attrs()), children)
    return Node("Ctrl0", draw(attrs()), children, draw(st.sampled_from(["", "Control"])))


PORTS = st.builds(Port, st.sampled_from(["input", "output", "inout"]), NAMES,
                  st.one_of(st.none(), AWKWARD), st.one_of(st.just(""), st.sampled_from(["double", "std::string"])),
                  AWKWARD.map(str.strip))


@st.composite
def documents(draw):
    tree_ids = draw(st.lists(AWKWARD.filter(lambda t: t and t not in BUILTIN and t not in CUSTOM), min_size=1,
                             max_size=3, unique=True))
    trees = tuple((tree_id, draw(node(0, tree_ids[k + 1:]))) for k, tree_id in enumerate(tree_ids))
    main = tree_ids[0]
    used = {n.type for _, root in trees for n in walk(root)} & set(CUSTOM)
    models = tuple(NodeModel(t, CUSTOM[t], tuple(draw(st.lists(PORTS, max_size=3, unique_by=lambda p: p.name))))
                   for t in sorted(used) if draw(st.booleans()))
    return Document(trees, main, models)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(documents())
def test_read_bt_of_write_bt_is_the_document(document):
    back = read_bt(write_bt(document), "generated.xml")
    assert back.trees == document.trees
    assert back.main == document.main
    assert back.models == document.models + infer_models(document)
    complete = Document(document.trees, document.main, back.models)
    assert read_bt(write_bt(complete), "again.xml") == complete   # with every model declared: equal, models too


# ---------------------------------------------------------------------------
# The written documents load in BT.CPP itself (behaviortreepy; custom leaves registered as stubs)

def _portless(document: Document) -> bool:
    return not any(n.type not in BUILTIN and n.ports for _, root in document.trees for n in walk(root))


LOADABLE = [p for p in corpus_files() if BTCPP in p.parents and _portless(read_corpus(p))
            and p.name != "t14_subtree_model_1.xml"]       # its tree reads ports only its caller remaps


def _bt_cpp_tick(document: Document):
    bt = pytest.importorskip("behaviortreepy")
    factory = bt.BehaviorTreeFactory()
    for node_type in {n.type for _, root in document.trees for n in walk(root) if n.type not in BUILTIN}:
        factory.register_simple_action(node_type, lambda node: bt.NodeStatus.SUCCESS)
    tree = factory.create_tree_from_text(write_bt(document))
    status = tree.tick_once()
    while status == bt.NodeStatus.RUNNING:
        status = tree.tick_once()
    return status == bt.NodeStatus.SUCCESS


@pytest.mark.parametrize("path", LOADABLE, ids=_ids(LOADABLE))
def test_a_written_corpus_tree_loads_and_runs_in_bt_cpp(path):
    assert len(LOADABLE) >= 10
    assert _bt_cpp_tick(read_corpus(path))


def test_written_scripts_subtree_models_and_awkward_values_run_in_bt_cpp():
    """The `&&` of t14's scripts, its SubTree model's defaults and an awkward literal (a quote,
    <, &, a newline; BT.CPP's script strings are ASCII) survive write_bt as BT.CPP reads them:
    the main tree succeeds only if all of them arrive intact."""
    top = ('<root BTCPP_format="4" main_tree_to_execute="MainTree">\n'
           '  <include path="t14_subtree_model_1.xml"/>\n  <include path="t14_subtree_model_2.xml"/>\n</root>\n')
    assert _bt_cpp_tick(read_bt(top, str(BTCPP / "tutorials" / "t14.xml"), read=_read_file))
    text = _tree("<Sequence>\n      <Script code=\"s:='a&lt;&amp;&#10;&quot;b'; n:=2\"/>\n"
                 "      <Precondition if=\"n>1 && s=='a<&&#10;&quot;b'\" else=\"FAILURE\">"
                 "<AlwaysSuccess/></Precondition>\n    </Sequence>")
    awkward = read_bt(text, "awkward.xml")
    script, pre = [n for n in walk(awkward.root) if n.type in ("Script", "Precondition")]
    assert script.attr("code") == "s:='a<&\n\"b'; n:=2" and pre.attr("if") == "n>1 && s=='a<&\n\"b'"
    bt = pytest.importorskip("behaviortreepy")
    assert bt.BehaviorTreeFactory().create_tree_from_text(text).tick_once() == bt.NodeStatus.SUCCESS   # as read
    assert _bt_cpp_tick(awkward)                                                                       # as written


@settings(max_examples=500, deadline=None)
@given(st.text(st.sampled_from("a&;#xX19quotlgmp<>\n\r"), max_size=14))
def test_attribute_values_read_as_bt_cpp_reads_them(raw):
    """What read_bt makes of a raw attribute value, bare `&`s and all, is what BT.CPP makes of
    it: a Precondition compares a string with the raw value as BT.CPP reads it, a Script assigns
    that string as read_bt read it (written back with proper references)."""
    bt = pytest.importorskip("behaviortreepy")
    condition = f"s=='{raw}'"
    read = read_bt(_tree(f'<Precondition if="{condition}" else="FAILURE"><AlwaysSuccess/></Precondition>'),
                   "raw.xml").root.attr("if")
    literal = re.fullmatch(r"s=='([^'\x00-\x09\x0b-\x1f]*)'", read)
    if literal is None or not read.isascii():
        return                                  # not one string literal of BT.CPP's script language
    check = _tree(f"<Sequence><Script code={xml_attribute('s:=' + repr_script(literal.group(1)))}/>"
                  f'<Precondition if="{condition}" else="FAILURE"><AlwaysSuccess/></Precondition></Sequence>')
    assert bt.BehaviorTreeFactory().create_tree_from_text(check).tick_once() == bt.NodeStatus.SUCCESS, (raw, read)


def repr_script(text: str) -> str:
    """Quote `text` as a string literal of BT.CPP's script language."""
    return "'" + text + "'"


def test_a_type_used_as_a_leaf_in_an_included_file_and_with_children_here_is_refused():
    """BT.CPP verifies every file against one registration, so the two uses may be in two files."""
    main = ('<root BTCPP_format="4" main_tree_to_execute="T">\n  <include path="inc.xml"/>\n'
            '  <BehaviorTree ID="T">\n    <Pick>\n      <A/>\n    </Pick>\n  </BehaviorTree>\n</root>\n')
    included = '<root BTCPP_format="4">\n  <BehaviorTree ID="U">\n    <Pick/>\n  </BehaviorTree>\n</root>\n'
    with pytest.raises(SchemalogError) as err:
        read_bt(main, "main.xml", read=lambda p: included)
    assert (err.value.file, err.value.line, err.value.column) == ("main.xml", 4, 5)
    assert err.value.message.startswith("<Pick> has 1 child here and no child at inc.xml:3:5: BT.CPP registers")


@pytest.mark.parametrize("target", ["fifo.xml", "/dev/zero", "."])
def test_an_include_of_a_fifo_a_device_or_a_folder_is_refused_without_opening_it(tmp_path, target):
    """A FIFO would block the reader for a writer that never comes; /dev/zero never ends."""
    os.mkfifo(tmp_path / "fifo.xml")
    tree = tmp_path / "t.xml"
    tree.write_text(_tree("<A/>", f'\n  <include path="{target}"/>'))
    with pytest.raises(SchemalogError) as err:
        read_bt(tree.read_text(), str(tree), read=_read_file)
    assert "not a file" in err.value.message
    assert (err.value.line, err.value.column) == (5, 3)
