"""Pictures of task trees: DOT text rendered to PNG, SVG or PDF by Graphviz's `dot` program.

    IMAGE_SUFFIXES          the suffixes rendered (.png, .svg, .pdf) -> dot's -T format
    REFUSED_SUFFIXES        other picture suffixes, refused rather than filled with text
    render(dot, fmt)        -> bytes: the picture, or a SchemalogError naming what is missing
    write_image(path, dot)  render, then write the bytes atomically (nothing is written on failure)

The picture is made in memory and written through documents.write_atomically, so a failed or
interrupted rendering leaves no file behind.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

from ..errors import READABLE, SchemalogError, UsageError
from .documents import write_atomically

IMAGE_SUFFIXES = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
# Names a person uses for pictures that schemalog does not make: refused, not written as text.
REFUSED_SUFFIXES = frozenset({".jpg", ".jpeg", ".gif", ".bmp", ".tif", ".tiff", ".webp", ".eps", ".ps"})
INSTALL_HINT = ("install Graphviz (Debian/Ubuntu: apt-get install graphviz; macOS: brew install graphviz), "
                "or write the DOT text with --format dot")


def image_format(path: str | None) -> str | None:
    """The picture format `path`'s suffix asks for (png, svg, pdf), or None."""
    if not path or path == "-":
        return None
    return IMAGE_SUFFIXES.get(Path(path).suffix.lower())


def refuse_unknown_picture(path: str | None) -> None:
    """Refuse a picture suffix that cannot be made (.jpg, .gif, ...) before any work is done:
    a wrong command line (exit 2), as `learn --plot` refuses one."""
    if path and path != "-" and Path(path).suffix.lower() in REFUSED_SUFFIXES:
        raise UsageError(f"{path}: cannot make a {Path(path).suffix.lower()[1:].upper()} picture; "
                             f"name the file .png, .svg or .pdf (rendered by Graphviz) or .dot")


def dot_program() -> str:
    """The path of Graphviz's `dot`, or a SchemalogError saying it is missing and how to get it."""
    found = shutil.which("dot")
    if found is None:
        raise SchemalogError(f"cannot draw a picture: Graphviz's `dot` program is not on PATH; {INSTALL_HINT}")
    return found


def render(dot: str, fmt: str) -> bytes:
    """The picture of `dot` in `fmt` (png, svg, pdf), rendered by `dot`."""
    program = dot_program()
    try:
        done = subprocess.run([program, f"-T{fmt}"], input=dot.encode("utf-8", READABLE), capture_output=True,
                              env={**os.environ, "LC_ALL": "C"})
    except OSError as err:
        raise SchemalogError(f"cannot run {program}: {err.strerror or err}") from None
    if done.returncode != 0 or not done.stdout:
        reason = done.stderr.decode("utf-8", "replace").strip().splitlines()
        raise SchemalogError(f"Graphviz's dot could not draw the picture (exit {done.returncode})"
                             + (f": {reason[-1]}" if reason else ""))
    return done.stdout


def write_image(path: str, dot: str, fmt: str) -> None:
    """Render `dot` as `fmt` and write it to `path` atomically."""
    write_atomically(path, render(dot, fmt))


__all__ = ["IMAGE_SUFFIXES", "REFUSED_SUFFIXES", "image_format", "refuse_unknown_picture", "dot_program",
           "render", "write_image"]
