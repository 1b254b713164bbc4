"""The REPL session: a query or a `:` command at a time, answered as query.py answers
(toplevel.py), `;` for more answers; Ctrl-C interrupts the running query, not the session.
Interactive sessions read with prompt_toolkit; piped ones line by line.
"""

from __future__ import annotations

import os
import re
import signal
import sys
from pathlib import Path
from typing import Callable, TextIO

from ..errors import SchemalogError
from ..logic.exceptions import PrologError
from ..logic.parse import parse_term
from ..logic.terms import term_to_text
from .completion import _WORD, _completer, completion_words
from .relations import COMPRESSED, ORIGINAL, RELATIONS, Workspace
from .toplevel import _Output, answer_text, answers, complete_input, error_text, read_query, split_queries


HELP = """\
Enter a query, ending with '.'; it may span lines. After an answer, ';' asks for the
next one and Enter stops. Ctrl-C stops a running query, Ctrl-D leaves.

  :load FILE       add a knowledge file (the workspace is rebuilt from all files)
  :tree [T]        print the focus tree, each behaviour with its id
  :compress [T]    focus on T's compressed tree and print it with its figures
  :original [T]    focus on T's original tree
  :run [T]         run the focus tree from the current state; the state is kept
  :reset           back to the initial state (the files' initial/1)
  :verify [T]      prove T's compressed tree against its original
  :state           the atoms true now
  :limit [N]       show or set the step limit of a query
  :help            this text        :quit   leave

Relations over the workspace (docs/queries.md):
"""


class Repl:
    """The interactive top level over a workspace; `input_line` and `more` do the I/O."""

    def __init__(self, workspace: Workspace, out: TextIO = sys.stdout, max_steps: int | None = None) -> None:
        self.workspace = workspace
        self.out = out
        self.max_steps = max_steps or workspace.options.max_steps

    # -- one input ------------------------------------------------------------------
    def handle(self, text: str, more: Callable[[], bool]) -> bool:
        """Run one query or command; False when the user asked to leave."""
        stripped = text.strip()
        if not stripped:
            return True
        if stripped.startswith(":") and not stripped.startswith(":-"):
            return self.command(stripped[1:].strip())
        # prompt_toolkit's event loop may leave its own SIGINT handling behind: a running
        # query gets Python's, so Ctrl-C raises KeyboardInterrupt in it.
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
        try:
            return self._answer(stripped, more)
        finally:
            signal.signal(signal.SIGINT, previous)

    def _answer(self, stripped: str, more: Callable[[], bool]) -> bool:
        try:
            query = read_query(stripped)
        except SchemalogError as e:
            self.say(str(e))
            return True
        shown = _Output(self._write)
        try:
            for answer, last in answers(self.workspace, query, shown.write, self.max_steps):
                shown.new_line()
                shown.write(answer_text(answer))
                if last or not more():
                    shown.write(".\n")
                    break
                shown.write(" ;\n")
            else:
                shown.new_line()
                shown.write("false.\n")
        except (PrologError, SchemalogError, RecursionError) as e:
            shown.new_line()
            self.say(error_text(e, ":limit N"))
        except KeyboardInterrupt:
            shown.new_line()
            self.say("% interrupted")
        except Exception as e:        # the session outlives a bug: say it, keep going
            shown.new_line()
            self.say(f"internal error: {type(e).__name__}: {e} (please report it)")
        return True

    def _write(self, text: str) -> None:
        self.out.write(text)
        self.out.flush()

    def say(self, text: str) -> None:
        self.out.write(text + "\n")
        self.out.flush()

    # -- commands -------------------------------------------------------------------
    def command(self, line: str) -> bool:
        name, _, rest = line.partition(" ")
        rest = rest.strip()
        try:
            if rest and name in ("quit", "q", "exit", "help", "h", "?", "reset", "state"):
                raise SchemalogError(f":{name} takes no argument")
            if name in ("quit", "q", "exit"):
                return False
            if name in ("help", "h", "?"):
                self.help()
            elif name == "load":
                if not rest:
                    raise SchemalogError(":load needs a file")
                self.workspace.load(rest)
                for note in self.workspace.notes:
                    self.say(note)
                self.say(f"% loaded {rest}: {self._tasks_line()}")
            elif name in ("tree", "compress", "original"):
                view, kind = self._tree(rest)
                kind = COMPRESSED if name == "compress" else ORIGINAL if name == "original" else kind
                self.workspace.set_focus(view, kind)
                self.show_tree(view, kind, figures=name == "compress")
            elif name == "run":
                self.run(*self._tree(rest))
            elif name == "reset":
                self.workspace.reset()
                self.say(f"% state: {self._state_text()}")
            elif name == "state":
                self.say(f"% state: {self._state_text()}")
            elif name == "verify":
                self.verify(self._tree(rest)[0])
            elif name == "limit":
                if rest:
                    if not re.fullmatch(r"[0-9]+", rest) or int(rest) < 1:
                        raise SchemalogError(f":limit needs a positive number of steps, not {rest!r}")
                    self.max_steps = int(rest)
                self.say(f"% step limit: {self.max_steps:,} resolution steps per query")
            else:
                self.say(f"unknown command :{name} (:help lists them)")
        except SchemalogError as e:
            self.say(str(e))
        return True

    def help(self) -> None:
        self.out.write(HELP)
        for text in RELATIONS.values():
            self.out.write(f"  {text}\n")
        self.out.flush()

    def _tree(self, text: str):
        """(view, kind) of a command's argument: a task or a root id; none: the focus."""
        ws = self.workspace
        if not text:
            if ws.focus is None:
                raise SchemalogError("no task here: :load a task file first")
            return ws.focus, ws.kind
        try:
            term = parse_term(text, "<task>")
        except SchemalogError as e:
            raise SchemalogError(f"not a task: {e}") from None
        return ws.find_tree(term)

    def _tasks_line(self) -> str:
        views = self.workspace.views
        if not views:
            return "no tasks"
        return "tasks " + ", ".join(term_to_text(v.task) for v in views)

    def _state_text(self) -> str:
        return ", ".join(sorted(term_to_text(a) for a in self.workspace.state)) or "(nothing true)"

    def show_tree(self, view, kind: str, figures: bool = False) -> None:
        from rich.console import Console

        from ..formats.render import rich_tree

        tree = view.tree(kind)
        console = Console(file=self.out, width=120, highlight=False,
                          force_terminal=self.out.isatty() if hasattr(self.out, "isatty") else False)
        console.print(f"% {term_to_text(view.task)}, {kind} tree (focus); ids as the relations number them")
        console.print(rich_tree(tree, first_id=view.first(kind)))
        if figures:
            from ..task.tree import count_nodes, depth

            before, after = count_nodes(view.original), count_nodes(view.compressed)
            self.say(f"% Bi = {before}, Bm = {after}, D = {depth(view.original)}, "
                     f"RD = {view.reduction_degree:.2f}")

    def run(self, view, kind: str) -> None:
        ws = self.workspace
        ws.set_focus(view, kind)
        executive = ws.execute(view, kind, ws.state)
        for d in executive.decisions:
            done = ", ".join(term_to_text(a) for a in d.executed) or "-"
            failed = f"  FAILED {term_to_text(d.failed)}" if d.failed is not None else ""
            self.say(f"{d.index:>4}  {term_to_text(d.behaviour)}  (e = {d.emphasis:.3g}; {done}){failed}")
        ws.state = executive.world.atoms
        self.say(f"% {executive.outcome.status.name.lower()}: {executive.outcome.reason}")

    def verify(self, view) -> None:
        from .relations import verdict_term

        report = self.workspace.verify(view)
        self.say(f"% {term_to_text(view.task)}: {term_to_text(verdict_term(report))} "
                 f"({report.compressed_states:,} + {report.original_states:,} states, {report.seconds:.2f} s)")
        for verdict in report.properties.values():
            self.say(f"%   {verdict.name}: {verdict.summary}")

    # -- the loop -------------------------------------------------------------------
    def loop(self, interactive: bool, stdin: TextIO = sys.stdin) -> int:
        """Read queries until the end of input or :quit."""
        self.say(f"% schemalog {_version()}: {len(self.workspace.files)} file(s), {self._tasks_line()}. "
                 f":help for help")
        for note in [*self.workspace.notes, self.workspace.clashes]:
            if note:
                self.say(note)
        if interactive:
            return self._interactive()
        return self._piped(stdin)

    def _piped(self, stdin: TextIO) -> int:
        """Line-based: a query may span lines; after an answer, a line ';' asks for the next
        one, an empty line stops, and any other line stops and is read as the next input."""
        pending: list[str] = []

        def read() -> str:
            return pending.pop() if pending else stdin.readline()

        def more() -> bool:
            reply = read()
            if reply.strip() in (";", "n", "r"):
                return True
            if reply.strip():
                pending.append(reply)
            return False

        buffer = ""
        while True:
            line = read()
            if not line:
                break
            stripped = line.strip()
            if not buffer.strip() and stripped.startswith(":") and not stripped.startswith(":-"):
                self.out.write(f"?- {stripped}\n")
                if not self.handle(line, more):
                    return 0
                continue
            if not buffer.strip() and stripped == ";":     # a spare ';' after the last answer
                continue
            buffer += line
            chunks, rest, unfinished = split_queries(buffer)
            buffer = rest if unfinished else ""
            for chunk in chunks:
                self.out.write(f"?- {chunk.strip()}\n")
                if not self.handle(chunk, more):
                    return 0
        if buffer.strip():
            self.say("error: the input ended inside a query (missing the final '.'?)")
            return 2
        return 0

    def _interactive(self) -> int:
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
            words = sorted(completion_words(self.workspace, word.group())) if word else []
            if len(words) == 1:                  # one way to go on: take it
                buffer.insert_text(words[0][len(word.group()):])
            elif words:
                buffer.start_completion(select_first=False)

        session = PromptSession(history=history, multiline=True, key_bindings=keys,
                                completer=_completer(self.workspace),
                                prompt_continuation=lambda width, line, soft: "|    ")
        more_keys = KeyBindings()
        for key in (";", "n", "r", " ", "tab"):
            more_keys.add(key)(lambda event: event.app.exit(result=True))
        for key in ("enter", ".", "c", "a", "escape"):
            more_keys.add(key)(lambda event: event.app.exit(result=False))
        more_keys.add("c-c")(lambda event: event.app.exit(result=False))
        answer_session = PromptSession(key_bindings=more_keys)

        def more() -> bool:
            try:
                return bool(answer_session.prompt(""))
            except (KeyboardInterrupt, EOFError):
                return False

        while True:
            try:
                text = session.prompt("?- ")
            except KeyboardInterrupt:
                continue
            except EOFError:
                self.say("")
                return 0
            stripped = text.strip()
            queries = [text] if stripped.startswith(":") and not stripped.startswith(":-") \
                else split_queries(text)[0]
            with _signals_from_keyboard():
                for query in queries:
                    if not self.handle(query, more):
                        return 0


class _signals_from_keyboard:
    """While a query runs, Ctrl-C must reach it as SIGINT: the terminal can still be in the
    raw mode prompt_toolkit read the query in (no ISIG), where Ctrl-C is only a byte."""

    def __enter__(self) -> None:
        self.saved = None
        try:
            import termios

            fd = sys.stdin.fileno()
            self.saved = termios.tcgetattr(fd)
            attrs = termios.tcgetattr(fd)
            attrs[3] |= termios.ISIG
            termios.tcsetattr(fd, termios.TCSANOW, attrs)
        except (ImportError, OSError, ValueError):
            self.saved = None

    def __exit__(self, *exc) -> None:
        if self.saved is not None:
            import termios

            termios.tcsetattr(sys.stdin.fileno(), termios.TCSANOW, self.saved)


def history_file() -> Path:
    """Where the REPL keeps its history: $SCHEMALOG_HISTORY, else the XDG state directory."""
    explicit = os.environ.get("SCHEMALOG_HISTORY")
    if explicit:
        return Path(explicit)
    state = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return Path(state) / "schemalog" / "history"


def _version() -> str:
    from .. import __version__

    return __version__
