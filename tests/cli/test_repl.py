"""The REPL as a user meets it: piped transcripts, a real terminal (pexpect), completion."""

import subprocess
import sys
import time

import pexpect

from schemalog.cli.completion import completion_words
from schemalog.cli.relations import Workspace

from conftest import MIX, ROOT


def run(*args, stdin=None, env=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=120, input=stdin, env=env)


TRANSCRIPT = """\
member(X, [1,2,3]).
;

append(X, Y,
  [a]).
;
;
:tree
:compress
enabled(B), node(B, L).
:run
holds(spoon.used).
:reset
holds(spoon.used).
foo(.
:limit 500
assertz((loop :- loop)), loop.
:verify
:quit
X = never.
"""


def test_repl_piped_transcript():
    r = run("repl", MIX, stdin=TRANSCRIPT)
    assert r.returncode == 0, r.stderr
    out = r.stdout
    assert "?- member(X, [1,2,3]).\nX = 1 ;\nX = 2.\n" in out
    assert "X = [], Y = [a] ;\nX = [a], Y = [] ;\nfalse.\n" in out
    assert "2 a1(spoon)  pre: true  post: a1.done" in out                 # :tree numbers as node/2
    assert "% Bi = 12, Bm = 6, D = 3, RD = 0.67" in out
    assert "?- enabled(B), node(B, L).\nB = 14, L = a1_a2(spoon)." in out
    assert "% completed: use(spoon) is accomplished" in out
    assert "?- holds(spoon.used).\ntrue.\n" in out and "?- holds(spoon.used).\nfalse.\n" in out
    assert "syntax error" in out and "    ^" in out
    assert "step limit of 500 resolution steps exceeded" in out
    assert "use(spoon): proved" in out
    assert "never" not in out


def test_repl_reads_several_queries_on_a_line_and_skips_comments():
    r = run("repl", "--plain", stdin="X = 1. Y = 2.\n% a comment\n/* another */\nZ = 3.\n;\n:tree 12\n:tree X\n:limit \u0661\n")
    assert r.returncode == 0, r.stdout
    assert "?- X = 1.\nX = 1.\n?- Y = 2.\nY = 2.\n?- Z = 3.\nZ = 3.\n" in r.stdout
    assert "no task 12 here" in r.stdout and "not a variable" in r.stdout
    assert "needs a positive number of steps" in r.stdout


def test_repl_load_and_unfinished_input(tmp_path):
    extra = tmp_path / "extra.pl"
    extra.write_text("colour(red). colour(green).\n")
    r = run("repl", f"--plain", stdin=f":load {extra}\nfindall(C, colour(C), L).\nX = \n")
    assert "L = [red, green]" in r.stdout
    assert r.returncode == 2 and "input ended inside a query" in r.stdout
    r = run("repl", stdin=":load /no/such.pl\n:tree\n")
    assert "no such file" in r.stdout and "no task here" in r.stdout


def test_repl_on_a_terminal(tmp_path):
    history = tmp_path / "history"
    child = pexpect.spawn(sys.executable, ["-m", "schemalog", "repl", str(MIX)], cwd=str(ROOT),
                          # a pseudo-terminal answers no cursor-position request: do not wait for one
                          env={"SCHEMALOG_HISTORY": str(history), "TERM": "xterm", "PATH": "/usr/bin:/bin",
                               "PROMPT_TOOLKIT_NO_CPR": "1"},
                          encoding="utf-8", timeout=30, dimensions=(40, 120))
    child.expect(r"\?-")
    child.send("member(X,\r")                    # not finished: Enter continues the query
    child.send("[1,2,3]).\r")
    child.expect("X = 1")
    child.send(";")                               # ';' asks for the next answer
    child.expect("X = 2")
    child.send("\r")                              # Enter stops
    child.expect(r"\?-")
    child.send("between(1, inf, X), X < 0.\r")   # runs until Ctrl-C
    child.expect(r"X < 0\.")
    time.sleep(1.5)
    child.sendintr()
    child.expect("interrupted")
    child.expect(r"\?-")
    child.send("sequen\t")                        # one completion: Tab takes it
    child.send("(X, Y).\r")
    child.expect("X = 1, Y = 5")
    child.send("\r")
    child.expect(r"\?-")
    child.sendeof()
    child.expect(pexpect.EOF)
    saved = history.read_text()
    assert "+member(X,\n+[1,2,3])." in saved and "+sequential(X, Y)." in saved


def test_completion_offers_predicates_relations_atoms_and_commands():

    ws = Workspace([str(MIX)])
    assert completion_words(ws, "sequen") == {"sequential"}
    assert completion_words(ws, ":co") == {":compress"}
    assert {"spoon", "subtask", "schema"} <= completion_words(ws, "s")       # atoms and predicates
    assert "next_action" in completion_words(ws, "next")
