"""The REPL as a user meets it: piped transcripts, a real terminal (pexpect), completion."""

import io
import os
import re
import signal
import subprocess
import sys
import time

import pexpect
import pytest

from schemalog.cli import session
from schemalog.cli.completion import completion_words
from schemalog.api.workspace import Workspace

from conftest import COFFEE, MIX, ROOT


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
    # :run's columns named, each row as schemalog run prints it
    assert ("?- :run\n% run use(spoon), compressed tree, from hand.free (as schemalog run: decision, winner, "
            "its emphasis e, runner-up, actions enabled)\n") in out
    assert re.search(r"\n   1  a1_a2\(spoon\) +e 2 +runner-up - +1 enabled\n      - a1\(spoon\)\n", out), out
    assert "?- holds(spoon.used).\ntrue.\n" in out and "?- holds(spoon.used).\nfalse.\n" in out
    assert "syntax error" in out and "    ^" in out
    assert "step limit of 500 resolution steps exceeded" in out
    assert "use(spoon): proved" in out
    assert "never" not in out


def test_the_start_says_what_to_do_about_a_relation_the_files_define_too(tmp_path):
    r = run("repl", "--plain", MIX, stdin="node(B, _), agent(B, gripper).\n")
    # issue 45: the note was one line a newcomer could not follow ("your files define agent/2 too:
    # agent(B, A) answers their clauses first, then schemalog's facts about behaviours; ...")
    lines = r.stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if "agent/2" in line)
    assert lines[start:start + 5] == [
        "note: agent/2 means two things here:",
        f"  your files' agent(gripper(_), gripper) ({MIX}:19), and",
        "  schemalog's agent(B, A): B is performed by agent A (B a behaviour's id, as :tree numbers them).",
        "  ?- agent(B, A). gives your clauses' answers first, then one per behaviour;",
        "  ?- node(B, _), agent(B, A). gives the behaviours only (docs/queries.md, Relations)."]
    assert all(len(line) <= 100 for line in lines[start:start + 5] if str(MIX) not in line)
    assert "?- node(B, _), agent(B, gripper).\nB = 4." in r.stdout        # the way it gives works
    mine = tmp_path / "mine.pl"
    mine.write_text("holds(x).\n")
    r = run("repl", "--plain", MIX, mine, stdin="")
    assert ("note: your files' clauses for holds/1 are not called: it is schemalog's relation here "
            "(docs/queries.md); rename yours to call it") in r.stdout


def test_repl_reads_several_queries_on_a_line_and_skips_comments():
    r = run("repl", "--plain", stdin="X = 1. Y = 2.\n% a comment\n/* another */\nZ = 3.\n;\n:tree 12\n:tree X\n:limit \u0661\n")
    assert r.returncode == 0, r.stdout
    assert "?- X = 1.\nX = 1.\n?- Y = 2.\nY = 2.\n?- Z = 3.\nZ = 3.\n" in r.stdout
    assert "no task 12 here" in r.stdout and "not a variable" in r.stdout
    assert "needs a positive number of steps" in r.stdout


def test_repl_load_and_unfinished_input(tmp_path):
    extra = tmp_path / "extra.pl"
    extra.write_text("colour(red). colour(green).\n")
    r = run("repl", "--plain", stdin=f":load {extra}\nfindall(C, colour(C), L).\nX = \n")
    assert "L = [red, green]" in r.stdout
    assert r.returncode == 2 and "input ended inside a query" in r.stdout
    r = run("repl", stdin=":load /no/such.pl\n:tree\n")
    assert "no such file" in r.stdout and "no task here" in r.stdout


def test_repl_load_of_a_loaded_file_reads_it_again_and_of_a_clashing_one_is_an_error(tmp_path):
    extra, other = tmp_path / "extra.pl", tmp_path / "other.pl"
    extra.write_text("colour(red). colour(green).\n")
    other.write_text("size(big).\ncolour(blue).\n")
    r = run("repl", "--plain", stdin=f":load {extra}\n:load {extra}\nfindall(C, colour(C), L).\n"
                                     f":load {other}\nfindall(C, colour(C), L).\n")
    assert r.returncode == 0, r.stdout
    assert f"% loaded {extra}" in r.stdout and f"% read again {extra}" in r.stdout
    assert r.stdout.count("L = [red, green]") == 2 and "error" not in r.stdout.split(f"{other}:2:1")[0]
    assert f"{other}:2:1: error: colour/1 is defined in two files, here and at {extra}:1:1" in r.stdout
    r = run("repl", "--plain", MIX, stdin=f":load {MIX}\n:tree\n")    # the file named at the start, again
    assert r.returncode == 0 and "error" not in r.stdout and "use(spoon)" in r.stdout, r.stdout


def spawn(*files, history, timeout=30):
    """The REPL on a pseudo-terminal, running this tree's schemalog (PYTHONPATH passed on)."""
    keep = {k: os.environ[k] for k in ("PYTHONPATH",) if k in os.environ}
    return pexpect.spawn(sys.executable, ["-m", "schemalog", "repl", *map(str, files)], cwd=str(ROOT),
                         # a pseudo-terminal answers no cursor-position request: do not wait for one
                         env={"SCHEMALOG_HISTORY": str(history), "TERM": "xterm", "PATH": "/usr/bin:/bin",
                              "PROMPT_TOOLKIT_NO_CPR": "1", **keep},
                         encoding="utf-8", timeout=timeout, dimensions=(40, 120))


def test_repl_on_a_terminal(tmp_path):
    history = tmp_path / "history"
    child = spawn(MIX, history=history)
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


# -- whatever happens in a query or command, the session goes on ---------------------------

def piped(workspace, text, repl=None):
    """Drive a REPL over `workspace` with `text` as its input; (exit status, what it printed)."""
    out = io.StringIO()
    repl = repl or session.Repl(workspace, out)
    repl.out = out
    return repl.loop(False, io.StringIO(text)), out.getvalue()


@pytest.mark.parametrize("error, said", [
    (ZeroDivisionError("boom"), "internal error: ZeroDivisionError: boom (please report it; "
                                "SCHEMALOG_DEBUG=1 shows the traceback)"),
    (KeyError("x"), "internal error: KeyError: 'x'"),
    (MemoryError(), "error: out of memory; the work was dropped"),
    (RecursionError("deep"), "error: a term nests too deeply"),
    (KeyboardInterrupt(), "% interrupted; :verify changed nothing"),
])
def test_a_command_that_raises_anything_is_reported_in_a_line_and_the_session_goes_on(monkeypatch, error, said):
    def verify(self, view):
        raise error
    monkeypatch.setattr(session.Repl, "verify", verify)
    code, out = piped(Workspace([str(MIX)]), ":verify\nX = 1.\n:state\n")
    assert code == 0
    after = out.split("?- :verify\n", 1)[1]
    assert after.startswith(said) and after.count("\n?- ") == 2 and "Traceback" not in out
    assert "?- X = 1.\nX = 1.\n" in out and "% state: hand.free" in out


def test_verify_in_the_repl_says_when_the_task_itself_cannot_complete(tmp_path):
    path = tmp_path / "stuck.pl"
    path.write_text("task(stuck).\nschema(stuck, [(s1, true), (s2, s1.done and lid.open)], s2.done).\n"
                    "schema(s1, [], s1.done).  schema(s2, [], s2.done).\n")
    code, out = piped(Workspace([str(path)]), ":verify\n")
    assert code == 0 and "% stuck: no_proof(task_cannot_complete)" in out and "proved" not in out
    assert "%   the task itself cannot complete: no run of the original accomplishes it" in out
    assert f"%     why (schemalog lint): {path}:2:45: error: s2 can never be released: lid.open never holds" in out
    assert "\n%       fix: correct the atom" in out     # every line of the cause is a comment line
    code, out = piped(Workspace([str(MIX)]), ":verify\n")
    assert "% use(spoon): proved" in out and "cannot complete" not in out


def test_verify_in_the_repl_says_in_words_what_it_explored():
    """Issue 45: `% prepareboth: proved (61 + 0 states, 0.17 s)` left `+ 0` unexplained (the
    original's states, not explored on their own when the proof works on sets of states)."""
    code, out = piped(Workspace([str(COFFEE)]), ":verify\n")
    verdict = next(line for line in out.splitlines() if line.startswith("% prepareboth:"))
    assert re.fullmatch(r"% prepareboth: proved, explored 61 states of the compressed tree as sets, "
                        r"in \d+\.\d\d s", verdict), verdict


def test_a_query_that_raises_anything_is_reported_and_the_traceback_is_only_for_debugging(monkeypatch, capsys):
    def answers(*args):
        raise ValueError("invalid literal for int() with base 16: '1b[2J'")
        yield
    monkeypatch.setattr(session, "answers", answers)
    code, out = piped(Workspace([]), 'X = "a".\n')
    assert code == 0 and "internal error: ValueError: invalid literal" in out and "Traceback" not in out
    assert "Traceback" not in capsys.readouterr().err
    monkeypatch.setenv("SCHEMALOG_DEBUG", "1")
    piped(Workspace([]), 'X = "a".\n')
    assert "Traceback" in capsys.readouterr().err


def test_an_interrupted_load_leaves_the_workspace_as_it_was(monkeypatch, tmp_path):
    extra = tmp_path / "extra.pl"
    extra.write_text("task(other). schema(other, [], other.done).\n")
    ws = Workspace([str(MIX)])
    before = dict(vars(ws))
    built = Workspace._build

    def half_built(self):        # interrupted once the new knowledge base is in, before the rest
        self.reset = lambda: (_ for _ in ()).throw(KeyboardInterrupt())
        built(self)
    monkeypatch.setattr(Workspace, "_build", half_built)
    code, out = piped(ws, f":load {extra}\n")
    assert "% interrupted; :load changed nothing" in out
    assert vars(ws) == before and ws.files == [str(MIX)]
    monkeypatch.setattr(Workspace, "_build", built)
    code, out = piped(ws, "task(T).\n:tree\n")
    assert "T = use(spoon)." in out and "other" not in out and "a1(spoon)" in out


# -- Ctrl-C on a terminal: long commands, long by their input --------------------------------

@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """Generated tasks: 2,047 behaviours (its :run and :compress print pages), 4,095 (seconds
    to load), a bushy 341 (quick to load; a signal during a command) and 5,461 (a second to
    load, seconds to prove by sets of states: a bushy 341 proves in a fraction of a second)."""
    folder = tmp_path_factory.mktemp("generated")
    for name, depth, children in (("t11", 11, 2), ("t12", 12, 2), ("bushy", 5, 4), ("proof", 7, 4)):
        r = run("generate", "--depth", depth, "--children", children, "--rd", "0.5", "--seed", 1,
                "-o", folder / f"{name}.pl")
        assert r.returncode == 0, r.stderr
    # t12 and then a directive of some ten million steps: a :load that lasts however fast the
    # machine (t12 alone now loads in well under a second), interrupted after its trees are read.
    # Renamed (s1, thing1 for b1, obj1): with t11's names it would be refused at once for
    # defining b1 in a second file, its directive never run, and the Ctrl-C would come too late.
    renamed = re.sub(r"\bobj(\d+)", r"thing\1", re.sub(r"\bb(\d+)", r"s\1", (folder / "t12.pl").read_text()))
    (folder / "slow.pl").write_text(renamed + "\n:- between(1, 9000000, _), fail ; true.\n")
    return folder


def interrupt(child, command, running=r"\x1b\[\?2004l"):
    """Send `command`, press Ctrl-C once it runs, and return what the REPL said."""
    child.send(command + "\r")
    child.expect(running)        # prompt_toolkit let go of the terminal (or the command printed)
    time.sleep(0.3)              # past the last moment of raw mode; the command takes seconds
    child.sendintr()
    child.expect(r"% interrupted[^\r\n]*")
    said = child.after
    child.expect(r"\?-")
    return said


def ask(child, query, pattern):
    child.send(query + "\r")
    child.expect(pattern)
    found = child.match
    child.expect(r"\?-")
    return found


def test_ctrl_c_interrupts_every_long_command_and_query_and_keeps_the_session(tmp_path, generated):
    child = spawn(generated / "t11.pl", history=tmp_path / "history", timeout=120)
    child.expect(r"\?-")
    state = ask(child, ":state", r"% state: [^\r\n]*").group()
    # :run and :compress print more than the terminal holds while nobody reads it
    assert interrupt(child, ":run", r" +1  b[0-9]+\(") == "% interrupted; :run changed nothing"
    assert ask(child, ":state", r"% state: [^\r\n]*").group() == state
    assert interrupt(child, ":compress", r"compressed tree \(focus\)") == "% interrupted; :compress changed nothing"
    child.send("enabled(B).\r")              # the focus is still the original tree: ids 0..2046
    child.expect(r"B = (\d+)")
    assert int(child.match.group(1)) < 2047
    child.send("\r")
    child.expect(r"\?-")
    assert interrupt(child, "between(1, inf, X), X < 0.") == "% interrupted"
    assert interrupt(child, f":load {generated / 'slow.pl'}") == "% interrupted; :load changed nothing"
    counted = ask(child, "findall(B, node(B, _), L), length(L, N), write(count(N)), nl, fail.", r"count\((\d+)\)")
    assert counted.group(1) == str(2047 + 1029)          # t11's trees only: no half-loaded slow.pl
    assert ask(child, "Y is 1 + 1.", r"Y = 2\.")
    child.sendeof()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0


def test_ctrl_c_interrupts_a_long_proof(tmp_path, generated):
    child = spawn(generated / "proof.pl", history=tmp_path / "history", timeout=120)
    child.expect(r"\?-")
    assert interrupt(child, ":verify") == "% interrupted; :verify changed nothing"
    assert ask(child, ":limit", r"% step limit: [0-9,]+")
    child.send(":verify\r\x03Y is 40 + 2.")      # Ctrl-C with the Enter: a key, not yet a signal
    child.expect(r"% interrupted")
    assert "proved" not in child.before
    child.send("\r")                                # what was typed after it is kept for the prompt
    child.expect(r"Y = 42\.")
    child.expect(r"\?-")
    child.sendeof()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0



def test_ctrl_c_at_the_moment_of_the_enter_interrupts_what_the_enter_began(tmp_path):
    # Pressed as the input is taken, Ctrl-C falls in prompt_toolkit's last moments: raw mode
    # (a byte typed ahead) or cooked mode with its SIGINT handler still in place (a signal that
    # was lost: the query then ran to its end, "false."). Each round must say "% interrupted".
    child = spawn(MIX, history=tmp_path / "history", timeout=60)
    child.expect(r"\?-")
    said = []
    for delay in (0, 0, 0, 0, 0, 0.0005, 0.001, 0.002, 0.005, 0.02):
        child.send("between(1, 5000000, _), fail.\r")
        child.expect(r"\x1b\[\?2004l")
        time.sleep(delay)
        child.sendintr()
        child.expect([r"% interrupted", r"false\."])
        said.append(child.after)
        child.expect(r"\?-")
    assert said == ["% interrupted"] * 10
    os.kill(child.pid, signal.SIGINT)            # a signal while the prompt reads: the line goes
    child.send("X = 1.\r")
    child.expect(r"X = 1\.")
    child.sendeof()
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0

# -- the end of the process: a signal after main() returned ----------------------------------

# The console script's wrapper: import, then run(). It says when run() has begun (its first
# call), so that the signals below fall on schemalog's code, not on the interpreter's start-up.
ENTRY = """import sys
import schemalog.cli.main as m
tune = m.tune_gc
def announced():
    sys.stderr.write("running\\n"); sys.stderr.flush(); tune()
m.tune_gc = announced
sys.argv[0] = "schemalog"
m.run()
"""


def test_a_signal_at_any_moment_of_a_command_exits_130_without_a_traceback(generated, tmp_path):
    argv = [sys.executable, "-c", ENTRY, "compress", str(generated / "bushy.pl"), "--json"]

    def start(out):
        p = subprocess.Popen(argv, cwd=ROOT, stdout=out, stderr=subprocess.PIPE, text=True)
        assert p.stderr.readline() == "running\n"
        return p, time.monotonic()

    with open(tmp_path / "out.json", "w") as out:
        p, started = start(out)
        assert p.wait(timeout=120) == 0, p.stderr.read()
        length = time.monotonic() - started
    seen = set()
    # From the start to well past the end, the flush and the exit included; the output goes to
    # a file, which never makes the command wait.
    for step in range(12):
        with open(tmp_path / "out.json", "w") as out:
            p, _ = start(out)
            time.sleep(length * 1.5 * step / 11)
            p.send_signal(signal.SIGINT)
            _, err = p.communicate(timeout=120)
        assert p.returncode in (0, 130) and "Traceback" not in err, (step, p.returncode, err)
        seen.add(p.returncode)
    assert seen == {0, 130}                  # some trials were interrupted, some had finished
