"""Files that ship with schemalog (grammar/, kb/): found in the installed package, or in
the source tree when running from a checkout."""

from __future__ import annotations

from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


def shipped_text(relative: str) -> str:
    """The text of a shipped file, e.g. `grammar/schemalog.lark` or `kb/compression.pl`."""
    packaged = PACKAGE / relative          # a wheel carries them inside the package
    if packaged.is_file():
        return packaged.read_text(encoding="utf-8")
    return (PACKAGE.parents[1] / relative).read_text(encoding="utf-8")
