"""Task trees as Python modules that build them with py_trees 2.x, and runs of those modules.

    export_pytrees(tree, initial, title) -> str      the module's source
    load_module(source)                  -> module   with create_tree(holds, perform) and run(...)
    run_pytrees(source, original, initial) -> BtRun  ticked against the World of `original`

The module holds the tree as data (NODES: one tuple (name, pre, post, steps, children) per
behaviour, the root first, children as indices into NODES, so that no depth of tree nests the
source deeper than Python's parser allows; conditions as ("lit", "hand.free"), ("not", c),
("and", ...), ("or", ...), True, False) and builds it from py_trees' own composites: every
behaviour is a Sequence(memory=False) of an `Active` guard (its pre-condition holds and its
post-condition does not) and either a Selector(memory=False) over its children or, for a leaf,
an `Act` that performs its actions, skipping those already accomplished. A behaviour returns SUCCESS exactly when it acted, so a
Selector stops at the first child that acted: one tick is one decision, the first enabled
leaf in tree order, the same order as the BT.CPP export (docs/formats.md).

Every name (the task's, a behaviour's, an atom's, the files') is embedded as a Python literal
through formats.quoting, and the module is parsed back before it is returned: its data must
evaluate to exactly what was meant, or the export is refused (Unquotable).
"""

from __future__ import annotations

import types

from .. import defaults
from ..logic.terms import Term, term_to_text
from ..task import conditions as cond
from ..task.conditions import Condition
from ..task.tree import Behaviour, depth, walk
from .btcpp import BtRun, steps_of
from .quoting import Unquotable, python_literal

_RUNTIME = '''
import contextlib
import sys

import py_trees
from py_trees.common import Status


def compile_condition(c, holds):
    """A function of no arguments that tells whether condition `c` holds now."""
    if c is True or c is False:
        return (lambda: True) if c else (lambda: False)
    kind = c[0]
    if kind == "lit":
        atom = c[1]
        return lambda: holds(atom)
    parts = [compile_condition(p, holds) for p in c[1:]]
    if kind == "not":
        inner = parts[0]
        return lambda: not inner()
    if kind == "and":
        return lambda: all(p() for p in parts)
    return lambda: any(p() for p in parts)


class Active(py_trees.behaviour.Behaviour):
    """SUCCESS when the behaviour is active: its pre-condition holds, its post-condition does
    not, and (a leaf) an action of it can run (not all are accomplished or inhibited)."""

    def __init__(self, name, pre, post, inhibited=lambda: False):
        super().__init__(name)
        self.pre, self.post, self.inhibited = pre, post, inhibited

    def update(self):
        return Status.SUCCESS if self.pre() and not self.post() and not self.inhibited() else Status.FAILURE


class Act(py_trees.behaviour.Behaviour):
    """Perform the leaf's actions in order, skipping the accomplished ones; SUCCESS: it acted.

    An action runs only once the one before it holds its post-condition. When the robot fails
    one (perform returns False), the leaf stops there: that failure was this tick's decision,
    and the next tick retries the action, until it has failed more than RETRIES times in a row;
    then it is inhibited, and so are those after it until its post-condition holds (the
    executive's rule: after `decompress`, each action is a leaf of its own)."""

    def __init__(self, name, steps, perform):
        super().__init__(name)
        self.steps, self.perform = steps, perform
        self.failures = [0] * len(steps)        # consecutive failures of each action

    def runnable(self, i):
        """Whether action i would run now: not accomplished, not inhibited, and the one before
        it holds its post-condition."""
        return (not self.steps[i][1]() and self.failures[i] <= RETRIES
                and (i == 0 or self.steps[i - 1][1]()))

    def blocked(self):
        """Whether no action of the leaf can run now (Active then lets the tick go on)."""
        return not any(self.runnable(i) for i in range(len(self.steps)))

    def update(self):
        for i, (action, _) in enumerate(self.steps):
            if not self.runnable(i):
                continue
            if self.perform(action) is False:
                self.failures[i] += 1
                break
            self.failures[i] = 0
        return Status.SUCCESS


def build(index, holds, perform):
    """The py_trees subtree of behaviour NODES[index]."""
    name, pre, post, steps, children = NODES[index]
    if children:
        guard = Active("active", compile_condition(pre, holds), compile_condition(post, holds))
        body = py_trees.composites.Selector(name="first that acts", memory=False,
                                            children=[build(c, holds, perform) for c in children])
    else:
        body = Act("act", [(a, compile_condition(p, holds)) for a, p in steps], perform)
        guard = Active("active", compile_condition(pre, holds), compile_condition(post, holds), body.blocked)
    return py_trees.composites.Sequence(name=name, memory=False, children=[guard, body])


def create_tree(holds, perform):
    """The live tree: `holds(atom_text)` perceives, `perform(action_text)` acts; one tick, one decision."""
    return py_trees.trees.BehaviourTree(build(0, holds, perform))


@contextlib.contextmanager
def deep_enough():
    """A context in which py_trees can tick this tree: it ticks by recursion, a few frames a
    level, and a tree a few hundred levels deep needs more than Python's default limit."""
    saved = sys.getrecursionlimit()
    sys.setrecursionlimit(max(saved, 8 * DEPTH + 1000))
    try:
        yield
    finally:
        sys.setrecursionlimit(saved)


def run(holds, perform, max_ticks=None):
    """Tick until the task is accomplished ("completed"), nothing acts ("stuck") or max_ticks."""
    tree = create_tree(holds, perform)
    done = compile_condition(NODES[0][2], holds)
    limit = max_ticks if max_ticks is not None else (RETRIES + 1) * (4 * LEAVES + 8)   # failures retried
    with deep_enough():
        for _ in range(limit):
            if done():
                return "completed"
            tree.tick()
            if tree.root.status != Status.SUCCESS:
                return "completed" if done() else "stuck"
    return "completed" if done() else "tick limit"


if __name__ == "__main__":
    import signal

    if hasattr(signal, "SIGPIPE"):   # a reader that stops early (| head) ends it quietly, as it ends cat
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    print(py_trees.display.unicode_tree(create_tree(lambda atom: atom in INITIAL, print).root))
'''


def condition_data(c: Condition):
    """A condition as nested tuples of Python literals."""
    if isinstance(c, cond.Const):
        return c.value
    if isinstance(c, cond.Lit):
        lit = ("lit", term_to_text(c.atom))
        return lit if c.positive else ("not", lit)
    if isinstance(c, cond.Not):
        return ("not", condition_data(c.item))
    return ("and" if isinstance(c, cond.And) else "or", *(condition_data(i) for i in c.items))


def tree_data(root: Behaviour) -> tuple:
    """The tree as NODES: (name, pre, post, steps, child indices) per behaviour, in pre-order."""
    order = list(walk(root))
    index = {id(node): i for i, node in enumerate(order)}
    return tuple((node.name, condition_data(node.pre), condition_data(node.post),
                  () if node.children else tuple((term_to_text(a), condition_data(p)) for a, p in steps_of(node)),
                  tuple(index[id(c)] for c in node.children))
                 for node in order)


_DOCSTRING = '''"""A task tree exported by schemalog, as a py_trees 2.x tree (TITLE says which).

    create_tree(holds, perform) -> py_trees.trees.BehaviourTree   one tick, one decision
    run(holds, perform, max_ticks=None) -> "completed" | "stuck" | "tick limit"

holds(atom) is the robot's perception ("hand.free" -> bool); perform(action) executes
one action ("a1(spoon)") and returns False when the robot failed it (anything else: done).
A failed action is retried at the next tick, RETRIES times, then inhibited.
`python this_file.py` prints the tree.
"""
'''
_DATA = ("TITLE", "TASK", "INITIAL", "RETRIES", "LEAVES", "DEPTH", "NODES")


def export_pytrees(tree: Behaviour, initial=None, title: str = "", retries: int = defaults.RETRIES) -> str:
    """The source of a module that builds `tree` with py_trees 2.x and runs it, a failed action
    retried `retries` times (Unquotable: refused). INITIAL is `initial`'s atoms, what `python
    the_module.py` prints the tree in; the robot's holds() is the state the tree runs in."""
    if not isinstance(retries, int) or isinstance(retries, bool) or retries < 0:
        raise ValueError(f"retries must be an int, 0 or more, not {retries!r}")
    nodes = tree_data(tree)
    data = {"TITLE": title or "a task tree exported by schemalog", "TASK": tree.name,
            "INITIAL": sorted(term_to_text(a) for a in initial or ()), "RETRIES": retries,
            "LEAVES": sum(1 for n in nodes if not n[4]), "DEPTH": depth(tree), "NODES": nodes}
    source = _DOCSTRING + "".join(f"{k} = {python_literal(data[k])}\n" for k in _DATA) + _RUNTIME
    check_module(source, data)
    return source


def check_module(source: str, data: dict) -> None:
    """Parse an exported module back: it must compile, and its data assignments (and nothing else
    before the fixed runtime) must evaluate to `data`; else Unquotable."""
    import ast

    try:
        module = ast.parse(source)
        compile(module, "<export>", "exec")
    except (SyntaxError, ValueError, MemoryError, RecursionError) as err:
        raise Unquotable(f"the module would not compile: {err}") from None
    body = module.body
    if not (body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)):
        raise Unquotable("the module's docstring does not read back")
    assigned = {}
    for statement in body[1:1 + len(_DATA)]:
        if not (isinstance(statement, ast.Assign) and len(statement.targets) == 1
                and isinstance(statement.targets[0], ast.Name)):
            raise Unquotable("the module's data does not read back as assignments")
        assigned[statement.targets[0].id] = ast.literal_eval(statement.value)
    if assigned != data:
        raise Unquotable("the module's data does not read back as the tree exported")


def load_module(source: str, name: str = "schemalog_pytrees_tree") -> types.ModuleType:
    """Execute exported source as a fresh module."""
    module = types.ModuleType(name)
    exec(compile(source, f"<{name}>", "exec"), module.__dict__)
    return module


def world_adapters(original: Behaviour, world, trace: list[Term], spent: list[float] | None = None,
                   robot=None, failed: list[Term] | None = None):
    """holds(text) and perform(text) over the World of `original`, recording the trace (and, in
    `spent[0]`, the seconds spent performing); `robot` (a RobotManager) may fail a command, which
    perform reports as False and records in `failed`."""
    import time

    from .btcpp import action_posts, atoms_of, performed

    atoms = {term_to_text(a): a for a in atoms_of(original)}
    posts = action_posts(original)
    def holds(text: str) -> bool:
        return atoms[text] in world

    def perform(text: str) -> bool:
        began = time.perf_counter()
        label, post = performed(posts, text, world)
        done = robot is None or robot.command(label, None)
        if done:
            world.perform(post)
            trace.append(label)
        elif failed is not None:
            failed.append(label)
        if spent is not None:
            spent[0] += time.perf_counter() - began
        return done

    return holds, perform


def run_pytrees(source: str, original: Behaviour, initial=(), max_ticks: int | None = None,
                failures: dict[Term, int | None] | None = None) -> BtRun:
    """Load exported source and run it against the World of `original` from `initial`; the robot
    fails the commands `failures` names that many times (None: always)."""
    import time

    from ..run.execute import RobotManager
    from ..run.world import World

    module = load_module(source)
    world = World(original, initial)
    trace: list[Term] = []
    failed: list[Term] = []
    spent = [0.0]
    holds, perform = world_adapters(original, world, trace, spent, RobotManager(failures=failures), failed)
    tree = module.create_tree(holds, perform)
    done = module.compile_condition(module.NODES[0][2], holds)
    limit = max_ticks if max_ticks is not None else 4 * module.LEAVES + 8
    limit += (module.RETRIES + 1) * len(failures or ())
    ticks, status = 0, "tick limit"
    each = []
    started = time.perf_counter()
    with module.deep_enough():
        while ticks < limit:
            if done():
                status = "completed"
                break
            before, began = spent[0], time.perf_counter()
            tree.tick()
            each.append(time.perf_counter() - began - (spent[0] - before))
            ticks += 1
            if tree.root.status != module.Status.SUCCESS:
                status = "completed" if done() else "stuck"
                break
        else:
            if done():
                status = "completed"
    return BtRun(status, trace, ticks, time.perf_counter() - started, spent[0], tuple(each), failed)


__all__ = ["export_pytrees", "check_module", "load_module", "run_pytrees", "tree_data", "condition_data",
           "world_adapters"]
