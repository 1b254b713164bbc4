"""End to end: the `schemalog` command as a user runs it."""

import json
import os
import re
import signal
import stat
import subprocess
import sys
import time

import pytest

from conftest import COFFEE, MIX, ROOT, SEED_COFFEE, SLOW_WRITE, read_fifo_in_thread


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=120)


def test_check_shipped_tasks():
    r = run("check", MIX)
    assert r.returncode == 0, r.stderr
    assert "use(spoon) (12 behaviours, depth 3)" in r.stdout
    r = run("check", COFFEE)
    assert "prepareboth (63 behaviours, depth 5)" in r.stdout


def test_show_json_reports_the_papers_figures():
    data = json.loads(run("show", COFFEE, "--task", "prepareboth", "--json").stdout)
    assert (data["nodes"], data["depth"], data["task"]) == (63, 5, "prepareboth")
    data = json.loads(run("show", MIX, "--format", "json").stdout)
    assert (data["nodes"], data["depth"]) == (12, 3)


def test_show_text_and_dot():
    r = run("show", MIX)
    assert r.returncode == 0 and "use(spoon): 12 behaviours, depth 3" in r.stdout
    assert "a3(cup)  pre: true  post: a3.done" in r.stdout
    dot = run("show", MIX, "--format", "dot").stdout
    assert dot.startswith("digraph") and dot.count(" -> ") == 11


@pytest.mark.parametrize("fmt", ["pl", "yaml"])
def test_show_as_knowledge_loads_back_to_the_same_tree(tmp_path, fmt):
    out = tmp_path / f"tree.{fmt}"
    assert run("show", COFFEE, "--format", fmt, "-o", out).returncode == 0
    again = json.loads(run("show", out, "--json").stdout)
    original = json.loads(run("show", COFFEE, "--json").stdout)
    assert again == original


def test_convert_seed_then_show(tmp_path):
    out = tmp_path / "task.pl"
    r = run("convert", SEED_COFFEE, "-o", out, "--task", "prepareboth")
    assert r.returncode == 0, r.stderr
    assert "skipped what is not task knowledge" in r.stderr
    text = out.read_text()
    assert text.startswith("% Converted by schemalog from the SEED long-term memory")
    assert "schema(add(OBJ),\n       [ (subtask(take,OBJ), kukahand.free)," in text
    data = json.loads(run("show", out, "--json").stdout)
    assert (data["nodes"], data["depth"]) == (63, 5)


def test_convert_pl_yaml_pl_round_trip(tmp_path):
    y, p = tmp_path / "t.yaml", tmp_path / "t.pl"
    assert run("convert", MIX, "-o", y).returncode == 0
    assert run("convert", y, "-o", p).returncode == 0
    assert run("convert", MIX).stdout.split("\n", 2)[2] == p.read_text().split("\n", 2)[2]


def test_convert_refuses_to_overwrite_its_input(tmp_path):
    src = tmp_path / "t.pl"
    src.write_text(MIX.read_text())
    r = run("convert", src, "-o", src)
    assert r.returncode == 2 and "would overwrite an input file" in r.stderr
    assert src.read_text() == MIX.read_text()


BAD = {
    "syntax.pl": ("schema(a, [(b, true)], a.done).\nschema(b, [], b.done)\n", "syntax.pl:2:22: error: unexpected end of file"),
    "operator.pl": ("foo(a) :- bar ==> baz.\n", "operator.pl:1:15: error: syntax error"),
    "brackets.pl": ("schema(a, [(b, true), a.done).\n", "brackets.pl:1:29: error: syntax error: unexpected ')'"),
    "notlist.pl": ("task(a).\nschema(a, notalist, a.done).\n", "notlist.pl:2:1: error: schema a: the sub-task list must be a list"),
    "releaser.pl": ("schema(a, [(b, 42)], a.done).\nschema(b, [], b.done).\n", "releaser.pl:1:1: error: schema a: the releaser of b is not a condition"),
    "cycle.pl": ("task(a).\nschema(a, [(b, true)], a.done).\nschema(b, [(a, true)], b.done).\n", "cycle.pl:3:1: error: recursive schema: a -> b -> a"),
    "undefined.pl": ("task(a).\nschema(a, [(b, true)], a.done).\n", "undefined.pl:2:1: error: no schema for b"),
    "deep.pl": ("x(" + "f(" * 10000 + "a" + ")" * 10000 + ").\n", "deep.pl:1:4002: error: brackets nested deeper than 2000 levels"),
    # issue 45: a task with variables had no position; a clause left open was reported at the
    # next clause, with no word of the one that was never closed
    "nonground.pl": ("object(plate).\n\ntask(set(Table)).\nschema(set(T), [], T.laid).\n",
                     "nonground.pl:3:1: error: the task set(Table) has variables: name a ground task"),
    "unclosed.pl": ("task(a).\n\nschema(a,\n       [ (b, true) ],\n       a.done\n\nschema(b, [], b.done).\n",
                    "unclosed.pl:7:1: error: syntax error: unexpected 'schema'; expected ')', ',' or an operator; "
                    "the clause from unclosed.pl:3:1 is still open here (a missing ')' or final '.' there?)"),
    "unfinished.pl": ("task(a).\nschema(a,\n       [ (b, true) ],\n       a.done\n",
                      "unfinished.pl:4:14: error: unexpected end of file: a clause is not finished (missing ')', ']' "
                      "or the final '.'?); the clause from unfinished.pl:2:1 is still open"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_gives_one_located_message(tmp_path, name):
    text, expected = BAD[name]
    path = tmp_path / name
    path.write_text(text)
    r = run("check", name, cwd=tmp_path)
    assert r.returncode == 1
    assert r.stderr.startswith(expected), r.stderr
    assert "Traceback" not in r.stderr and r.stdout == ""
    assert path.read_text() == text


def test_binary_garbage_and_missing_file_and_huge_file(tmp_path):
    garbage = tmp_path / "garbage.pl"
    garbage.write_bytes(bytes(range(256)) * 10)
    r = run("check", garbage)
    assert r.returncode == 1 and "binary data" in r.stderr and "garbage.pl:1:1" in r.stderr
    r = run("show", tmp_path / "missing.pl")
    assert r.returncode == 1 and "no such file" in r.stderr
    huge = tmp_path / "huge.pl"
    with open(huge, "wb") as f:
        f.truncate(50 * 2**20)  # 50 MiB, refused by size before reading
    r = run("check", huge)
    assert r.returncode == 1 and "50.0 MiB, over the 16.0 MiB limit" in r.stderr


def test_unknown_task_lists_the_known_ones():
    r = run("show", MIX, "--task", "nothere")
    assert r.returncode == 1
    assert "unknown task nothere" in r.stderr and "tasks here: use(spoon)" in r.stderr


@pytest.mark.parametrize("args", [["show"], ["show", MIX, "--task", "a(("], ["frobnicate"],
                                  ["show", MIX, "--max-depth", "0"], [],
                                  ["verify", MIX, "--sample", "1000000001"]])
def test_usage_errors_exit_2(args):
    r = run(*args)
    assert r.returncode == 2 and "Traceback" not in r.stderr


def test_failed_output_leaves_no_partial_file(tmp_path):
    out = tmp_path / "out.json"
    bad = tmp_path / "bad.pl"
    bad.write_text("task(a).\nschema(a, [(b, true)], a.done).\n")
    r = run("show", bad, "--json", "-o", out)
    assert r.returncode == 1 and not out.exists() and list(tmp_path.iterdir()) == [bad]


# --- compression -------------------------------------------------------------

def test_compress_prints_both_trees_and_the_figures():
    r = run("compress", MIX, "--propagate", "pre")
    assert r.returncode == 0, r.stderr
    assert "Bi = 12, Bm = 6, D = 3, RD = (Bi - Bm) / (Bi - D) = 0.67" in r.stdout
    assert "a3_a4_a5_a6_a7(cup)" in r.stdout and "a3(cup)" in r.stdout


def test_compress_json_reports_the_papers_figures():
    data = json.loads(run("compress", COFFEE, "--task", "prepareboth", "--json").stdout)
    assert (data["nodes_before"], data["nodes_after"]) == (63, 33)
    assert (data["depth_before"], data["depth_after"]) == (5, 5)
    assert abs(data["reduction_degree"] - 30 / 58) < 1e-3
    take = data["tree"]["children"][0]["children"][0]["children"][0]
    assert take["label"] == "subtask(take_pour,water)" and take["k"] == 2
    assert take["merged_from"] == ["subtask(take,water)", "subtask(pour,water)"]
    assert take["pre"] == "kukahand.free or water.taken"


@pytest.mark.parametrize("mode, a1a2", [("full", "hand.free and not spoon.taken"), ("pre", "hand.free"),
                                        ("none", "true")])
def test_propagate_modes(mode, a1a2):
    data = json.loads(run("compress", MIX, "--propagate", mode, "--json").stdout)
    assert data["tree"]["children"][0]["children"][0]["pre"] == a1a2


def test_compress_to_file_then_check_show_decompress(tmp_path):
    out = tmp_path / "out.pl"
    assert run("compress", COFFEE, "-o", out).returncode == 0
    assert out.read_text().startswith("% Compressed by schemalog (Algorithm 1, propagate full)")
    assert "prepareboth (33 behaviours, depth 5)" in run("check", out).stdout
    restored = json.loads(run("decompress", out, "--json").stdout)
    assert restored == json.loads(run("show", COFFEE, "--json").stdout)
    again = json.loads(run("compress", out, "--json").stdout)  # idempotent through the file
    assert (again["nodes_before"], again["nodes_after"]) == (63, 33)
    y = tmp_path / "out.yaml"
    assert run("compress", COFFEE, "-o", y).returncode == 0
    assert json.loads(run("decompress", y, "--json").stdout) == restored


def test_compress_dot_draws_figure_2_before_and_after():
    dot = run("compress", MIX, "--format", "dot").stdout
    assert "cluster_original" in dot and "cluster_aliased" in dot and "cluster_merged" in dot
    assert dot.count("[label=<") == 12 + 6 + 6      # learned, merged with aliasing, merged with propagation
    assert dot.count("a3_a4_a5_a6_a7(cup)") == 2 and dot.count("aliased</b>") == 1
    none = run("compress", MIX, "--format", "dot", "--propagate", "none").stdout
    assert "cluster_aliased" not in none and none.count("[label=<") == 12 + 6


def test_decompress_of_an_original_says_there_is_nothing_to_undo():
    r = run("decompress", MIX, "--json")
    assert r.returncode == 0 and "carries no provenance" in r.stderr
    assert json.loads(r.stdout)["nodes"] == 12


def test_compress_notes_a_releaser_cycle(tmp_path):
    src = tmp_path / "cycle.pl"
    src.write_text("task(t).\nschema(t, [(a(x), b.done), (b(x), a.done)], t.done).\n"
                   "schema(a(x), [], a.done).\nschema(b(x), [], b.done).\n")
    r = run("compress", src, "--json")
    assert r.returncode == 0 and "note: releasers form a cycle" in r.stderr
    assert json.loads(r.stdout)["nodes_after"] == 3


def test_compress_bad_options_are_usage_errors():
    assert run("compress", MIX, "--propagate", "sideways").returncode == 2
    assert run("compress", MIX, "--sympy-budget", "0").returncode == 2


def test_written_trees_keep_initial_state_and_no_merge(tmp_path):
    src = tmp_path / "protected.pl"
    src.write_text(MIX.read_text() + "\nno_merge(a2(spoon)).\n")
    out, again = tmp_path / "c.pl", tmp_path / "d.pl"
    assert run("compress", src, "-o", out).returncode == 0
    text = out.read_text()
    assert "initial(hand.free)." in text and "no_merge(a2(spoon))." in text
    first = json.loads(run("compress", src, "--json").stdout)["nodes_after"]
    assert json.loads(run("compress", out, "--json").stdout)["nodes_after"] == first  # still protected
    assert run("decompress", out, "-o", again).returncode == 0
    assert "initial(hand.free)." in again.read_text()


def test_sympy_budget_is_capped():
    r = run("compress", MIX, "--sympy-budget", "16")
    assert r.returncode == 2 and "at most 12" in r.stderr


def test_a_task_with_variables_is_refused():
    r = run("compress", COFFEE, "--task", "add(X)", "--json")
    assert r.returncode == 1 and "has variables: name a ground task" in r.stderr and r.stdout == ""


def test_output_never_overwrites_a_consulted_file(tmp_path):
    (tmp_path / "m.pl").write_text("object(cup).\n")
    (tmp_path / "inc.pl").write_text(":- [m].\n" + MIX.read_text())
    r = run("convert", "inc.pl", "-o", "m.pl", cwd=tmp_path)
    assert r.returncode == 2 and "would overwrite an input file" in r.stderr
    assert (tmp_path / "m.pl").read_text() == "object(cup).\n"


def test_consult_cycle_is_named(tmp_path):
    (tmp_path / "a.pl").write_text("task(t).\n:- [b].\n")
    (tmp_path / "b.pl").write_text(":- [a].\n")
    r = run("check", "a.pl", cwd=tmp_path)
    assert r.returncode == 1 and "consult cycle" in r.stderr and "b.pl:1:1" in r.stderr


def test_yaml_item_errors_point_into_the_yaml_file(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("schemalog: 1\nitems:\n- task: t\n- schema: t\n  subtasks:\n  - {behaviour: 'a(', releaser: x.y}\n"
                   "  post: t.done\n")
    r = run("check", bad)
    assert r.returncode == 1 and r.stderr.startswith(f"{bad}:4:3: error: items[1]:")
    assert "Traceback" not in r.stderr


@pytest.mark.parametrize("command", ["check", "lint", "run", "convert"])
def test_a_misspelt_yaml_key_is_refused_where_it_was_written(tmp_path, command):
    """`releasr:` was dropped: the fork's releaser became `true`, and check and lint said ok."""
    task = tmp_path / "table.yaml"
    task.write_text("schemalog: 1\nitems:\n- task: lay(dinner)\n- initial: hand.free\n- schema: lay(dinner)\n"
                    "  subtasks:\n  - behaviour: place(plate)\n    releaser: hand.free\n"
                    "  - behaviour: place(fork)\n    releasr: plate.placed\n  post: dinner.laid\n"
                    "- {schema: place(plate), post: plate.placed}\n- {schema: place(fork), post: fork.placed}\n")
    r = run(command, task, *(["-o", tmp_path / "out.pl"] if command == "convert" else []))
    assert r.returncode == 1, r.stdout
    shown = r.stdout + r.stderr                     # lint lists its findings on standard output
    assert (f"{task}:10:5: error: items[2].subtasks[1]: unknown key `releasr`; did you mean `releaser`?"
            in shown.splitlines()[0])
    if command != "lint":                           # a finding is one line, without the source
        assert "    releasr: plate.placed\n        ^" in shown
    assert not (tmp_path / "out.pl").exists()


def test_seed_import_declares_each_gripper_pattern_once(tmp_path):
    out = tmp_path / "t.pl"
    run("convert", SEED_COFFEE, "-o", out)
    assert out.read_text().count("agent(gripper(_),gripper).") == 1


# --- run: the attentional executive ------------------------------------------

KITCHEN = ROOT / "kb" / "scenes" / "kitchen.yaml"
FIG2_SCENE = ROOT / "kb" / "scenes" / "mix_with_spoon.yaml"


def test_run_prints_decisions_and_a_summary():
    r = run("run", COFFEE, "--task", "prepareboth", "--scene", KITCHEN, "--compressed")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("run prepareboth: compressed (propagate full) tree of 33 behaviours")
    assert "   1  a1_a2(water)" in r.stdout and "      - a1(water)" in r.stdout   # merged, expanded
    assert "runner-up" in lines[2] and " e " in lines[2]
    assert "completed: prepareboth is accomplished (spoon.used and tea.used)" in r.stdout
    assert "16 decisions, 36 actions; time per decision (incremental): mean" in r.stdout


def test_run_says_which_of_two_behaviours_of_one_label_won_and_which_came_second():
    r = run("run", COFFEE, "--task", "prepareboth", "--scene", KITCHEN)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert re.match(r" +1  a1\(water\) +e [0-9.]+ +runner-up a1\(water\) ", lines[2])
    assert lines[3] == "      (winner: in preparecoffee; runner-up: in preparetea)"
    r = run("run", COFFEE, "--task", "prepareboth", "--scene", KITCHEN, "--json")
    first, tenth = json.loads(r.stdout)["decisions"][0:10:9]
    assert (first["where"], first["runner_up"]["where"]) == ("in preparecoffee", "in preparetea")
    assert first["behaviour"] == first["runner_up"]["behaviour"] == "a1(water)"
    assert tenth["behaviour"] != tenth["runner_up"]["behaviour"] and tenth["where"] is None


def test_run_without_a_scene_says_so_in_words():
    r = run("run", MIX)
    assert r.returncode == 0, r.stderr
    header = r.stdout.splitlines()[0]
    assert header.endswith("; no scene (neutral distances)") and "scene no scene" not in r.stdout
    assert run("run", MIX, "--scene", FIG2_SCENE).stdout.splitlines()[0].endswith("; scene mix with spoon")


def test_run_json_for_both_selectors_and_trees():
    traces = {}
    for selector in ("scan", "incremental"):
        for compressed in ((), ("--compressed",)):
            r = run("run", COFFEE, "--scene", KITCHEN, "--json", "--selector", selector, *compressed,
                    "--seed", "3", "--jitter", "0.1")
            assert r.returncode == 0, r.stderr
            data = json.loads(r.stdout)
            assert data["completed"] is True and data["status"] == "completed"
            assert len(data["decision_times"]) == len(data["decisions"])
            traces[selector, bool(compressed)] = data["trace"]
            first = data["decisions"][0]
            assert set(first) >= {"behaviour", "emphasis", "runner_up", "executed", "seconds", "hand"}
    assert traces["scan", False] == traces["incremental", False] and len(traces["scan", False]) == 36
    assert traces["scan", True] == traces["incremental", True]


def test_run_with_another_state_and_a_failing_action():
    r = run("run", MIX, "--scene", FIG2_SCENE, "--state", "hand.free, spoon.taken")
    assert r.returncode == 0 and "   1  a3(cup)" in r.stdout
    r = run("run", MIX, "--scene", FIG2_SCENE, "--fail", "a5(cup)")
    assert r.returncode == 1
    assert "FAILED: the robot did not complete a5(cup)" in r.stdout
    assert "stuck: nothing is enabled" in r.stdout and "a5(cup): its command failed 3 times; inhibited" in r.stdout
    r = run("run", MIX, "--scene", FIG2_SCENE, "--fail", "a5(cup)", "--fail-times", "1", "--compressed",
            "--recovery", "resume")
    assert r.returncode == 0 and "- a5(cup) (failed)" in r.stdout and "(skipped: accomplished)" in r.stdout


def test_run_reports_bad_input_without_traceback(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text("end_effector: [0, 0, 0.4]\nobjects:\n  spoon: [0.3, near, 0]\n")
    r = run("run", MIX, "--scene", scene)
    assert r.returncode == 1 and f"{scene}:3:16: error: a coordinate of the position of spoon" in r.stderr
    scene.write_text("end_effector: [0, 0, 0.4]\nobjects:\n  spoon: [0.3, 0.1, 0]\n")
    r = run("run", MIX, "--scene", scene)
    assert r.returncode == 1 and "has no position for cup, which a3(cup) acts on" in r.stderr
    assert "mix_with_spoon.pl:" in r.stderr     # where the behaviour is defined
    r = run("run", MIX, "--state", "hand.fre")
    assert "warning: --state names hand.fre, which no condition of use(spoon) reads or sets" in r.stderr
    assert r.returncode == 1 and "stuck:" in r.stdout
    r = run("run", MIX, "--max-decisions", "2")
    assert r.returncode == 1 and "decision limit: no completion after 2 decisions" in r.stdout
    for bad in (("--seed", "1"), ("--selector", "fast"), ("--state", "hand.free(")):
        r = run("run", MIX, *bad)
        assert r.returncode == 2 and "Traceback" not in r.stderr


def test_run_output_file_is_written_and_inputs_are_protected(tmp_path):
    out = tmp_path / "run.json"
    r = run("run", MIX, "--scene", FIG2_SCENE, "--json", "-o", out)
    assert r.returncode == 0 and json.loads(out.read_text())["trace"][0] == "a1(spoon)"
    r = run("run", MIX, "--json", "-o", MIX)
    assert r.returncode == 2 and "would overwrite an input file" in r.stderr


def test_run_a_seed_file_and_a_compressed_file(tmp_path):
    r = run("run", SEED_COFFEE, "--task", "prepareboth", "--scene", KITCHEN)
    assert r.returncode == 1 and "declares no initial state (initial/1)" in r.stderr
    r = run("run", SEED_COFFEE, "--task", "prepareboth", "--scene", KITCHEN, "--state", "kukahand.free")
    assert r.returncode == 0 and "36 decisions, 36 actions" in r.stdout
    out = tmp_path / "c.pl"
    assert run("compress", COFFEE, "-o", out).returncode == 0
    r = run("run", out, "--scene", KITCHEN, "--json")
    data = json.loads(r.stdout)
    assert r.returncode == 0 and data["tree"] == "compressed" and data["behaviours"] == 33
    assert len(data["decisions"]) == 16 and len(data["trace"]) == 36


def test_run_review_regressions(tmp_path):
    compressed = tmp_path / "c.pl"
    assert run("compress", COFFEE, "-o", compressed).returncode == 0
    # a sub-task of a compressed file runs in the world rebuilt from its children's provenance
    r = run("run", compressed, "--task", "preparecoffee", "--scene", KITCHEN)
    assert r.returncode == 0 and "compressed tree" in r.stdout and "27 actions" in r.stdout
    r = run("run", compressed, "--task", "subtask(take_pour,water)")
    assert r.returncode == 1 and "is a merged behaviour" in r.stderr
    # the scene is an input too
    scene = tmp_path / "s.yaml"
    scene.write_text(FIG2_SCENE.read_text())
    r = run("run", MIX, "--scene", scene, "-o", scene)
    assert r.returncode == 2 and scene.read_text() == FIG2_SCENE.read_text()
    # an output that cannot be written is refused before running, as a usage error
    r = run("run", MIX, "-o", tmp_path)
    assert r.returncode == 2 and "is a directory" in r.stderr and "internal error" not in r.stderr
    # a non-finite importance is refused where it is written
    bad = tmp_path / "nan.pl"
    bad.write_text("task(t).\nschema(t, [(a, true, 1.5NaN)], a.done).\nschema(a, [], a.done).\n")
    r = run("run", bad)
    assert r.returncode == 1 and f"{bad}:2:1:" in r.stderr and "finite number" in r.stderr
    # --fail on a composite, --propagate without --compressed: said
    r = run("run", MIX, "--fail", "subtask(take,spoon)", "--propagate", "pre")
    assert "no action (leaf behaviour)" in r.stderr and "--propagate applies with --compressed" in r.stderr
    assert run("run", MIX, "--state", "").returncode == run("run", MIX, "--state", "not a.b").returncode == 2


# --- verify -----------------------------------------------------------------

def test_verify_proves_full_propagation_and_refutes_the_papers_rule():
    r = run("verify", COFFEE, "--task", "prepareboth")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "soundness (no perceptual aliasing): holds" in r.stdout
    assert "result: the compressed tree is sound and complete (exit 0)" in r.stdout
    r = run("verify", COFFEE, "--propagate", "pre")
    assert r.returncode == 1
    assert "counterexample, from the initial state kukahand.free:" in r.stdout
    assert "    then the compressed tree takes gripper(close)" in r.stdout
    assert "add(water) is accomplished (water.used holds)" in r.stdout


def test_a_sound_merge_reports_the_interleavings_it_removed_not_a_failure():
    # by sets of states (the default) the traces are not enumerated, and it says so
    r = run("verify", COFFEE, "--task", "prepareboth")
    assert r.returncode == 0 and "FAILS" not in r.stdout, r.stdout
    assert "trace equivalence (diagnostic): unknown: not counted" in r.stdout
    assert "(--method explicit counts them)" in r.stdout
    r = run("verify", COFFEE, "--task", "prepareboth", "--method", "explicit")
    assert r.returncode == 0 and "FAILS" not in r.stdout, r.stdout
    traces = json.loads(run("verify", COFFEE, "--task", "prepareboth", "--method", "explicit",
                            "--json").stdout)["properties"]["traces"]
    (row,) = traces["states"]
    assert traces["holds"] is False and row["original"] > row["compressed"]      # the JSON is unchanged
    line = next(x for x in r.stdout.splitlines() if x.startswith("trace equivalence (diagnostic): "))
    assert line.startswith(f"trace equivalence (diagnostic): {row['original'] - row['compressed']:,} "
                           f"interleavings removed by merging")
    assert f"the original has {row['original']:,} complete traces, the compressed tree {row['compressed']:,}" in line
    # an unsound tree's traces are not the original's: there it stays a difference
    r = run("verify", COFFEE, "--propagate", "pre", "--method", "explicit")
    assert "trace equivalence (diagnostic): FAILS" in r.stdout and "interleavings removed" not in r.stdout


def test_verify_json_and_all_states():
    data = json.loads(run("verify", MIX, "--states", "all", "--propagate", "none", "--json").stdout)
    assert data["sound"] is False and data["states"] == 4 and data["exhaustive"] is True
    ce = data["counterexample"]
    assert ce["action"] and ce["reasons"] and isinstance(ce["run"], list)
    assert set(data["properties"]) == {"soundness", "completion", "flexibility", "traces", "selection"}
    data = json.loads(run("verify", COFFEE, "--states", "all", "--json").stdout)
    assert (data["sound"], data["complete"], data["states"]) == (True, True, 64)


@pytest.mark.parametrize("method", ["auto", "explicit"])
def test_verify_all_states_says_why_fewer_can_start_than_can_complete(method):
    r = run("verify", COFFEE, "--states", "all", "--method", method)
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    assert ("completion: holds: no dead end that the original does not share; 40 of 64 initial state(s) can "
            "complete, in both trees (12 of them done already: the task's post-condition holds there, no "
            "action needed)") in lines
    assert ("flexibility (diagnostic): holds: the original can start from 28 of 64 initial state(s), the "
            "compressed tree from 28 of those; of the other 36, 12 are done already (nothing to start) and "
            "24 enable no action of the task") in lines


def test_verify_a_compressed_file_against_its_original(tmp_path):
    out = tmp_path / "pre.pl"
    assert run("compress", COFFEE, "--propagate", "pre", "-o", out).returncode == 0
    r = run("verify", COFFEE, out)
    assert r.returncode == 1 and f"compressed 33 ({out})" in r.stdout
    r = run("verify", out)                        # the file alone: its provenance gives the original
    assert r.returncode == 1 and "(the compressed file)" in r.stdout


def test_verify_inconclusive_runs_say_so():
    r = run("verify", COFFEE, "--max-states", "30", "--method", "explicit")
    assert r.returncode == 3 and "NOT a proof" in r.stdout and "soundness (no perceptual aliasing): unknown" in r.stdout
    r = run("verify", COFFEE, "--max-bdd-nodes", "100", "--method", "symbolic")
    assert r.returncode == 3 and "NOT a proof" in r.stdout and "grew past 100 nodes" in r.stdout
    r = run("verify", COFFEE, "--sample", "20", "--seed", "4")
    assert r.returncode == 3 and "sampled:" in r.stdout
    r = run("verify", COFFEE, "--sample", "20", "--propagate", "pre")
    assert r.returncode == 1 and "counterexample" in r.stdout


def test_verify_bad_input():
    for bad in (("verify", MIX, MIX), ("verify", MIX, "--states", "not hand.free"),
                ("verify", MIX, MIX, MIX), ("verify", MIX, "--max-states", "0")):
        r = run(*bad)
        assert r.returncode == 2 and "Traceback" not in r.stderr, (bad, r.stderr)


def test_verify_refuses_a_compressed_file_of_another_task(tmp_path):
    out = tmp_path / "coffee_only.pl"
    assert run("compress", COFFEE, "--task", "preparecoffee", "-o", out).returncode == 0
    r = run("verify", COFFEE, out)
    assert r.returncode == 1 and "compresses preparecoffee" in r.stderr
    r = run("verify", COFFEE, out, "--task", "preparecoffee")
    assert r.returncode == 0, r.stdout
    data = json.loads(run("verify", MIX, "--sample", "20", "--json").stdout)
    assert data["sound"] is None and data["complete"] is None       # nothing proved


# --- generate -------------------------------------------------------------------

def test_generate_writes_a_task_that_compresses_runs_and_verifies(tmp_path):
    task, scene = tmp_path / "t.pl", tmp_path / "s.yaml"
    done = run("generate", "--depth", 4, "--children", 2, "--rd", 0.5, "--seed", 1, "-o", task, "--scene", scene)
    assert done.returncode == 0, done.stderr
    assert done.stderr.startswith(f"wrote {task}: task b1, Bi = 15, D = 4; compressed: Bm = 9, RD = 0.55 (asked 0.50)")
    assert "note:" not in done.stdout + done.stderr and done.stdout == ""
    compressed = json.loads(run("compress", task, "--json").stdout)
    assert (compressed["nodes_before"], compressed["nodes_after"]) == (15, 9)
    ran = run("run", task, "--scene", scene, "--compressed")
    assert ran.returncode == 0 and "4 decisions, 8 actions" in ran.stdout
    assert "note:" not in ran.stderr                     # initial(true): the start state is declared
    assert run("verify", task).returncode == 0


@pytest.mark.parametrize("d, b", [(4, 2), (5, 3), (6, 2)])
def test_generate_hits_rd_07_where_sibling_links_alone_cannot(d, b, tmp_path):
    done = run("generate", "--depth", d, "--children", b, "--rd", 0.7, "-o", tmp_path / "t.pl")
    got = float(done.stderr.split("RD = ")[1].split()[0])
    assert done.returncode == 0 and abs(got - 0.7) <= 0.05
    strict = run("generate", "--depth", d, "--children", b, "--rd", 0.7, "--siblings-only", "-o", tmp_path / "s.pl")
    assert strict.returncode == 0
    if b == 2:   # binary trees: at most about 0.53-0.55 with sibling links, and the note says why
        assert "note: RD 0.5" in strict.stderr and "allows RD at most" in strict.stderr


def test_generate_to_stdout_yaml_and_bad_requests(tmp_path):
    done = run("generate", "--depth", 3, "--children", 2, "--format", "yaml")
    assert done.returncode == 0 and "- task: b1" in done.stdout and "- schema: b2(obj1)" in done.stdout
    assert done.stderr.startswith("task b1, Bi = 7, D = 3; compressed: Bm = 7, RD = 0.00")
    for bad in (["--depth", 3, "--children", 2, "--rd", "1.5"], ["--depth", 0, "--children", 2],
                ["--depth", 3], ["--depth", 12, "--children", 4], ["--depth", 20000, "--children", 2],
                ["--depth", 50000, "--children", 1], ["--depth", 3, "--children", 2, "--rd", "nan"]):
        refused = run("generate", *bad, "-o", tmp_path / "x.pl")
        assert refused.returncode == 2 and "Traceback" not in refused.stderr, bad
        assert len(refused.stderr) < 600 and "internal error" not in refused.stderr, bad
        assert not (tmp_path / "x.pl").exists()


def test_generate_checks_every_destination_before_writing_any(tmp_path):
    scene = tmp_path / "s.yaml"
    missing = run("generate", "--depth", 3, "--children", 2, "-o", tmp_path / "nowhere" / "x.pl", "--scene", scene)
    assert missing.returncode == 2 and "no such directory" in missing.stderr
    assert not scene.exists()
    same = run("generate", "--depth", 3, "--children", 2, "-o", scene, "--scene", scene)
    assert same.returncode == 2 and "-o and --scene name the same file" in same.stderr and not scene.exists()
    dash = run("generate", "--depth", 3, "--children", 2, "--scene", "-", cwd=tmp_path)
    assert dash.returncode == 2 and not (tmp_path / "-").exists()


def test_run_decompresses_a_merged_behaviour_that_fails_part_way():
    args = ("run", COFFEE, "--scene", KITCHEN, "--compressed", "--fail", "a4(cup)", "--fail-times", "1")
    r = run(*args)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    failed = lines.index("      - a4(cup) (failed)")
    # the decision, which of the two a3_a4_a5_a6_a7(cup) won (coffee's), its first action, the failed one
    assert "a3_a4_a5_a6_a7(cup)" in lines[failed - 3] and "FAILED: the robot did not complete a4(cup)" in lines[failed - 3]
    assert lines[failed - 2] == "      (winner: in preparecoffee; runner-up: in preparetea)"
    assert lines[failed + 1] == ("      decompressed a3_a4_a5_a6_a7(cup) into a3(cup), a4(cup), a5(cup), a6(cup), "
                                 "a7(cup): a4(cup) is retried on its own")
    assert lines[failed + 2].startswith("   4  a4(cup) ")
    assert "decompressed 1 merged behaviour after failures (a3_a4_a5_a6_a7(cup)): the tree went from 33 to " \
           "37 behaviours" in r.stdout
    assert "completed: prepareboth is accomplished" in r.stdout
    data = json.loads(run(*args, "--json").stdout)
    assert data["completed"] and data["recovery"] == "decompress"
    assert data["behaviours"] == 33 and data["final_behaviours"] == 37
    assert data["trace"].count("a4(cup)") == 1 and len(data["trace"]) == 36
    split = [d for d in data["decisions"] if d["decompressed"]]
    assert [(d["index"], d["decompressed"]["behaviour"], d["decompressed"]["into"]) for d in split] == [
        (3, "a3_a4_a5_a6_a7(cup)", ["a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"])]
    assert data["decisions"][3]["behaviour"] == "a4(cup)" and data["decisions"][3]["executed"] == ["a4(cup)"]
    # resume keeps the tree and the old behaviour; an always failing a4(cup) is inhibited on its own
    old = json.loads(run(*args, "--json", "--recovery", "resume").stdout)
    assert old["final_behaviours"] == 33 and not any(d["decompressed"] for d in old["decisions"])
    assert old["decisions"][3]["skipped"] == ["a3(cup)"]
    r = run("run", COFFEE, "--scene", KITCHEN, "--compressed", "--fail", "a4(cup)")
    assert r.returncode == 1 and "  a4(cup): its command failed 3 times; inhibited" in r.stdout
    assert "a3_a4_a5_a6_a7(cup): its command failed" not in r.stdout
    assert run("run", MIX, "--recovery", "replan").returncode == 2


# --- outputs that never destroy anything (docs/formats.md, Outputs) -----------------------------

def test_output_onto_a_fifo_a_device_or_a_link_writes_into_it(tmp_path):
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    reader, got = read_fifo_in_thread(fifo)
    r = run("show", MIX, "--json", "-o", fifo)
    reader.join(30)
    assert r.returncode == 0, r.stderr
    assert json.loads(got[0])["task"] == "use(spoon)" and stat.S_ISFIFO(os.lstat(fifo).st_mode)
    null = tmp_path / "null"
    os.mknod(null, stat.S_IFCHR | 0o666, os.makedev(1, 3))   # the null device, inside tmp_path
    r = run("compress", MIX, "-o", null)
    assert r.returncode == 0, r.stderr
    assert stat.S_ISCHR(os.lstat(null).st_mode) and os.lstat(null).st_rdev == os.makedev(1, 3)
    link = tmp_path / "link.json"
    link.symlink_to(fifo)
    reader, got = read_fifo_in_thread(fifo)
    r = run("show", MIX, "--json", "-o", link)
    reader.join(30)
    assert r.returncode == 0 and json.loads(got[0])["task"] == "use(spoon)"
    assert link.is_symlink() and stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert sorted(os.listdir(tmp_path)) == ["fifo.json", "link.json", "null"]


@pytest.mark.parametrize("args", [("show", MIX), ("compress", MIX), ("convert", MIX), ("generate", "--depth", "2", "--children", "2"),
                                  ("run", MIX), ("verify", MIX)])
@pytest.mark.parametrize("name", ["newdir/", "newdir/x.pl"])
def test_output_into_a_directory_that_is_not_there_is_refused(tmp_path, args, name):
    r = run(*args, "-o", name, cwd=tmp_path)
    assert r.returncode == 2 and "directory" in r.stderr and "newdir" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and os.listdir(tmp_path) == []


def test_output_never_overwrites_any_input(tmp_path):
    scene = tmp_path / "s.yaml"
    scene.write_text(FIG2_SCENE.read_text())
    for args in (("verify", MIX, "--scene", "s.yaml"), ("simulate-demo", MIX, "--scene", "s.yaml"),
                 ("run", MIX, "--scene", "s.yaml")):
        r = run(*args, "-o", "s.yaml", cwd=tmp_path)
        assert r.returncode == 2 and "-o s.yaml would overwrite an input file" in r.stderr, (args, r.stderr)
        assert scene.read_text() == FIG2_SCENE.read_text()
    # learn: a file the structure consults
    (tmp_path / "X.pl").write_text("object(cup).\n")
    (tmp_path / "st.pl").write_text(":- consult('X.pl').\n" + (ROOT / "kb" / "tasks" / "coffee_structure.pl").read_text())
    (tmp_path / "demo.csv").write_text("t,x,y,z\n")
    r = run("learn", "demo.csv", "--structure", "st.pl", "-o", "X.pl", cwd=tmp_path)
    assert r.returncode == 2 and "-o X.pl would overwrite an input file" in r.stderr, r.stderr
    r = run("learn", "demo.csv", "--structure", "st.pl", "--task", "preparecoffee", "--motions", "X.pl", cwd=tmp_path)
    assert r.returncode == 2 and "--motions X.pl would overwrite an input file" in r.stderr, r.stderr
    # show and verify: a consulted file, and the same file through a hard link
    (tmp_path / "inc.pl").write_text(":- [m].\n" + MIX.read_text())
    (tmp_path / "m.pl").write_text("object(cup).\n")
    os.link(tmp_path / "m.pl", tmp_path / "hard.pl")
    for args in (("show", "inc.pl", "-o", "m.pl"), ("verify", "inc.pl", "-o", "hard.pl")):
        r = run(*args, cwd=tmp_path)
        assert r.returncode == 2 and "would overwrite an input file" in r.stderr, (args, r.stderr)
    assert (tmp_path / "X.pl").read_text() == "object(cup).\n" == (tmp_path / "m.pl").read_text()


# SLOW_WRITE (conftest.py) stops after the first kilobyte, so that the signal arrives during the write.
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_during_a_write_leaves_no_temporary_file(tmp_path, signum):
    p = subprocess.Popen([sys.executable, "-c", SLOW_WRITE, "generate", "--depth", "4", "--children", "3", "-o", "out.pl"],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not any(n.endswith(".tmp") for n in os.listdir(tmp_path)) and p.poll() is None:
        assert time.monotonic() < deadline
        time.sleep(0.02)
    p.send_signal(signum)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 128 + signum, err
    assert os.listdir(tmp_path) == [] and "Traceback" not in err


def test_sigterm_while_generating_a_large_output_exits_143_and_leaves_nothing(tmp_path):
    p = subprocess.Popen([sys.executable, "-m", "schemalog", "generate", "--depth", "8", "--children", "4",
                          "-o", "big.pl"], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(1.0)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 143 and "Traceback" not in err, err
    assert not any(n.endswith(".tmp") for n in os.listdir(tmp_path))


def _zero_device(path):
    os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 5))   # the zero device, inside tmp_path
    return path


def test_inputs_that_never_end_are_read_only_up_to_the_limit(tmp_path):
    _zero_device(tmp_path / "zero")
    (tmp_path / "inc.pl").write_text(":- consult('zero').\n")
    (tmp_path / "st.pl").write_text((ROOT / "kb" / "tasks" / "coffee_structure.pl").read_text())
    for args in (("check", "zero"), ("check", "inc.pl"), ("run", MIX, "--scene", "zero"),
                 ("simulate-demo", MIX, "--scene", "zero"), ("learn", "zero", "--structure", "st.pl")):
        # --max-memory: were the device read whole, the run would end out of memory instead
        r = run(*args, "--max-bytes", "5000", "--max-memory", "1G", cwd=tmp_path)   # the task files are smaller
        assert r.returncode == 1, (args, r.stderr)
        assert "zero" in r.stderr and "5,000 bytes limit" in r.stderr, (args, r.stderr)
        assert "Traceback" not in r.stderr and "internal error" not in r.stderr


def test_a_byte_limit_past_any_file_size_is_no_limit_not_an_error():
    r = run("check", MIX, "--max-bytes", "99999999999999999999")
    assert r.returncode == 0 and r.stdout.startswith("ok:"), r.stderr


def test_verify_says_when_selection_ran_with_no_scene_and_names_a_scene_given():
    plain = run("verify", MIX)
    assert "winner-take-all runs with no scene (every distance neutral)" in plain.stdout, plain.stdout
    placed = run("verify", MIX, "--scene", ROOT / "kb" / "scenes" / "mix_with_spoon.yaml")
    assert "winner-take-all runs in scene mix with spoon" in placed.stdout, placed.stdout


# ---------------------------------------------------------------------------
# The README's Task knowledge snippet, and several files as one program

def _readme_snippet() -> str:
    """The first ```prolog block of README.md's Task knowledge section, as written there."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("\n## Task knowledge\n", 1)[1].split("\n## ", 1)[0]
    return section.split("```prolog\n", 1)[1].split("```", 1)[0]


def test_the_readme_task_knowledge_snippet_checks_and_runs_on_its_own(tmp_path):
    task = tmp_path / "task.pl"
    task.write_text(_readme_snippet())
    r = run("check", task)
    assert r.returncode == 0, r.stderr
    assert "use(spoon) (9 behaviours, depth 3)" in r.stdout           # the figure README gives
    r = run("run", task)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "completed: use(spoon) is accomplished (spoon.used)" in r.stdout
    assert "6 decisions, 6 actions" in r.stdout                       # README: in 6 actions
    r = run("verify", task)
    assert r.returncode == 0 and "1 of 1 initial state(s) can complete" in r.stdout, r.stdout


def test_the_readme_query_example_gives_its_bindings():
    r = run("query", COFFEE, "merged(T, B, Parts), length(Parts, N), N > 2", "--json")
    assert r.returncode == 0, r.stderr
    answers = json.loads(r.stdout)
    assert answers and all(a["T"] == "prepareboth" and a["N"] > 2 for a in answers)
    assert ["a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"] in [a["Parts"] for a in answers]


def test_the_shipped_files_together_are_not_one_program():
    """README: `schemalog check kb/tasks/*.pl` names the first thing two of them define."""
    r = subprocess.run(["bash", "-c", f"{sys.executable} -m schemalog check kb/tasks/*.pl"],
                       capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert r.returncode == 1 and "Traceback" not in r.stderr and r.stdout == ""
    assert r.stderr.startswith("kb/tasks/mix_with_spoon.pl:19:1: error: agent/2 for gripper(_) is defined in two "
                               "files: agent(gripper(_), ...) here")
    assert "at kb/tasks/coffee_structure.pl:22:1" in r.stderr and len(r.stderr.splitlines()) == 1


LIBRARY = """agent(gripper(_), gripper).
schema(gripper(close), [], not hand.free).
schema(gripper(open), [], hand.free).
"""
GRAB = """task(grab(spoon)).
object(spoon).
initial(hand.free).
schema(grab(spoon), [(a1(spoon), true), (gripper(close), a1.done)], spoon.taken).
schema(a1(spoon), [], a1.done).
"""


def test_a_task_and_its_library_on_one_command_line(tmp_path):
    library, task = tmp_path / "library.pl", tmp_path / "grab.pl"
    library.write_text(LIBRARY)
    task.write_text(GRAB)
    r = run("check", library, task)
    assert r.returncode == 0 and "grab(spoon) (3 behaviours, depth 2)" in r.stdout, r.stderr
    r = run("run", library, task, "--json")
    assert r.returncode == 0 and json.loads(r.stdout)["completed"], r.stderr
    # The task file defines a gripper command of its own too: both places, one message.
    task.write_text(GRAB + "\nschema(gripper(close), [], hand.closed).\n")
    for command in ("check", "run", "compress", "query"):
        r = run(command, library, task, *(["true"] if command == "query" else []))
        # query's status for bad input is 2 (1 is "no answer")
        assert r.returncode == (2 if command == "query" else 1) and "Traceback" not in r.stderr, (command, r.stderr)
        assert r.stderr.startswith(f"{task}:7:1: error: schema/3 for gripper(close) is defined in two files: "
                                   f"schema(gripper(close), ...) here and schema(gripper(close), ...) at "
                                   f"{library}:2:1; keep one, or, if both files are meant to define it, declare "
                                   f"`:- multifile(gripper/1).` before this clause"), r.stderr
    task.write_text(":- multifile gripper/1.\n" + GRAB + "\nschema(gripper(close), [], hand.closed).\n")
    r = run("check", library, task, "--no-lint")     # multifile: the two files load as one program
    assert r.returncode == 0, r.stderr
    r = run("check", library, task)                  # and lint finds the task's schema is never used
    assert r.returncode == 1 and f"{task}:8:1: error: the schema of gripper(close) is never used" in r.stderr
    r = run("check", task, task)                     # one file named twice is read once more
    assert r.returncode == 0, r.stderr


def test_a_prolog_predicate_in_two_files_on_the_command_line(tmp_path):
    a, b = tmp_path / "a.pl", tmp_path / "b.pl"
    a.write_text("colour(red).\n")
    b.write_text("size(big).\ncolour(blue).\n")
    r = run("query", a, b, "colour(C)")
    assert r.returncode == 2 and r.stderr.startswith(f"{b}:2:1: error: colour/1 is defined in two files, "
                                                     f"here and at {a}:1:1"), r.stderr
    b.write_text(":- multifile colour/1.\nsize(big).\ncolour(blue).\n")
    r = run("query", a, b, "colour(C)")
    assert r.returncode == 0 and r.stdout.split() == ["C", "=", "red", "C", "=", "blue"], r.stdout


def test_a_declaration_in_two_files_names_what_is_declared_twice_and_the_directive_for_it(tmp_path):
    a, b = tmp_path / "a.pl", tmp_path / "b.pl"
    a.write_text("agent(gripper(_), gripper).\n")
    b.write_text("agent(gripper(_), gripper).\n")
    r = run("check", a, b)
    assert r.returncode == 1
    assert r.stderr == (f"{b}:1:1: error: agent/2 for gripper(_) is defined in two files: agent(gripper(_), ...) "
                        f"here and agent(gripper(_), ...) at {a}:1:1; keep one, or, if both files are meant to "
                        f"define it, declare `:- multifile(agent/2).` before this clause (docs/syntax.md, "
                        f"Several files)\n"), r.stderr
    b.write_text(":- multifile(agent/2).\nagent(gripper(_), gripper).\n")     # what it says to do
    r = run("check", a, b)
    assert r.returncode == 0, r.stderr


# -- --help: what a person reads before anything else -----------------------------------

def test_every_positional_argument_of_every_command_is_described():
    from schemalog.cli.main import COMMANDS, build_parser

    for name in COMMANDS:
        command = name.replace("_", "-")
        r = run(command, "--help")
        assert r.returncode == 0, r.stderr
        parser = build_parser(command)._subparsers._group_actions[0].choices[command]
        positionals = [a for a in parser._actions if not a.option_strings]
        for action in positionals:
            assert action.help and len(action.help) > 10, (command, action.metavar)
            shown = " ".join(r.stdout.split("positional arguments:")[1].split("options:")[0].split())
            assert " ".join(action.help.split()[:4]) in shown, (command, action.metavar)   # --help shows it


@pytest.mark.parametrize("args", [("show", COFFEE), ("query", COFFEE, "node(B, L)"), ("run", COFFEE),
                                  ("compress", COFFEE, "--json")], ids=lambda a: " ".join(map(str, a[::2])))
def test_a_reader_that_stopped_early_gets_no_traceback(args):
    read, write = os.pipe()
    os.close(read)                       # `schemalog ... | head -1` once head has gone
    try:
        r = subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], stdout=write,
                           stderr=subprocess.PIPE, text=True, cwd=ROOT, timeout=120)
    finally:
        os.close(write)
    assert "Traceback" not in r.stderr and "BrokenPipeError" not in r.stderr, r.stderr


def test_the_top_level_help_names_every_input_convert_reads():
    shown = " ".join(run("--help").stdout.split())
    assert ("convert convert knowledge: SEED, schema text, YAML or BT.CPP XML -> schema text, YAML or SEED"
            in shown), shown
    assert "BehaviorTree.CPP v4 tree (.xml)" in " ".join(run("convert", "--help").stdout.split())


def test_the_two_jitter_defaults_are_stated_with_the_reason_for_two():
    from schemalog import defaults

    ran = " ".join(run("run", "--help").stdout.split())
    simulated = " ".join(run("simulate-demo", "--help").stdout.split())
    assert f"(default {defaults.JITTER}:" in ran and "simulate-demo's default is 0" in ran
    assert "default 0, at most" in simulated and f"run's default is {defaults.JITTER}" in simulated
    assert "also seeds the noise" in simulated


def test_a_wrong_option_prints_the_commands_usage_not_the_top_levels():
    for args in (("run", MIX, "--bogus"), ("query", MIX, "X = 1", "--bogus"), ("compress", MIX, "--nope", "1")):
        r = run(*args)
        assert r.returncode == 2
        assert r.stderr.startswith(f"usage: schemalog {args[0]} ["), r.stderr
        assert f"schemalog {args[0]}: error: unrecognized arguments: " in r.stderr


def test_a_commands_option_before_its_name_is_pointed_after_it():
    r = run("--json", "show", MIX)
    assert r.returncode == 2 and r.stdout == ""
    assert ("schemalog show: error: unrecognized arguments: --json (options of show go after its name: "
            "schemalog show --json ...)") in r.stderr
    assert "go after" not in run("--bogus", "show", MIX).stderr       # not one of show's: no hint
    assert run("show", "--json", MIX).returncode == 0


def test_the_top_level_help_states_each_exit_status_the_commands_return(tmp_path):
    text = run("--help").stdout
    stated = {int(line.split()[0]) for line in text.split("exit status:")[1].splitlines()
              if line[:6].strip().isdigit()}
    seen = {
        run("verify", MIX).returncode,                                   # proved
        run("verify", COFFEE, "--propagate", "pre").returncode,          # a counterexample
        run("run", MIX, "--bogus").returncode,                           # a wrong command line
        run("verify", COFFEE, "--method", "explicit", "--max-states", "10").returncode,   # no proof
        run("query", MIX, "repeat, fail", "--timeout", "1").returncode,  # out of time
    }
    assert seen == {0, 1, 2, 3, 124} and seen <= stated
    assert stated >= {70, 130}
    assert "128+N for signal N" in text


@pytest.mark.parametrize("args, said", [
    (("compress", COFFEE, "-o", "{out}/out.pl"),
     "wrote {out}/out.pl: prepareboth compressed (propagate full): 33 behaviours from 63, RD 0.52 (schema text)"),
    (("compress", MIX, "--propagate", "none", "-o", "{out}/c.json"),
     "wrote {out}/c.json: use(spoon) compressed (propagate none): "),
    (("show", MIX, "-o", "{out}/t.yaml"), "wrote {out}/t.yaml: use(spoon): 12 behaviours, depth 3 (YAML)"),
    (("convert", SEED_COFFEE, "--task", "prepareboth", "-o", "{out}/task.pl"),
     "wrote {out}/task.pl: 56 clauses as schema text; tasks: prepareboth"),
    (("run", MIX, "--scene", FIG2_SCENE, "-o", "{out}/run.txt"),
     "wrote {out}/run.txt: the run of use(spoon), 9 decisions, completed (text)"),
    (("verify", MIX, "-o", "{out}/v.txt"), "wrote {out}/v.txt: the verification of use(spoon): sound and complete (text)"),
    (("generate", "--depth", "3", "--children", "2", "--seed", "1", "-o", "{out}/g.pl", "--scene", "{out}/g.yaml"),
     "wrote {out}/g.yaml: the scene of b1: 2 objects"),
    (("generate", "--depth", "3", "--children", "2", "--seed", "1", "-o", "{out}/g.pl"),
     "wrote {out}/g.pl: task b1, Bi = 7, D = 3; compressed: "),
    (("export", MIX, "-o", "{out}/t.xml"), "wrote {out}/t.xml: use(spoon), original tree of 12 behaviours (BehaviorTree.CPP v4 XML)"),
    (("export", MIX, "--to", "py_trees", "-o", "{out}/t.py"), "wrote {out}/t.py: use(spoon), original tree of 12 behaviours (a py_trees module)"),
    (("simulate-demo", MIX, "--scene", FIG2_SCENE, "-o", "{out}/d.csv"), "wrote {out}/d.csv: simulated use(spoon) in "),
])
def test_a_command_writing_a_file_says_on_stderr_what_it_wrote(tmp_path, args, said):
    r = run(*(str(a).format(out=tmp_path) for a in args))
    assert r.returncode == 0, r.stderr
    line = said.format(out=tmp_path)
    assert any(x.startswith(line) for x in r.stderr.splitlines()), r.stderr
    written = line.split()[1].rstrip(":")
    assert os.path.getsize(written) > 0 and written not in r.stdout
    # to standard output, the data alone: nothing is said
    r = run(*(a for a in args if "{out}" not in str(a) and a not in ("-o", "--scene")))
    assert "wrote" not in r.stderr


def test_the_readmes_commands_write_each_output_once():
    # issue 35: `convert tree.xml -o task.pl` overwrote the task.pl that `convert task.pl -o
    # task.yaml` was meant to read, and fig2.png was written twice. (`--out` names a folder, where
    # bench --paper writes results.* and bench --runtimes runtimes.*.)
    import collections
    import re

    block = (ROOT / "README.md").read_text().split("## What you can do", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    commands = [re.sub(r"'[^']*'", "''", line.split("  #", 1)[0]) for line in block.splitlines()]  # not a query's >
    outputs = [m.group(1) for command in commands for m in re.finditer(r"(?:-o|--plot|--motions|>)\s+(\S+)", command)]
    assert len(outputs) > 15 and "fig2.png" in outputs
    twice = [name for name, n in collections.Counter(outputs).items() if n > 1]
    assert twice == []


def test_compress_verify_of_a_compressed_file(tmp_path):
    """compress -o, then compress --verify of what it wrote (issue 46: internal error, exit 70)."""
    small = tmp_path / "small.pl"
    assert run("compress", MIX, "-o", small).returncode == 0
    r = run("compress", small, "--verify")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "original 12 behaviours, compressed 6" in r.stdout
    assert "subtask(take,spoon)" in r.stdout        # its original, rebuilt from the provenance
    assert "result: the compressed tree is sound and complete (exit 0)" in r.stdout
