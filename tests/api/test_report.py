"""schemalog.verify and its Report: proofs, counterexamples in behaviours' names, vacuity, limits."""

from __future__ import annotations

import subprocess
import sys

import pytest

import schemalog
from conftest import COFFEE, MIX


def test_a_proof_is_what_the_command_line_prints():
    task = schemalog.load(MIX).task()
    report = schemalog.verify(task, task.compress())
    assert (report.sound, report.complete, report.exhaustive, report.vacuous) == (True, True, True, False)
    assert report.proved and report.verdict == "proved" and report.exit_status == 0
    assert report.counterexample is None
    cli = subprocess.run([sys.executable, "-m", "schemalog", "verify", str(MIX)], capture_output=True, text=True)
    strip = lambda text: [line for line in text.splitlines() if " in 0." not in line and "explored" not in line]
    assert strip(report.text()) == strip(cli.stdout)
    assert report.as_json()["sound"] is True


def test_a_hand_edited_unsound_file_is_refuted_in_behaviours(tmp_path):
    written = tmp_path / "small.pl"
    schemalog.load(MIX).task().compress().save(written)
    text = written.read_text()
    edited = text.replace("(gripper(open), spoon.taken and not spoon.used and a7.done)",
                          "(gripper(open), spoon.taken and not spoon.used)")
    assert edited != text
    written.write_text(edited)
    small = schemalog.load(written).task()
    report = schemalog.verify(small.original, small)
    assert report.sound is False and report.verdict == "refuted" and report.exit_status == 1
    ce = report.counterexample
    assert ce.property == "soundness"
    assert ce.steps == ("a1_a2(spoon)", "gripper(close)") and ce.behaviour == "gripper(open)"
    assert ce.actions[0] == ("a1(spoon)", "a2(spoon)")
    assert "the original would not take gripper(open)" in ce.text()
    assert ce.text() in report.text()


def test_propagate_none_aliases_on_coffee_and_tea():
    task = schemalog.load(COFFEE).task()
    report = task.verify(task.compress("none"), states="all")
    ce = report.counterexample
    assert report.verdict == "refuted" and ce.behaviour == "a8_a9(coffee)" and ce.action == "a8(coffee)"
    assert ce.initial == ("coffee.taken",)


def test_a_task_that_cannot_complete_is_vacuous_not_proved():
    kb = schemalog.loads("task(t).\nschema(t, [(a, b.done)], a.done).\nschema(a, [], a.done).\n")
    task = kb.task()
    report = task.verify()
    assert report.vacuous and not report.proved and report.verdict == "vacuous" and report.exit_status == 1
    assert "cannot complete" in report.text()


def test_a_limit_never_buys_a_proof():
    task = schemalog.load(COFFEE).task()
    report = schemalog.verify(task, task.compress(), method="explicit", max_states=3, split=False)
    assert not report.exhaustive and not report.proved
    assert report.verdict == "inconclusive" and report.exit_status == 3
    assert "NOT a proof" in report.text()
    sampled = schemalog.verify(task, task.compress(), sample=5)
    assert not sampled.proved and sampled.verdict == "inconclusive"


def test_states_and_bad_options():
    task = schemalog.load(MIX).task()
    small = task.compress()
    one = schemalog.verify(task, small, states="hand.free")
    assert one.proved
    assert schemalog.verify(task, small, states=["hand.free"]).proved
    with pytest.raises(schemalog.SchemalogError, match="method"):
        schemalog.verify(task, small, method="magic")
    with pytest.raises(schemalog.SchemalogError):
        schemalog.verify(task, small, states="hand.free and")


def test_proofs_in_a_loop_leave_nothing_on_stderr(tmp_path):
    # The decision diagrams of a symbolic proof are freed before their manager, whatever the
    # collector does: dd.cudd printed "Still N nodes referenced upon shutdown" twice here when
    # a collection freed the model's cycle manager first.
    from conftest import ROOT

    task_file = tmp_path / "gen.pl"
    subprocess.run([sys.executable, "-m", "schemalog", "generate", "--depth", "5", "--children", "5", "--rd", "0.5",
                    "--seed", "1", "-o", task_file], check=True, capture_output=True)
    code = ("import gc, sys, schemalog\n"
            "gc.set_threshold(50_000, 20, 100)\n"
            "task = schemalog.load(sys.argv[1]).task()\n"
            "for _ in range(3):\n"
            "    report = schemalog.verify(task, task.compress())\n"
            "    gc.collect()\n"
            "print(report.verdict, report.raw.method)\n")
    out = subprocess.run([sys.executable, "-c", code, task_file], cwd=ROOT, capture_output=True, text=True,
                         timeout=300)
    assert (out.returncode, out.stdout, out.stderr) == (0, "proved symbolic\n", "")


def test_a_limit_that_hides_vacuity_is_no_proof(tmp_path):
    # a28(cup) waits for an atom nothing sets: the task cannot complete. With too few states to
    # find that out, the report must not call the compressed tree proved.
    stuck = tmp_path / "stuck.pl"
    stuck.write_text(COFFEE.read_text().replace("(a28(cup), a27.done)", "(a28(cup), a27.done and never.holds)"))
    task = schemalog.load(stuck).task()
    assert task.verify().verdict == "vacuous"
    report = schemalog.verify(task, task.compress(), max_states=200)
    assert not report.proved and report.verdict == "inconclusive" and report.exit_status == 3
    assert "whether the task itself can complete is not known" in report.text()
    cli = subprocess.run([sys.executable, "-m", "schemalog", "verify", str(stuck), "--max-states", "200"],
                         capture_output=True, text=True)
    assert cli.returncode == 3 and "no proof: whether the task itself can complete" in cli.stdout
