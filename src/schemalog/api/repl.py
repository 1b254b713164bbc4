"""What the query top level asks of a workspace (api/workspace.py): opening one as `schemalog
query` and `schemalog repl` do (focused by --task, --compressed, --state, --scene), and what
the REPL's commands compute, as lines the command line prints (cli/session.py).

    open_workspace(files, ...)             -> Workspace
    tree_named(ws, text)                   -> (TaskView, kind)   :tree T, :run T, :verify T
    run_lines(ws, view, kind) / verify_lines(ws, view)           :run, :verify
    vocabulary(ws)                         -> the words Tab completes
"""

from __future__ import annotations

from typing import Iterable

from .. import defaults
from ..errors import SchemalogError, UsageError
from ..logic.terms import Term, term_to_text
from .workspace import COMPRESSED, Options, TaskView, Workspace


def open_workspace(files: Iterable[str], *, propagate: str = "full", max_bytes: int = defaults.MAX_BYTES,
                   max_depth: int = defaults.MAX_DEPTH, max_nodes: int = defaults.MAX_NODES,
                   max_steps: int = defaults.MAX_STEPS, sympy_budget: int = defaults.SYMPY_BUDGET,
                   scene: str | None = None, seed: int | None = None, jitter: float | None = None,
                   task: str | None = None, compressed: bool = False, state: str | None = None) -> Workspace:
    """The files as a query workspace, focused on `task` (default: the first), its compressed
    tree with `compressed`, in `state` (default: initial/1), its objects where `scene` puts them."""
    from ..run.scene import NO_SCENE

    from .arguments import atoms_option, scene_for_tree
    from .choosing import task_term

    options = Options(propagate=propagate, max_bytes=max_bytes, max_depth=max_depth, max_nodes=max_nodes,
                      max_steps=max_steps, sympy_budget=sympy_budget, scene=NO_SCENE)
    workspace = Workspace(list(files), options)
    if scene is not None:
        if workspace.focus is None:
            raise UsageError("--scene positions the objects of a task, and these files have none")
        found = scene_for_tree(workspace.focus.original, scene, seed, jitter, max_bytes)
        workspace.options = Options(**{**vars(options), "scene": found})
    if task is not None:
        workspace.set_focus(*workspace.find_tree(task_term(task)))
    if compressed:
        if workspace.focus is None:
            raise UsageError("--compressed needs a task: these files have none")
        workspace.set_focus(workspace.focus, COMPRESSED)
    if state is not None:
        workspace.set_state(atoms_option(state, "--state"))
    return workspace


def tree_named(ws: Workspace, text: str) -> tuple[TaskView, str]:
    """(view, kind) of a command's argument: a task or a root id; none: the focus."""
    from ..logic.opread import parse_term

    if not text:
        if ws.focus is None:
            raise SchemalogError("no task here: :load a task file first")
        return ws.focus, ws.kind
    try:
        term = parse_term(text, "<task>")
    except SchemalogError as e:
        raise SchemalogError(f"not a task: {e}") from None
    return ws.find_tree(term)


def task_name(view: TaskView) -> str:
    return term_to_text(view.task)


def tasks_line(ws: Workspace) -> str:
    """`tasks use(spoon), ...`, or `no tasks`."""
    if not ws.views:
        return "no tasks"
    return "tasks " + ", ".join(task_name(v) for v in ws.views)


def state_text(ws: Workspace) -> str:
    """The atoms true now, sorted, or `(nothing true)`."""
    return ", ".join(sorted(term_to_text(a) for a in ws.state)) or "(nothing true)"


def figures_line(view: TaskView) -> str:
    """`% Bi = 12, Bm = 6, D = 3, RD = 0.67`: the view's compression."""
    from ..task.tree import count_nodes, depth

    before, after = count_nodes(view.original), count_nodes(view.compressed)
    return f"% Bi = {before}, Bm = {after}, D = {depth(view.original)}, RD = {view.reduction_degree:.2f}"


def run_lines(ws: Workspace, view: TaskView, kind: str) -> list[str]:
    """Run `view`'s tree from the current state (kept as the run leaves it), each decision as
    `schemalog run` prints it, between a header and the outcome."""
    from .execution import decision_lines, decision_width

    ws.set_focus(view, kind)
    executive = ws.execute(view, kind, ws.state)
    lines = [f"% run {task_name(view)}, {kind} tree, from {state_text(ws)} "
             f"(as schemalog run: decision, winner, its emphasis e, runner-up, actions enabled)"]
    width = decision_width(view.tree(kind))
    for d in executive.decisions:
        lines.extend(decision_lines(d, width))
    ws.state = executive.world.atoms
    lines.append(f"% {executive.outcome.status.name.lower()}: {executive.outcome.reason}")
    return lines


def verify_lines(ws: Workspace, view: TaskView) -> list[str]:
    """Prove `view`'s compression from the files' initial state: the verdict, each property,
    and whether the task itself can complete."""
    from ..run.vacuity import verdict_term

    from .report import vacuity_lines

    report, vacuity = ws.verify(view)
    lines = [f"% {task_name(view)}: {term_to_text(verdict_term(report, vacuity))}, {explored_words(report)}"]
    lines.extend(f"%   {verdict.name}: {verdict.summary}" for verdict in report.properties.values())
    lines.extend(f"%   {line}" for line in "\n".join(vacuity_lines(vacuity)).splitlines())  # a lint cause has a fix: line
    return lines


def explored_words(report) -> str:
    """How much a proof looked at, in words: the states of each tree it explored (the original's
    only when it was explored on its own), how, and how long it took."""
    c, o = report.compressed_states, report.original_states
    states = f"{c:,} state{'' if c == 1 else 's'} of the compressed tree"
    if report.method == "symbolic":
        how = f"explored {states} as sets"
    elif o:
        how = f"explored {states} and {o:,} of the original"
    else:
        how = f"explored {states}"
    parts = f", in {report.parts} parts" if report.parts > 1 else ""
    return f"{how}{parts}, in {report.seconds:.2f} s"


def vocabulary(ws: Workspace) -> set[str]:
    """Predicate names (the files', built-in, relations) and the atoms of the files' clauses."""
    import re

    from ..logic.engine import BUILTINS, NONDET_BUILTINS
    from .workspace import RELATIONS

    words = {name for name, _ in ws.kb.predicates} | {name for name, _ in BUILTINS} | \
        {name for name, _ in NONDET_BUILTINS} | {name for name, _ in RELATIONS}
    for pred in ws.kb.predicates.values():
        for clause in pred.clauses[:2000]:      # atoms of the files' clauses, not of huge fact sets
            _atoms_of(clause.head, words)
    return {w for w in words if re.fullmatch(r"[a-z][A-Za-z0-9_]*", w)}


def _atoms_of(term: Term, out: set[str]) -> None:
    from ..logic.terms import Atom, Struct

    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, Atom):
            out.add(t.name)
        elif isinstance(t, Struct):
            out.add(t.name)
            stack.extend(t.args)
