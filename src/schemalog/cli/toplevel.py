"""The Prolog top level: answers as SWI-Prolog prints them, `schemalog query`, and the REPL.

    Query  = (goal: Term, names: list[(name, Var)])   the variables the user wrote, in order
    Answer = list[(name, Term)]                        resolved bindings, `X = Y` for aliases

An answer prints `X = f(Y), Z = 1`, or `true` when it binds nothing; no answer prints
`false`. Named variables with a leading `_` are shown too, as SWI-Prolog 9 does
(its flag toplevel_print_anon is true); `_` alone is not.
"""

from __future__ import annotations

import json
import math
import os
import re
import signal
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, TextIO

from ..logic.builtins import compare_terms
from ..logic.exceptions import PrologError, StepLimitExceeded
from ..errors import SchemalogError
from ..logic.parse import parse_term
from .relations import COMPRESSED, ORIGINAL, RELATIONS, Workspace
from ..logic.terms import Atom, Float, Int, Struct, Term, Var, iter_vars, term_to_text, variable_names
from ..logic.unify import Bindings



@dataclass(frozen=True)
class Query:
    """A parsed query and the variables to report."""

    goal: Term
    names: tuple[tuple[str, Var], ...]


def read_query(text: str, file: str = "<query>") -> Query:
    """Parse a query (the final '.' is optional); syntax errors carry a caret."""
    goal = parse_term(text, file)
    seen: dict[Var, None] = {}
    for v in iter_vars(goal):
        seen.setdefault(v, None)
    return Query(goal, tuple((v.name, v) for v in seen if v.name and v.name != "_"))


@dataclass(frozen=True)
class Answer:
    """One answer: each query variable's value, and the print names of the free variables
    in them (a free variable shared by query variables is named after the last of them)."""

    values: tuple[tuple[str, Term], ...]
    names: dict

    def groups(self) -> list[tuple[list[str], Term]]:
        """The query variables grouped by equal (==) values, in order of first appearance."""
        groups: list[tuple[list[str], Term]] = []
        for name, value in self.values:
            for members, shared in groups:
                if compare_terms(shared, value) == 0:     # ==, without recursion on deep terms
                    members.append(name)
                    break
            else:
                groups.append(([name], value))
        return groups


def answer_of(query: Query, b: Bindings) -> Answer:
    """The bindings of one answer, resolved."""
    values = tuple((name, b.resolve_finite(v)) for name, v in query.names)
    answer = Answer(values, variable_names([value for _, value in values]))
    for v in iter_vars(query.goal):             # `_Z` in the query keeps its name, as in SWI
        if v.name:
            answer.names[v] = v.name
    for members, value in answer.groups():
        if isinstance(value, Var):
            answer.names[value] = members[-1]
    return answer


def answer_text(answer: Answer) -> str:
    """`X = Y, Y = a, Z = [1, 2]` as SWI-Prolog prints it, or `true`."""
    parts = []
    for members, value in answer.groups():
        parts.extend(f"{a} = {b}" for a, b in zip(members, members[1:]))
        if not isinstance(value, Var):
            parts.append(f"{members[-1]} = {term_to_text(value, 699, answer.names, next_argument=True)}")
    return ", ".join(parts) or "true"


def answer_json(answer: Answer) -> dict:
    """{"X": 1, "Y": "[a, b]"}: integers and floats as JSON numbers, other terms as Prolog
    text, a free variable as its name."""
    out: dict = {}
    for name, value in answer.values:
        if isinstance(value, Int):
            out[name] = value.value
        elif isinstance(value, Float) and math.isfinite(value.value):
            out[name] = value.value
        else:
            out[name] = term_to_text(value, 699, answer.names, next_argument=True)
    return out


def error_text(err: BaseException, raise_limit: str = "--max-steps N") -> str:
    """An uncaught exception as the user should read it."""
    if isinstance(err, RecursionError):
        return "error: a term nests too deeply for schemalog to process (Python's recursion limit)"
    if isinstance(err, PrologError):
        return f"error: uncaught exception: {_explain(err.ball)}"
    if isinstance(err, StepLimitExceeded):
        return f"error: {err.message}; raise it with {raise_limit}"
    return str(err)


def _explain(ball: Term) -> str:
    """`error(type_error(integer, a), _)` with a plain-words gloss for the ISO errors."""
    text = term_to_text(ball, names=variable_names([ball]))
    if isinstance(ball, Struct) and ball.name == "error" and len(ball.args) == 2:
        formal = ball.args[0]
        name = formal.name if isinstance(formal, (Atom, Struct)) else ""
        args = formal.args if isinstance(formal, Struct) else ()
        if name == "existence_error" and len(args) == 2 and args[0] == Atom("procedure"):
            return f"{text}\n  unknown procedure {term_to_text(args[1])}"
        if name == "instantiation_error":
            return f"{text}\n  arguments are not sufficiently instantiated"
        if name == "type_error" and len(args) == 2:
            return f"{text}\n  {term_to_text(args[0])} expected, found {term_to_text(args[1])}"
        if name == "evaluation_error" and len(args) == 1:
            return f"{text}\n  arithmetic: {term_to_text(args[0])}"
    return text


def answers(workspace: Workspace, query: Query, output: Callable[[str], None] | None = None,
            max_steps: int | None = None) -> Iterator[tuple[Answer, bool]]:
    """Every answer of `query`, lazily, each with whether it is the last (no choicepoint
    left, so the REPL does not ask for more); errors propagate."""
    engine = workspace.engine(output, max_steps)
    for b in engine.solve(query.goal):
        yield answer_of(query, b), engine.deterministic


# ---------------------------------------------------------------------------
# schemalog query

def run_query(workspace: Workspace, text: str, *, first: bool = False, as_json: bool = False,
              out: TextIO = sys.stdout, err: TextIO = sys.stderr, max_steps: int | None = None) -> int:
    """Print the answers of `text`: 0 with an answer, 1 without, 2 on an error."""
    try:
        query = read_query(text)
    except SchemalogError as e:
        print(str(e), file=err)
        return 2
    found: list[dict] = []
    count = 0
    status = 0
    # In JSON mode what the query writes (write/1, format/2) goes to stderr: stdout is the list.
    shown = _Output(err.write if as_json else out.write)
    try:
        for answer, _ in answers(workspace, query, shown.write, max_steps):
            count += 1
            if as_json:
                found.append(answer_json(answer))
            else:
                shown.new_line()
                shown.write(answer_text(answer) + "\n")
                out.flush()
            if first:
                break
    except (PrologError, SchemalogError, RecursionError) as e:
        shown.new_line()
        print(error_text(e), file=err)
        status = 2
    if as_json:
        out.write(json.dumps(found, indent=2) + "\n")
    elif count == 0 and status == 0:
        shown.new_line()
        shown.write("false\n")
    if status:
        return status
    return 0 if count else 1


# ---------------------------------------------------------------------------
# The REPL

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


def complete_input(text: str) -> bool:
    """Whether `text` can be run: a ':' command line, or queries each ended by a full stop
    (a '.' outside quotes and comments, followed by layout), comments and layout after."""
    stripped = text.strip()
    if stripped.startswith(":") and not stripped.startswith(":-"):
        return True
    return not split_queries(text)[2]


def split_queries(text: str) -> tuple[list[str], str, bool]:
    """(the complete queries of `text`, each up to its full stop; what follows the last one;
    whether that is an unfinished query). Comments and layout alone are no query."""
    chunks: list[str] = []
    start, significant = 0, False
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c in "'\"`":
            j = i + 1
            while j < n:
                if text[j] == "\\":
                    j += 2
                    continue
                if text[j] == c:
                    if j + 1 < n and text[j + 1] == c:   # 'it''s'
                        j += 2
                        continue
                    break
                j += 1
            else:
                return chunks, text[start:], True        # an open quote
            significant = True
            i = j + 1
            continue
        if c == "%":
            while i < n and text[i] != "\n":
                i += 1
            continue
        if c == "/" and i + 1 < n and text[i + 1] == "*":
            end = text.find("*/", i + 2)
            if end < 0:
                return chunks, text[start:], True        # an open comment
            i = end + 2
            continue
        if c == "0" and text[i + 1:i + 2] == "'" and not (i > 0 and (text[i - 1].isalnum() or text[i - 1] == "_")):
            significant = True                           # 0'c, a character code
            i += 3
            continue
        if c == "." and (i + 1 == n or text[i + 1].isspace() or text[i + 1] == "%") \
                and not (i > 0 and text[i - 1] in "#$&*+-./:<=>?@^~\\"):
            if significant:
                chunks.append(text[start:i + 1])
            start, significant = i + 1, False
        elif not c.isspace():
            significant = True
        i += 1
    return chunks, text[start:], significant


class _Output:
    """Where a query's answers and its own output go; remembers whether the last thing
    written ended its line, so an answer after `write(hello)` starts on a new one."""

    def __init__(self, write: Callable[[str], object]) -> None:
        self._write = write
        self.at_line_start = True

    def write(self, text: str) -> None:
        if text:
            self._write(text)
            self.at_line_start = text.endswith("\n")

    def new_line(self) -> None:
        if not self.at_line_start:
            self.write("\n")


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


def _completer(workspace: Workspace):
    """Tab completion of predicate names, relations, atoms and REPL commands: the workspace's
    words, gathered once per knowledge base (not on every key)."""
    from prompt_toolkit.completion import Completer, Completion

    cache: dict[int, set[str]] = {}

    class Words(Completer):
        def get_completions(self, document, complete_event):
            word = document.get_word_before_cursor(pattern=_WORD)
            if not word:
                return
            known = cache.get(id(workspace.kb))
            if known is None:
                cache.clear()
                known = cache[id(workspace.kb)] = vocabulary(workspace)
            for candidate in sorted(completions(known, word)):
                yield Completion(candidate, start_position=-len(word))

    return Words()


_WORD = re.compile(r"[:a-z][A-Za-z0-9_]*$")


COMMANDS = (":load", ":tree", ":compress", ":original", ":run", ":reset", ":verify", ":state",
            ":limit", ":help", ":quit")


def vocabulary(workspace: Workspace) -> set[str]:
    """Predicate names (the files', built-in, relations) and the atoms of the files' clauses."""
    from ..logic.engine import BUILTINS, NONDET_BUILTINS

    words = {name for name, _ in workspace.kb.predicates} | {name for name, _ in BUILTINS} | \
        {name for name, _ in NONDET_BUILTINS} | {name for name, _ in RELATIONS}
    for pred in workspace.kb.predicates.values():
        for clause in pred.clauses[:2000]:      # atoms of the files' clauses, not of huge fact sets
            _atoms_of(clause.head, words)
    return {w for w in words if re.fullmatch(r"[a-z][A-Za-z0-9_]*", w)}


def completions(words: set[str], prefix: str) -> set[str]:
    """The words that complete `prefix`: commands after ':', else `words`."""
    pool = COMMANDS if prefix.startswith(":") else words
    return {w for w in pool if w.startswith(prefix)}


def completion_words(workspace: Workspace, prefix: str) -> set[str]:
    """The words that complete `prefix` in `workspace`."""
    return completions(vocabulary(workspace) if not prefix.startswith(":") else set(), prefix)


def _atoms_of(term: Term, out: set[str]) -> None:
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Atom):
            out.add(t.name)
        elif isinstance(t, Struct):
            out.add(t.name)
            stack.extend(t.args)


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


__all__ = ["Query", "read_query", "answer_of", "answer_text", "answer_json", "run_query", "Repl",
           "complete_input", "completion_words", "history_file"]
