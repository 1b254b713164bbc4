"""`schemalog diff A.pl B.pl` on task knowledge: two versions of the paper's Figure 2 task, and
the task against the compressed form `schemalog compress` wrote, compared on the verifier's runs."""

from __future__ import annotations

import json
import subprocess
import sys

from conftest import ROOT

MIX = ROOT / "kb" / "tasks" / "mix_with_spoon.pl"


def run(*args, cwd):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def versions(tmp_path, old: str, new: str):
    text = MIX.read_text(encoding="utf-8")
    assert old in text
    (tmp_path / "a.pl").write_text(text, encoding="utf-8")
    (tmp_path / "b.pl").write_text(text.replace(old, new, 1), encoding="utf-8")


def test_a_releaser_made_weaker_lets_b_do_more_and_the_run_shows_where(tmp_path):
    versions(tmp_path, "(a4(cup), a3.done)", "(a4(cup), true)")
    r = run("diff", "a.pl", "b.pl", cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0] == "a.pl -> b.pl: behaviour changed"
    assert lines[1] == "direction: every run of A is a run of B (B only adds behaviour), not the converse"
    # the place is the schema/3 clause of the behaviour, by file:line:col
    clause = next(i for i, t in enumerate((tmp_path / "b.pl").read_text().splitlines(), 1)
                  if t.startswith("schema(subtask(mix, spoon)"))
    assert f"  b.pl:{clause}:1: B releases a4(cup) on true instead of a3.done" in lines
    assert "then the compressed tree takes a4(cup)" in r.stdout and "(state: a1.done, a2.done, spoon.taken)" in r.stdout


def test_the_same_task_is_the_same_behaviour_and_a_compression_is_said_as_such(tmp_path):
    versions(tmp_path, "spoon.used).", "spoon.used).")
    r = run("diff", "a.pl", "b.pl", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    assert (report["equal"], report["direction"], report["changes"]) == (True, "equal", [])
    c = run("compress", MIX, "-o", tmp_path / "small.pl", cwd=tmp_path)
    assert c.returncode == 0, c.stderr
    r = run("diff", MIX, "small.pl", cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.splitlines()[0].endswith("small.pl: a sound and complete compression")
    assert "B merges a1(spoon), a2(spoon) into a1_a2(spoon)" in r.stdout


def test_bt_options_and_pictures_are_refused_for_task_knowledge(tmp_path):
    versions(tmp_path, "spoon.used).", "spoon.used).")
    r = run("diff", "a.pl", "b.pl", "--profile", "nav2", cwd=tmp_path)
    assert r.returncode == 2 and "applies to BT.CPP trees" in r.stderr
    r = run("diff", "a.pl", "b.pl", "-o", tmp_path / "d.svg", cwd=tmp_path)
    assert r.returncode == 2 and "text, JSON or Markdown" in r.stderr and not (tmp_path / "d.svg").exists()
