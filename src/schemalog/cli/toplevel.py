"""The Prolog top level: reading queries and printing answers as SWI-Prolog does, for
`schemalog query` (query.py) and the REPL (repl.py).

    Query  = (goal: Term, names: list[(name, Var)])   the variables the user wrote, in order
    Answer = list[(name, Term)]                        resolved bindings, `X = Y` for aliases

An answer prints `X = f(Y), Z = 1`, or `true` when it binds nothing; no answer prints
`false`. Named variables with a leading `_` are shown too, as SWI-Prolog 9 does
(its flag toplevel_print_anon is true); `_` alone is not.
"""

from __future__ import annotations

import sys
from typing import Callable, TextIO

from .. import defaults
from ..api import failures
from ..api.answers import (Query, answer_json, answer_of, answer_text, answers, behaviour_labels,
                           behaviour_variables, json_text, labels_comment, read_query)
from ..api.failures import PrologError
from ..api.workspace import Workspace
from ..errors import SchemalogError


def error_text(err: BaseException, raise_limit: str = "--max-steps N") -> str:
    """An uncaught exception as the user should read it (api/failures.py), running out of
    memory with the ceiling in force."""
    return failures.error_text(err, raise_limit, _memory_words)


def _memory_words() -> str:
    """What running out of memory means here: the ceiling in force as the error is told
    (--max-memory's, not the default, when that option set it)."""
    from ..api.limits import ceiling_in_force, size_text

    ceiling = ceiling_in_force()
    if ceiling is None:
        return f"out of memory (no ceiling was set: the system refused more; set one with --max-memory " \
               f"or {defaults.MEMORY_ENV})"
    return (f"out of memory: the ceiling is {size_text(ceiling)} (raise it with --max-memory or "
            f"{defaults.MEMORY_ENV}, or set it to off)")


# ---------------------------------------------------------------------------
# schemalog query

def run_query(workspace: Workspace, text: str, *, first: bool = False, as_json: bool = False,
              out: TextIO = sys.stdout, err: TextIO = sys.stderr, max_steps: int | None = None) -> int:
    """Print the answers of `text`: 0 with an answer, 1 without, 2 on an error."""
    try:
        query = read_query(text, operators=workspace.kb.operators)
    except SchemalogError as e:
        print(str(e), file=err)
        return 2
    found: list[dict] = []
    count = 0
    status = 0
    # a behaviour's id gets its label beside it in text (JSON stays bare: join node/2 there)
    named = [] if as_json or not workspace.views else behaviour_variables(query)
    labels = behaviour_labels(workspace) if named else {}
    # In JSON mode what the query writes (write/1, format/2) goes to stderr: stdout is the list.
    shown = _Output(err.write if as_json else out.write)
    try:
        for answer, _ in answers(workspace, query, shown.write, max_steps):
            count += 1
            if as_json:
                found.append(answer_json(answer))
            else:
                shown.new_line()
                shown.write(answer_text(answer) + labels_comment(answer, named, labels) + "\n")
                out.flush()
            if first:
                break
    except (PrologError, SchemalogError, RecursionError) as e:
        shown.new_line()
        print(error_text(e), file=err)
        status = 2
    if as_json:
        out.write(json_text(found) + "\n")
    elif count == 0 and status == 0:
        shown.new_line()
        shown.write("false\n")
    if status:
        return status
    return 0 if count else 1


# ---------------------------------------------------------------------------
# The REPL



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


__all__ = ["Query", "read_query", "answer_of", "answer_text", "answer_json", "answers", "run_query",
           "complete_input", "split_queries"]
