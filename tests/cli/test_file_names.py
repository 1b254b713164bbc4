"""End to end: file names the system refuses (longer than NAME_MAX) or that are not UTF-8, given
to every command that reads or writes: `FILE: reason` messages and exit 1 for the first, the
work done for the second, the name shown readably (`\\xff`) in messages and in what is written."""

import ast
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

import pytest

from conftest import MIX, ROOT

ENV = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
ENV.pop("SCHEMALOG_DEBUG", None)
STRUCTURE = ROOT / "kb" / "tasks" / "coffee_structure.pl"
KITCHEN = ROOT / "kb" / "scenes" / "kitchen.yaml"
MIX_SCENE = ROOT / "kb" / "scenes" / "mix_with_spoon.yaml"
LONG = "x" * 300 + ".pl"             # past NAME_MAX (255 bytes): ENAMETOOLONG, not ENOENT


def run(*args, cwd):
    """The command with bytes arguments (a name that is not UTF-8 is passed as its bytes)."""
    argv = [a if isinstance(a, bytes) else os.fsencode(str(a)) for a in args]
    return subprocess.run([sys.executable.encode(), b"-m", b"schemalog", *argv], capture_output=True,
                          cwd=cwd, timeout=120, env=ENV)


def clean(r):
    """Standard error as text: it must be UTF-8, with no traceback and no internal error."""
    err = r.stderr.decode("utf-8")           # strict: an undecodable byte fails the test
    assert "Traceback" not in err and "internal error" not in err and r.returncode != 70, err[-2000:]
    return err


# (argv with NAME standing for the long name, the exit status: query says 2 for a file it cannot read)
LONG_INPUTS = [
    (["check", "NAME"], 1), (["show", "NAME"], 1), (["compress", "NAME"], 1), (["run", "NAME"], 1),
    (["verify", "NAME"], 1), (["query", "NAME", "true"], 2), (["convert", "NAME"], 1), (["decompress", "NAME"], 1),
    (["lint", "NAME"], 1), (["export", "NAME", "--to", "btcpp"], 1), (["simulate-demo", "NAME", "--scene", MIX_SCENE], 1),
    (["run", MIX, "--scene", "NAME"], 1), (["learn", "NAME", "--structure", STRUCTURE], 1),
    (["learn", "demo.csv", "--structure", "NAME"], 1), (["check", "inc.pl"], 1),
]


@pytest.mark.parametrize("argv, status", LONG_INPUTS, ids=[" ".join(map(str, a[:1] + a[-1:])) for a, _ in LONG_INPUTS])
def test_an_input_name_longer_than_name_max_is_a_message(tmp_path, argv, status):
    (tmp_path / "demo.csv").write_text("t,x,y,z\n0,0,0,0\n")
    (tmp_path / "inc.pl").write_text(f"task(t).\n:- consult('{LONG}').\n")
    before = sorted(os.listdir(tmp_path))
    r = run(*[LONG if a == "NAME" else a for a in argv], cwd=tmp_path)
    err = clean(r)
    assert r.returncode == status, (r.returncode, err)
    said = err + r.stdout.decode("utf-8")       # lint reports on standard output
    errors = [line for line in said.splitlines() if "error:" in line]
    assert len(errors) == 1 and "File name too long" in errors[0] and len(errors[0]) < 300, said
    assert "(a name of 303 characters)" in errors[0], err       # named, by its two ends
    if argv == ["check", "inc.pl"]:
        assert errors[0].startswith("inc.pl:2:1: error: "), err  # the consult directive's place
    assert sorted(os.listdir(tmp_path)) == before


def test_bench_out_longer_than_name_max_is_refused(tmp_path):
    r = run("bench", "--quick", "--out", LONG, cwd=tmp_path)
    err = clean(r)
    assert r.returncode == 2 and "File name too long" in err and os.listdir(tmp_path) == [], err


NOT_UTF8 = b"t\xff\xfeask.pl"          # bytes no UTF-8 decoder takes: os.fsdecode keeps them as surrogates
SHOWN = "t\\xff\\xfeask.pl"             # what messages and written files show


@pytest.fixture
def odd(tmp_path):
    """A directory holding the shipped task under a name that is not UTF-8."""
    shutil.copy(MIX, os.path.join(os.fsencode(str(tmp_path)), NOT_UTF8))
    shutil.copy(MIX_SCENE, tmp_path / "scene.yaml")
    return tmp_path


def module_title(source: str) -> str:
    """The TITLE an exported py_trees module assigns (the module holds names only as literals)."""
    for statement in ast.parse(source).body:
        if isinstance(statement, ast.Assign) and statement.targets[0].id == "TITLE":
            return ast.literal_eval(statement.value)
    raise AssertionError("the module assigns no TITLE")


@pytest.mark.parametrize("argv", [
    ["check"], ["lint"], ["show"], ["compress"], ["decompress"], ["run"], ["verify"], ["convert"], ["query", "true"],
    ["export", "--to", "btcpp"], ["export", "--to", "py_trees"], ["show", "--json"], ["lint", "--json"]],
    ids=lambda a: " ".join(a))
def test_a_name_that_is_not_utf8_works_and_is_shown_readably(odd, argv):
    r = run(argv[0], NOT_UTF8, *argv[1:], cwd=odd)
    clean(r)
    assert r.returncode == 0, r.stderr
    out = r.stdout.decode("utf-8")           # strict: what is printed is UTF-8 text
    if argv[0] == "export" and argv[-1] == "py_trees":
        assert SHOWN in module_title(out)
    elif argv[0] == "export":
        ElementTree.fromstring(r.stdout)
        assert SHOWN in out
    elif argv[0] == "check":
        assert out.startswith(f"ok: {SHOWN}: 12 schemas")


@pytest.mark.parametrize("argv, output", [
    (["compress", "-o"], "out.pl"), (["convert", "-o"], "out.pl"), (["convert", "--to", "seed", "-o"], "out.prolog"),
    (["show", "--format", "pl", "-o"], "out.pl"), (["export", "--to", "btcpp", "-o"], "out.xml"),
    (["export", "--to", "py_trees", "-o"], "out.py"), (["compress", "--format", "dot", "-o"], "out.dot"),
    (["run", "--json", "-o"], "out.json"), (["verify", "--json", "-o"], "out.json"),
    (["simulate-demo", "--scene", "scene.yaml", "-o"], "d.csv")], ids=lambda a: " ".join(a) if isinstance(a, list) else a)
def test_what_is_written_from_a_name_that_is_not_utf8_is_utf8_and_names_it_readably(odd, argv, output):
    r = run(argv[0], NOT_UTF8, *argv[1:], output, cwd=odd)
    err = clean(r)
    assert r.returncode == 0, err
    assert f"wrote {output}" in err
    text = (odd / output).read_bytes().decode("utf-8")      # strict
    if output.endswith(".py"):
        assert SHOWN in module_title(text)
    elif output.endswith(".xml"):
        ElementTree.fromstring(text.encode())
    if output in ("out.pl", "out.prolog", "out.xml") and argv[0] != "show":   # a header or title names it
        assert SHOWN in text, text[:400]
    if output == "out.pl":
        assert run("check", output, cwd=odd).returncode == 0


def test_learn_from_a_demonstration_whose_name_is_not_utf8(tmp_path):
    demo = b"d\xff.csv"
    r = run("simulate-demo", "--scene", KITCHEN, "--task", "preparecoffee", "-o", demo, cwd=tmp_path)
    assert r.returncode == 0, clean(r)
    r = run("learn", demo, "--structure", STRUCTURE, "--task", "preparecoffee", "-o", "learned.pl", cwd=tmp_path)
    clean(r)
    assert r.returncode == 0, r.stderr
    text = (tmp_path / "learned.pl").read_text(encoding="utf-8")
    assert "from d\\xff.csv" in text and run("check", "learned.pl", cwd=tmp_path).returncode == 0


@pytest.mark.parametrize("name", [b"gone\xff.pl", b"new\nline.pl", b"esc\x1b[2J.pl", b"-dash.pl"])
def test_a_missing_file_with_an_odd_name_is_one_readable_line(tmp_path, name):
    r = run("check", b"./" + name if name.startswith(b"-") else name, cwd=tmp_path)
    err = clean(r)
    assert r.returncode == 1 and err.count("\n") == 1 and err.endswith(": no such file\n"), err
    assert "\x1b" not in err


@pytest.mark.parametrize("name", ['q"""q.pl', "b\\N{x}.pl", "quote'.pl", "dash--dash.pl", "new\nline.pl"])
def test_an_exported_module_or_document_survives_the_name_it_comes_from(tmp_path, name):
    shutil.copy(MIX, tmp_path / name)
    r = run("export", name, "--to", "py_trees", "-o", "t.py", cwd=tmp_path)
    assert r.returncode == 0, clean(r)
    ast.parse((tmp_path / "t.py").read_text())
    r = run("export", name, "--to", "btcpp", "-o", "t.xml", cwd=tmp_path)
    assert r.returncode == 0, clean(r)
    ElementTree.parse(tmp_path / "t.xml")
    for command, output in (("compress", "c.pl"), ("convert", "v.pl")):
        r = run(command, name, "-o", output, cwd=tmp_path)
        assert r.returncode == 0, clean(r)
        assert run("check", output, cwd=tmp_path).returncode == 0, (name, (tmp_path / output).read_text()[:300])
