"""The one error type users see: a message with file:line:column and a caret."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class SourcePos:
    """Where something was written: file, 1-based line and column."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


class SchemalogError(Exception):
    """A problem in the user's input or request, reported without a traceback."""

    def __init__(self, message: str, pos: SourcePos | None = None,
                 source_line: str | None = None, exit_code: int = 1) -> None:
        super().__init__(message)
        self.message = message
        self.pos = pos
        self.source_line = source_line
        self.exit_code = exit_code

    def __str__(self) -> str:
        head = f"{self.pos}: error: {self.message}" if self.pos else f"error: {self.message}"
        if self.source_line is None or self.pos is None:
            return head
        line = self.source_line.rstrip("\n").expandtabs(1)
        if len(line) > 160:  # keep the caret in view on very long lines
            start = max(0, self.pos.column - 80)
            line = line[start:start + 160]
            caret_at = self.pos.column - 1 - start
        else:
            caret_at = self.pos.column - 1
        return f"{head}\n    {line}\n    {' ' * max(0, caret_at)}^"


class UsageError(SchemalogError):
    """A wrong command line: exit status 2."""

    def __init__(self, message: str) -> None:
        super().__init__(message, exit_code=2)


def shown_name(name: str, most: int = 160) -> str:
    """A file name as a message shows it: whole, or its two ends when it is too long to read."""
    if len(name) <= most:
        return name
    half = most // 2 - 10
    return f"{name[:half]}...{name[-half:]} (a name of {len(name):,} characters)"


def shown_number(text: str, most: int = 40) -> str:
    """A number's text as a message shows it: whole, or its two ends and its count of digits
    when it is too long to read (a 5,000-digit weight would bury the message)."""
    if len(text) <= most:
        return text
    digits = sum(c.isdigit() for c in text)
    return f"{text[:most // 2]}...{text[-10:]} ({digits:,} digits)"


class CannotWrite(SchemalogError):
    """The system refused to write an output (a name too long, no permission, a full device):
    `cannot write FILE: reason`, exit status 1 (a name that cannot be a file is a UsageError)."""

    def __init__(self, name: str, reason: str) -> None:
        super().__init__(f"cannot write {shown_name(str(name))}: {reason}")
