"""The top level: answers printed as SWI-Prolog prints them, `schemalog query` and the REPL,
run as a user runs them (a subprocess; the REPL also on a pseudo-terminal)."""

import json
import subprocess
import sys

import pytest

from schemalog.api.workspace import Workspace
from schemalog.api.answers import answer_of, answer_text, answers, read_query
from schemalog.cli.toplevel import complete_input
from schemalog.logic.engine import Engine
from schemalog.logic.kb import KnowledgeBase

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
    ("_X = 1", "_X = 1"),                                       # swipl 9 shows named _ variables
    ("_Y = 1, X = _Y", "_Y = X, X = 1"),
    ("X = f(_A), _A = Y", "X = f(Y), _A = Y"),
    ("_ = 1", "true"),
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
    ("X == Y.", True), ("X = [1,2|T]", False), ("", True), ("% a comment", True), ("/* c */", True),
    ("/* open", False), ("X = 1. Y = 2.", True), ("X = 1. Y = ", False),
])
def test_a_query_ends_at_its_full_stop(text, complete):
    assert complete_input(text) is complete


# ---------------------------------------------------------------------------
# schemalog query

def test_query_prints_every_answer_one_per_line():
    r = run("query", MIX, "sequential(X, Y), in_tree(X, _, original)")
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == [
        "X = 1, Y = 5  % 1: subtask(take, spoon), 5: subtask(mix, spoon)", "X = 2, Y = 3  % 2: a1(spoon), 3: a2(spoon)",
        "X = 6, Y = 7  % 6: a3(cup), 7: a4(cup)", "X = 7, Y = 8  % 7: a4(cup), 8: a5(cup)",
        "X = 8, Y = 9  % 8: a5(cup), 9: a6(cup)", "X = 9, Y = 10  % 9: a6(cup), 10: a7(cup)"]


def test_query_shows_a_behaviours_label_beside_its_id_in_text_and_bare_ids_in_json():
    r = run("query", MIX, "sequential(X, Y)", "--first")
    assert r.stdout == "X = 1, Y = 5  % 1: subtask(take, spoon), 5: subtask(mix, spoon)\n"
    # a label the answer shows already is not repeated; a number that is no id gets none
    r = run("query", MIX, "sequential(X, Y), node(X, L), length([a, b], N)", "--first")
    assert r.stdout == "X = 1, Y = 5, L = subtask(take, spoon), N = 2  % 5: subtask(mix, spoon)\n"
    r = run("query", MIX, "agent(B, gripper)")             # the file's own clause is no id
    assert r.stdout.splitlines()[:2] == ["B = gripper(_)", "B = 4  % 4: gripper(close)"]
    assert json.loads(run("query", MIX, "sequential(X, Y)", "--first", "--json").stdout) == [{"X": 1, "Y": 5}]
    assert run("query", "X = 1").stdout == "X = 1\n"       # no task: no behaviours


def test_query_json_over_several_files(tmp_path):
    wave = tmp_path / "wave.pl"             # a second task: one program with MIX (no sub-task of both)
    wave.write_text("task(wave).\nschema(wave, [(w1, true), (w2, w1.done), (w3, w2.done)], w3.done).\n"
                    "schema(w1, [], w1.done).  schema(w2, [], w2.done).  schema(w3, [], w3.done).\n")
    r = run("query", MIX, wave, "merged(T, B, Parts), length(Parts, N), N > 2", "--json")
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    assert {d["T"] for d in data} == {"use(spoon)", "wave"}
    assert data[-1]["Parts"] == ["w1", "w2", "w3"]
    assert all(isinstance(d["B"], int) and d["N"] > 2 for d in data)
    assert data[0]["Parts"] == ["a3(cup)", "a4(cup)", "a5(cup)", "a6(cup)", "a7(cup)"]


def test_query_json_gives_a_list_as_the_api_gives_it():
    """A Prolog list was a string in --json (`"[a, b]"`) where the API gives a list."""
    import schemalog

    query = 'X = [1, a, [b, 2.5], f(x)], Y = [], Z = [a|_], W = g([c])'
    r = run("query", MIX, query, "--json")
    assert r.returncode == 0, r.stderr
    shown = json.loads(r.stdout)
    assert shown == [{"X": [1, "a", ["b", 2.5], "f(x)"], "Y": [], "Z": "[a|_]", "W": "g([c])"}]
    api, = schemalog.load(MIX).query(query)
    assert api["X"][:3] == shown[0]["X"][:3] and api["Y"] == shown[0]["Y"] == []


def test_query_exit_status_is_0_with_answers_1_without_2_on_errors():
    assert run("query", MIX, "next_action(B)", "--first").stdout == "B = 2  % 2: a1(spoon)\n"
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


def test_a_module_qualified_goal_is_said_to_be_unsupported_at_its_colon(tmp_path):
    r = run("query", "lists:append(X, Y, [a])")
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.splitlines() == [
        "<query>:1:6: error: syntax error: unexpected ':': modules are not supported (docs/queries.md)",
        "    lists:append(X, Y, [a])", "         ^"]
    program = tmp_path / "mod.pl"
    program.write_text("p :- true.\nq(X) :- lists : member(X, [a]).\n")
    r = run("check", program)
    assert r.returncode == 1 and f"{program}:2:15: error: syntax error: unexpected ':': modules are not " \
        "supported (docs/queries.md)" in r.stderr
    for other in ("X = a :: b", "X = :a"):          # a ':' that qualifies nothing: as before
        assert "unknown operator or unbalanced quote?" in run("query", other).stderr


def test_query_options_may_stand_between_files_and_query():
    r = run("query", MIX, "--state", "spoon.taken", "--first", "enabled(B), node(B, L)")
    assert (r.returncode, r.stdout) == (0, "B = 6, L = a3(cup)\n")
    r = run("query", MIX, "--bogus", "true")
    assert r.returncode == 2 and "unrecognized arguments: --bogus" in r.stderr


def test_the_step_limit_stops_endless_answers_too():
    # two steps an answer: the answer, and between/3's further solution (docs/syntax.md)
    r = run("query", "--max-steps", "1000", "between(1, inf, X)")
    assert r.returncode == 2 and r.stdout.splitlines()[-1] == "X = 500" and "step limit" in r.stderr


def test_a_program_without_tasks_keeps_its_own_run_and_holds(tmp_path):
    program = tmp_path / "pure.pl"
    program.write_text("run(X, Y) :- Y is X * 2.\nholds(sunny).\n")
    assert run("query", program, "run(3, Y), holds(S)").stdout == "Y = 6, S = sunny\n"
    r = run("query", "enabled(X)")
    assert r.returncode == 2 and "unknown procedure enabled/1" in r.stderr


def test_deep_terms_are_answered():
    r = run("repl", stdin="assertz((mk(0, a) :- !)), assertz((mk(N, f(T)) :- M is N - 1, mk(M, T))).\n"
                          "mk(50000, T), mk(50000, U), T == U, copy_term(T, C), C == T, Ok = yes.\nX = 1.\n")
    assert r.returncode == 0 and "Ok = yes." in r.stdout and "X = 1." in r.stdout, r.stdout[-500:]


def test_query_focus_options():
    r = run("query", MIX, "enabled(B), node(B, L)", "--state", "hand.free, a1.done, a2.done")
    assert r.stdout == "B = 4, L = gripper(close)\n"
    r = run("query", MIX, "enabled(B), node(B, L)", "--compressed")
    assert r.stdout == "B = 14, L = a1_a2(spoon)\n"
    assert run("query", MIX, "enabled(B)", "--task", "12").stdout == "B = 14  % 14: a1_a2(spoon)\n"   # a compressed root
    r = run("query", COFFEE, "next_action(B), node(B, L)", "--scene", ROOT / "kb" / "scenes" / "kitchen.yaml")
    assert r.returncode == 0 and r.stdout.startswith("B = ")


def test_query_output_of_write_goes_with_the_answers():
    r = run("query", "forall(member(X, [a, b]), (write(X), nl))")
    assert r.stdout == "a\nb\ntrue\n"
    assert run("query", "write(hello)").stdout == "hello\ntrue\n"           # answers start a line
    assert run("query", "write(hello), fail").stdout == "hello\nfalse\n"
    r = run("query", "write(hello), nl", "--json")
    assert json.loads(r.stdout) == [{}] and r.stderr.endswith("hello\n")


def test_a_cyclic_copy_prints_closed_on_its_own_name():
    # swipl 9.0.4's top level: the copy equals the original as a rational tree, so the two
    # are one group, closed on the last name: X = Y, Y = f(Y) (not f(f(_)), nor X = f(X), ...)
    for text, shown in (("X = f(X), copy_term(X, Y)", "X = Y, Y = f(Y)"),
                        ("X = [a|X], copy_term(X, Y)", "X = Y, Y = [a|Y]"),
                        ("X = f(X), Y = X", "X = Y, Y = f(Y)"),
                        ("X = f(X), Y = f(Y), X == Y", "X = Y, Y = f(Y)"),
                        ("X = f(Y), Y = f(X)", "X = Y, Y = f(f(Y))"),
                        ("X = [a|X], Y = [a,a|Y], X == Y", "X = Y, Y = [a, a|Y]"),
                        ("X = f(X, a), Y = f(Y, b)", "X = f(X, a), Y = f(Y, b)")):
        query = read_query(text)
        b = Engine(KnowledgeBase()).first(query.goal)
        assert answer_text(answer_of(query, b)) == shown


def test_printing_answers_counts_against_the_step_limit():
    # select(X, L, R) with L unbound has ever longer answers: each cost one resolution step
    # and O(n) to print, so --max-steps 20000 let it print without end (fuzz, long profile)
    done = subprocess.run([sys.executable, "-m", "schemalog", "query", str(MIX), "--max-steps", "20000",
                           "select(X, L, R)"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and "step limit of 20,000 resolution steps exceeded" in done.stderr, done.stderr
    assert 50 < len(done.stdout.splitlines()) < 1000
