"""Tab completion in the REPL: predicate names, relations, atoms and `:` commands."""

from __future__ import annotations

import re

from ..api.repl import vocabulary
from ..api.workspace import Workspace


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


def completions(words: set[str], prefix: str) -> set[str]:
    """The words that complete `prefix`: commands after ':', else `words`."""
    pool = COMMANDS if prefix.startswith(":") else words
    return {w for w in pool if w.startswith(prefix)}


def completion_words(workspace: Workspace, prefix: str) -> set[str]:
    """The words that complete `prefix` in `workspace`."""
    return completions(vocabulary(workspace) if not prefix.startswith(":") else set(), prefix)
