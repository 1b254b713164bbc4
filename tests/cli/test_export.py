"""End to end: `schemalog export` and `schemalog convert tree.xml` as a user runs them."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import COFFEE, MIX, ROOT

FIXTURES = Path(__file__).parents[1] / "formats" / "btcpp"


def run(*args):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=120)


@pytest.mark.parametrize("compressed", [False, True])
def test_export_then_convert_back_gives_the_same_tree(tmp_path, compressed):
    xml, back, reference = tmp_path / "tree.xml", tmp_path / "back.pl", tmp_path / "reference.pl"
    flag = ["--compressed"] if compressed else []
    r = run("export", COFFEE, "--task", "prepareboth", *flag, "--initial", "-o", xml)
    assert r.returncode == 0, r.stderr
    assert xml.read_text().count('<root BTCPP_format="4"') == 1
    assert run("convert", xml, "-o", back).returncode == 0
    if compressed:
        assert run("compress", COFFEE, "--task", "prepareboth", "-o", reference).returncode == 0
    else:
        assert run("show", COFFEE, "--task", "prepareboth", "--format", "pl", "-o", reference).returncode == 0
    shown = [json.loads(run("show", f, "--json").stdout) for f in (back, reference)]
    assert shown[0] == shown[1]
    assert shown[0]["nodes"] == (33 if compressed else 63)
    assert "initial(kukahand.free)." in back.read_text()


def test_the_state_comes_from_the_robot_unless_asked(tmp_path):
    """By default no fact is written into the tree: the robot writes the entries the second
    comment lists before the first tick; --initial and --state write one for the first tick."""
    plain = run("export", MIX, "--to", "btcpp").stdout
    script = next(line for line in plain.splitlines() if 'name="initial state"' in line)
    assert "hand__free" not in script and "acted := false" in script
    assert "the robot writes these boolean blackboard entries" in plain and "hand__free = hand.free" in plain
    asked = run("export", MIX, "--to", "btcpp", "--initial").stdout
    assert "hand__free := true" in asked and "spoon__taken := false" in asked
    other = run("export", MIX, "--to", "btcpp", "--state", "spoon.taken").stdout
    assert "spoon__taken := true" in other and "hand__free := false" in other
    both = run("export", MIX, "--to", "btcpp", "--state", "hand.free", "--initial")
    assert both.returncode == 2 and "not allowed with" in both.stderr
    back = tmp_path / "back.pl"
    (tmp_path / "t.xml").write_text(plain)
    assert run("convert", tmp_path / "t.xml", "-o", back).returncode == 0
    assert "initial(" not in back.read_text()


def test_export_to_py_trees_writes_a_module_that_runs(tmp_path):
    out = tmp_path / "tree.py"
    r = run("export", MIX, "--compressed", "-o", out)          # the suffix picks py_trees
    assert r.returncode == 0, r.stderr
    shown = subprocess.run([sys.executable, str(out)], capture_output=True, text=True, timeout=60)
    assert shown.returncode == 0 and "a1_a2(spoon)" in shown.stdout
    assert "import py_trees" in run("export", MIX, "--to", "py_trees").stdout


def test_export_needs_a_runtime():
    r = run("export", MIX)
    assert r.returncode == 2 and "--to btcpp or --to py_trees" in r.stderr


def test_imported_user_tree_compresses():
    converted = run("convert", FIXTURES / "long_sequence.xml")
    assert converted.returncode == 0, converted.stderr
    r = subprocess.run([sys.executable, "-m", "schemalog", "compress", "/dev/stdin", "--json"],
                       input=converted.stdout, capture_output=True, text=True, cwd=ROOT, timeout=120)
    data = json.loads(r.stdout)
    assert (data["nodes_before"], data["nodes_after"]) == (17, 9)


@pytest.mark.parametrize("name, where", [("refused_fallback.xml", ":5:7: error: <Fallback>"),
                                         ("refused_billion_laughs.xml", ":3:16: error: the XML declares the entity lol"),
                                         ("refused_malformed.xml", ":6:7: error: malformed XML")])
def test_bad_xml_is_one_message_exit_1_and_nothing_written(tmp_path, name, where):
    out = tmp_path / "task.pl"
    r = run("convert", FIXTURES / name, "-o", out)
    assert r.returncode == 1 and not out.exists()
    lines = r.stderr.strip("\n").splitlines()
    assert where in lines[0] and "Traceback" not in r.stderr
    # one message; a syntax error also shows its line, and a caret under the spot
    assert len(lines) == 1 or ("malformed XML" in lines[0] and len(lines) == 3 and lines[2].strip() == "^")


@pytest.mark.parametrize("command", ["convert", "check --no-lint", "show --json", "lint", "compress --json"])
def test_an_xml_tree_without_the_suffix_is_read_as_xml(tmp_path, command):
    """Told by its content (a first `<`), as every command that reads a BT.CPP tree tells it: the
    same as the file named .xml (it was read as Prolog: `unexpected character '<'`)."""
    named, plain = tmp_path / "long_sequence.xml", tmp_path / "long_sequence"
    for tree in (named, plain):
        tree.write_text((FIXTURES / "long_sequence.xml").read_text())       # <?xml ...?> first
    expected, r = run(*command.split(), named), run(*command.split(), plain)
    assert "unexpected" not in r.stderr and r.returncode == expected.returncode, r.stderr
    assert r.stdout == expected.stdout.replace(str(named), str(plain))
    assert "approach_object" in r.stdout or "17" in r.stdout or command == "lint"


def test_a_prolog_file_is_not_taken_for_xml(tmp_path):
    task = tmp_path / "task"
    task.write_text("% <not xml>\n" + MIX.read_text())
    r = run("check", task)
    assert r.returncode == 0 and "use(spoon) (12 behaviours, depth 3)" in r.stdout, r.stderr


def test_includes_are_followed_from_the_file(tmp_path):
    out = tmp_path / "tea.pl"
    r = run("convert", FIXTURES / "subtrees_main.xml", "-o", out)
    assert r.returncode == 0, r.stderr
    assert "approach_object(kettle)" in out.read_text()


def test_a_hundred_thousand_node_file_is_refused_and_nothing_written(tmp_path):
    big, out = tmp_path / "big.xml", tmp_path / "big.pl"
    big.write_text('<root BTCPP_format="4">\n<BehaviorTree ID="M">\n<Sequence>\n' + "<Wave/>\n" * 100_000 +
                   "</Sequence>\n</BehaviorTree>\n</root>\n")
    r = run("convert", big, "-o", out)
    assert r.returncode == 1 and not out.exists() and "Traceback" not in r.stderr
    assert f"{big}:50001:1: error: the XML has more than 50,000 elements" in r.stderr


def test_the_written_xml_runs_in_bt_cpp(tmp_path):
    from schemalog.formats.btcpp import run_btcpp
    from schemalog.formats.documents import read_document
    from schemalog.run.execute import replay
    from schemalog.run.world import World, initial_state
    from schemalog.task.tree import instantiate
    from schemalog.logic.parse import parse_term

    xml = tmp_path / "tree.xml"
    assert run("export", MIX, "--compressed", "--to", "btcpp", "-o", xml).returncode == 0
    kb = read_document(MIX).to_kb()
    original = instantiate(kb, parse_term("use(spoon)"))
    initial = World(original, initial_state(kb)).atoms
    outcome = run_btcpp(xml.read_text(), original, initial)
    assert outcome.status == "completed" and replay(original, initial, outcome.trace).valid


@pytest.mark.parametrize("to, suffix", [("btcpp", "xml"), ("py_trees", "py")])
def test_a_failed_action_is_retried_then_stuck_as_run_does(tmp_path, to, suffix):
    """`run --fail 'a5(cup)' --fail-times N`: retried and completed for N <= --retries, stuck
    after --retries + 1 failures; the exported compressed tree does the same in its runtime."""
    from schemalog.formats.btcpp import run_btcpp
    from schemalog.formats.documents import read_document
    from schemalog.formats.pytrees import run_pytrees
    from schemalog.logic.parse import parse_term
    from schemalog.run.world import World, initial_state
    from schemalog.task.tree import instantiate

    kb = read_document(MIX).to_kb()
    original = instantiate(kb, parse_term("use(spoon)"))
    initial = World(original, initial_state(kb)).atoms
    runner = run_btcpp if to == "btcpp" else run_pytrees
    for retries, times in ((2, 2), (2, 3), (0, 1), (4, 4)):
        out = tmp_path / f"tree{retries}.{suffix}"
        assert run("export", MIX, "--compressed", "--retries", retries, "-o", out).returncode == 0
        ran = run("run", MIX, "--compressed", "--fail", "a5(cup)", "--fail-times", times,
                  "--retries", retries, "--json")
        expected = json.loads(ran.stdout)
        got = runner(out.read_text(), original, initial, failures={parse_term("a5(cup)"): times})
        assert (got.status == "completed") == expected["completed"] == (times <= retries)
        assert ran.returncode == (0 if times <= retries else 1)
        assert list(map(str, got.trace)) == expected["trace"]
        assert got.failed == [parse_term("a5(cup)")] * min(times, retries + 1)
        assert "a6(cup)" in expected["trace"] if times <= retries else "a6(cup)" not in list(map(str, got.trace))


# Issue 32: names that reach the exported files, and files that must not be written over.

INJECTED_TASK = 'a""" if __import__("os").system("touch PWNED") else """b'
TINY = "task({t}).\nschema({t}, [(x1, true), (x2, x1.done)], {t}.done).\nschema(x1, [], x1.done).\nschema(x2, [], x2.done).\n"


def quoted(name: str) -> str:
    from schemalog.logic.terms import Atom, term_to_text
    return term_to_text(Atom(name))


@pytest.mark.parametrize("task, file_name", [
    (INJECTED_TASK, "k.pl"),
    ("t", 'a"""+__import__("os").system("touch PWNED2")+""".pl'),
    ('x"""\n\\', 'b"""\n\\.pl'),
], ids=["task name", "file name", "quotes, newline, backslash"])
def test_a_py_trees_export_runs_no_code_a_name_brings(tmp_path, task, file_name):
    work = tmp_path / "work"
    work.mkdir()
    (work / file_name).write_text(TINY.format(t=quoted(task)))
    r = subprocess.run([sys.executable, "-m", "schemalog", "export", file_name, "--to", "py_trees", "-o", "out.py"],
                       cwd=work, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    imported = subprocess.run([sys.executable, "-c", "import runpy; runpy.run_path('out.py')"], cwd=work,
                              capture_output=True, text=True, timeout=120)
    assert imported.returncode == 0, imported.stderr
    ran = subprocess.run([sys.executable, "out.py"], cwd=work, capture_output=True, text=True, timeout=120)
    assert ran.returncode == 0, ran.stderr
    assert sorted(p.name for p in work.iterdir()) == sorted(["out.py", file_name])   # no PWNED
    assert ran.stdout.startswith(f"[-] {quoted(task)}\n")                          # it printed its tree


@pytest.mark.parametrize("task, file_name", [("---", "k.pl"), ("t", "x --- y.pl"), ("a\x01b", "k\x01.pl"),
                                             ("t", "k-.pl")],
                         ids=["task ---", "file ---", "control characters", "file ending in -"])
def test_an_exported_document_is_well_formed_whatever_the_names(tmp_path, task, file_name):
    import xml.dom.minidom

    (tmp_path / file_name).write_text(TINY.format(t=quoted(task)))
    r = subprocess.run([sys.executable, "-m", "schemalog", "export", file_name, "-o", "tree.xml"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    xml.dom.minidom.parse(str(tmp_path / "tree.xml"))
    back = run("convert", tmp_path / "tree.xml", "-o", tmp_path / "back.pl")
    assert back.returncode == 0, back.stderr
    shown = [json.loads(run("show", f, "--json").stdout) for f in (tmp_path / file_name, tmp_path / "back.pl")]
    assert shown[0]["task"] == shown[1]["task"] == quoted(task)
    assert shown[0]["tree"] == shown[1]["tree"]


def test_actions_named_outside_bt_cpp_identifiers_come_back_unchanged(tmp_path):
    names = ["Ω", "a&b", "-->", "SubTree", "Action", "acted"]
    entries, previous = [], "true"
    for name in names:
        entries.append(f"({quoted(name)}, {previous})")
        previous = f"{quoted(name)}.done" if quoted(name)[0] in "'abcdefghijklmnopqrstuvwxyz" else f"({name}).done"
    source = tmp_path / "odd.pl"
    source.write_text(f"task(t).\nschema(t, [{', '.join(entries)}], t.done).\n"
                      + "".join(f"schema({quoted(n)}, [], {p}).\n" for n, p in
                                zip(names, [e.split(', ', 1)[1][:-1] for e in entries[1:]] + [previous])))
    xml, back = tmp_path / "odd.xml", tmp_path / "back.pl"
    assert run("export", source, "-o", xml).returncode == 0
    r = run("convert", xml, "-o", back)
    assert r.returncode == 0, r.stderr
    shown = [json.loads(run("show", f, "--json").stdout) for f in (source, back)]
    assert shown[0]["tree"] == shown[1]["tree"]


def test_convert_never_writes_over_a_file_the_document_includes(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "main.xml").write_text('<root BTCPP_format="4" main_tree_to_execute="Main">\n'
                                       '  <include path="sub/inc.xml"/>\n'
                                       '  <BehaviorTree ID="Main"><Sequence><SubTree ID="Sub"/></Sequence></BehaviorTree>\n'
                                       '</root>\n')
    included = ('<root BTCPP_format="4">\n  <BehaviorTree ID="Sub"><Sequence><OpenDoor/><PassDoor/></Sequence>'
                '</BehaviorTree>\n</root>\n')
    (tmp_path / "sub" / "inc.xml").write_text(included)
    for target in ("sub/inc.xml", "sub/../sub/inc.xml"):
        r = subprocess.run([sys.executable, "-m", "schemalog", "convert", "main.xml", "-o", target], cwd=tmp_path,
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and "would overwrite an input file" in r.stderr
        assert (tmp_path / "sub" / "inc.xml").read_text() == included


def test_node_types_from_a_yaml_file_and_their_errors_with_positions(tmp_path):
    types = tmp_path / "types.yaml"
    types.write_text("a1: PickUp(object)\ngripper: GripperCommand(command)\n")
    r = run("export", MIX, "--compressed", "--to", "btcpp", "--node-types", types)
    assert r.returncode == 0, r.stderr
    assert '<PickUp name="a1(spoon)" object="spoon"' in r.stdout
    assert '<input_port name="command" type="std::string">' in r.stdout
    for text, where in (("a1: Sequence(x)\n", ":1:5: error: a1: 'Sequence' cannot be a node type"),
                        ("a1: [x]\n", ":1:1: error: each entry is"),
                        ("a1: P(_x)\n", ":1:5: error: a1: '_x' cannot be a port name"),
                        ("a1: P\na1: Q\n", ":2:1: error: a1 is given twice")):
        types.write_text(text)
        out = tmp_path / "t.xml"
        r = run("export", MIX, "--to", "btcpp", "--node-types", types, "-o", out)
        assert r.returncode == 1 and where in r.stderr and "Traceback" not in r.stderr and not out.exists()
    types.write_text("a1: PickUp\n")
    r = run("export", MIX, "--to", "btcpp", "--node-types", types)
    assert r.returncode == 1 and "PickUp 0 port(s), and a1(spoon) has 1 argument(s)" in r.stderr
    r = run("export", MIX, "--to", "py_trees", "--node-types", types)
    assert r.returncode == 2 and "node types are for BehaviorTree.CPP exports" in r.stderr


def test_a_converted_bt_cpp_tree_exports_back_with_its_own_nodes_and_ports(tmp_path):
    """convert keeps each action's node type and ports (bt_node/3); compress merges the chains
    Algorithm 1 finds; export gives every action back its own node, so the robot's plugins
    load it: no node type or port the original document does not declare."""
    import xml.etree.ElementTree as ET
    from schemalog.formats.btcpp import run_btcpp
    from schemalog.formats.documents import read_document
    from schemalog.run.execute import replay
    from schemalog.task.tree import instantiate
    from schemalog.logic.parse import parse_term

    source = FIXTURES / "long_sequence.xml"
    model = {a.get("ID"): {p.get("name") for p in a} for a in ET.parse(source).getroot().find("TreeNodesModel")}
    knowledge = tmp_path / "clear.pl"
    assert run("convert", source, "-o", knowledge).returncode == 0
    assert "bt_node(approach_object(cup),'ApproachObject',[object=cup])." in knowledge.read_text()
    out = tmp_path / "small.xml"
    r = run("export", knowledge, "--compressed", "--to", "btcpp", "-o", out)
    assert r.returncode == 0, r.stderr
    root = ET.fromstring(out.read_text().split("?>", 1)[1])
    declared = {a.get("ID"): {p.get("name") for p in a} for a in root.find("TreeNodesModel")}
    assert set(declared) == set(model) and all(declared[t] <= model[t] for t in declared)
    actions = [e for t in root.findall("BehaviorTree") for e in t.iter() if e.tag in declared]
    assert len(actions) == 16 and all({k for k in e.attrib if not k.startswith("_")} - {"name"} <= model[e.tag]
                                      for e in actions)
    assert any(e.tag == "Sequence" and e.get("name") == "approach_object_grasp_object_place_in_bin(cup)"
               for t in root.findall("BehaviorTree") for e in t.iter())           # a merged chain
    kb = read_document(str(knowledge)).to_kb()
    original = instantiate(kb, parse_term("clear_table"))
    ran = run_btcpp(out.read_text(), original, ())
    assert ran.status == "completed" and replay(original, (), ran.trace).valid and len(ran.trace) == 16


def test_a_malformed_bt_node_fact_is_an_error_at_its_clause(tmp_path):
    knowledge = tmp_path / "k.pl"
    knowledge.write_text(MIX.read_text() + "\nbt_node(a1(spoon), 'PickUp', object).\n")
    r = run("export", knowledge, "--to", "btcpp")
    line = len(MIX.read_text().splitlines()) + 2
    assert r.returncode == 1 and f"k.pl:{line}:1: error: bt_node/3 reads" in r.stderr, r.stderr


def test_a_port_the_model_declares_is_a_port_even_when_named_agent(tmp_path):
    """`agent` and `importance` are the schema's, unless the node's TreeNodesModel declares them
    as its ports: then convert keeps them as ports and export gives them back (found in review:
    PickUp's agent port came back as _agent, which BT.CPP ignores)."""
    knowledge = tmp_path / "serve.pl"
    assert run("convert", FIXTURES / "agent_port.xml", "-o", knowledge).returncode == 0
    text = knowledge.read_text()
    assert "bt_node(pick_up(left_arm,cup),'PickUp',[agent=left_arm,object=cup])." in text
    assert "agent(place(cup),right_arm)." in text
    exported = run("export", knowledge, "--to", "btcpp").stdout
    assert '<PickUp name="pick_up(left_arm,cup)" agent="left_arm" object="cup"' in exported
    assert '<Place name="place(cup)" object="cup"' in exported and '_agent="right_arm"' in exported
