"""Figures of a benchmark run, in the layout of the paper's Figures 3 and 4 (matplotlib).

    figure4(results, out)            execution time against RD, a panel per depth, a line per branching
    selectors_by_size(results, out)  time per decision against behaviours: scan, incremental, py_trees
    figure3(out)                     a generated tree (depth 4, 2 children, RD 0.5) and its merged form
    demonstration_figure(lesson, p)  a learned demonstration: segments, objects, merged primitives

Each figure is written as PNG and SVG, atomically (a temporary file renamed into place).
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")   # files only: no display is needed, or wanted, on a CI machine

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
from matplotlib.text import Text  # noqa: E402

from ..task.compress import compress  # noqa: E402
from ..formats.documents import write_atomically, write_in_folder  # noqa: E402
from .generate import generate  # noqa: E402
from ..formats.render import compare_dot  # noqa: E402
from ..logic.terms import term_to_text  # noqa: E402
from ..task.tree import Behaviour  # noqa: E402

FORMATS = ("png", "svg")
COLOURS = {2: "#1f77b4", 3: "#d62728", 4: "#e6a000"}
DPI = 150
# A figure is at most this wide, so that at DPI it fits a 1920-pixel screen (1860 px, with room
# for what bbox_inches="tight" keeps around the axes).
MAX_INCHES = 12.4


def save(fig, out: Path, stem: str) -> list[Path]:
    """Write `fig` as stem.png and stem.svg in `out`, each atomically."""
    written = [_write(fig, out / f"{stem}.{fmt}") for fmt in FORMATS]
    plt.close(fig)
    return written


def _write(fig, target: Path) -> Path:
    """Write `fig` to `target` atomically, in the format of its suffix (write_in_folder)."""
    fmt = target.suffix.lstrip(".").lower() or "png"
    return write_in_folder(target, lambda handle: fig.savefig(handle, format=fmt, dpi=DPI, bbox_inches="tight"))


def _log_axis(ax, which: str) -> None:
    """A log scale labelled with plain numbers (0.5, 20, 1,000), not powers of ten."""
    getattr(ax, f"set_{which}scale")("log")
    axis = ax.xaxis if which == "x" else ax.yaxis
    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:,.10g}"))
    axis.set_minor_formatter(ticker.NullFormatter())


def figure4(results, out: Path) -> list[Path]:
    """Fig. 4: time per run against RD, one panel per depth, one line per branching; the scan
    selector (the paper's cost model) on top, the incremental selector below."""
    fig = figure4_figure(results)
    return [] if fig is None else save(fig, out, "figure4")


def figure4_figure(results):
    """The matplotlib figure of figure4, each panel's legend under it (never over a point);
    None without cells."""
    cells = results.cells
    depths = sorted({c.depth for c in cells})
    if not depths:
        return None
    fig, axes = plt.subplots(2, len(depths), figsize=(min(4.4 * len(depths), MAX_INCHES), 7.6), squeeze=False,
                             layout="constrained")
    for row, selector in enumerate(("scan", "incremental")):
        for col, depth in enumerate(depths):
            ax = axes[row][col]
            for children in sorted({c.children for c in cells if c.depth == depth}):
                line = sorted((c for c in cells if c.depth == depth and c.children == children),
                              key=lambda c: c.rd_asked)
                xs = [c.rd_got for c in line]
                ys = [(c.timing("compressed", selector).ms_per_run if c.rd_asked else
                       c.timing("original", selector).ms_per_run) for c in line]
                ax.plot(xs, ys, marker="o", color=COLOURS.get(children),
                        label=f"{children} children ({line[0].behaviours:,} behaviours)")
            _log_axis(ax, "y")
            ax.set_xlim(-0.03, 0.78)
            ax.grid(True, which="both", alpha=0.3)
            ax.set_title(f"({chr(ord('a') + row * len(depths) + col)}) D = {depth}, {selector} selector",
                         fontsize=10)
            ax.set_xlabel("reduction degree (achieved)")
            if col == 0:
                ax.set_ylabel("execution time per run (ms)")
            # Below the axes: inside, it hid the points of 4 children (panels b and e).
            ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), frameon=False)
    fig.suptitle("Execution time against the reduction degree (the paper's Fig. 4; "
                 f"{results.plan.runs} runs per tree)", fontsize=11)
    return fig


def selectors_by_size(results, out: Path) -> list[Path]:
    """Time per decision against the number of behaviours, original trees: the paper's scan,
    the incremental selector, and a py_trees tick of the same tree."""
    points: dict[str, list[tuple[int, float]]] = {"scan": [], "incremental": [], "py_trees": []}
    for c in results.cells:
        if c.rd_asked == 0.0:
            for selector in points:
                value = c.timing("original", selector).us_per_decision
                if not math.isnan(value):
                    points[selector].append((c.behaviours, value))
    for r in results.sizes:
        points["incremental"].append((r.behaviours, r.incremental_us))
        points["scan"].append((r.behaviours, r.scan_us))
        if not math.isnan(r.py_trees_us):
            points["py_trees"].append((r.behaviours, r.py_trees_us))
    if not any(points.values()):    # no original tree timed (no RD 0 cell, no sizes): no figure, not an empty one
        return []
    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    styles = {"scan": ("#d62728", "scan selector (every behaviour, every decision)"),
              "incremental": ("#2ca02c", "incremental selector"),
              "py_trees": ("#7f7f7f", "py_trees: one tick of the same tree")}
    for selector, series in points.items():
        if not series:
            continue
        best: dict[int, float] = {}
        for size, value in series:       # one point per size: the grid's RD 0 cell or the size row
            best[size] = min(value, best.get(size, value))
        xs = sorted(best)
        colour, label = styles[selector]
        ax.plot(xs, [best[x] for x in xs], marker="o", color=colour, label=label)
    _log_axis(ax, "x")
    _log_axis(ax, "y")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_xlabel("behaviours in the task tree")
    ax.set_ylabel("time per decision (us)")
    ax.set_title("Selecting the next action: cost against tree size", fontsize=11)
    ax.legend(fontsize=8)
    return save(fig, out, "selectors")


def _layout(root: Behaviour) -> tuple[list[tuple[float, int, Behaviour]], list[tuple[int, int]]]:
    """Positions for a tidy drawing: leaves left to right, a parent centred over its children."""
    nodes: list[tuple[float, int, Behaviour]] = []
    edges: list[tuple[int, int]] = []
    next_leaf = [0.0]

    def place(node: Behaviour, level: int) -> int:
        index = len(nodes)
        nodes.append((0.0, level, node))
        kids = [place(c, level + 1) for c in node.children]
        if kids:
            x = (nodes[kids[0]][0] + nodes[kids[-1]][0]) / 2
            edges.extend((index, k) for k in kids)
        else:
            x = next_leaf[0]
            next_leaf[0] += 1.0
        nodes[index] = (x, level, node)
        return index

    place(root, 0)
    return nodes, edges


def _draw_tree(ax, root: Behaviour, title: str) -> None:
    nodes, edges = _layout(root)
    for a, b in edges:
        ax.plot([nodes[a][0], nodes[b][0]], [-nodes[a][1], -nodes[b][1]], color="#888888", lw=0.8, zorder=1)
    for x, level, node in nodes:
        merged = len(node.origins) > 1
        name = term_to_text(node.label)
        ax.text(x, -level, name.replace("_", "_\n") if merged and len(name) > 10 else name,
                ha="center", va="center", fontsize=6.5, zorder=2,
                bbox=dict(boxstyle="round,pad=0.25", fc="#ffe9a8" if merged else "#dbe9f6",
                          ec="#b8860b" if merged else "#4a7ab0", lw=0.8))
    width = max((x for x, _, _ in nodes), default=0)
    ax.set_xlim(-0.8, width + 0.8)
    ax.set_ylim(-max(level for _, level, _ in nodes) - 0.6, 0.6)
    ax.set_title(title, fontsize=10)
    ax.axis("off")


def figure3(out: Path, depth: int = 4, children: int = 2, rd: float = 0.5, seed: int = 1) -> list[Path]:
    """Fig. 3: a generated tree (top) and the merged tree (bottom), as DOT and as pictures."""
    tree = generate(depth, children, rd, seed)
    result = compress(tree)
    written = []
    dot = out / "figure3.dot"
    write_in_folder(dot, compare_dot(result.original, result.tree, "figure3", result.propagate))
    written.append(dot)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), layout="constrained")
    _draw_tree(top, result.original, f"Generated: depth {depth}, {children} children, RD {rd:g} asked "
                                     f"({result.nodes_before} behaviours)")
    _draw_tree(bottom, result.tree, f"Merged by Algorithm 1: {result.nodes_after} behaviours, "
                                    f"RD = {result.reduction_degree:.2f} (merged behaviours in yellow)")
    return written + save(fig, out, "figure3")


__all__ = ["figure4", "figure4_figure", "selectors_by_size", "figure3", "save", "demonstration_figure",
           "demonstration_plot", "place_apart", "stack_apart"]


def demonstration_figure(lesson, path: Path) -> Path:
    """Write demonstration_plot's figure atomically, in the format of `path`'s suffix."""
    fig = demonstration_plot(lesson)
    try:
        # a -o style output, not a folder's file: written as -o writes (through a link, into a FIFO)
        picture = io.BytesIO()
        fig.savefig(picture, format=Path(path).suffix.lstrip(".").lower() or "png", dpi=DPI, bbox_inches="tight")
        write_atomically(path, picture.getvalue())
        return Path(path)
    finally:
        plt.close(fig)


def place_apart(fig, ax, labels, fixed=()) -> None:
    """Move each annotation of `labels` (offset in points from its point) to the nearest offset
    where its box overlaps neither a label placed before it nor a text of `fixed`, inside
    `ax`; then keep the layout as it is, so that saving does not move them again."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    points = fig.dpi / 72

    def text_box(t):                  # the text alone, not its leader line, a point of white around it
        return Text.get_window_extent(t, renderer).padded(points)

    taken = [text_box(t) for t in fixed]
    offsets = sorted(((dx, dy) for dx in range(-60, 61, 10) for dy in range(-120, 121, 4)),
                     key=lambda o: (math.hypot(o[0], o[1] * 1.5), o[1] > 0))
    for label in labels:
        box = text_box(label)
        x, y = label.xyann
        for dx, dy in offsets:
            moved = box.translated(dx * points, dy * points)
            inside = (frame.x0 <= moved.x0 and moved.x1 <= frame.x1 and frame.y0 <= moved.y0
                      and moved.y1 <= frame.y1)
            if inside and not any(moved.overlaps(t) for t in taken):
                label.xyann = (x + dx, y + dy)
                box = moved
                break
        taken.append(box)
    fig.set_layout_engine("none")


def demonstration_plot(lesson):
    """A demonstration, segmented and learned: (left) the hand's path seen from above, a colour
    per action, the objects with their proximity circles, the labels placed apart; (middle) the
    hand's height over time, the segments shaded and labelled; (right) each merged action's
    demonstrated path against its merged primitive's reproduction."""
    from ..learn.primitives import rollout

    demo = lesson.demo
    labelled = {}
    for step in lesson.teaching.steps:
        labelled[id(step.segment)] = term_to_text(getattr(step, "label", None) or step.action)
    motions = [s for s in lesson.segments if s.kind == "motion"]
    colours = plt.get_cmap("tab20")
    merged = lesson.motions.merged if lesson.motions is not None else ()
    # The path from above and the merged primitives side by side, the height over time under
    # them, the whole width: at most MAX_INCHES wide (three panels in a row were 2,806 px).
    fig = plt.figure(figsize=(MAX_INCHES, 10.4), layout="constrained")
    grid = fig.add_gridspec(2, 2 if merged else 1, height_ratios=(3, 2))
    top = fig.add_subplot(grid[0, 0])
    height = fig.add_subplot(grid[1, :])
    steps = []
    p = demo.positions
    labels, names = [], []
    for k, seg in enumerate(motions):
        colour = colours(k % 20)
        part = p[seg.start:seg.end + 1]
        name = labelled.get(id(seg), term_to_text(seg.label))
        top.plot(part[:, 0], part[:, 1], color=colour, linewidth=1.4)
        # Placed apart at the end (place_apart): five pours end at the cup.
        labels.append(top.annotate(name, part[-1, :2], fontsize=7, color=colour, xytext=(4, 4),
                                   textcoords="offset points", va="bottom",
                                   arrowprops=dict(arrowstyle="-", color=colour, linewidth=0.5, shrinkA=0,
                                                   shrinkB=0),
                                   bbox=dict(boxstyle="square,pad=0.05", fc="white", ec="none", alpha=0.75)))
        height.axvspan(demo.times[seg.start], demo.times[seg.end], color=colour, alpha=0.18, linewidth=0)
        steps.append(height.annotate(name, ((demo.times[seg.start] + demo.times[seg.end]) / 2, 1.0),
                                     xycoords=height.get_xaxis_transform(), xytext=(0, -2),
                                     textcoords="offset points", rotation=90, fontsize=7, ha="center", va="top"))
    height.plot(demo.times, p[:, 2], color="black", linewidth=0.9)
    for seg in lesson.segments:
        if seg.kind == "gripper":
            closing = seg.label.args[0].name == "close"
            marker = "v" if closing else "^"
            top.plot(p[seg.start, 0], p[seg.start, 1], marker=marker, color="black", markersize=6)
            height.plot(demo.times[seg.start], p[seg.start, 2], marker=marker, color="black", markersize=6)
    for name, track in sorted(demo.objects.items()):
        start = track[0]
        top.add_patch(plt.Circle(start[:2], lesson.radius, fill=False, linestyle="--", linewidth=0.8, color="grey"))
        top.plot(start[0], start[1], "s", color="grey", markersize=5)
        names.append(top.annotate(name, start[:2], fontsize=8, xytext=(4, -10), textcoords="offset points"))
        if np.ptp(track, axis=0).max() > 1e-6:
            top.plot(track[:, 0], track[:, 1], color="grey", linewidth=0.6, linestyle=":")
    top.set_aspect("equal", adjustable="datalim")
    top.set(xlabel="x (m)", ylabel="y (m)",
            title=f"{demo.file}: {len(motions)} motions (v close, ^ open)")
    height.set(xlabel="time (s)", ylabel="z (m)", title="height of the hand; segments shaded")
    if merged:
        ax = fig.add_subplot(grid[0, 1])
        for k, m in enumerate(merged):
            colour = colours((2 * k) % 20)
            ax.plot(m.poses[:, 0], m.poses[:, 1], color="grey", linewidth=2.5, alpha=0.5)
            out = rollout(m.dmp, m.times)
            ax.plot(out[:, 0], out[:, 1], color=colour, linewidth=1.2, linestyle="--",
                    label=f"{term_to_text(m.label)}: RMS {m.error.rms * 1000:.1f} mm")
        ax.set_aspect("equal", adjustable="datalim")
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
        ax.set(xlabel="x (m)", ylabel="y (m)", title="merged primitives (dashed) over the demonstration (grey)")
    place_apart(fig, top, labels, names)
    stack_apart(fig, steps)
    return fig


def stack_apart(fig, labels) -> None:
    """Move each label of `labels` (annotations hanging from the top of their axes, in order
    along it) down, in steps of 2 points, until it overlaps no label before it: segments shorter
    than their label's width (a4, a5, a6 at the cup) get a staircase instead of one blot."""
    renderer = fig.canvas.get_renderer()
    points = fig.dpi / 72
    taken = []
    for label in labels:
        box = Text.get_window_extent(label, renderer)
        x, y = label.xyann
        shift = 0
        while shift < 300 and any(box.translated(0, -shift * points).overlaps(t) for t in taken):
            shift += 2
        label.xyann = (x, y - shift)
        taken.append(box.translated(0, -shift * points))
