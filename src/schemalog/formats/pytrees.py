"""Task trees as Python modules that build them with py_trees 2.x, and runs of those modules.

    export_pytrees(tree, initial, title) -> str      the module's source
    load_module(source)                  -> module   with create_tree(holds, perform) and run(...)
    run_pytrees(source, original, initial) -> BtRun  ticked against the World of `original`

The module holds the tree as data (TREE: nested tuples name, pre, post, steps, children,
conditions as ("lit", "hand.free"), ("not", c), ("and", ...), ("or", ...), True, False) and
builds it from py_trees' own composites: every behaviour is a Sequence(memory=False) of an
`Active` guard (its pre-condition holds and its post-condition does not) and either a
Selector(memory=False) over its children or, for a leaf, an `Act` that performs its actions,
skipping those already accomplished. A behaviour returns SUCCESS exactly when it acted, so a
Selector stops at the first child that acted: one tick is one decision, the first enabled
leaf in tree order, the same order as the BT.CPP export (docs/formats.md).
"""

from __future__ import annotations

import types

from ..logic.terms import Term, term_to_text
from ..task import conditions as cond
from ..task.conditions import Condition
from ..task.tree import Behaviour, walk
from .btcpp import BtRun, steps_of

_RUNTIME = '''
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
    """SUCCESS when the behaviour is active: its pre-condition holds and its post-condition not."""

    def __init__(self, name, pre, post):
        super().__init__(name)
        self.pre, self.post = pre, post

    def update(self):
        return Status.SUCCESS if self.pre() and not self.post() else Status.FAILURE


class Act(py_trees.behaviour.Behaviour):
    """Perform the leaf's actions in order, skipping the accomplished ones; SUCCESS: it acted."""

    def __init__(self, name, steps, perform):
        super().__init__(name)
        self.steps, self.perform = steps, perform

    def update(self):
        for action, done in self.steps:
            if not done():
                self.perform(action)
        return Status.SUCCESS


def build(node, holds, perform):
    """The py_trees subtree of one behaviour of TREE."""
    name, pre, post, steps, children = node
    guard = Active("active", compile_condition(pre, holds), compile_condition(post, holds))
    if children:
        body = py_trees.composites.Selector(name="first that acts", memory=False,
                                            children=[build(c, holds, perform) for c in children])
    else:
        body = Act("act", [(a, compile_condition(p, holds)) for a, p in steps], perform)
    return py_trees.composites.Sequence(name=name, memory=False, children=[guard, body])


def create_tree(holds, perform):
    """The live tree: `holds(atom_text)` perceives, `perform(action_text)` acts; one tick, one decision."""
    return py_trees.trees.BehaviourTree(build(TREE, holds, perform))


def run(holds, perform, max_ticks=None):
    """Tick until the task is accomplished ("completed"), nothing acts ("stuck") or max_ticks."""
    tree = create_tree(holds, perform)
    done = compile_condition(TREE[2], holds)
    limit = max_ticks if max_ticks is not None else 4 * LEAVES + 8
    for _ in range(limit):
        if done():
            return "completed"
        tree.tick()
        if tree.root.status != Status.SUCCESS:
            return "completed" if done() else "stuck"
    return "completed" if done() else "tick limit"


if __name__ == "__main__":
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


def tree_data(root: Behaviour):
    """The tree as nested tuples (name, pre, post, steps, children), built bottom-up."""
    built: dict[int, tuple] = {}
    stack: list[tuple[Behaviour, bool]] = [(root, False)]
    while stack:
        node, ready = stack.pop()
        if node.children and not ready:
            stack.append((node, True))
            stack.extend((c, False) for c in node.children)
            continue
        steps = () if node.children else tuple((term_to_text(a), condition_data(p)) for a, p in steps_of(node))
        built[id(node)] = (node.name, condition_data(node.pre), condition_data(node.post), steps,
                           tuple(built.pop(id(c)) for c in node.children))
    return built[id(root)]


def export_pytrees(tree: Behaviour, initial=(), title: str = "") -> str:
    """The source of a module that builds `tree` with py_trees 2.x and runs it."""
    leaves = sum(1 for n in walk(tree) if not n.children)
    # The title names the input file: a backslash or a quote in its name must not end the
    # docstring or start an escape Python refuses (b\N.pl, q""".pl).
    title = (title or "A task tree exported by schemalog").replace("\\", "\\\\").replace('"', '\\"')
    head = f'"""{title}, as a py_trees 2.x tree.\n\n' \
           '    create_tree(holds, perform) -> py_trees.trees.BehaviourTree   one tick, one decision\n' \
           '    run(holds, perform, max_ticks=None) -> "completed" | "stuck" | "tick limit"\n\n' \
           'holds(atom) is the robot\'s perception ("hand.free" -> bool); perform(action) executes\n' \
           'one action ("a1(spoon)"). `python this_file.py` prints the tree.\n"""\n'
    data = (f"TASK = {tree.name!r}\nINITIAL = {sorted(term_to_text(a) for a in initial)!r}\n"
            f"LEAVES = {leaves}\nTREE = {tree_data(tree)!r}\n")
    return head + data + _RUNTIME


def load_module(source: str, name: str = "schemalog_pytrees_tree") -> types.ModuleType:
    """Execute exported source as a fresh module."""
    module = types.ModuleType(name)
    exec(compile(source, f"<{name}>", "exec"), module.__dict__)
    return module


def world_adapters(original: Behaviour, world, trace: list[Term], spent: list[float] | None = None):
    """holds(text) and perform(text) over the World of `original`, recording the trace (and, in
    `spent[0]`, the seconds spent performing)."""
    import time

    from .btcpp import action_posts, atoms_of, performed

    atoms = {term_to_text(a): a for a in atoms_of(original)}
    posts = action_posts(original)
    def holds(text: str) -> bool:
        return atoms[text] in world

    def perform(text: str) -> None:
        began = time.perf_counter()
        label, post = performed(posts, text, world)
        world.perform(post)
        trace.append(label)
        if spent is not None:
            spent[0] += time.perf_counter() - began

    return holds, perform


def run_pytrees(source: str, original: Behaviour, initial=(), max_ticks: int | None = None) -> BtRun:
    """Load exported source and run it against the World of `original` from `initial`."""
    import time

    from ..run.world import World

    module = load_module(source)
    world = World(original, initial)
    trace: list[Term] = []
    spent = [0.0]
    holds, perform = world_adapters(original, world, trace, spent)
    tree = module.create_tree(holds, perform)
    done = module.compile_condition(module.TREE[2], holds)
    limit = max_ticks if max_ticks is not None else 4 * module.LEAVES + 8
    ticks, status = 0, "tick limit"
    each = []
    started = time.perf_counter()
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
    return BtRun(status, trace, ticks, time.perf_counter() - started, spent[0], tuple(each))


__all__ = ["export_pytrees", "load_module", "run_pytrees", "tree_data", "condition_data", "world_adapters"]
