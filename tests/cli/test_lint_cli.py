"""End to end: `schemalog lint`, the warnings `check` prints, and verification that says when
the task itself cannot complete (issue 17), run as a user runs them."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from conftest import COFFEE, GRIPPER, MIX, ROOT, SEED_COFFEE

STRUCTURE = ROOT / "kb" / "tasks" / "coffee_structure.pl"


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=300)


@pytest.fixture
def typo(tmp_path):
    """The issue's typo: kb/tasks/prepare_coffee_and_tea.pl with water.usd in a releaser."""
    text = COFFEE.read_text()
    assert "(add(tea), water.used)" in text
    path = tmp_path / "typo.pl"
    path.write_text(text.replace("(add(tea), water.used)", "(add(tea), water.usd)"))
    return path


@pytest.mark.parametrize("path", [MIX, COFFEE, STRUCTURE, SEED_COFFEE])
def test_every_shipped_file_lints_clean_even_strictly(path):
    r = run("lint", path, "--strict")
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout == "" and "clean" in r.stderr


def test_the_typo_is_an_error_at_its_line_and_column_with_what_to_do(typo):
    r = run("lint", typo)
    assert r.returncode == 1
    line = next(n for n, text in enumerate(typo.read_text().splitlines(), 1) if "water.usd" in text)
    column = typo.read_text().splitlines()[line - 1].index("water.usd") + 1
    assert r.stdout.startswith(f"{typo}:{line}:{column}: error: add(tea) can never be released: water.usd")
    assert "fix: did you mean water.used?" in r.stdout
    assert "1 error, 0 warnings" in r.stderr


def test_lint_json_for_tools(typo):
    r = run("lint", typo, "--json")
    data = json.loads(r.stdout)
    assert r.returncode == 1 and (data["errors"], data["warnings"]) == (1, 0)
    (finding,) = data["findings"]
    assert finding["code"] == "unreachable-releaser" and finding["file"] == str(typo)
    assert finding["severity"] == "error" and "water.used" in finding["hint"]


def test_strict_fails_on_warnings_only_when_asked(tmp_path):
    path = tmp_path / "w.pl"
    path.write_text("task(t).\ntask(t).\nschema(t, [], t.done).\n")
    assert run("lint", path).returncode == 0
    r = run("lint", path, "--strict")
    assert r.returncode == 1 and "warning: the task t is declared twice" in r.stdout


def test_what_the_loader_refuses_is_an_error_finding(tmp_path):
    path = tmp_path / "bad.pl"
    path.write_text("task(t).\nschema(t, [(a, true)], t.done\n")
    r = run("lint", path, "--json")
    data = json.loads(r.stdout)
    assert r.returncode == 1 and data["findings"][0]["code"] == "load"
    assert data["findings"][0]["file"] == str(path) and "Traceback" not in r.stderr


def test_lint_over_several_files_finds_schemas_that_shadow_others():
    r = run("lint", STRUCTURE, COFFEE, "--json")
    data = json.loads(r.stdout)
    assert r.returncode == 1
    shadowed = [f for f in data["findings"] if f["code"] == "shadowed-schema"]
    # coffee_structure.pl's leaf-less subtask(take, O) answers every take of the learned file first.
    assert any("subtask(take,water) is never used" in f["message"] and f["file"] == str(COFFEE) for f in shadowed) \
        or any(f["code"] == "load" for f in data["findings"])


def test_check_fails_on_lints_errors_with_one_severity_everywhere(typo):
    # issue 35: a finding is an error in check as in lint, and check's last line never says ok over it
    r = run("check", typo)
    assert r.returncode == 1
    assert "error: add(tea) can never be released: water.usd never holds" in r.stderr
    assert "warning" not in r.stderr and "ok" not in r.stdout.split(":")[0]
    assert r.stdout.startswith(f"failed: {typo}: ") and "lint found 1 error above" in r.stdout
    assert "--no-lint" in r.stdout
    linted = run("lint", typo)
    assert linted.returncode == 1 and "error: add(tea) can never be released" in linted.stdout
    unlinted = run("check", typo, "--no-lint")
    assert unlinted.returncode == 0 and unlinted.stdout.startswith("ok:") and "not linted (--no-lint)" in unlinted.stdout
    assert unlinted.stderr == ""
    clean = run("check", MIX)
    assert clean.returncode == 0 and clean.stdout.startswith("ok:") and clean.stderr == ""


def test_check_prints_warnings_as_warnings_and_passes(tmp_path):
    path = tmp_path / "twice.pl"
    path.write_text("task(t).\ntask(t).\nschema(t, [(a, true)], a.done).\nschema(a, [], a.done).\n")
    r = run("check", path)
    assert r.returncode == 0 and r.stdout.startswith("ok:")
    assert "warning: the task t is declared twice" in r.stderr


def test_verify_says_the_typoed_task_cannot_complete_and_why(typo):
    r = run("verify", typo)
    assert r.returncode == 1, r.stdout
    assert "the task itself cannot complete" in r.stdout
    assert "why (schemalog lint):" in r.stdout and "water.usd never holds" in r.stdout
    assert r.stdout.rstrip().endswith("(exit 1)") and "sound and complete" not in r.stdout
    data = json.loads(run("verify", typo, "--json").stdout)
    assert data["vacuous"] is True and data["completing_states"] == []
    assert data["not_completing_states"] == [["kukahand.free"]]
    assert data["vacuous_because"]["code"] == "unreachable-releaser"


def test_verify_of_the_gripper_livelock_is_not_a_proof(tmp_path):
    path = tmp_path / "g.pl"
    path.write_text(GRIPPER)
    r = run("verify", path)
    assert r.returncode == 1 and "the task itself cannot complete" in r.stdout
    assert "gripper(open) undoes not hand.free, the post-condition of gripper(close)" in r.stdout
    assert run("lint", path).returncode == 1


def test_verify_of_the_seed_example_which_declares_no_initial_state():
    r = run("verify", SEED_COFFEE, "--task", "prepareboth")
    assert r.returncode == 1 and "the task itself cannot complete" in r.stdout
    assert "kukahand.free never holds" in r.stdout and "no initial/1" in r.stdout


def test_compress_verify_says_it_too(typo):
    r = run("compress", typo, "--verify", "--json")
    data = json.loads(r.stdout)["verification"]
    assert r.returncode == 1 and data["vacuous"] is True
    text = run("compress", typo, "--verify")
    assert text.returncode == 1 and "vacuous: the task itself cannot complete" in text.stdout


def test_a_task_that_completes_is_not_vacuous_and_names_the_states_that_cannot():
    r = run("verify", COFFEE, "--json")
    data = json.loads(r.stdout)
    assert r.returncode == 0 and data["vacuous"] is False
    assert data["completing_states"] == [["kukahand.free"]] and data["not_completing_states"] == []
    every = run("verify", COFFEE, "--states", "all")
    assert every.returncode == 0
    # With nothing true at the start the hand is not free: nothing can ever start.
    assert "the original task cannot complete from" in every.stdout and "(nothing true)" in every.stdout


def test_lint_of_a_generated_task_is_clean(tmp_path):
    out = tmp_path / "g.pl"
    assert run("generate", "--depth", "4", "--children", "3", "--rd", "0.5", "-o", out).returncode == 0
    r = run("lint", out, "--strict")
    assert r.returncode == 0, r.stdout


def test_a_compressed_file_is_linted_as_its_original(tmp_path):
    out = tmp_path / "out.pl"
    assert run("compress", COFFEE, "-o", out).returncode == 0
    r = run("lint", out, "--strict")
    assert r.returncode == 0, r.stdout       # merged take-and-pour leaves are not a livelock
    assert run("check", out).stderr.count("warning") == 0


def test_without_a_declared_task_lint_says_it_linted_only_the_clauses():
    r = run("lint", SEED_COFFEE, "--json")
    assert r.returncode == 0 and json.loads(r.stdout)["tasks"] == []
    assert "no task/1 declared" in run("lint", SEED_COFFEE).stderr
    assert json.loads(run("lint", SEED_COFFEE, "--task", "prepareboth", "--json").stdout)["tasks"] == ["prepareboth"]


def test_a_task_named_with_task_does_not_make_the_declared_ones_unused():
    r = run("lint", COFFEE, "--task", "preparecoffee", "--strict")
    assert r.returncode == 0, r.stdout
    assert "warning" not in run("check", COFFEE, "--task", "preparecoffee").stderr


def test_a_free_rule_that_raises_is_a_finding_and_check_still_passes(tmp_path):
    path = tmp_path / "f.pl"
    path.write_text("task(t).\nfree(X) :- throw(oops).\nschema(t, [], t.done).\n")
    r = run("lint", path)
    assert r.returncode == 1 and f"{path}:2:1: error: asking free/1 failed: oops" in r.stdout
    checked = run("check", path)
    assert checked.returncode == 1 and "error: asking free/1 failed" in checked.stderr


def long_chain_yaml(n, op):
    """A task whose releaser is an n-literal chain `a0.done OP a1.done OP ...` in YAML."""
    chain = f" {op} ".join(f"a{i}.done" for i in range(n))
    return (f"schemalog: 1\nitems:\n- task: t0\n- schema: t0\n  subtasks:\n  - behaviour: b\n"
            f"    releaser: {chain}\n  post: t0.done\n- schema: b\n  subtasks: []\n  post: b.done\n")


@pytest.mark.parametrize("op, n", [("and", 200_000), (";", 20_000)])
def test_a_long_releaser_nothing_makes_true_is_checked_in_linear_time(tmp_path, op, n):
    # each literal is a finding on the one line; each was searched for from the clause's start,
    # quadratic: 44 s for 100,000 literals, about 3 minutes for 200,000 (issue 32), 5 s and 10 s now
    path = tmp_path / "chain.yaml"
    path.write_text(long_chain_yaml(n, op))
    r = run("check", path, "--timeout", 60)
    assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr[-500:]   # lint's errors fail check
    lines = [x for x in r.stderr.splitlines() if "[unreachable-releaser]" in x]
    assert len(lines) == n
    line = path.read_text().splitlines()[6]
    for x in lines:                # each at its own literal
        where, _, rest = x.partition(": error: ")
        column = int(where.rsplit(":", 1)[1])
        atom = rest.split(": ")[1].split(" never holds")[0]
        end = column - 1 + len(atom)
        assert line.startswith(atom, column - 1) and line[end:end + 1] in ("", " "), x


def test_a_finding_points_at_its_word_not_inside_a_longer_one(tmp_path):
    path = tmp_path / "t.pl"
    path.write_text("task(t).\nschema(t, [(b, xa1.done and a1.done)], t.done).\nschema(b, [], b.done).\n")
    r = run("lint", path, "--json")
    found = {f["message"].split(": ")[1].split(" never")[0]: f["column"] for f in json.loads(r.stdout)["findings"]}
    assert found == {"xa1.done": 16, "a1.done": 29}, found


@pytest.mark.parametrize("op", ["and", "or", ";"])
def test_a_long_condition_is_verified_at_the_state_limit_in_linear_time(tmp_path, op):
    # the decision diagram of a 20,000-literal condition was built top-down, quadratic (106 s)
    path = tmp_path / "chain.yaml"
    atoms = [f"a{i}.done" for i in range(20_000)]
    path.write_text(long_chain_yaml(20_000, op).replace("- task: t0\n", f"- task: t0\n- initial: ({','.join(atoms)})\n"))
    r = run("verify", path, "--max-states", 3000, "--timeout", 60)
    assert r.returncode == 0 and "sound and complete" in r.stdout, r.stderr[-500:]
