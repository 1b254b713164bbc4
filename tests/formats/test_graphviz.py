"""Pictures: `show`/`compress -o fig.png|.svg|.pdf` rendered by Graphviz, or refused.

These run the command line as a user does and read the files back: real PNG, SVG and PDF
bytes, sizes a person can read, the labels and the legend in the SVG's text, and the
refusals (no `dot` on PATH, a picture suffix that cannot be made) leaving no file behind.
"""

import os
import re
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
    for words in ("Legend", "enabled behaviour", "not enabled", "pre-condition, true",
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


def pictures_written(done, output) -> list:
    """The files a picture command says it wrote: `output`, and the pages it lists when split."""
    assert done.returncode == 0, done.stderr
    listed = [line.strip().split(": ", 1)[0] for line in done.stderr.splitlines() if line.startswith("  ")]
    return [output] + [type(output)(name) for name in listed]


def smallest_points(dot: str) -> float:
    """The smallest font size, in points, that a DOT text asks for."""
    return min(float(size) for size in re.findall(r'(?:fontsize=|point-size=")([0-9.]+)', dot))


def readable_on_a_screen(png, smallest: float) -> bool:
    """Whether a PNG (dot renders 96 pixels an inch) shrunk to fit 1920x1080, never enlarged,
    keeps text of `smallest` points at least 9 points (12 pixels) high."""
    width, height = png_size(png.read_bytes())
    scale = min(1.0, 1920 / width, 1080 / height)
    return smallest * 96 / 72 * scale >= 12


def test_every_picture_fits_a_screen_with_its_text_readable(tmp_path):
    generated = tmp_path / "t15.pl"
    assert run("generate", "--depth", 4, "--children", 2, "--rd", 0.5, "--seed", 1, "-o", generated).returncode == 0
    for command, source, pages in (("compress", MIX, 1), ("show", MIX, 1), ("show", COFFEE, 1),
                                   ("compress", COFFEE, 4), ("show", generated, 1), ("compress", generated, 1)):
        png = tmp_path / f"{command}-{source.stem}.png"
        done = run(command, source, "-o", png)
        written = pictures_written(done, png)
        assert len(written) == pages, (command, source, done.stderr)
        smallest = smallest_points(run(command, source, "--format", "dot").stdout)
        assert smallest >= 9
        for picture in written:
            assert readable_on_a_screen(picture, smallest), (command, source, picture, png_size(picture.read_bytes()))
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]    # no temporary file left


def test_a_drawing_a_screen_cannot_hold_is_split_into_an_overview_and_named_pictures(tmp_path):
    png, svg = tmp_path / "ct.png", tmp_path / "ct.svg"
    done = run("compress", COFFEE, "-o", png)
    assert "wrote " + str(png) + " (overview) and " + str(tmp_path / "ct-1.png") + " ... " in done.stderr
    written = pictures_written(done, png)
    assert [p.name for p in written] == ["ct.png", "ct-1.png", "ct-2.png", "ct-3.png"]
    assert f"{tmp_path / 'ct-1.png'}: (a) Learned symbolic representation: 63 behaviours" in done.stderr
    assert run("compress", COFFEE, "-o", svg).returncode == 0
    overview = svg.read_text().replace("&#45;", "-")
    assert ">preparecoffee<" in overview and ">36 below<" in overview and "whole in ct-1.svg" in overview
    learned = (tmp_path / "ct-1.svg").read_text()
    assert "a21(cup)" in learned and "Legend" in learned and "below:" not in learned
    big = tmp_path / "big.pl"                      # 364 behaviours: an overview, a picture per sub-task
    assert run("generate", "--depth", 5, "--children", 3, "--rd", 0.5, "--seed", 2, "-o", big).returncode == 0
    out = tmp_path / "big.png"
    done = run("show", big, "-o", out)
    written = pictures_written(done, out)
    assert len(written) > 3 and all(p.exists() for p in written)
    for picture in written:
        assert readable_on_a_screen(picture, 9), (picture, png_size(picture.read_bytes()))


def plain_positions(dot: str) -> dict[str, tuple[float, float]]:
    """Each node's centre as dot lays it out (-Tplain: inches, y upwards)."""
    out = subprocess.run(["dot", "-Tplain"], input=dot, capture_output=True, text=True, check=True).stdout
    return {f[1]: (float(f[2]), float(f[3])) for f in (line.split() for line in out.splitlines()) if f[0] == "node"}


def assert_children_in_order(tree, prefix: str, at: dict) -> None:
    """Each behaviour's children drawn in order: each next one right of or below the one before."""
    nodes = list(walk(tree))
    index = {id(n): i for i, n in enumerate(nodes)}
    for node in nodes:
        for a, b in zip(node.children, node.children[1:]):
            (xa, ya), (xb, yb) = at[f"{prefix}{index[id(a)]}"], at[f"{prefix}{index[id(b)]}"]
            assert xb > xa + 0.01 or yb < ya - 0.01, (node.name, a.name, b.name)


def test_children_and_panels_are_drawn_in_order():
    kb = document_from_text(COFFEE.read_text(), str(COFFEE)).to_kb()
    tree = instantiate(kb, parse_term("prepareboth"))
    dot = run("show", COFFEE, "--format", "dot").stdout
    at = plain_positions(dot)
    assert at["n1"][0] < at["n37"][0]              # preparecoffee, the first child, left of preparetea
    assert_children_in_order(tree, "n", at)
    figure = run("compress", COFFEE, "--format", "dot").stdout
    clusters = re.findall(r"subgraph (cluster_\w+)", figure)
    assert clusters == ["cluster_original", "cluster_aliased", "cluster_merged"]
    at = plain_positions(figure)
    assert at["p0_0"][0] < at["p1_0"][0] < at["p2_0"][0]   # (a), (b), (c) from the left
    assert_children_in_order(tree, "p0_", at)
    assert_children_in_order(compress(tree, "full").tree, "p2_", at)


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


# -- the legend says what is drawn (issue 45) -------------------------------------------------------
ACTIVE, INACTIVE = "#2e7d32", "#8d6e63"          # render.py's green and brown


def _svg_nodes(svg_text: str) -> dict[str, dict]:
    """Each drawn behaviour of an SVG by its DOT id (p0_6): its label, outline colour, the colour
    of its pre-condition's text, and its box in the SVG's user units."""
    import xml.etree.ElementTree as ET

    ns = {"s": "http://www.w3.org/2000/svg"}
    root = ET.fromstring(svg_text)
    nodes = {}
    for group in root.iter("{http://www.w3.org/2000/svg}g"):
        if group.get("class") != "node":
            continue
        name = group.find("s:title", ns).text
        texts = group.findall("s:text", ns)
        shapes = [e for e in group if e.tag.split("}")[1] in ("path", "ellipse", "polygon") and e.get("stroke")]
        if not texts or not shapes:
            continue                              # the comb's joints
        numbers = [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?", shapes[0].get("d") or shapes[0].get("points") or "")]
        xs, ys = numbers[0::2], numbers[1::2]
        nodes[name] = {"label": texts[0].text, "outline": shapes[0].get("stroke"),
                       "pre": texts[1].get("fill") if len(texts) > 1 else None,
                       "box": (min(xs), min(ys), max(xs), max(ys))}
    return nodes


def test_the_legend_says_what_the_outlines_show_and_the_picture_shows_it(tmp_path):
    """Issue 45: the legend called a green outline "pre-condition holds, post-condition does
    not", but the picture draws the paper's Fig. 2 rule, in which a3(cup) (pre-condition `true`,
    under subtask(mix,spoon), not released) is outlined brown. The legend now says enabled: active,
    and so is every behaviour above it. Read off the rendered SVG and PNG, not the DOT text."""
    import matplotlib.image

    svg, png = tmp_path / "fig2.svg", tmp_path / "fig2.png"
    assert run("compress", MIX, "-o", svg).returncode == 0
    assert run("compress", MIX, "-o", png).returncode == 0
    text = svg.read_text()
    legend = re.sub(r"\s+", " ", " ".join(re.findall(r">([^<>]+)</text>", text))).replace("&#45;", "-")
    assert ("enabled behaviour: active (its pre-condition holds, its post-condition does not), and so is "
            "every behaviour above it") in legend
    assert "not enabled: it or a behaviour above it is not active" in legend
    # every outline in panel (a) is what the legend says, in the initial state
    tree = instantiate(document_from_text(MIX.read_text(), str(MIX)).to_kb(), parse_term("use(spoon)"))
    state = World(tree, initial_state(document_from_text(MIX.read_text(), str(MIX)).to_kb())).atoms
    from schemalog.task import conditions as cond

    nodes = _svg_nodes(text)
    enabled, stack = [], [(tree, True)]
    while stack:                                  # pre-order, as the picture numbers p0_0, p0_1, ...
        node, above = stack.pop()
        on = above and cond.holds(node.pre, state) and not cond.holds(node.post, state)
        enabled.append((node, on))
        stack.extend((child, on) for child in reversed(node.children))
    for i, (node, on) in enumerate(enabled):
        drawn = nodes[f"p0_{i}"]
        assert drawn["outline"] == (ACTIVE if on else INACTIVE), (i, drawn)
        assert drawn["pre"] == (ACTIVE if cond.holds(node.pre, state) else INACTIVE), (i, drawn)
    a3 = next(d for d in nodes.values() if d["label"] == "a3(cup)")
    assert (a3["outline"], a3["pre"]) == (INACTIVE, ACTIVE)      # green text in a brown outline
    # and the PNG: the pixels of a3(cup)'s outline are brown, those of its `true` green
    pixels = matplotlib.image.imread(str(png))[..., :3]
    width = float(re.search(r'viewBox="[\d.]+ [\d.]+ ([\d.]+)', text).group(1))
    scale = pixels.shape[1] / width
    tx, ty = (float(v) for v in re.search(r'translate\(([\d.-]+) ([\d.-]+)\)', text).groups())
    x0, y0, x1, y1 = a3["box"]
    left, top, right, bottom = ((x0 + tx) * scale, (y0 + ty) * scale, (x1 + tx) * scale, (y1 + ty) * scale)

    def near(colour: str, region) -> int:
        rgb = [int(colour[k:k + 2], 16) / 255 for k in (1, 3, 5)]
        return int((abs(region - rgb).sum(axis=-1) < 0.12).sum())

    border = pixels[int(top) + 4:int(bottom) - 4, max(0, int(left) - 3):int(left) + 4]   # the left side
    assert near(INACTIVE, border) > 10 and near(ACTIVE, border) == 0
    inside = pixels[int(top) + 3:int(bottom) - 3, int(left) + 4:int(right) - 4]
    assert near(ACTIVE, inside) > 5                                                       # its `true`
