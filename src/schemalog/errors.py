"""The one error type users see: a message with file:line:column and a caret; and how file
names are shown, in messages and in what is written (readable_name, the READABLE handler)."""

from __future__ import annotations

import codecs
import copyreg
import os
from dataclasses import dataclass

# The encoding error handler every output of schemalog is written with (files, standard output
# and error): what UTF-8 cannot hold is written as an escape, never an exception. It is only
# ever met in a file name that is not UTF-8 (os.fsdecode keeps its bytes as lone surrogates)
# or text made from one: the byte 0xff is written `\xff`, as readable_name shows it.
READABLE = "schemalog-readable"


def _escape(char: str) -> str:
    """One character as the escape readable_name and READABLE write for it."""
    code = ord(char)
    if 0xDC80 <= code <= 0xDCFF:                      # a byte os.fsdecode could not decode
        return f"\\x{code - 0xDC00:02x}"
    return {"\n": "\\n", "\t": "\\t", "\r": "\\r"}.get(char) or (
        f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}")


def _readable(err: UnicodeError) -> tuple[str, int]:
    if not isinstance(err, UnicodeEncodeError):
        raise err
    return "".join(_escape(c) for c in err.object[err.start:err.end]), err.end


codecs.register_error(READABLE, _readable)


def readable_name(name: str | bytes | os.PathLike) -> str:
    """A file name as text any output can hold and a reader can follow back to the file: bytes
    that are not UTF-8 as `\\xff`, control characters (a newline, an escape) as `\\n`, `\\x1b`,
    so a name never breaks a message's line or a written file's comment, nor drives a terminal."""
    return visible(os.fsdecode(name))


@dataclass(frozen=True, slots=True)
class SourcePos:
    """Where something was written: file, 1-based line and column."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{readable_name(self.file)}:{self.line}:{self.column}"


class SchemalogError(Exception):
    """A problem in the user's input or request, reported without a traceback."""

    def __init__(self, message: str, pos: SourcePos | None = None,
                 source_line: str | None = None, exit_code: int = 1) -> None:
        super().__init__(message)
        self.message = message
        self.pos = pos
        self.source_line = source_line
        self.exit_code = exit_code

    def __reduce__(self):
        """Rebuild from the attributes, as pickle rebuilds any object: an exception is
        otherwise unpickled by calling its class with `args`, the message alone, which the
        subclasses that take more (LimitExceeded's limit, QueryError's term) refuse."""
        return copyreg.__newobj__, (type(self), *self.args), self.__dict__

    @property
    def file(self) -> str | None:
        """The file the problem is in, or None when it is in no file."""
        return self.pos.file if self.pos else None

    @property
    def line(self) -> int | None:
        return self.pos.line if self.pos else None

    @property
    def column(self) -> int | None:
        return self.pos.column if self.pos else None

    def __str__(self) -> str:
        message = "\n".join(map(visible, self.message.split("\n")))
        head = f"{self.pos}: error: {message}" if self.pos else f"error: {message}"
        if self.source_line is None or self.pos is None:
            return head
        line = self.source_line.rstrip("\n").expandtabs(1)
        if len(line) > 160:  # keep the caret in view on very long lines
            start = max(0, self.pos.column - 80)
            line = line[start:start + 160]
            caret_at = self.pos.column - 1 - start
        else:
            caret_at = self.pos.column - 1
        # control characters and NULs as escapes: a line shown must not drive the terminal, and
        # the caret stays under the character it points at
        caret_at = len(visible(line[:max(0, caret_at)]))
        return f"{head}\n    {visible(line)}\n    {' ' * caret_at}^"


def visible(text: str) -> str:
    """Text as a message shows it: what is not printable (a NUL, an escape, a carriage return)
    as its escape, as readable_name writes a file name."""
    return text if text.isprintable() else "".join(c if c.isprintable() else _escape(c) for c in text)


def unquoted(pos: SourcePos, what: str, via: str) -> SchemalogError:
    """An error in a file the command line does not name (reached through an <include> or a
    consult, `via`): its place and `what` it is not, and nothing of its text, which may be any
    file this process can read (/etc/passwd, /proc/self/environ)."""
    return SchemalogError(f"{what}; {via}, and a file not named on the command line is never quoted "
                          f"(name it to see its text)", pos)


class UsageError(SchemalogError):
    """A wrong command line: exit status 2."""

    def __init__(self, message: str) -> None:
        super().__init__(message, exit_code=2)


def shown_name(name: str, most: int = 160) -> str:
    """A file name as a message shows it (readable_name): whole, or its two ends when it is too
    long to read."""
    name = readable_name(name)
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
