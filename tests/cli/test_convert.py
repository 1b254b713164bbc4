"""`schemalog convert` and `compress -o x.prolog` with SEED, as a user runs them."""

import json
import subprocess
import sys
from pathlib import Path

from conftest import COFFEE, MIX, ROOT, SEED_COFFEE

HRI = ROOT / "tests" / "formats" / "seed" / "hri_ltm.prolog"


def run(*args):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=120)


def shown(path, *more):
    r = run("show", path, "--json", *more)
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    return data["nodes"], data["depth"], data["tree"]


def test_convert_to_seed_writes_memory_that_shows_the_same_tree(tmp_path):
    out = tmp_path / "ltm.prolog"
    r = run("convert", SEED_COFFEE, "--to", "seed", "--task", "prepareboth", "-o", out)
    assert r.returncode == 0, r.stderr
    text = out.read_text()
    assert ":- op(500, xfy, .).\n:- op(600, fx, -).\n" in text
    assert "schema(add(water), [\n\t[subtask(take, water), 1, [[kukahand|free]]]," in text
    assert "goal(gripper(close), [-[kukahand|free]])." in text
    assert shown(out) == shown(SEED_COFFEE, "--task", "prepareboth")


def test_compress_to_prolog_writes_seed_that_keeps_the_compressed_tree(tmp_path):
    seed, pl = tmp_path / "c.prolog", tmp_path / "c.pl"
    assert run("compress", MIX, "-o", seed).returncode == 0
    assert run("compress", MIX, "-o", pl).returncode == 0
    assert "exact_releaser(use(spoon), 0, 2," in seed.read_text()
    assert shown(seed) == shown(pl)
    r = run("decompress", seed, "--json")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["tree"] == shown(MIX)[2]


def test_a_task_the_file_does_not_define_is_refused_and_nothing_written(tmp_path):
    out = tmp_path / "t.pl"
    r = run("convert", SEED_COFFEE, "--task", "prepare_lunch", "-o", out)
    assert r.returncode == 1
    assert "error: prepare_lunch is not a task of" in r.stderr and "prepareboth" in r.stderr
    assert "Traceback" not in r.stderr and not out.exists()


def test_a_sub_task_without_schema_is_a_warning_with_its_place(tmp_path):
    out = tmp_path / "t.pl"
    r = run("convert", HRI, "--task", "serve(tea)", "-o", out)
    assert r.returncode == 0, r.stderr
    assert f"{HRI}:30:1: warning: no semantic for wave" in r.stderr
    assert "wave" not in out.read_text().split("schema(serve(Obj)", 1)[1].split(").", 1)[0]


def test_a_rule_that_loops_is_one_message_at_its_clause_exit_1_nothing_written(tmp_path):
    ltm = tmp_path / "loop.prolog"
    ltm.write_text(':- op(500, xfy, .).\n'
                   'schema(greet, [[en("hello there"), 1, ["TRUE"]]]).\n'
                   'schema(en(S), [[speech(hello), 1, ["TRUE"]]]) :-\n'
                   '    string(S), words(S, _).\n'
                   'schema(speech(_), []).\n'
                   'words(S, W) :- words(S, W).\n')
    for target in ("t.pl", "t.prolog"):
        out = tmp_path / target
        r = run("convert", ltm, "--task", "greet", "-o", out, "--max-steps", "20000")
        assert r.returncode == 1
        errors = [line for line in r.stderr.splitlines() if "error" in line]
        assert errors == [f"{ltm}:3:1: error: while instantiating en(\"hello there\"), the schema's body "
                          f"exceeded the step limit of 20,000 steps (raise it with --max-steps N)"]
        assert not out.exists()


def test_a_releaser_too_large_for_seed_is_refused_with_the_reason(tmp_path):
    # (a1 or b1) and ... and (a10 or b10): 1024 disjuncts, more than a SEED file should hold
    releaser = " and ".join(f"(a{i}.x or b{i}.x)" for i in range(10))
    task = tmp_path / "t.pl"
    task.write_text(f"task(t).\nschema(t, [(a, {releaser})], t.done).\nschema(a, [], a.done).\n")
    out = tmp_path / "t.prolog"
    r = run("convert", task, "-o", out)
    assert r.returncode == 1 and "the releaser of a has more than 512 disjuncts" in r.stderr
    assert not out.exists() and "Traceback" not in r.stderr


def test_readme_seed_commands_work(tmp_path):
    for args, nodes in ((("convert", "examples/coffee_and_tea_seed.prolog", "--to", "seed", "--task",
                          "prepareboth", "-o", tmp_path / "out.prolog"), 63),
                        (("compress", "kb/tasks/prepare_coffee_and_tea.pl", "-o", tmp_path / "c.prolog"), 33)):
        r = run(*args)
        assert r.returncode == 0, r.stderr
        assert shown(Path(args[-1]))[0] == nodes


def test_the_sources_constraints_and_helpers_survive_the_seed_file(tmp_path):
    # prepare_coffee_and_tea.pl's constraint/1 rules call its ingredient/1 facts
    out = tmp_path / "c.prolog"
    assert run("compress", COFFEE, "-o", out).returncode == 0
    assert "constraint((-[O|used];[O|taken])):-ingredient(O)." in out.read_text()
    r = run("verify", out, "--states", "all", "--json")
    assert "ingredient" not in r.stderr
    data = json.loads(r.stdout)
    assert (data["states"], data["sound"], data["complete"]) == (64, True, True)


def test_every_command_that_instantiates_leaves_out_a_sub_task_no_rule_applies_to(tmp_path):
    ltm = tmp_path / "m.prolog"
    ltm.write_text('task(greet).\n'
                   'schema(greet, [[en(hello), 1, ["TRUE"]], [en(dance), 2, ["TRUE"]]]).\n'
                   'schema(en(S), [[say(S), 1, ["TRUE"]]]) :- member(S, [hello, bye]).\n'
                   'schema(say(_), []).\n')
    warning = (f"{ltm}:2:1: warning: no semantic for en(dance) (a sub-task of greet): no schema applies "
               f"to it; left out, as SEED does")
    for args in (("check",), ("show",), ("compress",), ("run",), ("verify",), ("query", "task(T)"),
                 ("convert", "--task", "greet", "-o", tmp_path / "o.pl"),
                 ("convert", "--to", "seed", "-o", tmp_path / "o.prolog")):
        r = run(args[0], ltm, *args[1:])
        assert r.returncode == 0, (args, r.stderr)
        assert warning in r.stderr, args
        assert "Traceback" not in r.stderr and "dance" not in r.stdout, args
    assert shown(ltm)[0] == 3 and shown(tmp_path / "o.prolog")[0] == 3   # greet, en(hello), say(hello)
    r = run("lint", ltm)
    assert r.returncode == 0 and f"{warning} [no-semantic]" in r.stdout
    # The same knowledge in schema text keeps the schema language's error.
    pl = tmp_path / "m.pl"
    pl.write_text('task(greet).\nschema(greet, [(en(hello), true), (en(dance), true)], greet.done).\n'
                  'schema(en(S), [(say(S), true)], en(S).done) :- member(S, [hello, bye]).\n'
                  'schema(say(_), [], said).\n')
    r = run("show", pl)
    assert r.returncode == 1 and f"{pl}:2:1: error: no schema for en(dance)" in r.stderr
