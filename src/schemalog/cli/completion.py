"""Tab completion in the REPL: predicate names, relations, atoms and `:` commands."""

from __future__ import annotations

import re

from ..logic.terms import Atom, Struct, Term
from ..api.workspace import RELATIONS, Workspace


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
