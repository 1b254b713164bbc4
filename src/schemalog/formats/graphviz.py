"""Pictures of task trees: DOT text rendered to PNG, SVG or PDF by Graphviz's `dot` program.

    IMAGE_SUFFIXES          the suffixes rendered (.png, .svg, .pdf) -> dot's -T format
    REFUSED_SUFFIXES        other picture suffixes, refused rather than filled with text
    render(dot, fmt)        -> bytes: the picture, or a SchemalogError naming what is missing
    write_image(path, dot)  render, then write the bytes atomically (nothing is written on failure)
    drawing_size(dot)       -> (width, height) in points of what `dot` lays out, its margin included
    screen_scale(w, h)      -> how much a picture of that size shrinks to fit a 1920x1080 screen

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


# A picture must be readable whole on this screen: shrunk to fit it (never enlarged), its
# smallest text at least READABLE_POINTS on a screen of SCREEN_DPI (12 pixels).
SCREEN = (1920, 1080)
SCREEN_DPI = 96            # also the resolution dot renders a PNG at
READABLE_POINTS = 9
PAD_POINTS = 8             # dot's margin around a drawing (pad, 4 points a side)


def drawing_size(dot: str) -> tuple[float, float]:
    """The width and height, in points, of the picture dot draws of `dot` (its margin included)."""
    program = dot_program()
    done = subprocess.run([program, "-Tplain"], input=dot.encode("utf-8", READABLE), capture_output=True,
                          env={**os.environ, "LC_ALL": "C"})
    first = done.stdout.decode("utf-8", "replace").split("\n", 1)[0].split()
    if done.returncode != 0 or len(first) < 4 or first[0] != "graph":
        reason = done.stderr.decode("utf-8", "replace").strip().splitlines()
        raise SchemalogError(f"Graphviz's dot could not lay out the picture (exit {done.returncode})"
                             + (f": {reason[-1]}" if reason else ""))
    scale = float(first[1])
    return float(first[2]) * scale * 72 + PAD_POINTS, float(first[3]) * scale * 72 + PAD_POINTS


def screen_scale(width: float, height: float) -> float:
    """The factor a picture `width` x `height` points large (as a PNG: SCREEN_DPI pixels an
    inch) is shrunk by to fit the SCREEN whole; 1 when it fits as it is."""
    pixels = SCREEN_DPI / 72
    return min(1.0, SCREEN[0] / (width * pixels), SCREEN[1] / (height * pixels))


def readable_on_screen(width: float, height: float, smallest: float) -> bool:
    """Whether text of `smallest` points stays READABLE_POINTS large when a picture of
    `width` x `height` points is shrunk to fit the SCREEN."""
    return smallest * screen_scale(width, height) >= READABLE_POINTS - 1e-9


def write_image(path: str, dot: str, fmt: str) -> None:
    """Render `dot` as `fmt` and write it to `path` atomically."""
    write_atomically(path, render(dot, fmt))


__all__ = ["IMAGE_SUFFIXES", "REFUSED_SUFFIXES", "image_format", "refuse_unknown_picture", "dot_program",
           "render", "write_image", "drawing_size", "screen_scale", "readable_on_screen", "SCREEN", "SCREEN_DPI",
           "READABLE_POINTS"]
