"""schemalog.Task: compressing, writing and exporting a task from Python."""

from __future__ import annotations

import ast
import xml.etree.ElementTree as ET

import pytest

import schemalog
from conftest import COFFEE, MIX


@pytest.fixture(scope="module")
def mix():
    return schemalog.load(MIX).task()


def test_compress_gives_the_papers_figures_and_provenance(mix):
    small = mix.compress()
    assert (len(mix), len(small), mix.depth) == (12, 6, 3)
    assert small.original is mix and small.compressed and not mix.compressed and mix.original is mix
    c = small.compression
    assert (c.propagate, c.nodes_before, c.nodes_after, c.depth_before) == ("full", 12, 6, 3)
    assert c.reduction_degree == pytest.approx(6 / 9)
    assert c.figures() == "Bi = 12, Bm = 6, D = 3, RD = (Bi - Bm) / (Bi - D) = 0.67"
    assert small.compress("pre").compression.propagate == "pre"


def test_bad_options_are_usage_errors(mix):
    with pytest.raises(schemalog.UsageError, match="propagate 'most'"):
        mix.compress("most")
    with pytest.raises(schemalog.UsageError, match="sympy_budget"):
        mix.compress(sympy_budget=40)


def test_a_saved_compressed_task_loads_back_with_its_original(mix, tmp_path):
    small = mix.compress()
    path = tmp_path / "small.pl"
    assert small.save(path) == "pl"
    again = schemalog.load(path).task()
    assert again.compressed and len(again) == 6 and len(again.original) == 12
    assert again.original.tree == mix.tree
    assert schemalog.verify(again.original, again).proved


def test_save_refuses_to_overwrite_what_was_read(tmp_path):
    source = tmp_path / "mix.pl"
    source.write_text(MIX.read_text())
    task = schemalog.load(source).task()
    with pytest.raises(schemalog.UsageError, match="would overwrite an input file"):
        task.compress().save(source)
    assert source.read_text() == MIX.read_text()
    with pytest.raises(schemalog.UsageError, match="say the format"):
        task.save(tmp_path / "out.unknown")


def test_the_exports_are_what_the_command_line_writes(mix, tmp_path):
    import subprocess
    import sys

    small = mix.compress()
    xml = small.to_btcpp()
    assert ET.fromstring(xml).get("BTCPP_format") == "4"
    module = small.to_py_trees()
    ast.parse(module)
    cli = subprocess.run([sys.executable, "-m", "schemalog", "export", str(MIX), "--to", "btcpp", "--compressed"],
                         capture_output=True, text=True, check=True).stdout
    assert cli == xml
    assert small.to_seed().startswith("%") and "origins" in small.to_prolog()
    assert small.to_yaml() and '"task"' in small.to_json() and small.to_dot().startswith("digraph")


def test_run_completes_the_task_from_python(mix):
    run = mix.compress().run()
    assert run.completed and run.status == "completed"
    assert run.trace[0] == "a1(spoon)" and len(run.trace) == 9
    assert run.text().splitlines()[0].startswith("run use(spoon): compressed (propagate full) tree of 6")


def test_run_with_a_scene_and_failures():
    from conftest import ROOT

    task = schemalog.load(COFFEE).task()
    run = task.compress().run(ROOT / "kb" / "scenes" / "kitchen.yaml", seed=7, fail=["a5(cup)"], fail_times=1)
    assert run.completed
    assert any(d.failed is not None for d in run.decisions)
    assert run.as_json()["scene"] and run.notes == ()
    with pytest.raises(schemalog.SchemalogError, match="no position"):
        schemalog.loads("task(t).\nschema(t, [(a(x), true)], a.done).\nschema(a(x), [], a.done).\n").task().run(
            ROOT / "kb" / "scenes" / "kitchen.yaml")


def test_a_started_run_yields_each_decision_once(mix):
    run = mix.start()
    assert repr(run) == "<Run use(spoon): not started>"
    first = next(iter(run))
    assert first.index == 1
    assert [d.index for d in run] == list(range(2, 10))    # the rest, not again from the start
    assert run.completed and list(run) == [] and len(run.decisions) == 9


def test_reading_a_half_iterated_run_does_not_advance_it(mix):
    """Issue 45: reading .status, .trace or the repr of a run half iterated ran it to the end."""
    run = mix.start()
    assert (run.status, run.completed, run.trace, run.decisions) == ("not started", False, [], [])
    assert repr(run) == "<Run use(spoon): not started>" and len(run.decisions) == 0
    first, second = next(run), next(run)
    for _ in range(2):                      # read twice: nothing moves
        assert run.status == "running" and not run.completed
        assert run.trace == ["a1(spoon)", "a2(spoon)"] and [d.index for d in run.decisions] == [1, 2]
        assert repr(run) == "<Run use(spoon): running, 2 decisions so far, 2 actions>"
        assert run.reason.startswith("2 decisions taken so far")
        assert run.text().rstrip().endswith("running: 2 decisions taken so far; iterate the run for the next, "
                                            "or call finish() for the rest")
        assert run.as_json()["status"] == "running" and len(run.as_json()["decisions"]) == 2
    assert next(run).index == 3             # the run goes on where it was
    assert run.finish().status == "completed" and len(run.decisions) == 9
    assert repr(run) == "<Run use(spoon): completed, 9 actions>"


def test_a_sub_task_by_name():
    kb = schemalog.load(COFFEE)
    coffee = kb.task("preparecoffee")
    assert coffee.name == "preparecoffee" and len(coffee) < len(kb.task())


@pytest.mark.parametrize("path", [MIX, COFFEE])
def test_a_compressed_file_compressed_again_is_proved_against_its_original(path, tmp_path):
    """What a user who iterates does: compress, save, load, compress and prove (issue 46: an
    internal error). The proof is against the original the file was compressed from."""
    task = schemalog.load(path).task()
    saved = tmp_path / "small.pl"
    task.compress().save(saved)
    again = schemalog.load(saved).task()
    report = schemalog.verify(again, again.compress())
    assert report.proved
    assert len(report.tasks[0]) == len(task)           # the rebuilt original, not the merged tree
    assert any("is itself compressed" in n for n in report.notes)
    assert again.compress().original.tree == task.tree
