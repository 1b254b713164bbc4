"""schemalog.testing: the assertions, the strategies and the pytest plugin (docs/testing.md)."""

from __future__ import annotations

import importlib.metadata
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import schemalog
from schemalog.cli.main import main
from schemalog.testing import NotProved, assert_compression_sound, assert_equivalent
from schemalog.testing.strategies import task_files, tasks

ROOT = Path(__file__).resolve().parents[2]
MIX = ROOT / "kb" / "tasks" / "mix_with_spoon.pl"
COFFEE = ROOT / "kb" / "tasks" / "prepare_coffee_and_tea.pl"
EXAMPLE = ROOT / "tests" / "example_project"
BROKEN = EXAMPLE / "broken" / "serve_water_compressed.pl"
SRC = Path(schemalog.__file__).resolve().parents[1]

STUCK = """task(t).
schema(t, [(a1(cup), true), (a2(cup), cup.ready)], t.done).
schema(a1(cup), [], a1.done).
schema(a2(cup), [], a2.done).
"""


def timeless(text: str) -> str:
    """A report without its timings (`in 0.07 s`), which differ from run to run."""
    return re.sub(r"in \d+\.\d+ s", "in _ s", text)


def cli_report(capsys, *argv: str) -> str:
    capsys.readouterr()
    main(["verify", *argv])
    return capsys.readouterr().out


# --- the assertions ----------------------------------------------------------------

def test_a_sound_compression_returns_the_proof():
    report = assert_compression_sound(schemalog.load(str(MIX)).task())
    assert report.proved and report.verdict == "proved"


def test_an_unsound_file_fails_with_the_report_schemalog_verify_prints(capsys):
    task = schemalog.load(str(BROKEN)).task()
    assert task.compressed
    with pytest.raises(AssertionError) as failure:
        assert_compression_sound(task)
    message = str(failure.value)
    assert "counterexample, from the initial state hand.free" in message
    assert "then the compressed tree takes a3_a4_a5(bottle)" in message
    assert message.rstrip("\n").endswith("result: the compressed tree is not sound (exit 1)")
    assert timeless(message) == timeless(cli_report(capsys, str(BROKEN)))
    assert isinstance(failure.value, NotProved) and failure.value.report.verdict == "refuted"


def test_assert_equivalent_refutes_the_papers_literal_rule(capsys):
    """Figure 2 compressed without propagation is the paper's perceptual aliasing."""
    task = schemalog.load(str(MIX)).task()
    assert assert_equivalent(task, task.compress(propagate="full")).proved
    with pytest.raises(AssertionError, match="counterexample") as failure:
        assert_equivalent(task, task.compress(propagate="none"))
    assert timeless(str(failure.value)) == timeless(cli_report(capsys, str(MIX), "--propagate", "none"))


def test_a_vacuous_proof_fails_with_its_cause(capsys, tmp_path):
    task = schemalog.loads(STUCK, name="stuck.pl").task()
    with pytest.raises(AssertionError) as failure:
        assert_compression_sound(task)
    message = str(failure.value)
    assert "the task itself cannot complete" in message and "why (schemalog lint)" in message
    assert "result: vacuous" in message
    (tmp_path / "stuck.pl").write_text(STUCK)
    assert "result: vacuous" in cli_report(capsys, str(tmp_path / "stuck.pl"))


def test_a_proof_a_limit_cut_short_fails_saying_so():
    task = schemalog.load(str(COFFEE)).task()
    with pytest.raises(AssertionError, match="NOT a proof") as failure:
        assert_compression_sound(task, method="explicit", max_states=20)
    assert "result: no proof: stopped at the limit of" in str(failure.value)
    assert failure.value.report.verdict == "inconclusive"


def test_options_reach_the_verification():
    task = schemalog.load(str(MIX)).task()
    report = assert_compression_sound(task, states="all", method="explicit")
    assert len(report.as_json()["initial_states"]) > 1


# --- the strategies ----------------------------------------------------------------

@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(tasks(max_behaviours=24))
def test_every_drawn_task_compresses_soundly(task):
    assert_compression_sound(task)


@settings(max_examples=30, deadline=None)
@given(task_files(levels=(2, 5), max_children=3, max_behaviours=16, toggles=True), st.data())
def test_drawn_files_load_lint_and_check(text, data):
    kb = schemalog.loads(text, name="drawn.pl")
    assert kb.tasks() == ["t0"]
    task = kb.task()
    assert 2 <= len(task) <= 16
    assert task.to_prolog()


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(task_files(completing=False, max_behaviours=16))
def test_a_task_that_may_be_stuck_is_proved_or_says_why(text):
    task = schemalog.loads(text).task()
    try:
        assert_compression_sound(task)
    except NotProved as failure:
        assert failure.report.verdict == "vacuous", str(failure)
        assert "the task itself cannot complete" in str(failure)


@settings(max_examples=5)
@given(task_files())
def test_drawn_files_have_the_documented_shape(text):
    assert text.splitlines()[1] == "task(t0)."
    assert "schema(t0," in text and "object(cup)." in text


# --- what importing costs ---------------------------------------------------------

def loaded_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(' '.join(sorted(sys.modules)))"],
                         capture_output=True, text=True, timeout=60, check=True, env=environ())
    return set(out.stdout.split())


def environ() -> dict:
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")])}


@pytest.mark.parametrize("module", ["schemalog", "schemalog.testing", "schemalog.testing.plugin"])
def test_importing_loads_neither_hypothesis_nor_the_engine(module):
    loaded = loaded_after(f"import {module}")
    assert not {"hypothesis", "numpy", "sympy", "lark", "schemalog.logic.engine"} & loaded


def test_the_strategies_without_hypothesis_say_what_to_install():
    code = "import sys\nsys.modules['hypothesis'] = None\nimport schemalog.testing.strategies"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, env=environ())
    assert out.returncode == 1
    assert out.stderr.strip().splitlines()[-1] == \
        "ImportError: schemalog.testing.strategies needs hypothesis: pip install hypothesis"


# --- the pytest plugin ---------------------------------------------------------------

def _entry_point_installed() -> bool:
    return any(ep.name == "schemalog" and ep.value == "schemalog.testing.plugin"
               for ep in importlib.metadata.entry_points(group="pytest11"))


# where schemalog is installed with this checkout's metadata, pytest loads the plugin itself
# (a second -p would register it twice); elsewhere (PYTHONPATH on a checkout) it is named
PLUGIN = [] if _entry_point_installed() else ["-p", "schemalog.testing.plugin"]


def pytest_in(folder: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pytest", *PLUGIN, "-p", "no:cacheprovider", *args],
                          cwd=folder, capture_output=True, text=True, timeout=120, env=environ())


@pytest.fixture
def project(tmp_path):
    """A user's folder: a pytest.ini, one ordinary test, tasks/ with Figure 2 and the coffee."""
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_plain.py").write_text("def test_plain():\n    pass\n")
    (tmp_path / "tasks").mkdir()
    shutil.copy(MIX, tmp_path / "tasks")
    shutil.copy(COFFEE, tmp_path / "tasks")
    return tmp_path


def test_without_the_option_the_plugin_does_nothing(project):
    out = pytest_in(project, "-v")
    assert out.returncode == 0, out.stdout + out.stderr
    assert "test_plain.py::test_plain PASSED" in out.stdout
    # installed, pytest's header lists the plugin ("plugins: schemalog-0.1.0"); nothing else says it
    said = [line for line in out.stdout.splitlines() if "schemalog" in line and not line.startswith("plugins:")]
    assert said == [] and "1 passed" in out.stdout


def test_every_task_under_a_folder_is_one_item_and_proved(project):
    (project / "tasks" / "rules").mkdir()
    shutil.copy(ROOT / "kb" / "compression.pl", project / "tasks" / "rules")   # no task: skipped
    shutil.copy(ROOT / "examples" / "coffee_and_tea_seed.prolog", project / "seed.prolog")
    out = pytest_in(project, "-v", "--schemalog-tasks", "tasks")
    assert out.returncode == 0, out.stdout + out.stderr
    assert "schemalog: proving the tasks under tasks (propagate full, states default)" in out.stdout
    assert "tasks/mix_with_spoon.pl::use(spoon) PASSED" in out.stdout
    assert "tasks/prepare_coffee_and_tea.pl::prepareboth PASSED" in out.stdout
    assert "schemalog: tasks/rules/compression.pl: no task/1 and no root schema: no task to prove" in out.stdout
    assert "3 passed" in out.stdout          # the ordinary test too; the SEED file is not under tasks/
    out = pytest_in(project, "--collect-only", "-q", "--schemalog-tasks", "seed.prolog", "-k", "prepare")
    assert "seed.prolog::prepareboth" in out.stdout.splitlines()


def test_a_broken_task_fails_with_the_counterexample_not_a_traceback(project):
    shutil.copy(BROKEN, project / "tasks")
    out = pytest_in(project, "--schemalog-tasks", "tasks", "tasks/")
    assert out.returncode == 1, out.stdout + out.stderr
    assert "_ serve(water) in tasks/serve_water_compressed.pl _" in out.stdout
    assert "then the compressed tree takes a3_a4_a5(bottle): a3(bottle)" in out.stdout
    assert "result: the compressed tree is not sound (exit 1)" in out.stdout
    assert "FAILED tasks/serve_water_compressed.pl::serve(water)" in out.stdout
    assert "Traceback" not in out.stdout and "plugin.py" not in out.stdout
    assert "2 passed" in out.stdout


def test_propagate_and_states_options_and_the_ini_file(project):
    out = pytest_in(project, "--schemalog-tasks", "tasks", "--schemalog-propagate", "pre", "-k", "prepareboth")
    assert out.returncode == 1 and "soundness (no perceptual aliasing): FAILS" in out.stdout
    (project / "pytest.ini").write_text("[pytest]\nschemalog_tasks = tasks\nschemalog_states = all\n")
    out = pytest_in(project, "-v", "-k", "spoon")
    assert out.returncode == 0, out.stdout + out.stderr
    assert "tasks/mix_with_spoon.pl::use(spoon) PASSED" in out.stdout and "states all" in out.stdout


@pytest.mark.parametrize("args, expected", [
    (["--schemalog-tasks", "nowhere"], "--schemalog-tasks: nowhere: no such folder or file"),
    (["--schemalog-tasks", "tasks", "--schemalog-propagate", "some"], "invalid choice: 'some'"),
])
def test_a_wrong_option_is_a_usage_error(project, args, expected):
    out = pytest_in(project, *args)
    assert out.returncode == 4 and expected in out.stderr
    assert "Traceback" not in out.stderr


def test_a_file_that_does_not_load_is_a_collection_error_with_its_position(project):
    (project / "tasks" / "bad.pl").write_text("task(t).\nschema(t, [(a, true)], t.done\n")
    out = pytest_in(project, "--schemalog-tasks", "tasks")
    assert out.returncode == 2, out.stdout + out.stderr
    assert "ERROR collecting tasks/bad.pl" in out.stdout
    assert re.search(r"bad\.pl:\d+:\d+: ", out.stdout), out.stdout
    assert "Traceback" not in out.stdout and "plugin.py" not in out.stdout


SEED = ROOT / "examples" / "coffee_and_tea_seed.prolog"

# a conftest that makes collection fail if it instantiates, compresses or queries a task
NO_WORK_AT_COLLECTION = """
import schemalog.api.knowledge as knowledge, schemalog.api.task as task

def refused(*args, **kwargs):
    raise RuntimeError("schemalog work at collection")

knowledge.Knowledge.task = knowledge.Knowledge.query = task.Task.compress = refused
"""


def collected_ids(out: subprocess.CompletedProcess) -> list[str]:
    return [line for line in out.stdout.splitlines() if "::" in line]


def test_a_seed_file_gives_one_item_its_first_root_schema_and_collecting_proves_nothing(project):
    shutil.copy(SEED, project / "tasks")
    (project / "conftest.py").write_text(NO_WORK_AT_COLLECTION)
    out = pytest_in(project, "--collect-only", "-q", "--schemalog-tasks", "tasks")
    assert out.returncode == 0, out.stdout + out.stderr
    assert [i for i in collected_ids(out) if i.startswith("tasks/coffee_and_tea_seed")] == \
        ["tasks/coffee_and_tea_seed.prolog::prepareboth"]
    (project / "conftest.py").unlink()
    out = pytest_in(project, "-q", "--schemalog-tasks", "tasks/coffee_and_tea_seed.prolog")
    # one item, run: the SEED memory declares no initial state, so its proof is vacuous
    assert "FAILED tasks/coffee_and_tea_seed.prolog::prepareboth" in out.stdout, out.stdout + out.stderr
    assert "result: vacuous" in out.stdout and "1 failed, 1 passed" in out.stdout


def test_collect_only_counts_what_it_lists(project):
    """Issue: "4 tests collected" for 3 task items; the fourth is the project's own test."""
    for args in ([], ["-k", "spoon"], ["tasks"], ["test_plain.py"]):
        out = pytest_in(project, "--collect-only", "-q", "--schemalog-tasks", "tasks", *args)
        ids = collected_ids(out)
        total = re.search(r"(\d+) tests? collected|(\d+)/\d+ tests collected", out.stdout)
        assert total and int(total.group(1) or total.group(2)) == len(ids) == len(set(ids)), out.stdout
    assert len(collected_ids(pytest_in(project, "--collect-only", "-q", "--schemalog-tasks", "tasks"))) == 3


def test_a_folder_with_no_task_file_fails_saying_which(project):
    (project / "empty" / "sub").mkdir(parents=True)
    (project / "empty" / "notes.txt").write_text("nothing here\n")
    out = pytest_in(project, "--schemalog-tasks", "tasks", "--schemalog-tasks", "empty")
    assert out.returncode == 4, out.stdout + out.stderr
    assert "--schemalog-tasks: empty: no task files (*.pl, *.prolog) in this folder" in out.stderr
    (project / "pytest.ini").write_text("[pytest]\nschemalog_tasks = empty\n")
    out = pytest_in(project)
    assert out.returncode == 4 and "schemalog_tasks (ini): empty: no task files" in out.stderr


def test_folders_that_give_no_task_at_all_fail_naming_their_files(project):
    (project / "rules").mkdir()
    shutil.copy(ROOT / "kb" / "compression.pl", project / "rules")
    (project / "rules" / "tool.pl").write_text("#!/usr/bin/perl\nuse strict;\nprint \"hi\\n\";\n")
    out = pytest_in(project, "--schemalog-tasks", "rules")
    assert out.returncode == 2, out.stdout + out.stderr
    assert "schemalog: no task to prove under rules:" in out.stdout
    assert "rules/compression.pl: no task/1 and no root schema" in out.stdout
    assert "rules/tool.pl: a script (#!/usr/bin/perl), not schemalog knowledge: skipped" in out.stdout
    out = pytest_in(project, "--collect-only", "-q", "--schemalog-tasks", "rules")
    assert out.returncode == 2
    out = pytest_in(project, "-q", "--schemalog-tasks", "rules", "--schemalog-tasks", "tasks")   # one among others: a note
    assert out.returncode == 0 and "3 passed" in out.stdout, out.stdout + out.stderr
    assert "schemalog: rules/compression.pl: no task/1 and no root schema: no task to prove" in out.stdout


def test_files_that_are_not_schemalog_knowledge_are_skipped_with_a_note(project):
    (project / "tasks" / "deploy.pl").write_text("#!/usr/bin/perl\nmy %h = (schema => 1);\nprint schema($x);\n")
    (project / "tasks" / "old.pl").write_text("use strict;\nmy $x = 1;\nprint \"$x\\n\";\n")
    out = pytest_in(project, "-q", "--schemalog-tasks", "tasks")
    assert out.returncode == 0 and "3 passed" in out.stdout, out.stdout + out.stderr
    assert "schemalog: tasks/deploy.pl: a script (#!/usr/bin/perl), not schemalog knowledge: skipped" in out.stdout
    assert "schemalog: tasks/old.pl: does not load and holds no schema(: not schemalog knowledge, skipped (" \
        in out.stdout


def test_the_ini_folders_are_collected_only_without_path_arguments(project):
    (project / "pytest.ini").write_text("[pytest]\nschemalog_tasks = tasks\n")
    out = pytest_in(project, "-v", "test_plain.py::test_plain")
    assert out.returncode == 0 and "1 passed" in out.stdout, out.stdout + out.stderr
    assert ".pl::" not in out.stdout and "schemalog: proving" not in out.stdout
    out = pytest_in(project, "-q", "test_plain.py", "--schemalog-tasks", "tasks")
    assert out.returncode == 0 and "3 passed" in out.stdout, out.stdout + out.stderr
    out = pytest_in(project, "-q")
    assert out.returncode == 0 and "3 passed" in out.stdout, out.stdout + out.stderr


def test_the_printed_node_id_reruns_its_item(project):
    shutil.copy(BROKEN, project / "tasks")
    out = pytest_in(project, "--schemalog-tasks", "tasks")
    failed = re.search(r"^FAILED (\S+) - ", out.stdout, re.M).group(1)
    assert failed == "tasks/serve_water_compressed.pl::serve(water)"
    for args in (["--schemalog-tasks", "tasks", failed], ["--schemalog-tasks", "tasks", "-k", "water"]):
        out = pytest_in(project, "-v", *args)
        assert out.returncode == 1 and "1 failed" in out.stdout and "passed" not in out.stdout, out.stdout
        assert f"{failed} FAILED" in out.stdout
    (project / "pytest.ini").write_text("[pytest]\nschemalog_tasks = tasks\n")
    out = pytest_in(project, "-v", "tasks/mix_with_spoon.pl::use(spoon)")
    assert out.returncode == 0 and "1 passed" in out.stdout, out.stdout + out.stderr
    assert "tasks/mix_with_spoon.pl::use(spoon) PASSED" in out.stdout


TABLE = """task(set(table)).
initial(cloth.folded).
schema(set(table), [(lay(cloth), cloth.folded), (put(plates), cloth.laid)], plates.put).
schema(lay(cloth), [], cloth.laid).
schema(put(plates), [], plates.put).
"""


def test_a_task_named_by_an_operator_word_is_its_node_id_in_either_spelling(project):
    """Issue 45: task(set(table)) was the item set('table'), as the writer quoted `table` (a prefix
    operator, for tabling), so `pytest "tasks/table.pl::set(table)"` was "not found". The node id is
    set(table), as swipl writes it, and the old spelling still names it."""
    (project / "tasks" / "table.pl").write_text(TABLE)
    out = pytest_in(project, "-v", "--schemalog-tasks", "tasks")
    assert "tasks/table.pl::set(table) PASSED" in out.stdout, out.stdout + out.stderr
    for spelling in ("set(table)", "set('table')", "set( table )"):
        out = pytest_in(project, "-v", "--schemalog-tasks", "tasks", f"tasks/table.pl::{spelling}")
        assert out.returncode == 0 and "1 passed" in out.stdout, spelling + out.stdout + out.stderr
        assert f"tasks/table.pl::{spelling} PASSED" in out.stdout
    out = pytest_in(project, "-v", "--schemalog-tasks", "tasks", "tasks/table.pl::set(chair)")
    assert out.returncode == 4 and "not found" in out.stdout + out.stderr


# a conftest that writes the options each proof was given
RECORD_VERIFY = """
import json, schemalog
proved = schemalog.verify

def recording(original, compressed, **options):
    with open("verified.json", "a") as out:
        out.write(json.dumps(options) + "\\n")
    return proved(original, compressed, **options)

schemalog.verify = recording
"""


def test_the_proof_limits_reach_each_proof(project):
    import inspect

    (project / "conftest.py").write_text(RECORD_VERIFY)
    record = project / "verified.json"

    def options(*args: str) -> dict:
        record.unlink(missing_ok=True)
        out = pytest_in(project, "-q", "--schemalog-tasks", "tasks", "-k", "spoon", *args)
        assert out.returncode == 0, out.stdout + out.stderr
        import json
        return json.loads(record.read_text())

    defaulted = options()
    assert "max_states" not in defaulted and "max_bdd_nodes" not in defaulted and defaulted["timeout"] is None
    given = options("--schemalog-max-states", "123", "--schemalog-max-bdd-nodes", "4567",
                    "--schemalog-timeout", "30")
    assert given["max_states"] == 123 and given["max_bdd_nodes"] == 4567 and 29 < given["timeout"] <= 30
    (project / "pytest.ini").write_text("[pytest]\nschemalog_max_states = 99\nschemalog_max_bdd_nodes = 77\n"
                                        "schemalog_timeout = 12.5\n")
    from_ini = options()
    assert from_ini["max_states"] == 99 and from_ini["max_bdd_nodes"] == 77 and 12 < from_ini["timeout"] <= 12.5
    # the defaults the help names are schemalog verify's
    out = pytest_in(project, "--help")
    from schemalog import defaults
    verify_default = inspect.signature(schemalog.verify).parameters["max_bdd_nodes"].default
    assert f"(default {defaults.MAX_STATES:,}; ini" in out.stdout
    assert f"(default {verify_default:,}; ini" in out.stdout


def test_a_timeout_fails_the_item_saying_how_to_raise_it(project):
    out = pytest_in(project, "--schemalog-tasks", "tasks", "-k", "prepareboth", "--schemalog-timeout", "0.001")
    assert out.returncode == 1, out.stdout + out.stderr
    assert "prepareboth: time limit of 0.001 s exceeded (raise it with --schemalog-timeout" in out.stdout
    assert "Traceback" not in out.stdout and "During handling" not in out.stdout


@pytest.mark.parametrize("args, expected", [
    (["--schemalog-max-states", "0"], "--schemalog-max-states: '0' is not a positive whole number"),
    (["--schemalog-max-bdd-nodes", "many"], "--schemalog-max-bdd-nodes: 'many' is not a positive whole number"),
    (["--schemalog-timeout", "soon"], "--schemalog-timeout: 'soon' is not a number of seconds"),
    (["--schemalog-timeout", "0"], "--schemalog-timeout: 0: from 0.001 to"),
])
def test_a_wrong_limit_is_a_usage_error(project, args, expected):
    out = pytest_in(project, "--schemalog-tasks", "tasks", *args)
    assert out.returncode == 4 and expected in out.stderr, out.stdout + out.stderr


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs and /dev/zero are POSIX")
def test_files_that_cannot_be_read_are_named_with_what_they_are_and_never_read(project):
    """A FIFO, a link loop, a link to /dev/zero or to nothing under a task folder were skipped
    without a word (issue 46); a FIFO named alone gave 'no task to prove' and nothing else.
    Reading any of them would wait for a writer, never end, or fail."""
    tasks = project / "tasks"
    os.mkfifo(tasks / "pipe.pl")
    (tasks / "loop.pl").symlink_to("loop.pl")
    (tasks / "zero.pl").symlink_to("/dev/zero")
    (tasks / "gone.pl").symlink_to("missing.pl")
    out = pytest_in(project, "-q", "--schemalog-tasks", "tasks")
    assert out.returncode == 0 and "3 passed" in out.stdout, out.stdout + out.stderr
    for line in ("schemalog: tasks/pipe.pl: a FIFO (reading it would wait for a writer): skipped",
                 "schemalog: tasks/loop.pl: a link loop: skipped",
                 "schemalog: tasks/zero.pl: a link to /dev/zero, a device: skipped",
                 "schemalog: tasks/gone.pl: a link to missing.pl, which does not exist: skipped"):
        assert line in out.stdout.splitlines(), out.stdout
    (project / "pipes").mkdir()
    os.mkfifo(project / "pipes" / "only.pl")
    out = pytest_in(project, "--schemalog-tasks", "pipes")
    assert out.returncode == 4 and "pipes: no task files (*.pl, *.prolog) in this folder: no task to prove; " \
        "pipes/only.pl: a FIFO (reading it would wait for a writer): skipped" in out.stderr, out.stderr
    out = pytest_in(project, "--schemalog-tasks", "tasks/loop.pl")
    assert out.returncode == 2 and "tasks/loop.pl: a link loop: skipped" in out.stdout, out.stdout + out.stderr


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root reads any file")
def test_a_file_this_process_may_not_read_is_named(project):
    secret = project / "tasks" / "secret.pl"
    shutil.copy(MIX, secret)
    secret.chmod(0)
    out = pytest_in(project, "-q", "--schemalog-tasks", "tasks")
    assert out.returncode == 0 and "3 passed" in out.stdout, out.stdout + out.stderr
    assert "schemalog: tasks/secret.pl: cannot be read (Permission denied): skipped" in out.stdout.splitlines()


def test_a_file_the_system_refuses_to_open_is_named_with_its_reason(tmp_path, monkeypatch):
    # what the test above shows where it runs; as root (CI containers) a refused open stands in
    from schemalog.testing import plugin

    secret = tmp_path / "secret.pl"
    shutil.copy(MIX, secret)
    opened = os.open

    def refuse(path, flags, *args):
        if Path(path) == secret:
            raise PermissionError(13, "Permission denied")
        return opened(path, flags, *args)

    monkeypatch.setattr(os, "open", refuse)
    assert list(plugin.task_files([tmp_path])) == [(secret, "cannot be read (Permission denied): skipped")]
