"""The SEED importer: the authors' LTM format becomes the paper's schema form."""

from schemalog.task import conditions as cond
from schemalog.formats.documents import document_from_text, read_document, to_pl
from schemalog.logic.parse import parse_term
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import count_nodes, depth, instantiate, walk

from conftest import COFFEE, SEED_COFFEE


def test_seed_example_instantiates_to_the_shipped_task():
    seed_tree = instantiate(read_document(SEED_COFFEE).to_kb(), parse_term("prepareboth"))
    shipped = instantiate(read_document(COFFEE).to_kb(), parse_term("prepareboth"))
    assert (count_nodes(seed_tree), depth(seed_tree)) == (63, 5)
    assert seed_tree == shipped  # labels, releasers, posts, agents, objects, importance


def test_server_code_and_directives_are_skipped_and_said():
    doc = read_document(SEED_COFFEE)
    assert doc.seed
    (note,) = doc.notes
    assert "lookupSchema/1" in note and "rememberSchema/3" in note and ":- op(500,xfy,'.')" in note


SEED = '''
:- op(500, xfy, .).
:- op(600, fx, -).
schema(add(OBJ), [[subtask(take, OBJ), 1, [kukahand.free]], [subtask(pour, OBJ), 2.5, [OBJ.taken]]]).
schema(subtask(take, water), [[kuka(gripper(close)), 1, ["TRUE"]]]).
schema(subtask(_, _), []).
schema(kuka(_), []).
schema(object(water), []).
schema(en(S), [[speech(stop), 2, ["TRUE"]]]) :- string(S), split_string(S, " ", "", [_, "stop"]).
schema(speech(_), []).
goal(add(Obj), [Obj.used]).
goal(subtask(take, Obj), [Obj.taken]).
goal(subtask(pour, Obj), [Obj.used]).
goal(kuka(gripper(close)), [-kukahand.free]).
'''


def test_goals_become_posts_and_generic_schemas_specialise():
    tree = instantiate(document_from_text(SEED, "ltm.prolog").to_kb(), parse_term("add(water)"))
    take, pour = tree.children
    assert cond.to_text(tree.post) == "water.used"
    assert cond.to_text(take.post) == "water.taken" and cond.to_text(pour.post) == "water.used"
    assert pour.importance == 2.5
    (close,) = take.children
    assert close.agent == "gripper" and cond.to_text(close.post) == "not kukahand.free"
    assert pour.children == ()


def test_generic_schema_without_goal_gets_label_done():
    tree = instantiate(document_from_text(SEED, "ltm.prolog").to_kb(), parse_term("speech(stop)"))
    assert cond.to_text(tree.post) == "speech(stop).done"


def test_rule_schema_keeps_its_body_and_runs():
    doc = document_from_text(SEED, "ltm.prolog")
    assert 'split_string(S," ","",[_,"stop"])' in to_pl(doc)
    tree = instantiate(doc.to_kb(), parse_term('en("please stop")'))
    assert [term_to_text(c.label) for c in tree.children] == ["speech(stop)"]


def test_swi7_autosave_list_cells_read_as_dot_literals():
    # SWI-Prolog 7 reads SEED's `hand.free` as the list cell [hand|free]; its saved files say so.
    saved = ('schema(add(_1), [[subtask(take, _1), 1, [[kukahand|free]]], [subtask(pour, _1), 1, [[_1|taken]]]]).\n'
             'schema(subtask(_, _), []).\n'
             'goal(kuka(gripper(close)), [-([kukahand|free])]).\n')
    tree = instantiate(document_from_text(saved).to_kb(), parse_term("add(tea)"))
    assert [cond.to_text(c.releaser) for c in tree.children] == ["kukahand.free", "tea.taken"]
    assert all(cond.to_text(n.post).endswith(".done") for n in walk(tree))
