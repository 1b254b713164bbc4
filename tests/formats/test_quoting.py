"""Names that reach generated files (issue 32): a task's, an action's, an object's, an agent's and
the files' names, arbitrary text, can neither run code nor break an export, and come back from it.

    python_literal / xml_attribute / xml_comment   each reads back, or refuses
    export --to py_trees    the module imports in an empty folder, creates nothing, runs
    export --to btcpp       the XML is well-formed, imports back to the same tree, runs in BT.CPP
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
import xml.dom.minidom

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from schemalog.errors import SchemalogError
from schemalog.formats.btcpp import export_btcpp, import_btcpp, run_btcpp
from schemalog.formats.pytrees import export_pytrees, run_pytrees
from schemalog.errors import readable_name
from schemalog.formats.quoting import Unquotable, python_literal, xml_attribute, xml_comment
from schemalog.logic.kb import KnowledgeBase
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import Atom, Struct, term_to_text
from schemalog.task.compress import compress
from schemalog.task.tree import instantiate, walk

# All of Unicode, surrogates included (a non-UTF-8 file name's bytes arrive as lone surrogates).
ANY_TEXT = st.text(st.characters(), max_size=24)
HOSTILE = st.sampled_from(['"""', "'''", '\\', '\n', '\0', '-->', '--', '---', '<!--', ']]>', '&amp;', '{x}',
                           '__import__("os").system("touch PWNED")', 'Ω', '\x01', '\udcff', '\u2028', 'SubTree',
                           'Action', 'acted', 'true', ' ', "'"])
NAMES = st.one_of(ANY_TEXT, st.lists(st.one_of(HOSTILE, ANY_TEXT), min_size=1, max_size=4).map("".join))
# Atom names: what a knowledge file can hold (no surrogates: files are UTF-8).
ATOM_NAMES = NAMES.filter(lambda s: not any("\ud800" <= c <= "\udfff" for c in s))
SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@given(st.recursive(st.one_of(NAMES, st.integers(), st.booleans()),
                    lambda inner: st.lists(inner, max_size=3).map(tuple) | st.lists(inner, max_size=3)))
def test_python_literal_evaluates_back_to_the_value(value):
    assert ast.literal_eval(python_literal(value)) == value


def test_python_literal_refuses_what_does_not_read_back():
    with pytest.raises(Unquotable):
        python_literal(float("nan"))


@given(NAMES)
def test_xml_attribute_reads_back_or_is_refused(text):
    try:
        quoted = xml_attribute(text)
    except Unquotable:
        assert any(not (c in "\t\n\r" or " " <= c <= "\ud7ff" or "\ue000" <= c <= "\ufffd" or c >= "\U00010000")
                   for c in text)
        return
    element = xml.dom.minidom.parseString(f"<a v={quoted}/>").documentElement
    assert element.getAttribute("v") == text


@given(NAMES)
def test_xml_comment_is_well_formed_and_shows_the_text(text):
    document = xml.dom.minidom.parseString(f"<a>{xml_comment(text)}</a>")
    comment = document.documentElement.firstChild
    assert comment.nodeType == document.COMMENT_NODE
    shown = comment.data[1:-1]
    assert shown.isprintable()
    if " " not in text:      # `--` is shown as `- -`
        assert shown.replace(" ", "") == readable_name(text)


def knowledge(task: str, actions: list[str], obj: str, agent: str) -> str:
    """A task `task` of the actions in sequence, the last one acting on `obj` and done by `agent`."""
    def q(term) -> str:
        return term_to_text(term)

    labels = [Atom(a) for a in actions[:-1]] + [Struct(actions[-1], (Atom(obj),))]
    entries, previous = [], Atom("true")
    for label in labels:
        entries.append(f"({q(label)}, {q(previous)})")
        previous = Struct(".", (label, Atom("done")))
    lines = [f"task({q(Atom(task))}).", f"object({q(Atom(obj))}).",
             f"agent({q(labels[0])}, {q(Atom(agent))}).",
             f"schema({q(Atom(task))}, [{', '.join(entries)}], {q(Struct('.', (Atom(task), Atom('done'))))})."]
    lines += [f"schema({q(label)}, [], {q(Struct('.', (label, Atom('done'))))})." for label in labels]
    return "\n".join(lines) + "\n"


@st.composite
def hostile_tasks(draw):
    """A small task whose every name is drawn from hostile text, loaded, with its tree."""
    names = draw(st.lists(ATOM_NAMES.filter(bool), min_size=4, max_size=4, unique=True))
    task, first, last, obj = names
    agent = draw(ATOM_NAMES.filter(bool))
    text = knowledge(task, [first, last], obj, agent)
    kb = KnowledgeBase()
    try:
        kb.consult_text(text, "hostile.pl")
        tree = instantiate(kb, parse_term(term_to_text(Atom(task))))
    except SchemalogError:
        assume(False)     # names the schema language gives a meaning of its own (true, [], ...)
    return tree


def run_module_in_empty_folder(source: str, tmp_path) -> tuple[subprocess.CompletedProcess, list[str]]:
    folder = tmp_path / "empty"
    folder.mkdir(exist_ok=True)
    for leftover in folder.iterdir():
        leftover.unlink()
    (folder / "tree.py").write_text(source, encoding="utf-8")
    program = ("import runpy; m = runpy.run_path('tree.py', run_name='exported'); "
               "print(m['run'](lambda atom: False, lambda action: None))")
    done = subprocess.run([sys.executable, "-c", program], cwd=folder, capture_output=True, text=True, timeout=60)
    return done, sorted(os.listdir(folder))


@SETTINGS
@given(hostile_tasks(), NAMES)
def test_a_py_trees_export_with_any_names_imports_and_runs_nothing_else(tmp_path_factory, tree, file_name):
    tmp_path = tmp_path_factory.mktemp("module")
    title = f"{term_to_text(tree.label)} from {file_name}: exported by schemalog"
    source = export_pytrees(tree, (), title)
    done, files = run_module_in_empty_folder(source, tmp_path)
    assert done.returncode == 0, done.stderr
    assert files == ["tree.py"]                 # nothing created: no injected code ran
    assert done.stdout.strip() in ("completed", "stuck", "tick limit")   # a blind robot: nothing ever holds
    world_run = run_pytrees(source, tree, ())
    assert world_run.status == "completed"      # every action released in turn: the whole task runs


@SETTINGS
@given(hostile_tasks(), NAMES, st.booleans())
def test_a_btcpp_export_with_any_names_is_well_formed_and_imports_back(tree, file_name, compressed):
    exported = compress(tree).tree if compressed else tree
    text = export_btcpp(exported, (), f"{term_to_text(tree.label)} from {file_name}")
    xml.dom.minidom.parseString(text.encode("utf-8"))
    back = import_btcpp(text, "t.xml")
    assert back.tree == exported
    assert [n.label for n in walk(back.tree)] == [n.label for n in walk(exported)]


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(hostile_tasks())
def test_a_btcpp_export_with_any_names_runs_in_bt_cpp(tree):
    run = run_btcpp(export_btcpp(tree, ()), tree, ())
    assert run.status == "completed"
    assert list(run.trace) == [n.label for n in walk(tree) if not n.children]


@pytest.mark.parametrize("task, program", [
    # a task called SubTree: its BehaviorTree ID would name BT.CPP's own node (found by the test above)
    ("'SubTree'", knowledge("SubTree", ["a", "b"], "cup", "arm")),
    # a sub-task pick(x) beside an action pick_x: the tree's ID would be the action's node type
    ("go", "task(go).\nobject(x).\nschema(go, [(pick(x), true), (pick_x, pick(x).done)], go.done).\n"
           "schema(pick(x), [(a, true)], pick(x).done).\nschema(a, [], a.done).\n"
           "schema(pick_x, [], pick_x.done).\n"),
])
def test_a_btcpp_export_names_no_behaviour_tree_after_a_node_type(task, program):
    kb = KnowledgeBase()
    kb.consult_text(program, "names.pl")
    tree = instantiate(kb, parse_term(task))
    assert tree.children   # the task is a BehaviorTree of its own, named after its label
    run = run_btcpp(export_btcpp(tree, ()), tree, ())
    assert run.status == "completed"
    assert list(run.trace) == [n.label for n in walk(tree) if not n.children]


def test_a_name_xml_cannot_hold_at_all_is_refused_with_a_message():
    # an agent name is kept as written where it is printable; a control character gets it quoted,
    # so nothing a knowledge file can say is refused: the one refusal left is a lone surrogate
    with pytest.raises(Unquotable, match="XML 1.0"):
        xml_attribute("a\udcffb")
    kb = KnowledgeBase()
    kb.consult_text(knowledge("t", ["a", "b"], "cup", "arm\x01"), "k.pl")
    tree = instantiate(kb, parse_term("t"))
    assert import_btcpp(export_btcpp(tree, ()), "t.xml").tree == tree


def test_a_deep_tree_exports_a_module_that_imports(tmp_path):
    # 250 levels: the tree as nested tuples went past Python's 200 nested parentheses
    kb = KnowledgeBase()
    kb.consult_text("task(c0).\n" + "".join(f"schema(c{i}, [(c{i + 1}, true)], c{i}.done).\n" for i in range(250))
                    + "schema(c250, [], c250.done).\n", "deep.pl")
    tree = instantiate(kb, parse_term("c0"))
    done, files = run_module_in_empty_folder(export_pytrees(tree, ()), tmp_path)
    assert done.returncode == 0, done.stderr[-500:]      # imported, and ticked 250 levels deep
    assert done.stdout.strip() == "tick limit"            # a blind robot: its first action never holds
    assert run_pytrees(export_pytrees(tree, ()), tree, ()).status == "completed"
