"""The REPL session: a query or a `:` command at a time, answered as query.py answers
(toplevel.py), `;` for more answers. Ctrl-C, or any error, stops the running query or command,
not the session; a command that does not finish leaves the workspace as it was (its attributes
are put back). Interactive sessions read with prompt_toolkit (terminal.py); piped ones line by line.
"""

from __future__ import annotations

import os
import re
import signal
import sys
import traceback
from typing import Callable, TextIO

from ..api import repl as commands
from ..api.failures import PrologError, StepLimitExceeded
from ..api.workspace import COMPRESSED, ORIGINAL, RELATIONS, Workspace
from ..errors import SchemalogError
from .toplevel import _Output, answer_text, answers, error_text, read_query, split_queries


HELP = """\
Enter a query, ending with '.'; it may span lines. After an answer, ';' asks for the
next one (so do n, r, space and Tab), Enter stops (so do '.', c, a and Escape) and h lists
these keys; any other key is no input there.
Ctrl-C stops a running query or command, Ctrl-D leaves.

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


def failure_text(err: BaseException) -> str:
    """What the REPL says, in a line, when a query or command stops on `err`."""
    if isinstance(err, KeyboardInterrupt):
        return "% interrupted"
    if isinstance(err, MemoryError):
        return "error: out of memory; the work was dropped (a smaller input or a lower :limit may fit)"
    if isinstance(err, (PrologError, StepLimitExceeded, RecursionError)):
        return error_text(err, ":limit N")
    if isinstance(err, SchemalogError):
        return str(err)
    return (f"internal error: {type(err).__name__}: {err} (please report it; SCHEMALOG_DEBUG=1 "
            f"shows the traceback)")


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
        command = stripped.startswith(":") and not stripped.startswith(":-")
        saved = dict(vars(self.workspace)), self.max_steps
        # prompt_toolkit's event loop may leave its own SIGINT handling behind: whatever runs
        # gets Python's, so Ctrl-C raises KeyboardInterrupt in it, command or query.
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
        try:
            return self.command(stripped[1:].strip()) if command else self._answer(stripped, more)
        except (KeyboardInterrupt, Exception) as err:      # the session outlives anything but SIGTERM
            if isinstance(err, BrokenPipeError):
                raise
            if command:     # a command that did not finish changed nothing (no half-loaded file)
                vars(self.workspace).clear()
                vars(self.workspace).update(saved[0])
                self.max_steps = saved[1]
            undone = f"; :{(stripped[1:].split() or [''])[0]} changed nothing" if command else ""
            self.say(failure_text(err) + (undone if isinstance(err, KeyboardInterrupt) else ""))
            if os.environ.get("SCHEMALOG_DEBUG") and not isinstance(err, (KeyboardInterrupt, SchemalogError)):
                traceback.print_exception(err)
            return True
        finally:
            signal.signal(signal.SIGINT, previous)

    def _answer(self, stripped: str, more: Callable[[], bool]) -> bool:
        query = read_query(stripped, operators=self.workspace.kb.operators)
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
        except BaseException:
            shown.new_line()         # the message that follows starts a line of its own
            raise
        return True

    def _write(self, text: str) -> None:
        self.out.write(text)
        self.out.flush()

    def say(self, text: str) -> None:
        self.out.write(text + "\n")
        self.out.flush()

    # -- commands -------------------------------------------------------------------
    def command(self, line: str) -> bool:
        """Run a `:` command (`line` without the colon); False for :quit."""
        name, _, rest = line.partition(" ")
        rest = rest.strip()
        if rest and name in ("quit", "q", "exit", "help", "h", "?", "reset", "state"):
            raise SchemalogError(f":{name} takes no argument")
        if name in ("quit", "q", "exit"):
            return False
        if name in ("help", "h", "?"):
            self.help()
        elif name == "load":
            if not rest:
                raise SchemalogError(":load needs a file")
            known = len(self.workspace.files)
            self.workspace.load(rest)        # clauses asserted at the prompt are not kept
            new = len(self.workspace.files) > known
            for note in self.workspace.notes:
                self.say(note)
            self.say(f"% {'loaded' if new else 'read again'} {rest}: {self._tasks_line()}")
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
        return True

    def help(self) -> None:
        self.out.write(HELP)
        for text in RELATIONS.values():
            self.out.write(f"  {text}\n")
        self.out.flush()

    def _tree(self, text: str):
        """(view, kind) of a command's argument: a task or a root id; none: the focus."""
        return commands.tree_named(self.workspace, text)

    def _tasks_line(self) -> str:
        return commands.tasks_line(self.workspace)

    def _state_text(self) -> str:
        return commands.state_text(self.workspace)

    def show_tree(self, view, kind: str, figures: bool = False) -> None:
        from rich.console import Console

        from ..formats.render import rich_tree

        tree = view.tree(kind)
        console = Console(file=self.out, width=120, highlight=False,
                          force_terminal=self.out.isatty() if hasattr(self.out, "isatty") else False)
        console.print(f"% {commands.task_name(view)}, {kind} tree (focus); ids as the relations number them; "
                      f"pre green/brown: true/false now")
        console.print(rich_tree(tree, first_id=view.first(kind), state=self.workspace.state))
        if figures:
            self.say(commands.figures_line(view))

    def run(self, view, kind: str) -> None:
        """Run `view`'s tree from the current state, each decision as `schemalog run` prints it."""
        for line in commands.run_lines(self.workspace, view, kind):
            self.say(line)

    def verify(self, view) -> None:
        for line in commands.verify_lines(self.workspace, view):
            self.say(line)

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
            try:
                reply = read()
            except KeyboardInterrupt:
                return False
            if reply.strip() in (";", "n", "r"):
                return True
            if reply.strip():
                pending.append(reply)
            return False

        buffer = ""
        while True:
            try:
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
            except (KeyboardInterrupt, Exception) as err:   # Ctrl-C while reading, the reader failing
                if isinstance(err, BrokenPipeError):
                    raise
                self.say(failure_text(err))                  # the input read so far is dropped
                buffer = ""
        if buffer.strip():
            self.say("error: the input ended inside a query (missing the final '.'?)")
            return 2
        return 0

    def _interactive(self) -> int:
        from .terminal import no_echo_between_prompts

        with no_echo_between_prompts():
            return self._prompting()

    def _prompting(self) -> int:
        from .terminal import prompts, signals_from_keyboard

        prompt, more = prompts(self.workspace)
        while True:
            try:
                text = prompt()
            except KeyboardInterrupt:
                continue
            except EOFError:
                self.say("")
                return 0
            except Exception as err:        # a completion failing, say: the session goes on
                self.say(failure_text(err))
                continue
            stripped = text.strip()
            try:
                queries = [text] if stripped.startswith(":") and not stripped.startswith(":-") \
                    else split_queries(text)[0]
                with signals_from_keyboard(prompt):
                    for query in queries:
                        if not self.handle(query, more):
                            return 0
            except KeyboardInterrupt:       # between two queries of a line
                self.say("% interrupted")
            except Exception as err:
                self.say(failure_text(err))


def _version() -> str:
    from .. import __version__

    return __version__
