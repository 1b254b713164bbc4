"""The top level: answers printed as SWI-Prolog prints them, `schemalog query` and the REPL,
run as a user runs them (a subprocess; the REPL also on a pseudo-terminal)."""

import json
import subprocess
import sys
import time

import pexpect
import pytest

from schemalog.relations import Workspace
from schemalog.toplevel import answer_text, answers, complete_input, read_query

from conftest import COFFEE, MIX, ROOT


def run(*args, stdin=None, env=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=120, input=stdin, env=env)


# What swipl 9.0.4's top level printed for each query (joined on one line).
SWIPL_ANSWERS = [
    ("member(X, [a,b]), Y = X", "X = Y, Y = a"),
    ("X = a, Y = a, Z = b", "X = Y, Y = a, Z = b"),
    ("X = Y, Z = f(X, W)", "X = Y, Z = f(Y, W)"),
    ("length(L, 2)", "L = [_, _]"),
    ("X = f(Y), Y = g(_Z)", "X = f(g(_Z)), Y = g(_Z)"),
    ("X = (a:-b), Y = (p,q), Z = [1,2|T]", "X = (a:-b), Y = (p, q), Z = [1, 2|T]"),
    ("X = 'hello world', Y = \"str\", Z = -(1), W = - 1, V = 1-2",
     "X = 'hello world', Y = \"str\", Z = W, W = - 1, V = 1-2"),
    ("X = f(A, B, A)", "X = f(A, B, A)"),
    ("true", "true"),
    ("X = f(X)", "X = f(X)"),
    ("X = (is), Y = ',', Z = f(is), W = (mod)-1", "X = (is), Y = (','), Z = f(is), W = (mod)-1"),
    ("X = '/*'(a)", "X = '/*'(a)"),                                   # cyclic: made without occurs check
    ("_X = 1", "true"),
]


@pytest.mark.parametrize("query, printed", SWIPL_ANSWERS)
def test_answers_print_as_in_swi_prolog(query, printed):
    ws = Workspace([])
    first = next(answers(ws, read_query(query)))[0]
    assert answer_text(first) == printed


@pytest.mark.parametrize("text, complete", [
    ("X = 1.", True), ("X = 1", False), ("member(X,\n[1]).", True), ("X = 'a.", False),
    ("X = 'a.'.", True), ("X = \"end.\"", False), ("X = 1. % done", True), ("X = 1 % not yet.", False),
    ("X = a /* . */", False), ("X = '.'", False), (":tree", True), ("X = 0'.", False), ("X = 0'. .", True),
    ("X == Y.", True), ("X = [1,2|T]", False), ("", True),
])
def test_a_query_ends_at_its_full_stop(text, complete):
    assert complete_input(text) is complete


# ---------------------------------------------------------------------------
# schemalog query

def test_query_prints_every_answer_one_per_line():
    r = run("query", MIX, "sequential(X, Y), in_tree(X, _, original)")
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == ["X = 1, Y = 5", "X = 2, Y = 3", "X = 6, Y = 7", "X = 7, Y = 8",
                                     "X = 8, Y = 9", "X = 9, Y = 10"]


def test_query_json_over_several_files():
    r = run("query", MIX, COFFEE, "merged(T, B, Parts), length(Parts, N), N > 2", "--json")
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    assert {d["T"] for d in data} == {"use(spoon)", "prepareboth"}
    assert all(isinstance(d["B"], int) and d["N"] > 2 for d in data)
    assert data[0]["Parts"] == "[a3(cup), a4(cup), a5(cup), a6(cup), a7(cup)]"


def test_query_exit_status_is_0_with_answers_1_without_2_on_errors():
    assert run("query", MIX, "next_action(B)", "--first").stdout == "B = 2\n"
    r = run("query", MIX, "holds(spoon.used)")
    assert (r.returncode, r.stdout) == (1, "false\n")
    r = run("query", MIX, "sequential(X")
    assert r.returncode == 2 and "^" in r.stderr and "<query>:1:" in r.stderr
    r = run("query", "atom_length(X, Y)")
    assert r.returncode == 2 and "instantiation_error" in r.stderr and "Traceback" not in r.stderr
    r = run("query", "nope(1)")
    assert r.returncode == 2 and "unknown procedure nope/1" in r.stderr
    r = run("query", "--max-steps", "1000", "length(L, N), N > 10000")
    assert r.returncode == 2 and "step limit of 1,000" in r.stderr
    r = run("query", ROOT / "no-such-file.pl", "true")
    assert r.returncode == 2 and "no-such-file.pl" in r.stderr
    r = run("query", MIX, "X = 1", "--json", "--task", "nothing")
    assert r.returncode == 2 and "no task nothing" in r.stderr


def test_query_focus_options():
    r = run("query", MIX, "enabled(B), node(B, L)", "--state", "hand.free, a1.done, a2.done")
    assert r.stdout == "B = 4, L = gripper(close)\n"
    r = run("query", MIX, "enabled(B), node(B, L)", "--compressed")
    assert r.stdout == "B = 14, L = a1_a2(spoon)\n"
    r = run("query", COFFEE, "next_action(B), node(B, L)", "--scene", ROOT / "kb" / "scenes" / "kitchen.yaml")
    assert r.returncode == 0 and r.stdout.startswith("B = ")


def test_query_output_of_write_goes_with_the_answers():
    r = run("query", "forall(member(X, [a, b]), (write(X), nl))")
    assert r.stdout == "a\nb\ntrue\n"
    r = run("query", "write(hello), nl", "--json")
    assert json.loads(r.stdout) == [{}] and r.stderr.endswith("hello\n")


# ---------------------------------------------------------------------------
# The REPL

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
