"""Files that ship with schemalog (grammar/, kb/): found in the installed package, or in
the source tree when running from a checkout."""

from __future__ import annotations

from importlib import resources
from pathlib import Path


def shipped_text(relative: str) -> str:
    """The text of a shipped file, e.g. `grammar/schemalog.lark` or `kb/compression.pl`."""
    packaged = resources.files("schemalog").joinpath(relative)
    if packaged.is_file():
        return packaged.read_text(encoding="utf-8")
    return (Path(__file__).resolve().parents[2] / relative).read_text(encoding="utf-8")
