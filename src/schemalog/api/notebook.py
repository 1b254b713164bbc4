"""How a Task, a Report and a Run show themselves in a notebook (Jupyter's _repr_*_ methods).

    task_svg(task)      the tree, coloured in the initial state; a compressed task beside its
                        original when both fit a notebook's width, else alone, its aliased
                        behaviours marked
    report_svg(report)  the compressed tree with a counterexample's steps numbered and the
                        behaviour that breaks soundness marked (None without a counterexample)
    run_svg(run)        the tree that ran, each behaviour numbered by the decisions that took it
    report_html, run_html: the text the command line prints, a headline, a table of decisions,
                        and the picture (when Graphviz is installed) as an image in the page

Pictures need Graphviz's `dot` on PATH, looked up at each call: without it every *_svg is None
and the HTML holds text only, so a notebook shows text instead of failing. Nothing here is
imported by `import schemalog`: the _repr_*_ methods import it when a notebook first asks.
"""

from __future__ import annotations

import html
import re
import shutil
from typing import TYPE_CHECKING, Iterable, Sequence

from ..errors import SchemalogError
from ..logic.terms import Term, term_to_text

if TYPE_CHECKING:
    from ..task.tree import Behaviour
    from .execution import Run
    from .report import Report
    from .task import Task

# A notebook's output area is about 960 pixels wide (JupyterLab, VS Code, the classic
# notebook with its prompt): 720 points at 96 pixels an inch. A wider picture is shrunk to
# fit it, and its 9-point conditions with it, so the first layout that fits is drawn.
NOTEBOOK_POINTS = 720
MARK_COLOUR = "#6a1b9a"      # the decision or step numbers written on behaviours
VERDICT_COLOURS = {"proved": "#2e7d32", "refuted": "#c62828", "vacuous": "#b26a00", "inconclusive": "#b26a00"}


def have_dot() -> bool:
    """Whether Graphviz's `dot` is on PATH now (a notebook's PATH can change while it runs)."""
    return shutil.which("dot") is not None


# -- pictures ---------------------------------------------------------------------------
def fitted_dot(name: str, panels: list, initial: frozenset | None, marks: dict[int, str] | None = None,
               width: float = NOTEBOOK_POINTS) -> tuple[str, float]:
    """The DOT of `panels` in the first layout (render.LAYOUTS) whose drawing is at most `width`
    points wide, else the narrowest; `marks` (pre-order index -> text) written on the first
    panel's behaviours. Also the drawing's width."""
    from ..formats.graphviz import drawing_size
    from ..formats.render import LAYOUTS, page_dot

    best: tuple[float, str] | None = None
    for layout in LAYOUTS:
        text = marked(page_dot(name, panels, initial, layout), panels, marks or {})
        drawn = drawing_size(text)[0]
        if drawn <= width:
            return text, drawn
        if best is None or drawn < best[0]:
            best = (drawn, text)
    assert best is not None
    return best[1], best[0]


def marked(dot: str, panels: list, marks: dict[int, str]) -> str:
    """`dot` with each text of `marks` written above the name of the first panel's behaviour at
    that pre-order index, in bold purple."""
    if not marks:
        return dot
    prefix = "p0_" if panels[0].title else "n"

    def mark(found: re.Match) -> str:
        text = html.escape(marks[int(found.group(2))], quote=False)
        return f'{found.group(1)}<font color="{MARK_COLOUR}"><b>{text}</b></font><br/>'

    wanted = "|".join(str(i) for i in sorted(marks))
    return re.sub(rf"^(\s*{re.escape(prefix)}({wanted}) \[label=<)", mark, dot, flags=re.M)


def svg_of(dot: str) -> str:
    from ..formats.graphviz import render

    return render(dot, "svg").decode("utf-8")


def task_dot(task: Task) -> str:
    """A task's picture for a notebook (see task_svg)."""
    from ..formats.render import Panel, aliased_behaviours

    if not task.compressed:
        return fitted_dot(task.name, [Panel("tree", f"{task.name}: {len(task)} behaviours, depth {task.depth}",
                                            task.tree)], task.initial_atoms())[0]
    original = task.original
    initial = original.initial_atoms()
    aliased, searched = aliased_behaviours(original.tree, task.tree, initial)
    figures = f", RD {task.compression.reduction_degree:.2f}" if task.compression else ""
    said = f", {len(aliased)} aliased" if aliased else ", no perceptual aliasing" + (
        "" if searched else " in the first 2,000 reachable states")
    merged = Panel("merged", f"{task.name}, {task.kind}: {len(task)} behaviours from {len(original)}{figures}"
                   f"{said}", task.tree, aliased)
    both = [Panel("original", f"{original.name}, original: {len(original)} behaviours", original.tree), merged]
    text, width = fitted_dot(task.name, both, initial)
    if width <= NOTEBOOK_POINTS:
        return text
    return fitted_dot(task.name, [merged], initial)[0]


def task_svg(task: Task) -> str | None:
    """The task drawn by Graphviz for a notebook, or None without `dot` (or when it fails)."""
    if not have_dot():
        return None
    try:
        return svg_of(task_dot(task))
    except SchemalogError:
        return None


def replayed(tree: Behaviour, original: Behaviour, initial: Iterable[Term],
             steps: Sequence[tuple[Term, Sequence[Term]]]) -> list[int | None]:
    """The pre-order index in `tree` of the behaviour each step took: a step is its winner's
    label and the actions it performed, replayed in the original's world from `initial`; among
    enabled behaviours of one label, the first in tree order. None where no enabled behaviour
    has the step's label (the replay is lost: every later step is None too)."""
    from ..run.execute import Plan, enabled_indices
    from ..run.world import World

    plan = Plan.of(tree)
    world = World(original)
    world.reset(initial)
    found: list[int | None] = []
    for label, actions in steps:
        candidates = [i for i in enabled_indices(plan, world.atoms) if plan.nodes[i].label == label]
        if not candidates:
            return found + [None] * (len(steps) - len(found))
        leaf = candidates[0]
        performed = set(actions)
        for action, post in plan.steps[leaf]:
            if action in performed:
                world.perform(post)
        found.append(leaf)
    return found


def numbered(indices: Iterable[int | None], word: str) -> dict[int, str]:
    """pre-order index -> `#1, #4`: the steps (from 1) that took each behaviour."""
    marks: dict[int, list[str]] = {}
    for k, i in enumerate(indices, 1):
        if i is not None:
            marks.setdefault(i, []).append(f"#{k}")
    return {i: f"{word} {', '.join(ks)}" for i, ks in marks.items()}


def report_dot(report: Report) -> str | None:
    """The compressed tree with the counterexample's steps numbered, the behaviour it takes
    last marked aliased (soundness); None without a counterexample or the tasks verified."""
    from ..formats.render import Panel

    properties = report.raw.properties
    ce = properties["soundness"].counterexample or properties["completion"].counterexample
    if ce is None or report.tasks is None:
        return None
    original, compressed = report.tasks
    steps = [(s.behaviour, s.actions) for s in ce.path]
    if ce.behaviour is not None:
        steps.append((ce.behaviour, ce.done_first))
    indices = replayed(compressed.tree, original.tree, ce.initial, steps)
    marks = numbered(indices[:len(ce.path)], "step")
    aliased: frozenset[int] = frozenset()
    if ce.behaviour is not None and indices and indices[-1] is not None:
        last = indices[-1]
        marks[last] = (marks[last] + ", then " if last in marks else "") + f"#{len(ce.path) + 1}: not allowed"
        aliased = frozenset({last})
    prop = "soundness" if ce.behaviour is not None else "completion"
    title = (f"{report.task}: counterexample to {prop} in the compressed tree ({report.how}), from "
             f"{', '.join(sorted(term_to_text(a) for a in ce.initial)) or 'nothing true'}")
    return fitted_dot(report.task, [Panel("compressed", title, compressed.tree, aliased)],
                      frozenset(ce.initial), marks)[0]


def report_svg(report: Report) -> str | None:
    if not have_dot():
        return None
    try:
        dot = report_dot(report)
        return None if dot is None else svg_of(dot)
    except SchemalogError:
        return None


def run_dot(run: Run) -> str:
    """The tree that ran, coloured in the initial state, each behaviour numbered by the
    decisions that took it (up to a decompression, which changes the tree)."""
    from ..formats.render import Panel
    from ..run.world import World

    ex = run.executive
    steps = []
    for d in ex.decisions:
        if d.decompressed:
            break
        steps.append((d.behaviour, d.executed))
    indices = replayed(ex.given_tree, run.task.original.tree, run.initial, steps)
    title = (f"{run.task.name}: run of the {run.task.kind} tree, {run.status} after "
             f"{plural(len(ex.decisions), 'decision')} (#k: the k-th decision took it)")
    initial = World(run.task.original.tree, run.initial).atoms
    return fitted_dot(run.task.name, [Panel("run", title, ex.given_tree)], initial, numbered(indices, "decision"))[0]


def run_svg(run: Run) -> str | None:
    if not have_dot():
        return None
    try:
        return svg_of(run_dot(run))
    except SchemalogError:
        return None


# -- pages ------------------------------------------------------------------------------
def image(svg: str | None) -> str:
    """An SVG as an <img> of the page (its ids cannot clash with another picture's)."""
    if svg is None:
        return ""
    import base64

    data = base64.b64encode(svg.encode("utf-8")).decode("ascii")
    return f'<div><img alt="picture" src="data:image/svg+xml;base64,{data}"/></div>'


def plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def pre(text: str) -> str:
    return f'<pre style="white-space: pre; overflow-x: auto">{html.escape(text)}</pre>'


def report_html(report: Report) -> str:
    """A headline with the verdict, the counterexample's picture, and the report as verify prints it."""
    verdict = report.verdict
    colour = VERDICT_COLOURS.get(verdict, "#333333")
    ce = report.counterexample
    head = (f'<p><b>verify {html.escape(report.task)}</b>: <b style="color: {colour}">{verdict}</b> '
            f"({html.escape(report.how)}; {report.nodes_before} behaviours, compressed "
            f"{report.nodes_after})")
    if ce is not None:
        steps = f"after {plural(len(ce.steps), 'step')}" if ce.steps else "at the start"
        head += (f" &mdash; counterexample to {ce.property} {steps}, from "
                 f"{html.escape(', '.join(ce.initial) or 'nothing true')}")
    parts = [head + "</p>", image(report_svg(report)) if ce is not None else ""]
    if report.notes:
        parts.append(pre("\n".join(report.notes)))
    parts.append(pre(report.text()))
    return "\n".join(p for p in parts if p)


def run_html(run: Run, summary: list[str]) -> str:
    """The run's header, a table of its decisions, how it ended (`summary`: execution's
    summary_lines, its status first; or how far it has gone), and its picture."""
    ex = run.executive
    colour = ("#333333" if not run.ended else
              VERDICT_COLOURS["proved"] if run.completed else VERDICT_COLOURS["refuted"])
    head = "<br/>".join(html.escape(line) for line in run.header())
    rows = []
    for d in ex.decisions:
        runner = "" if d.runner_up is None else f"{term_to_text(d.runner_up[0])} ({d.runner_up[1]:.4g})"
        actions = [*(f"{term_to_text(a)} (skipped)" for a in d.skipped), *map(term_to_text, d.executed),
                   *([f"{term_to_text(d.failed)} (FAILED)"] if d.failed is not None else [])]
        rows.append(f"<tr><td>{d.index}</td><td><b>{html.escape(term_to_text(d.behaviour))}</b></td>"
                    f"<td>{d.emphasis:.4g}</td><td>{html.escape(runner)}</td><td>{d.enabled}</td>"
                    f"<td>{html.escape(', '.join(actions))}</td></tr>")
    table = ('<table><thead><tr><th>#</th><th>winner</th><th>emphasis</th><th>runner-up (emphasis)</th>'
             '<th>enabled</th><th>actions</th></tr></thead><tbody>' + "".join(rows) + "</tbody></table>")
    parts = [f'<p>{head}<br/><b style="color: {colour}">{html.escape(summary[0])}</b></p>',
             image(run_svg(run)),
             f"<details{' open' if len(ex.decisions) <= 20 else ''}><summary>{plural(len(ex.decisions), 'decision')}"
             f"</summary>{table}</details>",
             pre("\n".join([*summary[1:], *run.notes]))]
    return "\n".join(p for p in parts if p)
