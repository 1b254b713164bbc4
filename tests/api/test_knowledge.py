"""schemalog.load / loads / Knowledge: reading knowledge, choosing tasks, queries, lint."""

from __future__ import annotations

import subprocess
import sys

import pytest

import schemalog
from conftest import COFFEE, MIX, ROOT, SEED_COFFEE


def test_the_issue_one_liner_prints_the_paper_figures():
    code = ("import schemalog; kb = schemalog.load('kb/tasks/mix_with_spoon.pl'); t = kb.task(); "
            "c = t.compress(); r = schemalog.verify(t, c); print(len(t), len(c), r.sound, r.complete)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout == "12 6 True True\n"
    assert out.stderr == ""            # the API prints nothing


def test_several_paths_are_one_program_and_every_format_loads(tmp_path):
    assert schemalog.load(COFFEE).tasks() == ["prepareboth"]
    seed = schemalog.load(SEED_COFFEE)
    assert "prepareboth" in seed.tasks() and len(seed.task("prepareboth")) > 3
    xml = schemalog.load(ROOT / "tests" / "formats" / "btcpp" / "subtrees_main.xml")
    assert len(xml.task()) > 1
    yaml_file = tmp_path / "mix.yaml"
    yaml_file.write_text(subprocess.run([sys.executable, "-m", "schemalog", "convert", str(MIX), "--to", "yaml"],
                                        capture_output=True, text=True, check=True).stdout)
    assert len(schemalog.load(yaml_file).task()) == 12


def test_loads_reads_text_and_names_it_in_errors():
    kb = schemalog.loads("task(t).\nschema(t, [(a, true)], a.done).\nschema(a, [], a.done).\n", name="mine.pl")
    assert kb.tasks() == ["t"] and len(kb.task()) == 2
    with pytest.raises(schemalog.SchemalogError) as err:
        schemalog.loads("task(t).\nschema(t, [(a, true)], a.done\n", name="mine.pl")
    assert (err.value.file, err.value.line, err.value.column) == ("mine.pl", 2, 30)
    assert str(err.value).startswith("mine.pl:2:30: error: unexpected end of file")


def test_a_missing_file_is_a_schemalog_error_with_no_output(capsys):
    with pytest.raises(schemalog.SchemalogError, match="no/such/file.pl: no such file"):
        schemalog.load("no/such/file.pl")
    assert capsys.readouterr() == ("", "")


def test_an_unknown_task_names_the_known_ones():
    with pytest.raises(schemalog.SchemalogError, match="unknown task nope.*tasks here: prepareboth"):
        schemalog.load(COFFEE).task("nope")
    assert schemalog.load(COFFEE).task("preparecoffee").name == "preparecoffee"


def test_query_gives_python_values():
    kb = schemalog.load(MIX)
    answers = list(kb.query("merged(T, B, Parts), length(Parts, N), N > 2"))
    assert [a["N"] for a in answers] == [5]
    assert str(answers[0]["T"]) == "use(spoon)"
    assert [str(p) for p in answers[0]["Parts"]] == ["a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"]
    assert list(kb.query("X = [1, 2.5, a, \"s\"]")) == [{"X": [1, 2.5, "a", "s"]}]
    assert list(kb.query("member(X, [1, 2, 3])", first=True)) == [{"X": 1}]
    assert list(kb.query("fail")) == []


def test_query_errors_and_limits_raise():
    kb = schemalog.loads("loop :- loop.\n")
    with pytest.raises(schemalog.SchemalogError, match="step"):
        list(kb.query("loop", max_steps=1000))
    with pytest.raises(schemalog.SchemalogError):
        list(kb.query("X = ("))


def test_lint_gives_findings_as_objects():
    kb = schemalog.loads("task(t).\nschema(t, [(a, b.done)], a.done).\nschema(a, [], a.done).\n", name="stuck.pl")
    findings = kb.lint()
    assert findings, "a releaser nothing sets is a finding"
    f = findings[0]
    assert f.file == "stuck.pl" and f.line >= 1 and f.code and f.message and f.severity in ("error", "warning")
    assert isinstance(f.fix, str)
    assert schemalog.load(MIX).lint() == []


def test_import_schemalog_is_light():
    code = "import sys, schemalog; print(sorted(m for m in ('sympy', 'numpy', 'lark', 'rich', 'schemalog.logic.engine') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == "[]"


def test_every_public_name_resolves_and_private_ones_do_not():
    for name in schemalog.__all__:
        assert getattr(schemalog, name) is not None
    with pytest.raises(AttributeError):
        schemalog.Engine


def test_queries_share_a_session_and_their_output_goes_where_asked():
    kb = schemalog.load(MIX)
    written: list[str] = []
    assert list(kb.query("assertz(seen(1)), write(hi)", output=written.append)) == [{}]
    assert written == ["hi"]
    assert list(kb.query("seen(X)")) == [{"X": 1}]
    assert len(kb.task()) == 12                     # the task reads the files alone
    with pytest.raises(schemalog.UsageError, match="propagate"):
        list(kb.query("true", propagate="most"))


def test_an_uncaught_prolog_exception_is_a_query_error_with_its_ball():
    kb = schemalog.loads("fact.\n")
    with pytest.raises(schemalog.QueryError) as err:
        list(kb.query("atom_length(X, Y)"))
    assert str(err.value.term).startswith("error(instantiation_error")
    assert "arguments are not sufficiently instantiated" in err.value.message
    with pytest.raises(schemalog.QueryError, match="unknown procedure foo/1"):
        list(kb.query("foo(1)"))
    assert list(kb.query("catch(foo(1), error(E, _), true)"))[0]["E"] is not None   # caught: an answer
