"""What the command line calls in the API layer (issue 34: cli/ only parses, calls and
prints), called directly: the same answers without a command line."""

from __future__ import annotations

from pathlib import Path

import pytest

import schemalog
from schemalog.api.check import Checking, errors
from schemalog.api.convert import Conversion
from schemalog.api.generate import check_shape, generated
from schemalog.api.repl import open_workspace, run_lines, state_text, tree_named
from schemalog.errors import SchemalogError, UsageError

ROOT = Path(__file__).resolve().parents[2]
MIX = str(ROOT / "kb/tasks/mix_with_spoon.pl")
COFFEE = str(ROOT / "kb/tasks/prepare_coffee_and_tea.pl")
SEED = str(ROOT / "examples/coffee_and_tea_seed.prolog")


def test_check_instantiates_every_task_and_lints_them():
    checked = schemalog.load(MIX).check()
    assert checked.schemas == 12 and [len(t) for t in checked.tasks] == [12]
    assert checked.findings == () and checked.ok and checked.errors == 0
    assert schemalog.load(MIX).check(lint=False).findings is None


def test_check_finds_lints_errors(tmp_path):
    path = tmp_path / "stuck.pl"
    path.write_text("task(stuck).\nschema(stuck, [(s1, true), (s2, s1.done and lid.open)], s2.done).\n"
                    "schema(s1, [], s1.done).  schema(s2, [], s2.done).\n")
    checked = schemalog.load(path).check()
    assert not checked.ok and checked.errors == errors(checked.findings) >= 1


def test_checking_names_a_task_as_asked():
    checking = Checking(schemalog.load(COFFEE), "preparecoffee")
    assert [(name, len(task)) for name, task in checking.tasks()] == [("preparecoffee", 37)]
    assert checking.lint(unused=False) == ()


def test_decompress_restores_the_original_of_a_compressed_file(tmp_path):
    task = schemalog.load(COFFEE).task()
    out = tmp_path / "small.pl"
    task.compress().save(out)
    small = schemalog.load(out).task()
    restored = small.decompress()
    assert len(small) == 33 and len(restored) == 63 and restored.notes == ()
    assert restored.to_json() == task.to_json()
    again = task.decompress()
    assert len(again) == 63 and "carries no provenance" in again.notes[0]


def test_text_takes_the_header_asked_for():
    task = schemalog.load(MIX).task()
    assert task.text("pl", header="Mine.").startswith("% Mine.")
    assert "written by schemalog" in task.text("pl")


def test_generated_reaches_the_figures_generate_prints():
    task = generated(4, 2, 0.5, 1)
    assert task.task == "b1" and task.figures == "Bi = 15, D = 4; compressed: Bm = 9, RD = 0.55 (asked 0.50)"
    assert task.shortfall is None and "objects:" in task.scene
    assert len(schemalog.loads(task.text).task()) == 15
    with pytest.raises(UsageError, match="at most"):
        check_shape(10_000, 2)


def test_conversion_of_seed_knowledge_declares_the_task():
    conversion = Conversion(SEED)
    converted = conversion.convert(task="prepareboth")
    assert "task(prepareboth)." in converted.text and "tasks: prepareboth" in converted.what
    with pytest.raises(SchemalogError, match="is not a task of"):
        Conversion(SEED).convert(task="nope")


def test_the_repl_commands_over_an_opened_workspace():
    ws = open_workspace([MIX], state="hand.free")
    view, kind = tree_named(ws, "use(spoon)")
    lines = run_lines(ws, view, kind)
    assert lines[0].startswith("% run use(spoon), original tree, from hand.free")
    assert lines[-1].startswith("% completed") and "spoon.used" in state_text(ws)
    with pytest.raises(UsageError, match="is not a term"):
        open_workspace([MIX], state="a1(")
