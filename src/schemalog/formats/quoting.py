"""Text that reaches a generated file: every name a task or a file name brings is embedded here.

    python_literal(value) -> str     Python source that evaluates to `value` (str, int, bool, tuples, lists)
    xml_attribute(text)   -> str     a quoted XML attribute value that reads back as `text`
    xml_comment(text)     -> str     <!-- ... --> holding a readable form of `text`

A Python literal is evaluated back (ast.literal_eval) before it is returned; an attribute holds
only characters XML 1.0 allows, the markup ones as references; a comment holds no `--` and no
unprintable character. What XML cannot hold at all raises Unquotable. Exporters embed names
through nothing else, and parse their whole document back before it is written (export_btcpp,
export_pytrees), so a name holding `\"\"\"`, `-->`, `--`, a newline, a NUL or a lone surrogate (a
non-UTF-8 file name) can neither run code nor break the file.
"""

from __future__ import annotations

import ast
import re
from xml.sax.saxutils import quoteattr

from ..errors import SchemalogError, readable_name

Literal = str | int | bool | float | None | tuple | list


class Unquotable(SchemalogError):
    """A value that the target language cannot hold exactly; the message says which and why."""


def python_literal(value: Literal) -> str:
    """Python source for `value`, checked to evaluate back to it (repr is not trusted blindly)."""
    text = repr(value)
    try:
        back = ast.literal_eval(text)
    except (ValueError, SyntaxError, MemoryError, RecursionError) as err:
        raise Unquotable(f"{type(value).__name__} value does not read back as a Python literal: {err}") from None
    if back != value or type(back) is not type(value):
        raise Unquotable(f"{type(value).__name__} value does not read back as a Python literal")
    return text


# XML 1.0 (section 2.2, Char) holds tab, newline, carriage return and U+0020 upwards, without
# surrogates and U+FFFE/U+FFFF; no character reference can stand for the others either.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def xml_attribute(text: str) -> str:
    """`text` as a quoted attribute value (quotes, <, &, tab and newlines as references)."""
    bad = _NOT_XML.search(text)
    if bad:
        raise Unquotable(f"{_character(text, bad.start())} cannot be written in XML 1.0 (it has no character "
                         f"reference either)")
    return quoteattr(text, {"\t": "&#9;", "\n": "&#10;", "\r": "&#13;"})


def _character(text: str, at: int) -> str:
    """The character at `at` as a message names it. A run of lone surrogates stands for bytes
    that are not UTF-8 (surrogateescape): `&#xD800;` decoded as tinyxml2 decodes it is the bytes
    ED A0 80, the UTF-8 form of the surrogate U+D800, which is named so, not as U+DCED."""
    if not 0xDC80 <= ord(text[at]) <= 0xDCFF:
        return f"U+{ord(text[at]):04X}"
    end = at
    while end < len(text) and 0xDC80 <= ord(text[end]) <= 0xDCFF:
        end += 1
    raw = text[at:end].encode("utf-8", "surrogateescape")
    try:
        code = ord(raw[:3].decode("utf-8", "surrogatepass"))
        return f"U+{code:04X} (a surrogate, no character)"
    except (UnicodeDecodeError, TypeError):
        return f"the byte{'s' if len(raw) > 1 else ''} {raw.hex(' ').upper()} (not UTF-8)"


def xml_comment(text: str) -> str:
    """A comment showing `text` readably; `--` (which XML forbids in comments) is split by spaces."""
    shown = readable_name(text)
    while "--" in shown:
        shown = shown.replace("--", "- -")
    return f"<!-- {shown} -->"


__all__ = ["python_literal", "xml_attribute", "xml_comment", "Unquotable", "Literal"]
