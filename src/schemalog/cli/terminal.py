"""The REPL's terminal (session.py): prompt_toolkit's query prompt, the one-key "more?" prompt
after an answer (read straight from the terminal, on the answer's line), its history file, and
the terminal mode a running query needs for Ctrl-C to be a signal.

    Prompts = (query: () -> str, more: () -> bool)   query raises EOFError at Ctrl-D and
                                                     KeyboardInterrupt at Ctrl-C
"""

from __future__ import annotations

import os
import signal
import sys
from pathlib import Path
from typing import Callable

from .completion import _WORD, _completer, completion_words
from ..api.workspace import Workspace
from .toplevel import complete_input


def prompts(workspace: Workspace) -> tuple[Callable[[], str], Callable[[], bool]]:
    """The query prompt (Enter ends a complete query, Tab completes) and the more-answers one."""
    from prompt_toolkit import PromptSession
    from prompt_toolkit.history import FileHistory, InMemoryHistory
    from prompt_toolkit.key_binding import KeyBindings

    history_path = history_file()
    try:
        history_path.parent.mkdir(parents=True, exist_ok=True)
        history = FileHistory(str(history_path))
    except OSError:
        history = InMemoryHistory()
    keys = KeyBindings()

    @keys.add("enter")
    def _(event) -> None:
        buffer = event.current_buffer
        if complete_input(buffer.text):
            buffer.validate_and_handle()
        else:
            buffer.insert_text("\n")

    @keys.add("tab")
    def _(event) -> None:
        buffer = event.current_buffer
        word = _WORD.search(buffer.document.text_before_cursor)
        words = sorted(completion_words(workspace, word.group())) if word else []
        if len(words) == 1:                  # one way to go on: take it
            buffer.insert_text(words[0][len(word.group()):])
        elif words:
            buffer.start_completion(select_first=False)

    session = PromptSession(history=history, multiline=True, key_bindings=keys,
                            completer=_completer(workspace),
                            prompt_continuation=lambda width, line, soft: "|    ")

    def more() -> bool:
        return more_answers(session.input)

    # SIGINT while the query prompt reads. prompt_toolkit's own handler (handle_sigint) stays
    # in place for a while after the Enter that ended the input, with the terminal back in
    # cooked mode: a Ctrl-C pressed then was lost and the query ran to its end. Ours passes a
    # signal on to the prompt while it reads, and after the Enter keeps it for the command.
    interrupted: list[int] = []

    def on_sigint(signum, frame) -> None:
        app = session.app
        if app.is_running and not app.is_done:
            app.loop.call_soon_threadsafe(app.key_processor.send_sigint)
        else:
            interrupted.append(signum)

    def prompt() -> str:
        interrupted.clear()
        # left in place when the input is taken: signals_from_keyboard replaces it
        signal.signal(signal.SIGINT, on_sigint)
        return session.prompt("?- ", handle_sigint=False)

    prompt.input = session.input         # whose keys typed ahead signals_from_keyboard looks at
    prompt.interrupted = interrupted     # and the Ctrl-C that came as a signal after the Enter
    return prompt, more


# The keys of the "more?" prompt, as SWI-Prolog's top level takes them: True asks for the next
# answer, False stops. h and ? list them; any other key is said to be no action (SWI-Prolog's
# "Unknown action: f (h for help)") and is not taken as input. A cursor-position report is no key.
MORE_KEYS = {";": True, "n": True, "r": True, " ": True, "c-i": True,
             "c-m": False, "c-j": False, ".": False, "c": False, "a": False, "escape": False,
             "c-c": False, "c-d": False}
HELP_KEYS = ("h", "?")
MORE_HELP = "Keys: ; n r space Tab: next answer | Enter . c a Escape: stop | h ?: this help"


def more_answers(input_obj=None) -> bool:
    """Read one key of the "more?" prompt; the keys typed after it stay for the next prompt.

    Not a prompt_toolkit application: one assumes it starts at column 0, and once the terminal
    answers its cursor-position request it reserves the rows below with CR-LFs, moves back up
    and erases to the end of the screen: the answer on the cursor's line was erased.
    The caller ends the answer's line (" ;" or "."); a key that is no action gets a line
    of its own and "Action?", which that " ;" or " ." then ends, as in SWI-Prolog.
    """
    import codecs
    import select
    import termios

    from prompt_toolkit.input.typeahead import get_typeahead, store_typeahead
    from prompt_toolkit.input.vt100_parser import Vt100Parser

    keys = list(get_typeahead(input_obj)) if input_obj is not None else []
    parser = Vt100Parser(keys.append)
    decoder = codecs.getincrementaldecoder("utf-8")("replace")
    try:
        fd = sys.stdin.fileno()
        saved = termios.tcgetattr(fd)
    except (OSError, ValueError, termios.error):
        return False
    quiet = list(saved)
    # no line editing, no echo, Ctrl-C a key rather than a signal; one byte is enough to go on
    quiet[3] &= ~(termios.ICANON | termios.ECHO | termios.ISIG | termios.IEXTEN)
    quiet[6] = list(saved[6])
    quiet[6][termios.VMIN], quiet[6][termios.VTIME] = 1, 0
    asked = False            # whether "Action?" ends the line: a stop's "." then needs a space

    def say(text: str) -> None:
        nonlocal asked
        os.write(sys.stdout.fileno(), f"\n{text}\nAction?".encode("utf-8", "replace"))
        asked = True

    try:
        termios.tcsetattr(fd, termios.TCSANOW, quiet)
        while True:
            unknown: list[str] = []
            for i, key in enumerate(keys):
                name = _key_name(key)
                verdict = MORE_KEYS.get(name)
                if name == "<cursor-position-response>":
                    continue
                if name in HELP_KEYS:
                    if unknown:
                        say(_unknown(unknown))
                        unknown = []
                    say(MORE_HELP)
                    continue
                if verdict is None:
                    unknown.append(key.data if len(key.data) == 1 and key.data.isprintable() else f"<{name}>")
                    continue
                if unknown:
                    say(_unknown(unknown))
                if input_obj is not None:
                    store_typeahead(input_obj, keys[i + 1:])
                if asked and not verdict:
                    os.write(sys.stdout.fileno(), b" ")
                return verdict
            if unknown:
                say(_unknown(unknown))
            keys.clear()
            # a lone escape is a key only when nothing follows it soon (else a sequence begins)
            if not select.select([fd], [], [], 0.05)[0]:
                parser.flush()
                if keys:
                    continue
            data = os.read(fd, 1024)
            if not data:
                return False
            parser.feed(decoder.decode(data))
    except KeyboardInterrupt:       # a SIGINT sent by another process
        return False
    except OSError:
        return False
    finally:
        try:
            termios.tcsetattr(fd, termios.TCSANOW, saved)
        except (OSError, termios.error):
            pass


def _unknown(keys: list[str]) -> str:
    """The hint for keys of the "more?" prompt that are no action (typed together: one line)."""
    return f"Unknown action: {''.join(keys)} (h for help)"


def _key_name(key) -> str:
    """A key press's name as MORE_KEYS spells it ("c-m", ";")."""
    return getattr(key.key, "value", key.key)


class no_echo_between_prompts:
    """For the whole session: the terminal echoes no key typed ahead between two prompts (an
    Enter would open an empty line among the answers); the next prompt shows what was typed.
    The terminal's mode is put back when the session ends."""

    def __enter__(self) -> None:
        self.saved = None
        try:
            import termios

            fd = sys.stdin.fileno()
            self.saved = termios.tcgetattr(fd)
            attrs = termios.tcgetattr(fd)
            # not canonical either: a Ctrl-D typed as an answer appears is a key kept for the
            # next prompt (canonical mode takes it as end of file, and the prompt never sees it)
            attrs[3] &= ~(termios.ECHO | termios.ECHOCTL | termios.ICANON)
            termios.tcsetattr(fd, termios.TCSANOW, attrs)
        except (ImportError, OSError, ValueError):
            self.saved = None

    def __exit__(self, *exc) -> None:
        if self.saved is not None:
            import termios

            try:
                termios.tcsetattr(sys.stdin.fileno(), termios.TCSANOW, self.saved)
            except (OSError, ValueError, termios.error):
                pass


class signals_from_keyboard:
    """While a query or command runs, Ctrl-C must reach it as SIGINT: the terminal can still
    be in the raw mode prompt_toolkit read the input in (no ISIG), where Ctrl-C is only a byte.
    A Ctrl-C typed with the Enter that ended the input came in raw mode: it is found among the
    keys typed ahead and raises KeyboardInterrupt at once (the other keys stay for the prompt);
    one that came as a signal after the Enter (the prompt's `interrupted`) raises it too."""

    def __init__(self, prompt=None) -> None:
        self.input = getattr(prompt, "input", None)
        self.interrupted = getattr(prompt, "interrupted", [])

    def __enter__(self) -> None:
        self.saved = None
        self.handler = signal.signal(signal.SIGINT, signal.default_int_handler)
        if self.interrupted:
            self.__exit__()
            raise KeyboardInterrupt
        try:
            import termios

            fd = sys.stdin.fileno()
            self.saved = termios.tcgetattr(fd)
            attrs = termios.tcgetattr(fd)
            attrs[3] |= termios.ISIG
            # no echo of keys typed while it runs, "^C" included: "% interrupted" starts its line
            attrs[3] &= ~(termios.ECHO | termios.ECHOCTL | termios.ICANON)   # Ctrl-D: a key, as above
            termios.tcsetattr(fd, termios.TCSANOW, attrs)
        except (ImportError, OSError, ValueError):
            self.saved = None
            return
        if self.input is not None and _typed_ctrl_c(self.input, fd, attrs):
            self.__exit__()
            raise KeyboardInterrupt

    def __exit__(self, *exc) -> None:
        signal.signal(signal.SIGINT, self.handler)
        if self.saved is not None:
            import termios

            termios.tcsetattr(sys.stdin.fileno(), termios.TCSANOW, self.saved)


def _typed_ctrl_c(input_obj, fd: int, attrs: list) -> bool:
    """Whether Ctrl-C is among the keys typed ahead: prompt_toolkit's, then the terminal's
    queue (read without waiting); the keys after the last Ctrl-C are kept for the next prompt."""
    import termios

    from prompt_toolkit.input.typeahead import get_typeahead, store_typeahead
    from prompt_toolkit.input.vt100_parser import Vt100Parser
    from prompt_toolkit.keys import Keys

    keys = list(get_typeahead(input_obj))
    quiet = list(attrs)
    quiet[3] &= ~(termios.ICANON | termios.ECHO)       # not canonical: a lone byte reads at once
    quiet[6] = list(attrs[6])
    quiet[6][termios.VMIN], quiet[6][termios.VTIME] = 0, 0     # and nothing there: no wait
    termios.tcsetattr(fd, termios.TCSANOW, quiet)
    try:
        data = os.read(fd, 65536)
    finally:
        termios.tcsetattr(fd, termios.TCSANOW, attrs)
    parser = Vt100Parser(keys.append)
    parser.feed(data.decode("utf-8", "replace"))
    parser.flush()
    found = [i for i, k in enumerate(keys) if k.key == Keys.ControlC]
    store_typeahead(input_obj, keys[found[-1] + 1:] if found else keys)
    return bool(found)


def history_file() -> Path:
    """Where the REPL keeps its history: $SCHEMALOG_HISTORY, else the XDG state directory."""
    explicit = os.environ.get("SCHEMALOG_HISTORY")
    if explicit:
        return Path(explicit)
    state = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return Path(state) / "schemalog" / "history"
