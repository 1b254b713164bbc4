"""The REPL on a real terminal, read as a person reads it: tmux runs it (send-keys types,
capture-pane shows the screen), with the terminal answering prompt_toolkit's cursor-position
requests (no PROMPT_TOOLKIT_NO_CPR), under the TERMs people use.

With CI set, a missing tmux fails these tests (.ci/run installs it); elsewhere they skip.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import pytest

from conftest import MIX, ROOT

WIDTH, HEIGHT = 120, 40
PATIENCE = 60.0          # seconds to wait for a text on the screen: CI is slower than a laptop


@pytest.fixture
def tmux():
    if shutil.which("tmux") is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but tmux is not on PATH: the REPL cannot be tested on a real "
                        "terminal (.ci/run installs tmux)")
        pytest.skip("tmux is not installed")
    home = tempfile.mkdtemp(prefix="sl-tmux-")       # short: a socket path has ~100 bytes
    terminal = Terminal(home)
    yield terminal
    terminal.close()
    shutil.rmtree(home, ignore_errors=True)


class Terminal:
    """One tmux server on its own socket, one pane running the REPL."""

    def __init__(self, home: str) -> None:
        self.home = home
        self.socket = os.path.join(home, "sock")
        conf = os.path.join(home, "tmux.conf")
        with open(conf, "w") as f:     # keep the pane after :quit so the last screen can be read
            f.write("set -g remain-on-exit on\nset -g history-limit 5000\n")
        self.conf = conf

    def tmux(self, *args: str) -> str:
        r = subprocess.run(["tmux", "-S", self.socket, "-f", self.conf, *args],
                           capture_output=True, text=True, timeout=30)
        assert r.returncode == 0, (args, r.stderr)
        return r.stdout

    def start(self, term: str, *files) -> None:
        env = ["env", "-u", "PROMPT_TOOLKIT_NO_CPR", f"TERM={term}",
               f"PYTHONPATH={os.environ.get('PYTHONPATH', '')}",
               f"SCHEMALOG_HISTORY={os.path.join(self.home, 'history')}"]
        command = [*env, sys.executable, "-m", "schemalog", "repl", *map(str, files)]
        # the exit status goes to a file: tmux's pane_dead_status is at times never set
        self.status = os.path.join(self.home, "status")
        # and the terminal's mode, before and after: the REPL must leave it as it found it
        modes = [_quoted(os.path.join(self.home, f"stty-{when}")) for when in ("before", "after")]
        shell = (f"stty -g > {modes[0]}; {' '.join(map(_quoted, command))}; echo $? > {_quoted(self.status)}; "
                 f"stty -g > {modes[1]}")
        self.tmux("new-session", "-d", "-s", "repl", "-x", str(WIDTH), "-y", str(HEIGHT),
                  "-c", str(ROOT), shell)

    def run(self, term: str, *arguments, width: int = WIDTH, height: int = HEIGHT) -> None:
        """`schemalog ARGUMENTS` in a pane of that size, as a person runs it, its colours kept
        (NO_COLOR, FORCE_COLOR and COLORTERM left out: the terminal's TERM decides)."""
        env = ["env", "-u", "NO_COLOR", "-u", "FORCE_COLOR", "-u", "COLORTERM", f"TERM={term}",
               f"PYTHONPATH={os.environ.get('PYTHONPATH', '')}"]
        command = [*env, sys.executable, "-m", "schemalog", *map(str, arguments)]
        self.status = os.path.join(self.home, "status")
        shell = f"{' '.join(map(_quoted, command))}; echo $? > {_quoted(self.status)}"
        self.tmux("new-session", "-d", "-s", "repl", "-x", str(width), "-y", str(height), "-c", str(ROOT), shell)

    def finished(self) -> int:
        """The exit status of the command `run` started, once it has ended."""
        return int(self._written([self.status], "the command did not end")[0])

    def _written(self, paths: list[str], what: str) -> list[str]:
        """The contents of `paths` once each holds a whole line (the shell writes them as the
        command ends); `what` is said, with the screen, if that does not happen in time."""
        deadline = time.monotonic() + PATIENCE
        while True:
            try:
                found = []
                for path in paths:
                    with open(path) as f:
                        found.append(f.read())
                if all(text.endswith("\n") for text in found):
                    return found
            except FileNotFoundError:
                pass
            assert time.monotonic() < deadline, f"{what}; the screen:\n" + "\n".join(self.lines())
            time.sleep(0.05)

    def coloured_lines(self) -> list[str]:
        """The screen and its scrollback with the escape codes of its colours (capture-pane -e)."""
        text = self.tmux("capture-pane", "-p", "-e", "-t", "repl", "-S", "-")
        return text.splitlines()

    def type(self, text: str) -> None:
        self.tmux("send-keys", "-t", "repl", "-l", text)

    def key(self, name: str) -> None:
        # tmux reads a lone ';' as its command separator: '\;' is the key
        self.tmux("send-keys", "-t", "repl", "\\;" if name == ";" else name)

    def lines(self, history: bool = False) -> list[str]:
        """The screen (and with `history`, the scrollback above it), trailing blanks dropped."""
        text = self.tmux("capture-pane", "-p", "-t", "repl", *(["-S", "-"] if history else []))
        lines = [line.rstrip() for line in text.splitlines()]
        while lines and not lines[-1]:
            lines.pop()
        return lines

    def wait_for(self, *expected: str) -> list[str]:
        """The screen once its last lines are `expected` (regular expressions, whole lines)."""
        deadline = time.monotonic() + PATIENCE
        while True:
            lines = self.lines()
            tail = lines[-len(expected):]
            if len(tail) == len(expected) and all(re.fullmatch(e, l) for e, l in zip(expected, tail)):
                return lines
            if time.monotonic() > deadline:
                pytest.fail(f"waited {PATIENCE:.0f} s for {expected!r}; the screen:\n" + "\n".join(lines))
            time.sleep(0.05)

    def exit_status(self) -> int:
        status, after = self._written([self.status, os.path.join(self.home, "stty-after")],
                                      "the REPL did not leave")
        with open(os.path.join(self.home, "stty-before")) as f:
            assert f.read() == after, "the REPL left the terminal in another mode"
        return int(status)

    def close(self) -> None:
        subprocess.run(["tmux", "-S", self.socket, "kill-server"], capture_output=True, timeout=30)


def _quoted(word: str) -> str:
    return "'" + word.replace("'", "'\\''") + "'"


PROMPT = r"\?-"


@pytest.mark.parametrize("term", ["tmux-256color", "xterm-256color"])
def test_the_screen_keeps_every_answer_an_interrupt_an_error_and_the_goodbye(tmux, term):
    tmux.start(term, MIX)
    tmux.wait_for(PROMPT)

    tmux.type("member(X, [a, b, c]).")
    tmux.key("Enter")
    tmux.wait_for(r"\?- member\(X, \[a, b, c\]\)\.", "X = a")
    tmux.key(";")                  # the answer stays; ' ;' ends its line, the next one follows
    tmux.wait_for(r"\?- member\(X, \[a, b, c\]\)\.", "X = a ;", "X = b")
    tmux.key("Enter")              # Enter stops: '.' ends the last answer's line
    tmux.wait_for(r"\?- member\(X, \[a, b, c\]\)\.", "X = a ;", "X = b.", PROMPT)

    tmux.type("x = y.")            # no answer: nothing waits for a key
    tmux.key("Enter")
    tmux.wait_for("X = b.", r"\?- x = y\.", r"false\.", PROMPT)

    tmux.type("between(1, inf, X), X < 0.")
    tmux.key("Enter")
    tmux.wait_for(r"\?- between\(1, inf, X\), X < 0\.")
    time.sleep(0.5)                # let it run: Ctrl-C stops a running query, not only its start
    tmux.key("C-c")
    tmux.wait_for(r"\?- between\(1, inf, X\), X < 0\.", "% interrupted", PROMPT)

    tmux.type("foo(.")
    tmux.key("Enter")
    screen = tmux.wait_for(r"\?- foo\(\.", r"<query>:1:5: error: syntax error: .*", r"    foo\(\.",
                           r"        \^", PROMPT)
    error = screen[-4]
    assert "unexpected '.'" in error and "expected" in error
    assert not re.search(r"symatom|symfunctor|'prefix'|'infix'|'dot'", error), error

    tmux.type(":quit")
    tmux.key("Enter")
    assert tmux.exit_status() == 0
    # everything said is still there, in order, on the screen and in the scrollback
    said = ["?- member(X, [a, b, c]).", "X = a ;", "X = b.", "?- x = y.", "false.",
            "?- between(1, inf, X), X < 0.", "% interrupted", "?- foo(.", "?- :quit"]
    for lines in (tmux.lines(), tmux.lines(history=True)):
        kept = [line for line in lines if line in said]
        assert kept == said, "\n".join(lines)


def test_keys_typed_ahead_of_an_answer_are_taken_in_order(tmux):
    tmux.start("tmux-256color", MIX)
    tmux.wait_for(PROMPT)
    # the query, two ';' and the next query typed at once, before the first answer shows
    tmux.type("member(X, [a, b, c, d]).")
    tmux.key("Enter")
    tmux.key(";")
    tmux.key(";")
    tmux.key("Enter")
    tmux.type("Y = 1.")
    tmux.key("Enter")
    tmux.wait_for(r"\?- member\(X, \[a, b, c, d\]\)\.", "X = a ;", "X = b ;", r"X = c\.",
                  r"\?- Y = 1\.", r"Y = 1\.", PROMPT)
    tmux.type("member(X, [a, b]).")
    tmux.key("Enter")
    tmux.wait_for("X = a")
    tmux.type("q")                 # no key of the "more?" prompt: a hint, the answer stays
    tmux.wait_for(r"\?- member\(X, \[a, b\]\)\.", "X = a", r"Unknown action: q \(h for help\)", r"Action\?")
    tmux.key("Escape")             # a lone Escape stops
    tmux.wait_for(r"\?- member\(X, \[a, b\]\)\.", "X = a", r"Unknown action: q \(h for help\)", r"Action\? \.",
                  PROMPT)


def test_a_key_that_is_no_action_at_the_more_prompt_says_so_and_is_not_input(tmux):
    tmux.start("tmux-256color", MIX)
    tmux.wait_for(PROMPT)
    tmux.type("member(X, [a, b, c]).")
    tmux.key("Enter")
    tmux.wait_for("X = a")
    tmux.type("f")                 # the next query begun too early: said, not silently dropped
    tmux.wait_for("X = a", r"Unknown action: f \(h for help\)", r"Action\?")
    tmux.type("h")                 # h lists the keys
    tmux.wait_for(r"Unknown action: f \(h for help\)", r"Action\?",
                  r"Keys: ; n r space Tab: next answer \| Enter \. c a Escape: stop \| h \?: this help",
                  r"Action\?")
    tmux.key(";")
    tmux.wait_for(r"Action\? ;", "X = b")
    tmux.type("oo")
    tmux.wait_for("X = b", r"Unknown action: oo \(h for help\)", r"Action\?")
    tmux.key("Enter")
    tmux.wait_for("X = b", r"Unknown action: oo \(h for help\)", r"Action\? \.", PROMPT)
    tmux.type("Y = 1.")            # the prompt starts empty: the keys were no input
    tmux.key("Enter")
    tmux.wait_for(r"Action\? \.", r"\?- Y = 1\.", r"Y = 1\.", PROMPT)
    tmux.type("lists:append(X, Y, [a]).")
    tmux.key("Enter")
    tmux.wait_for(r"\?- lists:append\(X, Y, \[a\]\)\.",
                  r"<query>:1:6: error: syntax error: unexpected ':': modules are not supported \(docs/queries\.md\)",
                  r"    lists:append\(X, Y, \[a\]\)\.", r"         \^", PROMPT)


# -- colours: what the README promises for the first command --------------------------------------
_SGR = re.compile(r"\x1b\[([0-9;]*)m")
GREEN, BROWN = "green", "brown"


def _colour_before(line: str, text: str) -> str:
    """The foreground colour `text`, the first time it follows `pre: ` in `line`, is shown in."""
    plain, colour = "", None
    for piece in re.split(r"(\x1b\[[0-9;]*m)", line):
        found = _SGR.fullmatch(piece)
        if found:
            codes = found.group(1).split(";")
            if "38" in codes:                       # 38;5;N: a colour of the 256
                colour = f"38;5;{codes[codes.index('38') + 2]}"
            elif any(c in {"30", "31", "32", "33", "34", "35", "36", "37", "39", "0", ""} for c in codes):
                colour = next((c for c in codes if c.startswith("3")), None)
            continue
        start = len(plain)
        plain += piece
        at = plain.find("pre: " + text, max(0, start - len("pre: ")))
        if at >= 0 and at + len("pre: ") >= start:
            return {"32": GREEN, "38;5;94": BROWN, "33": BROWN}.get(colour, f"other ({colour})")
    raise AssertionError(f"no 'pre: {text}' on the line {line!r}")


def _line_of(lines: list[str], label: str) -> str:
    found = [line for line in lines if re.search(rf"(^|[^a-z_0-9(]){re.escape(label)}", _SGR.sub("", line))]
    assert found, f"{label} is not on the screen:\n" + "\n".join(_SGR.sub("", line) for line in lines)
    return found[0]


@pytest.mark.parametrize("term", ["xterm-256color", "xterm"])
@pytest.mark.parametrize("command", ["show", "compress"])
def test_a_tree_colours_each_pre_condition_by_whether_it_holds_in_the_initial_state(tmux, term, command):
    """Issue 45: the README's first command promised pre-conditions "green when it holds in the
    initial state, brown when it does not"; the terminal drew every one green. Brown is xterm's
    colour 94 on 256 colours, the 16's yellow (the old brown) on 16."""
    tmux.run(term, command, MIX, width=200, height=60)
    assert tmux.finished() == 0
    lines = tmux.coloured_lines()
    # the initial state is hand.free
    assert _colour_before(_line_of(lines, "subtask(take,spoon)"), "hand.free") == GREEN
    assert _colour_before(_line_of(lines, "a3(cup)"), "true") == GREEN          # true, under a false parent
    assert _colour_before(_line_of(lines, "a2(spoon)"), "a1.done") == BROWN
    assert _colour_before(_line_of(lines, "subtask(mix,spoon)"), "spoon.taken") == BROWN
    if command == "compress":                   # the compressed tree, beside it, in the same state
        assert _colour_before(_line_of(lines, "a1_a2(spoon)"), "hand.free and not spoon.taken") == GREEN
        assert _colour_before(_line_of(lines, "a3_a4_a5_a6_a7(cup)"), "spoon.taken and not") == BROWN
