"""Teaching (Sec. II-D): segmented actions attached to the enabled sub-task with the highest
activation reproduce the paper's learned tasks."""

import pytest
from hypothesis import given, settings, strategies as st

from conftest import COFFEE, MIX, ROOT
from schemalog.formats.documents import document_from_text, load_kb
from schemalog.errors import SchemalogError
from schemalog.logic.kb import KnowledgeBase
from schemalog.learn.learn import learn
from schemalog.logic.parse import parse_term
from schemalog.run.scene import read_scene
from schemalog.learn.segment import segment
from schemalog.learn.simulate import simulate
from schemalog.learn.teach import Attachment, Recognised, next_action_number, teach
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import instantiate, walk

STRUCTURE = ROOT / "kb" / "tasks" / "coffee_structure.pl"
KITCHEN = ROOT / "kb" / "scenes" / "kitchen.yaml"
MIX_SCENE = ROOT / "kb" / "scenes" / "mix_with_spoon.yaml"

MIX_STRUCTURE = """
task(use(spoon)).
object(spoon).  object(cup).
agent(gripper(_), gripper).
initial(hand.free).
schema(use(spoon), [(subtask(take, spoon), hand.free), (subtask(mix, spoon), spoon.taken)], spoon.used).
schema(subtask(take, O), [], O.taken).
schema(subtask(mix, O), [], O.used).
schema(gripper(close), [], not hand.free).
schema(gripper(open), [], hand.free).
"""


def demonstrate(tmp_path, knowledge, task, scene, name, seed=0):
    from schemalog.learn.demo import write_demonstration
    demo = simulate(load_kb([knowledge]), parse_term(task), read_scene(scene), seed=seed)
    path = tmp_path / name
    write_demonstration(demo, path)
    return path


def test_figure_2_is_learned_from_a_demonstration_of_mixing(tmp_path):
    structure = tmp_path / "mix_structure.pl"
    structure.write_text(MIX_STRUCTURE)
    demo = demonstrate(tmp_path, MIX, "use(spoon)", MIX_SCENE, "mix.csv")
    lesson = learn(str(demo), str(structure), None)
    expected = instantiate(load_kb([MIX]), parse_term("use(spoon)"))
    assert lesson.tree == expected                      # labels, releasers, posts, agents, objects
    steps = lesson.teaching.steps
    assert [term_to_text(s.subtask) for s in steps] == ["subtask(take,spoon)"] * 3 + ["subtask(mix,spoon)"] * 6
    assert [term_to_text(s.releaser.atom) if hasattr(s.releaser, "atom") else "true" for s in steps] == \
        ["true", "a1.done", "a2.done", "true", "a3.done", "a4.done", "a5.done", "a6.done", "a7.done"]


def test_coffee_then_tea_joined_as_prepareboth_is_the_63_behaviour_task(tmp_path):
    coffee = demonstrate(tmp_path, COFFEE, "preparecoffee", KITCHEN, "coffee.csv", seed=1)
    tea = demonstrate(tmp_path, COFFEE, "preparetea", KITCHEN, "tea.json", seed=2)
    first = learn(str(coffee), str(STRUCTURE), parse_term("preparecoffee"))
    learned = tmp_path / "learned.pl"
    learned.write_text(first.text)
    second = learn(str(tea), str(learned), parse_term("preparetea"))
    # The tea demonstration takes and pours water again: recognised, not taught twice.
    recognised = [s for s in second.teaching.steps if isinstance(s, Recognised)]
    assert [term_to_text(s.action) for s in recognised] == [
        "a1(water)", "a2(water)", "gripper(close)", "a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)",
        "gripper(open)"]
    assert [term_to_text(a.label) for a in second.teaching.attachments][:2] == ["a22(tea)", "a23(tea)"]
    kb = document_from_text(second.text, "learned2.pl").to_kb(KnowledgeBase())
    both = instantiate(kb, parse_term("prepareboth"))
    assert both == instantiate(load_kb([COFFEE]), parse_term("prepareboth"))


def test_the_first_action_goes_to_the_sub_task_nearest_the_hand(tmp_path):
    # Both take sub-tasks are enabled at the start; the hand ends its first motion at the water.
    coffee = demonstrate(tmp_path, COFFEE, "preparecoffee", KITCHEN, "coffee.csv")
    lesson = learn(str(coffee), str(STRUCTURE), parse_term("preparecoffee"))
    first = lesson.teaching.steps[0]
    assert isinstance(first, Attachment)
    assert term_to_text(first.subtask) == "subtask(take,water)"
    assert term_to_text(first.runner_up[0]) == "subtask(take,coffee)" and first.runner_up[1] < first.emphasis


def test_action_numbers_continue_after_the_knowledge():
    assert next_action_number(load_kb([STRUCTURE])) == 1
    assert next_action_number(load_kb([COFFEE])) == 29


def test_an_action_with_nowhere_to_go_is_refused_with_its_line(tmp_path):
    # Demonstrate the coffee task to a structure whose only sub-task is done after one grasp.
    structure = tmp_path / "s.pl"
    structure.write_text(MIX_STRUCTURE.replace("(subtask(mix, spoon), spoon.taken)", "(subtask(mix, spoon), false)"))
    demo = demonstrate(tmp_path, MIX, "use(spoon)", MIX_SCENE, "mix.csv")
    with pytest.raises(SchemalogError) as info:
        learn(str(demo), str(structure), None)
    message = str(info.value)
    assert message.startswith(f"{demo}:")
    assert "a3(cup) (line " in message and "no enabled sub-task of use(spoon) to attach it to" in message
    assert "subtask(mix,spoon): pre-condition false is false" in message


def test_a_structure_without_sub_tasks_to_teach_is_refused(tmp_path):
    demo = demonstrate(tmp_path, MIX, "use(spoon)", MIX_SCENE, "mix.csv")
    structure = tmp_path / "full.pl"
    structure.write_text(MIX.read_text() + "\naction(A) :- schema(A, [], _).\n")
    with pytest.raises(SchemalogError, match="nothing is left to teach"):
        learn(str(demo), str(structure), None)


def test_a_gripper_command_needs_its_schema(tmp_path):
    structure = tmp_path / "s.pl"
    structure.write_text(MIX_STRUCTURE.replace("schema(gripper(open), [], hand.free).", ""))
    demo = demonstrate(tmp_path, MIX, "use(spoon)", MIX_SCENE, "mix.csv")
    with pytest.raises(SchemalogError, match=r"no schema for gripper\(open\)"):
        learn(str(demo), str(structure), None)


def test_teach_reports_untaught_sub_tasks(tmp_path):
    # Demonstrating only preparetea against prepareboth leaves the coffee sub-tasks untaught.
    tea = demonstrate(tmp_path, COFFEE, "preparetea", KITCHEN, "tea.csv")
    lesson = learn(str(tea), str(STRUCTURE), parse_term("prepareboth"))
    assert not lesson.teaching.accomplished
    assert {term_to_text(t) for t in lesson.teaching.untaught} == {
        "subtask(take,coffee)", "subtask(pour,coffee)", "subtask(take,spoon)", "subtask(mix,spoon)"}


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 2**16), st.floats(0.0, 0.03), st.sampled_from(["preparecoffee", "preparetea"]))
def test_any_kitchen_teaches_the_same_task(seed, jitter, task):
    # Wherever the objects stand and whatever the noise, the demonstration teaches the task it shows
    # (labels numbered in teaching order, as a first demonstration numbers them).
    scene = read_scene(KITCHEN).jittered(seed, jitter)
    demo = simulate(load_kb([COFFEE]), parse_term(task), scene, seed=seed)
    structure = load_kb([STRUCTURE])
    teaching = teach(structure, parse_term(task), demo, segment(demo))
    assert teaching.accomplished and not teaching.untaught
    shapes = {term_to_text(s.task): [(term_to_text(e.behaviour).split("(")[1], term_to_text(cond_term(e.releaser)))
                                     for e in s.entries] for s in teaching.schemas}
    expected = {term_to_text(s.task): [(term_to_text(e.behaviour).split("(")[1], term_to_text(cond_term(e.releaser)))
                                       for e in s.entries] for s in teach_reference(task)}
    # The same sub-tasks, each with actions on the same objects in the same order; releasers chain.
    assert {k: [obj for obj, _ in v] for k, v in shapes.items()} == {k: [obj for obj, _ in v] for k, v in expected.items()}
    for entries in shapes.values():
        assert entries[0][1] == "true" and all(r.endswith(".done") for _, r in entries[1:])


def cond_term(c):
    from schemalog.task.conditions import to_term
    return to_term(c)


def teach_reference(task):
    """The sub-task schemas of the shipped task that `task` uses, from kb/tasks/prepare_coffee_and_tea.pl."""
    from schemalog.task.schema import check_schemas
    tree = instantiate(load_kb([COFFEE]), parse_term(task))
    used = {term_to_text(b.label) for b in walk(tree) if b.children and all(not c.children for c in b.children)}
    return [s for s in check_schemas(load_kb([COFFEE])) if term_to_text(s.task) in used]


def extended(demo, offsets):
    """The demonstration with the hand moving on by `offsets` after its last sample."""
    import numpy as np
    from schemalog.learn.demo import Demonstration
    n, k = len(demo), len(offsets)
    times = np.concatenate([demo.times, demo.times[-1] + 0.01 * np.arange(1, k + 1)])
    positions = np.vstack([demo.positions, demo.positions[-1] + np.array(offsets)])
    orientations = np.vstack([demo.orientations, np.repeat(demo.orientations[-1:], k, axis=0)])
    objects = {name: np.vstack([t, np.repeat(t[-1:], k, axis=0)]) for name, t in demo.objects.items()}
    return Demonstration(times, positions, orientations, demo.gripper, objects, np.arange(2, n + k + 2), "x.csv")


def test_moving_away_after_the_task_is_accomplished_is_ignored_with_a_note():
    demo = simulate(load_kb([MIX]), parse_term("use(spoon)"), read_scene(MIX_SCENE))
    demo = extended(demo, [(0.0, 0.0, 0.003 * k) for k in range(1, 101)])      # 30 cm up, after the release
    structure = document_from_text(MIX_STRUCTURE, "s.pl").to_kb(KnowledgeBase())
    teaching = teach(structure, parse_term("use(spoon)"), demo, segment(demo))
    assert teaching.accomplished and len(teaching.attachments) == 9
    assert any(n.endswith("after use(spoon) was accomplished: ignored") for n in teaching.notes)


def test_a_grasp_of_another_object_than_the_sub_tasks_is_noted(tmp_path):
    tea = demonstrate(tmp_path, COFFEE, "preparetea", KITCHEN, "tea.csv")
    lesson = learn(str(tea), str(STRUCTURE), parse_term("preparecoffee"))
    assert any("gripper(close)" in n and "at tea is attached to subtask(take,coffee), which acts on coffee" in n
               for n in lesson.teaching.notes)


def test_a_demonstration_that_teaches_nothing_new_is_refused(tmp_path):
    coffee = demonstrate(tmp_path, COFFEE, "preparecoffee", KITCHEN, "coffee.csv")
    learned = tmp_path / "learned.pl"
    learned.write_text(learn(str(coffee), str(STRUCTURE), parse_term("preparecoffee"), bases=0).text)
    with pytest.raises(SchemalogError, match="teaches nothing new: each of its 27 actions is one"):
        learn(str(coffee), str(learned), parse_term("prepareboth"), bases=0)
