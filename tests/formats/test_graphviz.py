"""Pictures: `show`/`compress -o fig.png|.svg|.pdf` rendered by Graphviz, or refused.

These run the command line as a user does and read the files back: real PNG, SVG and PDF
bytes, sizes a person can read, the labels and the legend in the SVG's text, and the
refusals (no `dot` on PATH, a picture suffix that cannot be made) leaving no file behind.
"""

import os
import struct
import subprocess
import sys

from conftest import COFFEE, MIX, ROOT

from schemalog.formats.documents import document_from_text
from schemalog.formats.render import aliased_behaviours
from schemalog.logic.parse import parse_term
from schemalog.run.world import World, initial_state
from schemalog.task.compress import compress
from schemalog.task.tree import instantiate, walk

PNG = b"\x89PNG\r\n\x1a\n"


def run(*args, env=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=120, env=env)


def png_size(data: bytes) -> tuple[int, int]:
    assert data.startswith(PNG) and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def test_compress_draws_figure_2_in_three_panels_with_a_legend(tmp_path):
    svg = tmp_path / "fig2.svg"
    done = run("compress", MIX, "-o", svg)
    assert done.returncode == 0, done.stderr
    text = svg.read_text().replace("&#45;", "-")      # SVG writes a hyphen as &#45;
    assert text.lstrip().startswith("<?xml") and "<svg" in text
    assert "(a) Learned symbolic representation: 12 behaviours" in text
    assert "(b) Merged with perceptual aliasing (propagate none): 6 behaviours, 1 aliased" in text
    assert "(c) Merged Symbolic Representation (propagate full): 6 behaviours, no perceptual aliasing" in text
    assert text.count("a3_a4_a5_a6_a7(cup)") == 2 and text.count("k=5") == 2      # panels (b) and (c)
    assert text.count(">aliased<") == 2           # the marked behaviour and the legend's sample
    for words in ("Legend", "active behaviour", "inactive behaviour", "pre-condition, true",
                  "pre-condition, false", "post-condition", "merged behaviour standing", "perceptual aliasing"):
        assert words in text, words
    assert "hand.free" in text                     # the initial state the colours are drawn in


def test_png_and_pdf_are_real_pictures_of_a_readable_size(tmp_path):
    png, pdf = tmp_path / "fig2.png", tmp_path / "fig2.pdf"
    assert run("compress", MIX, "-o", png).returncode == 0
    width, height = png_size(png.read_bytes())
    assert 1000 < width < 6000 and 200 < height < 1500
    assert run("compress", MIX, "-o", pdf).returncode == 0
    assert pdf.read_bytes().startswith(b"%PDF-")
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]    # no temporary file left


def test_a_large_task_is_drawn_left_to_right_a_cluster_per_sub_task(tmp_path):
    png, svg = tmp_path / "ct.png", tmp_path / "ct.svg"
    assert run("compress", COFFEE, "-o", png).returncode == 0
    width, height = png_size(png.read_bytes())
    assert width < 2500 < height                   # not 17,264 pixels wide: the tree reads downwards
    assert run("show", COFFEE, "-o", svg).returncode == 0
    text = svg.read_text().replace("&#45;", "-")      # SVG writes a hyphen as &#45;
    assert ">preparecoffee<" in text and ">preparetea<" in text            # the sub-tasks' clusters
    assert "a21(cup)" in text and "Legend" in text


def test_show_draws_one_tree_coloured_in_the_initial_state(tmp_path):
    svg = tmp_path / "mix.svg"
    assert run("show", MIX, "-o", svg).returncode == 0
    text = svg.read_text().replace("&#45;", "-")      # SVG writes a hyphen as &#45;
    assert "subtask(take,spoon)" in text and "gripper(close)" in text and "Legend" in text
    dot = run("show", MIX, "--format", "dot").stdout          # the same drawing as DOT text
    assert dot.startswith("digraph") and "Legend" in dot


def test_without_dot_a_picture_is_refused_naming_the_program(tmp_path):
    empty = tmp_path / "bin"
    empty.mkdir()
    for command in ("show", "compress"):
        target = tmp_path / f"{command}.png"
        done = run(command, MIX, "-o", target, env={**os.environ, "PATH": str(empty)})
        assert done.returncode == 1 and "Traceback" not in done.stderr
        assert "`dot`" in done.stderr and "Graphviz" in done.stderr and "apt-get install graphviz" in done.stderr
        assert not target.exists() and list(tmp_path.iterdir()) == [empty]
    text = run("compress", MIX, "-o", tmp_path / "fig.dot", env={**os.environ, "PATH": str(empty)})
    assert text.returncode == 0 and (tmp_path / "fig.dot").read_text().startswith("digraph")


def test_a_picture_suffix_that_cannot_be_made_is_refused_and_other_suffixes_get_text(tmp_path):
    jpg = tmp_path / "fig.jpg"
    done = run("show", MIX, "-o", jpg)
    assert done.returncode == 2 and ".png, .svg or .pdf" in done.stderr and not jpg.exists()
    txt = tmp_path / "tree.txt"
    assert run("show", MIX, "-o", txt).returncode == 0
    assert "use(spoon): 12 behaviours, depth 3" in txt.read_text()


def test_perceptual_aliasing_is_found_without_propagation_and_not_with_it():
    kb = document_from_text(MIX.read_text(), str(MIX)).to_kb()
    tree = instantiate(kb, parse_term("use(spoon)"))
    initial = World(tree, initial_state(kb)).atoms
    none = compress(tree, "none").tree
    marked, complete = aliased_behaviours(tree, none, initial)
    nodes = list(walk(none))
    assert complete and [nodes[i].name for i in sorted(marked)] == ["a3_a4_a5_a6_a7(cup)"]
    assert aliased_behaviours(tree, compress(tree, "full").tree, initial) == (frozenset(), True)
