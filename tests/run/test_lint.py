"""Lint (run/lint.py): each diagnostic fires on a small file that has the problem, names the
place it was written, and stays quiet on the same file with the problem fixed."""

from __future__ import annotations

import pytest

from conftest import COFFEE, MIX, wide_task
from schemalog.formats.documents import load_kb
from schemalog.run.lint import ERROR, WARNING, Facts, lint_kb, lint_tree

LIMITS = dict(max_depth=64, max_nodes=100_000)


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)      # lint_text writes t.pl here: positions are refined from the file


def lint_text(text: str, name: str = "t.pl"):
    with open(name, "w") as handle:
        handle.write(text)
    return lint_kb(load_kb([name]), **LIMITS)


def codes(findings) -> list[str]:
    return [f.code for f in findings]


TAKE = """task(t).
object(spoon).
initial(hand.free).
schema(t, [(take(spoon), hand.free), (mix(spoon), {release})], spoon.used).
schema(take(spoon), [(a1(spoon), true), (grip(close), a1.done)], spoon.taken).
schema(mix(spoon), [(a2(spoon), true), (grip(open), a2.done)], spoon.used).
schema(a1(spoon), [], a1.done).
schema(a2(spoon), [], a2.done).
schema(grip(close), [], not hand.free).
schema(grip(open), [], hand.free).
"""


def test_a_releaser_atom_nothing_makes_true_is_an_error_at_its_place_with_a_suggestion():
    text = TAKE.format(release="spoon.takn")
    found = lint_text(text)
    assert codes(found) == ["unreachable-releaser"]
    f = found[0]
    line = text.splitlines()[3]
    assert f.severity == ERROR and (f.pos.line, f.pos.column) == (4, line.index("spoon.takn") + 1)
    assert "mix(spoon) can never be released: spoon.takn never holds" in f.message
    assert "did you mean spoon.taken?" in f.hint
    assert lint_text(TAKE.format(release="spoon.taken")) == ()


def test_a_negated_releaser_whose_atom_never_becomes_false():
    found = lint_text(TAKE.format(release="spoon.taken and not cup.full").replace(
        "initial(hand.free).", "initial(hand.free).\ninitial(cup.full)."))
    assert codes(found) == ["unreachable-releaser"]
    assert "not cup.full never holds" in found[0].message and "holds initially" in found[0].message
    freed = TAKE.format(release="spoon.taken and not cup.full").replace("initial(hand.free).",
                                                                         "initial(hand.free).\nfree(cup.full).")
    assert lint_text(freed) == ()


def test_an_atom_only_unreleasable_behaviours_make_true_names_them():
    # Nothing is true at the start: hand.free is made true only by grip(open), which never runs.
    found = lint_text(TAKE.format(release="spoon.taken").replace("initial(hand.free).", ""))
    assert codes(found) == ["unreachable-releaser"]
    assert "only grip(open) makes it true, and it can never run" in found[0].message
    assert "no initial/1" in found[0].hint


GRIPPER = """task(t).
initial(hand.free).
schema(t, [(move(cup), hand.free)], cup.moved).
schema(move(cup), [(a1(cup), true), (grip(close), a1.done), (a2(cup), not hand.free){last}], cup.moved).
schema(a1(cup), [], a1.done).
schema(a2(cup), [], a2.done).
schema(grip(close), [], not hand.free).
schema(grip(open), [], hand.free).
"""


def test_a_later_behaviour_that_undoes_an_earlier_ones_post_names_both():
    found = lint_text(GRIPPER.format(last=", (grip(open), a2.done)"))
    assert codes(found) == ["undone-post"]
    f = found[0]
    assert f.severity == ERROR and f.pos.line == 4
    assert "grip(open) undoes not hand.free, the post-condition of grip(close)" in f.message
    assert "livelock" in f.message
    assert codes(lint_text(GRIPPER.format(last=""))) == []


SHARED = """task(serve).
object(mug).  object(kettle).
schema(serve, [(fill(kettle), true), (pour(mug), kettle.filled)], mug.full).
schema(fill(kettle), [(approach(kettle), true), (grasp(kettle), {kettle})], kettle.filled).
schema(pour(mug), [(approach(mug), true), (tilt(mug), {mug})], mug.full).
{approach}
schema(grasp(_), [], grasp.done).
schema(tilt(_), [], tilt.done).
"""


def test_two_behaviours_with_one_post_that_nothing_undoes():
    found = lint_text(SHARED.format(kettle="approach.done", mug="approach.done",
                                    approach="schema(approach(_), [], approach.done)."))
    assert codes(found) == ["shared-post"]
    assert "approach(kettle) and approach(mug) have the same post-condition approach.done" in found[0].message
    assert found[0].pos.line == 6
    fixed = SHARED.format(kettle="kettle.near", mug="mug.near", approach="schema(approach(O), [], O.near).")
    assert lint_text(fixed) == ()


def test_one_sub_task_used_twice_and_a_parent_sharing_its_childs_post_are_not_shared_posts():
    assert lint_kb(load_kb([str(COFFEE)]), **LIMITS) == ()    # add(water) under coffee and tea


def test_a_sub_task_whose_post_its_behaviours_undo():
    text = GRIPPER.format(last="").replace("cup.moved).\nschema(a1", "cup.moved and hand.free).\nschema(a1")
    found = lint_text(text)
    assert codes(found) == ["post-not-produced"] and found[0].severity == WARNING
    assert "hand.free of move(cup) is not what its behaviours produce" in found[0].message


def test_releaser_cycles_among_siblings():
    text = """task(t).
schema(t, [(a, b.done), (b, a.done), (c, true)], t.done).
schema(a, [], a.done). schema(b, [], b.done). schema(c, [], c.done).
"""
    found = lint_text(text)
    assert codes(found) == ["releaser-cycle"] and found[0].severity == ERROR
    assert "the releasers of a, b (under t) form a cycle" in found[0].message
    assert lint_text(text.replace("(a, b.done)", "(a, c.done)")) == ()


def test_a_task_declared_twice():
    text = "task(t).\ntask(t).\nschema(t, [], t.done).\n"
    found = lint_text(text)
    assert codes(found) == ["duplicate-task"] and found[0].pos.line == 2
    assert "first at t.pl:1:1" in found[0].message
    assert lint_text(text.replace("task(t).\ntask(t).", "task(t).")) == ()


def test_a_schema_an_earlier_one_shadows():
    text = """task(t).
schema(t, [(take(water), true)], t.done).
schema(take(O), [], O.taken).
schema(take(water), [(a1, true)], water.taken).
schema(a1, [], a1.done).
"""
    found = lint_text(text)
    assert codes(found) == ["shadowed-schema"]
    assert found[0].severity == ERROR and found[0].pos.line == 4
    assert "take(water) is never used: the schema at t.pl:3:1 (take(O))" in found[0].message
    # The specific one first, then the general one: both are used, as in Prolog.
    swapped = text.replace("schema(take(O), [], O.taken).\nschema(take(water), [(a1, true)], water.taken).",
                           "schema(take(water), [(a1, true)], water.taken).\nschema(take(O), [], O.taken).")
    assert codes(lint_text(swapped)) == []


def test_a_schema_no_task_uses():
    text = "task(t).\nschema(t, [(a, true)], t.done).\nschema(a, [], a.done).\nschema(u, [(a, true)], u.done).\n"
    found = lint_text(text)
    assert codes(found) == ["unused-schema"] and found[0].pos.line == 4
    assert lint_text(text.replace("schema(t, [(a, true)]", "schema(t, [(u, true)]")) == ()


def test_an_argument_written_as_an_object_but_not_declared():
    text = """task(t).
object(cup).
schema(t, [(take(bowl), true), (fill(cup), bowl.taken)], t.done).
schema(take(bowl), [], bowl.taken).
schema(fill(cup), [], cup.full).
"""
    found = lint_text(text)
    assert codes(found) == ["undeclared-object"] and "declare object(bowl)" in found[0].hint
    assert lint_text(text.replace("object(cup).", "object(cup). object(bowl).")) == ()


def test_a_task_that_cannot_be_instantiated_is_an_error_finding():
    found = lint_text("task(t).\nschema(t, [(missing, true)], t.done).\n")
    assert codes(found) == ["load"] and "no schema for missing" in found[0].message


@pytest.mark.parametrize("path", [MIX, COFFEE])
def test_shipped_knowledge_is_clean(path):
    assert lint_kb(load_kb([str(path)]), **LIMITS) == ()


def test_a_wide_task_lints_clean_and_linear_passes_see_every_sibling():
    kb, tree = wide_task(5_000)
    assert lint_tree(tree, Facts(frozenset(), frozenset())) != []         # `go` is never true
    from schemalog.logic.parse import parse_term
    assert lint_tree(tree, Facts(frozenset({parse_term("go")}), frozenset())) == []


# Issue 35: actions that never run.

BREAD = """task(place(bread)).
object(bread). object(plate).
agent(gripper(_), gripper).
initial(hand.free).
schema(place(bread), [(subtask(take, bread), hand.free), (subtask(put, bread), bread.taken)], bread.placed).
schema(subtask(take, bread), [(a1(bread), true), (a2(bread), a1.done){close}], bread.taken).
schema(subtask(put, bread), [(a3(plate), true), (a4(plate), a3.done), (gripper(open), a4.done)], bread.placed).
schema(a1(bread), [], a1.done). schema(a2(bread), [], a2.done).
schema(a3(plate), [], a3.done). schema(a4(plate), [], a4.done).
schema(gripper(open), [], hand.free).
schema(gripper(close), [], not hand.free).
"""


def test_an_action_accomplished_from_the_start_and_a_take_without_its_close_are_warned():
    found = lint_text(BREAD.format(close=""))
    assert codes(found) == ["no-gripper-command", "dead-behaviour"]
    assert all(f.severity == WARNING for f in found)
    missing, dead = found
    assert "the learned sub-task subtask(take,bread) commands no gripper" in missing.message
    assert missing.pos.line == 6
    assert "gripper(open) never runs: its post-condition hand.free holds from the start" in dead.message
    line = BREAD.splitlines()[6]
    assert (dead.pos.line, dead.pos.column) == (7, line.index("gripper(open)") + 1)
    # the take closes the gripper: the open has something to undo, and both warnings go
    assert lint_text(BREAD.format(close=", (gripper(close), a2.done)")) == ()


def test_a_task_accomplished_from_the_start_is_one_warning_not_one_per_behaviour():
    found = lint_text(BREAD.format(close=", (gripper(close), a2.done)").replace(
        "initial(hand.free).", "initial(hand.free).\ninitial(bread.placed)."))
    assert codes(found) == ["dead-behaviour"]
    assert "the task place(bread) is accomplished from the start" in found[0].message


def test_a_post_that_may_be_false_at_the_start_is_no_dead_behaviour():
    # free/1: hand.free may or may not hold, so the open may have work to do
    found = lint_text(BREAD.format(close="").replace("initial(hand.free).", "free(hand.free)."))
    assert codes(found) == ["no-gripper-command"]
