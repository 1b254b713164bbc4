"""BehaviorTree.CPP v4: exported trees run in the real runtime (behaviortreepy) against the emulated
world, soundly (their trace replays through the ORIGINAL tree); they import back to the same tree;
anyone's trees import where they have a schema meaning and are refused where they do not."""

from pathlib import Path

import pytest
from hypothesis import given, settings, strategies as st

from conftest import COFFEE, MIX
from schemalog.testing.strategies import task_trees
from schemalog.errors import SchemalogError
from schemalog.evaluate.generate import generate
from schemalog.formats.btcpp import (export_btcpp, import_btcpp, key_atom, literal_key, parse_script_condition,
                                     run_btcpp, to_script)
from schemalog.formats.documents import read_document
from schemalog.logic.parse import parse_term
from schemalog.run.execute import Executive, replay
from schemalog.run.world import World, initial_state
from schemalog.task import conditions as cond
from schemalog.task.compress import compress
from schemalog.task.tree import instantiate

FIXTURES = Path(__file__).parent / "btcpp"


def shipped(path, task):
    kb = read_document(path).to_kb()
    tree = instantiate(kb, parse_term(task))
    return tree, World(tree, initial_state(kb)).atoms


def trees():
    cases = [("figure 2", *shipped(MIX, "use(spoon)")), ("coffee and tea", *shipped(COFFEE, "prepareboth"))]
    for depth, children, rd in ((4, 2, 0.5), (4, 3, 0.3), (5, 2, 0.7), (4, 3, 0.0)):
        tree = generate(depth, children, rd, seed=3)
        cases.append((f"generated {depth}x{children} RD {rd}", tree, World(tree, ()).atoms))
    return cases


CASES = trees()


@pytest.mark.parametrize("name, original, initial", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("which", ["original", "compressed"])
def test_exported_tree_runs_to_completion_in_btcpp_and_replays_through_the_original(name, original, initial, which):
    tree = original if which == "original" else compress(original).tree
    xml = export_btcpp(tree, initial)
    run = run_btcpp(xml, original, initial)
    assert run.status == "completed"
    assert replay(original, initial, run.trace).valid
    # It does what the task needs: the same actions as schemalog's own executive, one decision per tick.
    executive = Executive(tree, World(original, initial))
    assert executive.run().completed
    assert sorted(map(str, run.trace)) == sorted(map(str, executive.trace))
    assert run.ticks == len(executive.decisions) + 1      # the last tick finds the task accomplished


def test_compressed_tree_takes_fewer_ticks_than_the_original_for_the_same_actions():
    original, initial = shipped(COFFEE, "prepareboth")
    runs = {which: run_btcpp(export_btcpp(t, initial), original, initial)
            for which, t in (("original", original), ("compressed", compress(original).tree))}
    assert len(runs["original"].trace) == len(runs["compressed"].trace) == 36
    assert (runs["original"].ticks, runs["compressed"].ticks) == (37, 17)


def test_a_task_that_cannot_progress_ends_stuck_not_completed():
    original, _ = shipped(MIX, "use(spoon)")
    run = run_btcpp(export_btcpp(original, []), original, [])   # hand.free is false: nothing is released
    assert run.status == "stuck" and run.trace == []


def test_export_is_bt_cpp_v4_with_subtrees_scripts_and_kept_metadata():
    original, initial = shipped(COFFEE, "prepareboth")
    xml = export_btcpp(compress(original).tree, initial)
    assert '<root BTCPP_format="4" main_tree_to_execute="schemalog_run">' in xml
    assert '<SubTree ID="add_water" name="add(water)"' in xml
    assert xml.count('<BehaviorTree ID="add_water">') == 1       # used under coffee and under tea: defined once
    assert "kukahand__free := true" in xml                           # the initial state, a boolean entry
    assert '_agent="gripper"' in xml and "_origins=" in xml


@pytest.mark.parametrize("name, original, initial", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("which", ["original", "compressed"])
def test_exported_tree_imports_back_to_the_same_tree(name, original, initial, which):
    tree = original if which == "original" else compress(original).tree
    back = import_btcpp(export_btcpp(tree, initial), "t.xml")
    assert back.tree == tree
    assert set(back.initial) == set(initial)


@settings(max_examples=25, deadline=None)
@given(depth=st.integers(2, 4), children=st.integers(1, 3), rd=st.sampled_from([0.0, 0.3, 0.5, 0.7]),
       seed=st.integers(0, 1000), compressed=st.booleans())
def test_round_trip_of_generated_tasks(depth, children, rd, seed, compressed):
    tree = generate(depth, children, rd, seed)
    if compressed:
        tree = compress(tree).tree
    assert import_btcpp(export_btcpp(tree, [parse_term("b1.done")]), "t.xml").tree == tree


@settings(max_examples=30, deadline=None)
@given(task_trees(max_children=4, levels=3), st.booleans())
def test_round_trip_of_trees_with_agents_branches_and_cycles(tree, compressed):
    if compressed:
        tree = compress(tree).tree
    assert import_btcpp(export_btcpp(tree, []), "t.xml").tree == tree


@settings(max_examples=30, deadline=None)
@given(task_trees(max_children=4, levels=3))
def test_every_action_bt_cpp_takes_is_an_enabled_leaf_of_the_original(tree):
    run = run_btcpp(export_btcpp(tree, []), tree, [])
    assert replay(tree, [], run.trace).valid
    if Executive(tree, World(tree, ())).run().completed:
        assert run.status == "completed"


ATOMS = st.sampled_from(["hand.free", "spoon.taken", "a1.done", "on(a, b)", "acted", "x__y", "q__1", "(table).free", "'Hand'.free", "a.b.c", "(a.b).c"]).map(parse_term)
LITS = st.builds(cond.Lit, ATOMS, st.booleans())
CONDITIONS = st.recursive(
    st.one_of(LITS, st.sampled_from([cond.TRUE, cond.FALSE])),
    lambda inner: st.one_of(st.builds(cond.And, st.lists(inner, min_size=2, max_size=3).map(tuple)),
                            st.builds(cond.Or, st.lists(inner, min_size=2, max_size=3).map(tuple)),
                            st.builds(cond.Not, inner.filter(lambda c: isinstance(c, (cond.And, cond.Or))))),
    max_leaves=8)


@given(CONDITIONS)
def test_conditions_survive_the_scripting_language(c):
    assert parse_script_condition(to_script(c)) == c


@given(ATOMS)
def test_literal_keys_are_identifiers_that_name_their_atom(atom):
    key = literal_key(atom)
    assert key.isidentifier() and key not in ("acted", "true", "false")
    assert not key.startswith(("true", "false"))     # BT.CPP's script reads `truex` as true, then x
    assert key_atom(key) == atom


def test_an_entry_named_after_a_keyword_runs_in_bt_cpps_script():
    """`true.done` was the entry true__done, which BT.CPP 4.8's script refuses ("expected ';'"):
    the export of a task with such atoms runs in BT.CPP."""
    import behaviortreepy

    for atom in ("true.done", "falsey.x", "trueish"):
        key = literal_key(parse_term(atom))
        assert key.startswith("q__") and key_atom(key) == parse_term(atom)
        xml = f'<root BTCPP_format="4"><BehaviorTree ID="m"><Script code="{key} := false"/></BehaviorTree></root>'
        tree = behaviortreepy.BehaviorTreeFactory().create_tree_from_text(xml)
        assert tree.tick_while_running() == behaviortreepy.NodeStatus.SUCCESS


def read(path):
    return Path(path).read_text()


def imported(name):
    path = FIXTURES / name
    return import_btcpp(path.read_text(), str(path), read).tree


def test_long_sequence_imports_as_released_steps_and_compresses():
    tree = imported("long_sequence.xml")
    assert len(tree.children) == 16
    first, second, fourth, eighth = (tree.children[i] for i in (0, 1, 3, 7))
    assert str(second.label) == str(parse_term("grasp_object(cup)"))
    assert second.releaser == cond.Lit(parse_term("approach_object(cup).done"))
    # The same action twice is two behaviours with posts of their own.
    assert fourth.label == eighth.label and fourth.post != eighth.post
    result = compress(tree)
    assert result.nodes_after < result.nodes_before
    run = run_btcpp(export_btcpp(result.tree, []), tree, [])
    assert run.status == "completed" and replay(tree, [], run.trace).valid


def test_subtrees_from_an_included_file_keep_their_ports():
    tree = imported("subtrees_main.xml")
    pick, pour, ready = tree.children
    assert (pick.label, pick.importance) == (parse_term("pick_kettle"), 2)
    assert [str(c.label) for c in pick.children][0] == str(parse_term("approach_object(kettle)"))
    assert pour.releaser == cond.Lit(parse_term("pick_kettle.done"))
    assert ready.post == cond.Lit(parse_term("tea.ready"))      # a Script of booleans is its post-condition


def test_reactive_guard_releases_every_later_step():
    tree = imported("reactive_guard.xml")
    guard = [cond.Lit(parse_term("is_battery_ok")), cond.Lit(parse_term("door.closed"), False)]
    assert all(set(guard) <= set(cond.literals(c.releaser)) for c in tree.children)
    picture = tree.children[2]
    assert cond.Lit(parse_term("hall.lit")) in cond.literals(picture.releaser)        # Precondition if=
    assert cond.Lit(parse_term("alarm"), False) in cond.literals(tree.children[3].releaser)   # _while


REFUSED = [
    ("refused_fallback.xml", 5, 7, "Fallback"),
    ("refused_nav2.xml", 5, 5, "RecoveryNode"),
    ("refused_remapped.xml", 5, 7, "remapped"),
    ("refused_arithmetic.xml", 5, 7, "only assignments of true or false"),
    ("refused_retry.xml", 4, 5, "RetryUntilSuccessful"),
    ("refused_unknown_node.xml", 5, 7, "unknown node type <RateController>"),
    ("refused_undefined_subtree.xml", 6, 7, "SubTree 'Dance' is never defined"),
    ("refused_recursion.xml", 11, 7, "recursive SubTree: Ping -> Pong -> Ping"),
    ("refused_billion_laughs.xml", 3, 16, "entities are refused"),
    ("refused_external_entity.xml", 2, 61, "entities are refused"),
    ("refused_malformed.xml", 6, 7, "malformed XML: mismatched tag"),
]


@pytest.mark.parametrize("name, line, column, words", REFUSED, ids=[r[0] for r in REFUSED])
def test_what_has_no_schema_meaning_is_refused_at_its_element(name, line, column, words):
    with pytest.raises(SchemalogError) as err:
        imported(name)
    assert (err.value.pos.line, err.value.pos.column) == (line, column)
    assert err.value.pos.file.endswith(name) and words in err.value.message


def test_a_hundred_thousand_nodes_are_refused_before_they_are_built():
    text = '<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>\n' + "<Wave/>\n" * 100_000 + \
           "</Sequence></BehaviorTree></root>"
    with pytest.raises(SchemalogError) as err:
        import_btcpp(text, "big.xml")
    assert "more than 50,000 elements" in err.value.message and err.value.pos.line == 49_999


def test_subtrees_nested_past_the_limit_are_refused():
    trees = "".join(f'<BehaviorTree ID="T{i}"><SubTree ID="T{i + 1}"/></BehaviorTree>' for i in range(400))
    text = f'<root BTCPP_format="4" main_tree_to_execute="T0">{trees}<BehaviorTree ID="T400"><Wave/></BehaviorTree></root>'
    with pytest.raises(SchemalogError) as err:
        import_btcpp(text, "deep.xml")
    assert "SubTrees nest deeper than 256 levels" in err.value.message and err.value.pos.line == 1


def test_recursive_includes_are_refused(tmp_path):
    (tmp_path / "a.xml").write_text('<root BTCPP_format="4"><include path="b.xml"/>'
                                    '<BehaviorTree ID="A"><Wave/></BehaviorTree></root>')
    (tmp_path / "b.xml").write_text('<root BTCPP_format="4">\n<include path="a.xml"/></root>')
    with pytest.raises(SchemalogError) as err:
        import_btcpp((tmp_path / "a.xml").read_text(), str(tmp_path / "a.xml"), read)
    assert "recursive include" in err.value.message and err.value.pos.file.endswith("b.xml")


def test_parallel_children_are_released_together_and_condition_nodes_are_literals():
    text = '''<root BTCPP_format="4" main_tree_to_execute="Set">
      <BehaviorTree ID="Set">
        <Sequence name="set_table">
          <Condition ID="IsTableFree"/>
          <Parallel name="lay" success_count="-1" failure_count="1">
            <PlaceObject object="fork"/>
            <PlaceObject object="knife"/>
          </Parallel>
          <Script name="table_set" code="table__set := true; table__free := false"/>
        </Sequence>
      </BehaviorTree>
    </root>'''
    tree = import_btcpp(text, "set.xml").tree
    lay, script = tree.children
    assert lay.releaser == cond.Lit(parse_term("is_table_free"))
    assert [c.releaser for c in lay.children] == [cond.TRUE, cond.TRUE]
    assert script.post == cond.And((cond.Lit(parse_term("(table).set")), cond.Lit(parse_term("(table).free"), False)))
    assert script.releaser == cond.And((cond.Lit(parse_term("is_table_free")), cond.Lit(parse_term("lay.done"))))


def test_a_parallel_that_succeeds_on_one_child_is_refused():
    text = ('<root BTCPP_format="4"><BehaviorTree ID="M">\n  <Parallel success_count="1">'
            '<A/><B/></Parallel></BehaviorTree></root>')
    with pytest.raises(SchemalogError) as err:
        import_btcpp(text, "p.xml")
    assert (err.value.pos.line, err.value.pos.column) == (2, 3) and "success_count" in err.value.message


# ---------------------------------------------------------------------------
# Issue 33: a robot's own nodes plug in: arguments are ports, node types can be mapped

def _declared_ports(xml):
    """{node type: its declared input ports} from the document's TreeNodesModel, and every
    action element's (type, ports written) pairs."""
    import xml.etree.ElementTree as ET
    root = ET.fromstring(xml.split("?>", 1)[1])
    declared = {a.get("ID"): {p.get("name") for p in a.findall("input_port")}
                for a in root.find("TreeNodesModel").findall("Action")}
    used = [(e.tag, {k for k in e.attrib if not k.startswith("_") and k != "name"})
            for tree in root.findall("BehaviorTree") for e in tree.iter() if e.tag in declared]
    return declared, used


def test_arguments_are_ports_the_tree_nodes_model_declares():
    original, initial = shipped(MIX, "use(spoon)")
    for tree in (original, compress(original).tree):
        xml = export_btcpp(tree)
        assert '<a1 name="a1(spoon)" arg1="spoon"' in xml and '<gripper name="gripper(close)" arg1="close"' in xml
        declared, used = _declared_ports(xml)
        assert declared["a1"] == {"arg1"} and used
        assert all(ports <= declared[tag] for tag, ports in used)        # BT.CPP refuses an undeclared port
        assert import_btcpp(xml, "t.xml").tree == tree


def test_node_types_map_functors_to_a_robots_own_nodes_and_ports():
    from schemalog.formats.btcpp import NodeType, action_ids
    original, initial = shipped(MIX, "use(spoon)")
    types = {"a1": NodeType("PickUp", ("object",)), "gripper": NodeType("GripperCommand", ("command",))}
    tree = compress(original).tree
    xml = export_btcpp(tree, None, node_types=types)
    assert '<PickUp name="a1(spoon)" object="spoon"' in xml and '<GripperCommand name="gripper(open)" command="open"' in xml
    assert {"PickUp", "GripperCommand", "a2"} <= set(action_ids(xml)) and "a1" not in action_ids(xml)
    declared, used = _declared_ports(xml)
    assert declared["PickUp"] == {"object"} and all(ports <= declared[tag] for tag, ports in used)
    assert import_btcpp(xml, "t.xml").tree == tree                   # the label is the name: nothing lost
    run = run_btcpp(xml, original, initial)                           # behaviortreepy: ports taken out
    assert run.status == "completed" and replay(original, initial, run.trace).valid
    with pytest.raises(Exception, match="PickUp 0 port"):
        export_btcpp(tree, None, node_types={"a1": NodeType("PickUp", ())})
    for bad in (NodeType("Fallback", ()), NodeType("Pick Up", ()), NodeType("P", ("_x",)), NodeType("P", ("name",))):
        with pytest.raises(ValueError):
            export_btcpp(tree, None, node_types={"a1": bad})


def test_an_argument_bt_cpp_would_read_as_a_blackboard_entry_is_no_port():
    from schemalog.task.tree import Behaviour
    leaf = Behaviour(label=parse_term("put({x}, '=')"), post=cond.Lit(parse_term("put.done")))
    root = Behaviour(label=parse_term("t"), children=(leaf,), post=cond.Lit(parse_term("put.done")))
    xml = export_btcpp(root)
    element = next(line for line in xml.splitlines() if "name=\"put(" in line)
    assert " arg1=" not in element and " arg2=" not in element
    assert import_btcpp(xml, "t.xml").tree == root


def test_a_condition_first_fallback_is_the_post_condition_pattern():
    """Fallback(IsDoorOpen, OpenDoor): OpenDoor runs only while the door is not open, which is
    a schema behaviour whose post-condition is is_door_open; ReactiveFallback the same."""
    imported = import_btcpp((FIXTURES / "post_condition_pattern.xml").read_text(), "p.xml")
    open_door, through, close_door = imported.tree.children
    assert (str(open_door.label), open_door.post) == ("open_door", cond.Lit(parse_term("is_door_open")))
    assert (str(close_door.label), close_door.post) == ("close_door", cond.Lit(parse_term("is_door_closed")))
    assert through.releaser == cond.Lit(parse_term("is_door_open"))       # the Sequence: released by the goal
    assert imported.nodes[(open_door.label, open_door.post)] == ("OpenDoor", ())


@pytest.mark.parametrize("body, post", [
    ("<IsDoorOpen/><IsDoorBroken/><OpenDoor/>", "is_door_open or is_door_broken"),
    ('<ScriptCondition code="door__open"/><OpenDoor/>', "door.open"),
    ('<IsDoorOpen _skipIf="alarm"/><OpenDoor/>', None),
])
def test_the_post_condition_pattern_takes_any_of_its_conditions(body, post):
    text = ('<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence name="m"><Fallback>' + body +
            '</Fallback></Sequence></BehaviorTree><TreeNodesModel><Condition ID="IsDoorOpen"/>'
            '<Condition ID="IsDoorBroken"/></TreeNodesModel></root>')
    (leaf,) = import_btcpp(text, "f.xml").tree.children
    assert str(leaf.label) == "open_door"
    if post is not None:
        assert leaf.post == cond.from_term(parse_term(post))
    else:
        assert leaf.post == cond.conjoin([cond.Lit(parse_term("is_door_open")), cond.Lit(parse_term("alarm"), False)])


@pytest.mark.parametrize("body", ["<OpenDoor/><UnlockDoor/>", "<IsDoorOpen/>", "<IsDoorOpen/><OpenDoor/><UnlockDoor/>",
                                  "<OpenDoor/><IsDoorOpen/>"])
def test_a_fallback_of_alternatives_is_still_refused_at_its_element(body):
    text = ('<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence name="m">\n  <Fallback>' + body +
            '</Fallback></Sequence></BehaviorTree><TreeNodesModel><Condition ID="IsDoorOpen"/></TreeNodesModel></root>')
    with pytest.raises(SchemalogError, match="only as the post-condition pattern") as err:
        import_btcpp(text, "f.xml")
    assert (err.value.pos.line, err.value.pos.column) == (2, 3)


@pytest.mark.parametrize("label", ['a1("x")', 'a1("x y", "z")', "a1('it''s')", "a1('a&b<c>')", 'a1("say arg1=")',
                                   "a1('say arg1=\"')", "a1(' {x}')", "a1(f({x}))", "a1(' = ')"])
def test_ports_come_out_whole_for_behaviortreepy_whatever_the_quotes(label):
    """quoteattr writes a value holding `"` in single quotes; without_ports must take out the
    port attributes as attributes (not by a pattern that looks inside another value), leaving
    a document BT.CPP loads and the same tree (found in review: `a1("x")` kept its port)."""
    import xml.etree.ElementTree as ET
    from schemalog.formats.btcpp import without_ports
    from schemalog.task.tree import Behaviour
    leaf = Behaviour(label=parse_term(label), post=cond.Lit(parse_term("p.done")))
    root = Behaviour(label=parse_term("t"), children=(leaf,), post=cond.Lit(parse_term("t.done")))
    xml = export_btcpp(root)
    stripped = without_ports(xml)
    elements = [e for e in ET.fromstring(stripped.split("?>", 1)[1]).iter() if e.get("name") == label.replace("''", "'")
                or e.tag == "a1"]
    assert elements and all(not any(k.startswith("arg") for k in e.attrib) for e in elements)
    assert import_btcpp(stripped, "s.xml").tree == root
    run = run_btcpp(xml, root, ())
    assert run.status == "completed" and run.trace == [leaf.label]


def test_a_mapped_node_type_never_takes_another_actions_node_type():
    """A robot's a2 node has its own ports: mapping a1 onto a2 (or two functors onto one type
    with different ports, or onto SchemalogAction) would declare a mix BT.CPP refuses there."""
    from schemalog.formats.btcpp import NodeType
    from schemalog.formats.quoting import Unquotable
    from schemalog.task.tree import Behaviour
    leaves = tuple(Behaviour(label=parse_term(t), post=cond.Lit(parse_term(f"p{i}.done")))
                   for i, t in enumerate(["a1(spoon)", "a2(cup, x)", "a3(fork)"]))
    root = Behaviour(label=parse_term("t"), children=leaves, post=cond.Lit(parse_term("t.done")))
    with pytest.raises(Unquotable, match="which the action a2 already has"):
        export_btcpp(root, node_types={"a1": NodeType("a2", ("object",))})
    with pytest.raises(Unquotable, match="gives Pick to a1"):
        export_btcpp(root, node_types={"a1": NodeType("Pick", ("object",)), "a3": NodeType("Pick", ("thing",))})
    with pytest.raises(ValueError, match="nor SchemalogAction"):
        export_btcpp(root, node_types={"a1": NodeType("SchemalogAction", ("object",))})
    same = export_btcpp(root, node_types={"a1": NodeType("Pick", ("object",)), "a3": NodeType("Pick", ("object",))})
    assert same.count('<Action ID="Pick">') == 1 and import_btcpp(same, "t.xml").tree == root
    swapped = export_btcpp(root, node_types={"a1": NodeType("a2", ("object",)), "a2": NodeType("Place", ("what", "how"))})
    assert '<a2 name="a1(spoon)" object="spoon"' in swapped and '<Place name="a2(cup,x)" what="cup" how="x"' in swapped
