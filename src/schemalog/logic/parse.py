"""Text -> clauses, through the one lark grammar; every error carries file:line:column.

    Clause = (head: Term, body: Term, pos: SourcePos)      facts have body `true`
    Directive = (goal: Term, pos: SourcePos)               `:- dynamic schema/3.`

The LALR parser calls the transformer as it reduces, so no parse tree is built and
deep operator chains never recurse in Python. Bracket nesting is bounded
(`MAX_NESTING`) so that printing and unifying what we read stays safe.

Files are read by fastread.parse_text, which takes the common clauses faster and hands the
others to `lark_clause` here; parse_text_by_lark reads with lark alone.
"""

from __future__ import annotations

import bisect
import functools
import os
import re
from collections import deque
import threading
from dataclasses import dataclass
from pathlib import Path

import lark
from lark import Lark, TextSlice, Token, Transformer
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

from .. import defaults
from ..cache import cache_file
from ..errors import SchemalogError, SourcePos, shown_name
from ..inputs import read_limited
from ..shipped import shipped_text
from .terms import INFIX_OPS, NIL, PREFIX_OPS, TRUE, Atom, Float, Int, Str, Struct, Term, Var, int_of_digits, make_list

MAX_NESTING = 2_000
MAX_BYTES = defaults.MAX_BYTES


@dataclass(frozen=True, slots=True)
class Clause:
    """A fact or rule `head :- body`, with where it was written."""

    head: Term
    body: Term
    pos: SourcePos


@dataclass(frozen=True, slots=True)
class Directive:
    """A directive `:- goal.`, with where it was written."""

    goal: Term
    pos: SourcePos


def grammar_text() -> str:
    """Return the grammar, from the installed package or from the source tree."""
    return shipped_text("grammar/schemalog.lark")


def lark_version() -> str:
    """The version of lark that builds the parser (cached tables depend on it)."""
    return lark.__version__


_ESCAPE_CHARS = {"n": "\n", "t": "\t", "r": "\r", "a": "\a", "b": "\b", "f": "\f",
                 "v": "\v", "\\": "\\", "'": "'", '"': '"', "`": "`", "e": "\x1b",
                 "s": " "}
_HEX = re.compile(r"[0-9a-fA-F]*")
_OCTAL = re.compile(r"[0-7]*")
# Where a body needs translating: a backslash with something after it, or a doubled quote.
_SPECIAL = {q: re.compile(r"\\(?=.)|" + q + q, re.S) for q in ("'", '"', "`")}


class _BadEscape(Exception):
    """An escape sequence that denotes no character, at `offset` in the quoted text."""

    def __init__(self, offset: int, message: str) -> None:
        super().__init__(message)
        self.offset, self.message = offset, message


def _unescape(body: str, quote: str) -> str:
    """The text of a quoted item's body, as SWI-Prolog reads it: `\\xHH..\\` and `\\NNN\\`
    take every hex or octal digit, the closing backslash optional ("\\x1b[2J" is ESC [2J);
    an unknown escape (`\\z`, `\\q`) or a code that is no character is _BadEscape."""
    special = _SPECIAL[quote]
    found = special.search(body)
    if found is None:                 # most bodies: nothing to translate, no copy
        return body
    # The text between escapes is copied a run at a time: a list entry per character was
    # 8 bytes and a loop turn per character of a 10 MB atom.
    out, i, size = [], 0, len(body)
    while found is not None:
        j = found.start()
        out.append(body[i:j])
        if body[j] == quote:
            out.append(quote)
            i = j + 2
        else:
            nxt = body[j + 1]
            if nxt == "x" or nxt in "01234567":
                pattern, base, first = (_HEX, 16, j + 2) if nxt == "x" else (_OCTAL, 8, j + 1)
                end = pattern.match(body, first).end()
                if end == first:
                    raise _BadEscape(j, "undefined escape sequence \\x (hex digits expected)")
                code = int(body[first:end], base)
                if code > 0x10FFFF or 0xD800 <= code <= 0xDFFF:
                    raise _BadEscape(j, f"escape \\{body[j + 1:end]} is not a character code "
                                        f"(0 to 0x10FFFF, no surrogates)")
                out.append(chr(code))
                i = end + 1 if end < size and body[end] == "\\" else end
            elif nxt == "\n":  # a backslash before a newline continues the line
                i = j + 2
            elif nxt in _ESCAPE_CHARS:
                out.append(_ESCAPE_CHARS[nxt])
                i = j + 2
            else:
                raise _BadEscape(j, f"undefined escape sequence \\{nxt}")
        found = special.search(body, i)
    out.append(body[i:])
    return "".join(out)


def _atom_name(token: str) -> str:
    if token.startswith("'"):
        return _unescape(token[1:-1], "'")
    return token


def int_of_token(text: str) -> Int | None:
    """The integer an INT token denotes; None for a `0'` that is not one character (a bad
    escape in it is _BadEscape)."""
    sign, digits = (-1, text[1:]) if text.startswith("-") else (1, text)
    if digits.startswith("0'"):
        char = _unescape(digits[2:], "'")
        return Int(sign * ord(char)) if len(char) == 1 else None
    if digits[:2] in ("0x", "0o", "0b"):
        return Int(sign * int(digits, 0))
    return Int(sign * int_of_digits(digits.replace("_", "")))


def float_of_token(text: str) -> Float:
    """The float a FLOAT token denotes."""
    if text.endswith("Inf"):  # SWI-Prolog writes infinity as 1.0Inf
        return Float(float("-inf") if text.startswith("-") else float("inf"))
    if text.endswith("NaN"):
        return Float(float("nan"))
    return Float(float(text))


_LAYOUT = re.compile(r"(?:\s+|%[^\n]*|/\*.*?\*/)*", re.S)


def clause_item(term: Term, pos: SourcePos) -> Clause | Directive:
    """The clause or directive a term read as a clause stands for."""
    if isinstance(term, Struct) and term.name in (":-", "?-") and len(term.args) == 1:
        return Directive(term.args[0], pos)
    if isinstance(term, Struct) and term.name == ":-" and len(term.args) == 2:
        return Clause(term.args[0], term.args[1], pos)
    return Clause(term, TRUE, pos)


class _LineIndex:
    """Offset -> (line, column), by bisecting the offsets where lines start."""

    def __init__(self, text: str) -> None:
        self.starts = [0] + [m.end() for m in re.finditer("\n", text)]

    def __call__(self, offset: int) -> tuple[int, int]:
        line = bisect.bisect_right(self.starts, offset)
        return line, offset - self.starts[line - 1] + 1


class _Operand:
    """Prefix operators followed by their primary: `\\+ a`, `- - x`."""

    __slots__ = ("parts",)

    def __init__(self, parts: list) -> None:
        self.parts = parts


def arrange(items: list, clash) -> tuple[Term, int]:
    """The term of a run `operand (infix operand)*` and its priority, by operator priority
    (shunting-yard): an infix operator is its token (a str), an operand with prefix operators
    an _Operand; `clash(token, name)` is the exception for operands that do not fit."""
    out: list[tuple[Term, int]] = []          # operands with their priority
    ops: list[tuple[str, int, int, int, str]] = []  # (name, priority, left max, right max, token)

    def reduce() -> None:
        name, priority, left_max, right_max, token = ops.pop()
        right, right_p = out.pop()
        if right_p > right_max:
            raise clash(token, name)
        if left_max < 0:  # prefix operator
            out.append((Struct(name, (right,)), priority))
            return
        left, left_p = out.pop()
        if left_p > left_max:
            raise clash(token, name)
        out.append((Struct(name, (left, right)), priority))

    for item in items:
        if isinstance(item, str):  # an infix operator
            name = str(item)
            priority, kind = INFIX_OPS[name]
            left_max = priority if kind == "yfx" else priority - 1
            right_max = priority if kind == "xfy" else priority - 1
            while ops and ops[-1][1] <= left_max:
                reduce()
            ops.append((name, priority, left_max, right_max, item))
            continue
        parts = item.parts if isinstance(item, _Operand) else (item,)
        for part in parts[:-1]:  # prefix operators
            name = str(part)
            priority, kind = PREFIX_OPS[name]
            ops.append((name, priority, -1, priority if kind == "fy" else priority - 1, part))
        out.append((parts[-1], 0))
    while ops:
        reduce()
    return out[0]


class _ToTerms(Transformer):
    """A table of one-liners from grammar rules to terms."""

    def __init__(self, file: str) -> None:
        super().__init__()
        self.file = file
        self.varmap: dict[str, Var] = {}
        self.starts: deque[int] = deque()  # offsets where clauses may start (after each ".")
        self.text = ""
        self.line_at = _LineIndex("")

    def _fresh_clause(self) -> dict[str, Var]:
        names, self.varmap = self.varmap, {}
        return names

    # -- clauses ------------------------------------------------------------
    def start(self, clauses):
        return clauses

    def term_input(self, children):
        return children[0]

    def clause(self, children):
        term = children[0]
        self._fresh_clause()
        offset = _LAYOUT.match(self.text, self.starts.popleft()).end()
        return clause_item(term, SourcePos(self.file, *self.line_at(offset)))

    # -- operators: a flat run arranged by priority ----------------------------
    def expr(self, c): return self._arrange(c, 1200)
    # An argument may be any term but a bare comma: SWI-Prolog reads f(a;b) and f(a:-b),
    # though ISO limits arguments to priority 999 (the writer still brackets them).
    def arg(self, c): return c[0] if len(c) == 1 and not isinstance(c[0], _Operand) else self._arrange(c, 1200)
    def operand(self, c): return c[0] if len(c) == 1 else _Operand(c)
    def infix(self, c): return c[0]
    def arg_infix(self, c): return c[0]

    def _arrange(self, items: list, max_priority: int) -> Term:
        """Build the term of `operand (infix operand)*` by operator priority."""
        if len(items) == 1 and not isinstance(items[0], _Operand):
            return items[0]
        term, priority = arrange(items, self._clash)
        if priority > max_priority:
            raise SchemalogError(f"operator priority clash: a term of priority {priority} where at most "
                                 f"{max_priority} is allowed (put it in parentheses)",
                                 SourcePos(self.file, *self._first_position(items)))
        return term

    def _clash(self, token: Token, name: str) -> SchemalogError:
        return SchemalogError(f"operator priority clash at {name!r} (put the operands in parentheses)",
                              SourcePos(self.file, token.line, token.column))

    @staticmethod
    def _first_position(items: list) -> tuple[int, int]:
        for item in items:
            parts = item.parts if isinstance(item, _Operand) else (item,)
            for part in parts:
                if isinstance(part, Token):
                    return part.line, part.column
        return 1, 1

    # -- primaries ----------------------------------------------------------
    def _quoted(self, token: Token, read):
        """`read(text)`; a bad escape in the token is a syntax error at its line:column."""
        try:
            return read(str(token))
        except _BadEscape as bad:
            text = str(token)
            skip = 2 if text.lstrip("-").startswith("0'") else 1  # where the body starts in the token
            skip += len(text) - len(text.lstrip("-"))
            before = text[:bad.offset + skip]
            line = token.line + before.count("\n")
            column = len(before) - before.rfind("\n") if "\n" in before else token.column + len(before)
            raise SchemalogError(f"syntax error: {bad.message}", SourcePos(self.file, line, column),
                                 _source_line(self.text, line)) from None

    def atom(self, c): return Atom(self._quoted(c[0], _atom_name))

    def var(self, c):
        name = str(c[0])
        if name == "_":
            return Var("_")
        v = self.varmap.get(name)
        if v is None:
            v = self.varmap[name] = Var(name)
        return v

    def int(self, c):
        value = self._quoted(c[0], int_of_token)
        if value is None:
            raise SchemalogError(f"syntax error: {c[0]} is not one character",
                                 SourcePos(self.file, c[0].line, c[0].column), _source_line(self.text, c[0].line))
        return value

    def float(self, c): return float_of_token(str(c[0]))
    def string(self, c): return Str(self._quoted(c[0], lambda t: _unescape(t[1:-1], '"')))
    def compound(self, c): return Struct(self._quoted(c[0], _atom_name), tuple(c[1]))
    def args(self, c): return [a for a in c if not isinstance(a, Token)]
    def nil(self, c): return NIL
    def list(self, c): return make_list(c[0])
    def list_tail(self, c): return make_list(c[0], c[1])
    def curly_atom(self, c): return Atom("{}")
    def curly(self, c): return Struct("{}", (c[0],))
    def paren(self, c): return c[0]


class _TooDeep(Exception):
    def __init__(self, token: Token) -> None:
        super().__init__()
        self.token = token


class _Reader:
    """One compiled LALR table per start symbol, with its transformer and bracket guard.

    Lark keeps a reference to the transformer, so a parse resets its state (file name,
    variable names, nesting depth) instead of rebuilding the table. A lock keeps
    concurrent parses apart.
    """

    def __init__(self, start: str) -> None:
        self.transformer = _ToTerms("<string>")
        self.depth = 0
        self.lock = threading.Lock()
        callbacks = {name: self._open for name in ("LPAR", "LSQB", "LBRACE")}
        callbacks.update({name: self._close for name in ("RPAR", "RSQB", "RBRACE")})
        callbacks["END"] = self._end
        # lark checks a cached table against a hash of the grammar and options, and rebuilds
        # it (silently) when the file is stale, torn or unreadable: building takes ~60 ms.
        cached = cache_file(f"grammar-{start}", [grammar_text(), lark.__version__], ".cache")
        self.lark = Lark(grammar_text(), parser="lalr", start=start,
                         transformer=self.transformer, maybe_placeholders=False,
                         lexer_callbacks=callbacks, cache=cached or False)

    def _end(self, token: Token) -> Token:
        # The next clause starts at the first character after this "." that is not
        # layout or a comment; positions are found lazily, by offset, in `clause`.
        self.transformer.starts.append(token.end_pos)
        return token

    def _open(self, token: Token) -> Token:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise _TooDeep(token)
        return token

    def _close(self, token: Token) -> Token:
        self.depth = max(0, self.depth - 1)
        return token

    def _reset(self, text: str, file: str, offset: int, line_at: _LineIndex) -> None:
        self.transformer.file = file
        self.transformer.varmap = {}
        self.transformer.starts.clear()
        self.transformer.starts.append(offset)
        self.transformer.text = text
        self.transformer.line_at = line_at
        self.depth = 0

    def parse(self, text: str, file: str):
        with self.lock:
            self._reset(text, file, 0, _LineIndex(text))
            return self.lark.parse(text)

    def parse_clause(self, text: str, offset: int, file: str, line_at: _LineIndex) -> tuple[list, int]:
        """The items of the one clause from `offset` on (none if only layout is left) and
        the offset after its final "."; lark reads no further, so a later clause's errors
        are found when that clause is read."""
        with self.lock:
            self._reset(text, file, offset, line_at)
            interactive = self.lark.parse_interactive(TextSlice(text, offset, len(text)))
            try:
                for token in interactive.iter_parse():  # a token is fed when the loop goes on
                    if token.type == "END":
                        interactive.feed_token(token)
                        return interactive.feed_eof(token), token.end_pos
                return interactive.feed_eof(), len(text)
            except UnexpectedToken as err:
                # What lark's own parse does, so the error lists what a term may continue with.
                if err.interactive_parser is None:
                    err.interactive_parser = interactive
                raise


@functools.lru_cache(maxsize=None)
def _reader(start: str) -> _Reader:
    return _Reader(start)


# What a Prolog user calls the grammar's terminals (grammar/schemalog.lark), for the
# "expected ..." of a syntax error; any terminal a term can begin with is "a term".
_TERM_STARTS = frozenset({"NAME", "QATOM", "SYMATOM", "VAR", "INT", "FLOAT", "STRING", "FUNCTOR",
                          "SYMFUNCTOR", "PREFIX", "LPAR", "LSQB", "LBRACE"})
_EXPECTED_NAMES = {
    "END": "'.' (end of clause)", "RPAR": "')'", "RSQB": "']'", "RBRACE": "'}'",
    "COMMA": "','", "VBAR": "'|'", "INFIX": "an operator", "DOT": "an operator",
    "$END": "the end of the input",
}


def _expected_words(names) -> list[str]:
    """What a parser expecting the terminals `names` says it expected, a term first."""
    names = [n for n in names if not n.startswith("__")]
    words = sorted({_EXPECTED_NAMES.get(n, "a term" if n in _TERM_STARTS else n.lower()) for n in names}
                   - {"a term"})
    return (["a term"] if any(n in _TERM_STARTS for n in names) else []) + words


def _or(words: list[str]) -> str:
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " or " + words[-1]


def _describe_token(token: Token) -> str:
    if token.type == "$END":
        return "end of file"
    text = str(token)
    return repr(text) if len(text) < 40 else repr(text[:37] + "...")


def _source_line(text: str, line: int) -> str | None:
    lines = text.split("\n")  # lines as lark counts them: \f and \v do not end a line
    return lines[line - 1] if 0 < line <= len(lines) else None


def _module_colon(text: str, at: int) -> bool:
    """Whether the ':' at `at` qualifies a goal by its module (`lists:append(...)`, `m : g`): a
    ':' alone (not in a symbol run such as `::` or `:=`) right after a name, variable or bracket."""
    after = text[at + 1:at + 2]
    if text[at:at + 1] != ":" or (after and after in "+-*/\\^<>=~:?@#&$."):
        return False
    before = text[:at].rstrip()
    return bool(before) and (before[-1].isalnum() or before[-1] in "_)]}'\"")


def _error_from_lark(err: UnexpectedInput, text: str, file: str) -> SchemalogError:
    if isinstance(err, UnexpectedEOF) or isinstance(err, UnexpectedToken) and err.token.type == "$END":
        lines = text.rstrip("\n").split("\n")
        line, column = len(lines), len(lines[-1]) + 1
        message = "unexpected end of file: a clause is not finished (missing ')', ']' or the final '.'?)"
    elif isinstance(err, UnexpectedToken):
        line, column = err.line, err.column
        expected = _expected_words(err.accepts or err.expected)   # accepts: after reductions
        wanted = f"; expected {_or(expected)}" if expected else ""
        message = f"syntax error: unexpected {_describe_token(err.token)}{wanted}"
    elif isinstance(err, UnexpectedCharacters):
        line, column = err.line, err.column
        char = text[err.pos_in_stream] if err.pos_in_stream < len(text) else "?"
        if _module_colon(text, err.pos_in_stream):
            message = "syntax error: unexpected ':': modules are not supported (docs/queries.md)"
        elif text.startswith("=>", err.pos_in_stream) and text[err.pos_in_stream + 2:err.pos_in_stream + 3] not in \
                "+-*/\\^<>=~:?@#&$.":
            message = ("syntax error: unexpected '=>': SWI-Prolog's single-sided unification rules "
                       "(Head => Body) are not supported (docs/syntax.md); write Head :- Body")
        else:
            message = f"syntax error: unexpected character {char!r} (unknown operator or unbalanced quote?)"
    else:  # pragma: no cover - lark has no other UnexpectedInput kinds
        line, column, message = getattr(err, "line", 1), getattr(err, "column", 1), str(err)
    return SchemalogError(message, SourcePos(file, line, column), _source_line(text, line))


def _parse(text: str, file: str, start: str):
    return _lark_errors(text, file, lambda: _reader(start).parse(text, file))


def _lark_errors(text: str, file: str, parse):
    """`parse()`, its failures as SchemalogErrors at file:line:column."""
    try:
        return parse()
    except _TooDeep as deep:
        tok = deep.token
        raise SchemalogError(f"brackets nested deeper than {MAX_NESTING} levels",
                             SourcePos(file, tok.line, tok.column),
                             _source_line(text, tok.line)) from None
    except UnexpectedInput as err:
        raise _error_from_lark(err, text, file) from None
    except VisitError as err:  # a transformer callback failed, e.g. a bad character code
        if isinstance(err.orig_exc, SchemalogError):
            raise err.orig_exc from None
        raise SchemalogError(f"cannot read term: {err.orig_exc}", SourcePos(file, 1, 1)) from None


def lark_clause(text: str, offset: int, file: str, line_at: _LineIndex) -> tuple[list, int]:
    """The clause (or nothing but layout) lark reads in `text` from `offset`, and the offset
    after it: the fast reader's fallback, with lark's own errors and positions."""
    return _lark_errors(text, file, lambda: _reader("start").parse_clause(text, offset, file, line_at))


def parse_text_by_lark(text: str, file: str = "<string>") -> list[Clause | Directive]:
    """Parse program text with lark alone (what fastread.parse_text must agree with)."""
    return _parse(text, file, "start")


def parse_term(text: str, file: str = "<argument>") -> Term:
    """Parse one term (an optional final '.' is allowed)."""
    return _parse(text, file, "term_input")


def read_source(path: str | Path, max_bytes: int = MAX_BYTES) -> str:
    """Read a text file, refusing missing, oversized and binary files clearly."""
    name = str(path)
    if os.path.isdir(path):         # False for a name the system refuses: read_limited says why
        raise SchemalogError(f"{shown_name(name)}: is a directory, not a knowledge file")
    data = read_limited(path, max_bytes)
    nul = data.find(b"\0")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        column = nul - (data.rfind(b"\n", 0, nul) + 1) + 1
        raise SchemalogError("binary data (a NUL byte): not a text knowledge file",
                             SourcePos(name, line, column))
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data.count(b"\n", 0, err.start) + 1
        column = err.start - (data.rfind(b"\n", 0, err.start) + 1) + 1
        raise SchemalogError("not UTF-8 text (binary file?)", SourcePos(name, line, column)) from None
