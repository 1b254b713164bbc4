"""End to end: integers past Python's 4,300-digit str/int limit, and past what a float holds,
wherever a user can write one (a YAML task, a compressed file's provenance, a demonstration,
a query's answer): a message naming file:line:column, exit 1, never an internal error."""

import json
import os
import subprocess
import sys

import pytest

from conftest import MIX, ROOT

ENV = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
HUGE = "7" * 5000           # past Python's int <-> str limit of 4,300 digits
LARGE = "7" * 400           # within it, past the largest float (about 1.8e308)


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd or ROOT, timeout=120, env=ENV)


def refused(r, where):
    """Exit 1, one message that starts at `where` (file:line:col), no traceback, no internal error."""
    assert r.returncode == 1, (r.returncode, r.stderr[-2000:])
    assert "Traceback" not in r.stderr and "internal error" not in r.stderr, r.stderr[-2000:]
    errors = [line for line in r.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1 and errors[0].startswith(f"{where}: error: "), r.stderr[-2000:]
    assert len(errors[0]) < 400, errors[0][:600]        # the number is not printed whole
    return errors[0]


YAML_TASK = """schemalog: 1
items:
  - task: t
  - schema: t
    subtasks:
      - {{behaviour: a, releaser: true, importance: {weight}}}
      - {{behaviour: b, releaser: a.done}}
    post: b.done
  - behaviour: a
  - behaviour: b
"""


@pytest.mark.parametrize("digits", [HUGE, LARGE], ids=["5000-digits", "400-digits"])
@pytest.mark.parametrize("command", ["check", "convert", "show", "run", "verify", "compress"])
def test_a_huge_importance_in_yaml_is_refused_where_it_was_written(tmp_path, command, digits):
    task = tmp_path / "bigimp.yaml"
    task.write_text(YAML_TASK.format(weight=digits))
    before = task.read_bytes()
    message = refused(run(command, task.name, cwd=tmp_path), "bigimp.yaml:4:5")
    assert "importance of a" in message and f"({len(digits):,} digits)" in message
    assert task.read_bytes() == before


@pytest.mark.parametrize("digits", [HUGE, LARGE], ids=["5000-digits", "400-digits"])
@pytest.mark.parametrize("command", ["check", "show", "run"])
def test_a_huge_importance_in_a_pl_task_is_refused_where_it_was_written(tmp_path, command, digits):
    task = tmp_path / "imp.pl"
    task.write_text(f"task(t).\n\nschema(t, [(a, true, {digits}), (b, a.done)], b.done).\nbehaviour(a).\nbehaviour(b).\n")
    message = refused(run(command, task.name, cwd=tmp_path), "imp.pl:3:1")
    assert "importance of a" in message and "at most" in message


def test_an_importance_a_float_holds_still_works(tmp_path):
    task = tmp_path / "imp.yaml"
    task.write_text(YAML_TASK.format(weight="1" + "0" * 300))
    r = run("run", task.name, cwd=tmp_path)
    assert r.returncode == 0 and "completed" in r.stdout, r.stderr


@pytest.fixture(scope="module")
def compressed(tmp_path_factory):
    """mix_with_spoon compressed, as a user would make it, and the line of its first origins/2 fact."""
    directory = tmp_path_factory.mktemp("compressed")
    r = run("compress", MIX, "-o", directory / "c.pl")
    assert r.returncode == 0, r.stderr
    text = (directory / "c.pl").read_text()
    line = next(n for n, line in enumerate(text.splitlines(), 1)
                if line.startswith("origins(subtask(take_mix,spoon),"))
    return text, line


@pytest.mark.parametrize("field", ["importance", "large-importance", "slot"])
@pytest.mark.parametrize("command", ["check", "verify", "decompress", "show", "decompress --json"])
def test_a_huge_number_in_provenance_is_refused_where_it_was_written(tmp_path, compressed, command, field):
    text, line = compressed
    number = LARGE if field == "large-importance" else HUGE
    fields = f"1,0,{number}" if field == "slot" else f"{number},0,0"
    edited = text.replace("origin(a1(spoon),true,a1.done,1,0,0)", f"origin(a1(spoon),true,a1.done,{fields})")
    assert edited != text
    (tmp_path / "c.pl").write_text(edited)
    r = run(*command.split(), "c.pl", cwd=tmp_path)
    message = refused(r, f"c.pl:{line}:1")        # the origins/2 fact that holds it
    assert f"({len(number):,} digits)" in message
    assert (tmp_path / "c.pl").read_text() == edited


@pytest.mark.parametrize("where", ["time", "position", "object", "gripper"])
def test_a_huge_number_in_a_json_demonstration_is_refused(tmp_path, where):
    made = run("simulate-demo", "--scene", ROOT / "kb" / "scenes" / "kitchen.yaml", "--task", "preparecoffee",
               "-o", "demo.json", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    data = json.loads((tmp_path / "demo.json").read_text())
    marker = 123456.5                   # a number the file does not hold, replaced by the digits
    if where == "time":
        data["time"][1] = marker
    elif where == "position":
        data["position"][2][1] = marker
    elif where == "object":
        value = data["objects"][sorted(data["objects"])[0]]
        (value[0] if isinstance(value[0], list) else value)[0] = marker
    else:
        data["gripper"][0]["time"] = marker
    text = json.dumps(data).replace(repr(marker), HUGE, 1)
    (tmp_path / "demo.json").write_text(text)
    r = run("learn", "demo.json", "--structure", ROOT / "kb" / "tasks" / "coffee_structure.pl",
            "--task", "preparecoffee", "-o", "out.pl", cwd=tmp_path)
    # a JSON demonstration's messages name the sample or event, not a line (docs/learning.md)
    assert r.returncode == 1 and "Traceback" not in r.stderr and "internal error" not in r.stderr, r.stderr[-2000:]
    assert r.stderr.startswith("error: demo.json: ") and r.stderr.count("\n") == 1, r.stderr[-2000:]
    assert "(5,000 digits)" in r.stderr and len(r.stderr) < 400, r.stderr[-2000:]
    assert not (tmp_path / "out.pl").exists() and (tmp_path / "demo.json").read_text() == text


def test_a_query_answer_past_the_digit_limit_is_valid_json():
    r = run("query", MIX, "X is 10 ** 5000, Y is -(7 ** 6000), Z = f(X)", "--json")
    assert r.returncode == 0 and r.stderr == "", r.stderr[-2000:]
    answers = json.loads(r.stdout, parse_int=lambda digits: digits)      # any JSON reader's view, exactly
    assert answers[0]["X"] == "1" + "0" * 5000 and answers[0]["Z"] == "f(1" + "0" * 5000 + ")"
    assert answers[0]["Y"][0] == "-" and answers[0]["Y"][1:].isdigit() and len(answers[0]["Y"]) > 5000
    r = run("query", MIX, "X is 10 ** 5000")
    assert r.returncode == 0 and r.stdout.strip() == "X = 1" + "0" * 5000
