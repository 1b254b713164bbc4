"""Hypothesis strategies for task knowledge: task files (Prolog text), tasks, and trees.

For users' own property tests (docs/testing.md): `task_files()` draws the text of a task file
(schema/3 clauses with chains, branches and context releasers, task/1, initial/1), `tasks()` the
same loaded as a `schemalog.Task`. `task_trees()`, `trees()` and `starts()` draw the internal
trees the project's own tests use. hypothesis is a test dependency only: this module needs it,
`import schemalog` and `import schemalog.testing` do not.
"""

from __future__ import annotations

try:
    from hypothesis import strategies as st
except ImportError:  # pragma: no cover - depends on the environment
    raise ImportError("schemalog.testing.strategies needs hypothesis: pip install hypothesis") from None

from ..logic.opread import parse_term
from ..logic.terms import term_to_text
from ..task import conditions as cond
from ..task.tree import Behaviour

__all__ = ["task_files", "tasks", "task_trees", "trees", "starts"]

CONTEXT = ("hand.free", "cup.ready", "spoon.clean")   # atoms no action of task_files() sets


@st.composite
def task_files(draw, *, levels: tuple[int, int] = (2, 4), max_children: int = 4, max_behaviours: int = 30,
               chains: bool = True, context: bool = True, completing: bool = True, toggles: bool = False,
               agents: bool = True, root: str = "t0") -> str:
    """The text of a task file: task/1 `root`, object/1, initial/1, agent/2 and schema/3 clauses.

    A tree of `levels` (lowest, highest) levels, the root included, with 1 to `max_children`
    sub-tasks each and at most `max_behaviours` behaviours. Composite sub-tasks are `sN(Obj)`
    with post `sN.done`, actions `aN(Obj)` with post `aN.done`, on the objects cup and spoon.
    Releasers: the first sibling `true`; a later one, with `chains`, an earlier sibling's done (the
    one before: a chain; another: a branch, two siblings released by one), else `true`; with
    `context`, some are also conjoined with a context atom (hand.free, cup.ready, spoon.clean)
    or its negation, and initial/1 declares a random set of those atoms. With `completing` (the
    default) a releaser only reads context literals the initial state makes true, and no action
    changes them, so every drawn task completes and its compression is provable; without it the
    literals are random and a task may be stuck (a vacuous proof). `toggles` lets actions also
    set or clear context atoms (`aN.done and not hand.free`), as a gripper does. `agents` gives
    some actions the agent gripper (never merged with the arm's).
    """
    low, high = levels
    depth = draw(st.integers(max(low, 2), max(high, low, 2)))
    budget = [max(1, max_behaviours - 1)]
    ids = iter(range(1, 100_000))
    initial = sorted(draw(st.sets(st.sampled_from(CONTEXT)))) if context else []
    clauses: list[str] = []
    gripped: list[str] = []

    def literal() -> str:
        atom = draw(st.sampled_from(CONTEXT))
        positive = atom in initial if completing else draw(st.booleans())
        return atom if positive else f"not {atom}"

    def node(level: int) -> tuple[str, str]:
        """Write the schema of a new behaviour at `level`; its (head, name)."""
        n = next(ids)
        slot = len(clauses)                  # the schema goes before its sub-behaviours'
        clauses.append("")
        count = 0
        if level < depth and budget[0] > 0:
            count = min(draw(st.integers(1 if level == 1 else 0, max_children)), budget[0])
            budget[0] -= count
        obj = draw(st.sampled_from(["cup", "spoon"]))
        name = root if level == 1 else f"{'s' if count else 'a'}{n}"
        head = name if level == 1 else f"{name}({obj})"
        kids: list[tuple[str, str]] = []
        for i in range(count):
            kid_head, kid_name = node(level + 1)
            releaser = "true"
            if i and chains and draw(st.integers(0, 3)):
                before = kids[-1][1] if draw(st.booleans()) else draw(st.sampled_from([k[1] for k in kids]))
                releaser = f"{before}.done"
            if context and draw(st.integers(0, 4)) == 0:
                releaser = literal() if releaser == "true" else f"{releaser} and {literal()}"
            kids.append((kid_head, kid_name, releaser))
        post = f"{name}.done"
        if not count and toggles and draw(st.integers(0, 3)) == 0:
            atom = draw(st.sampled_from(CONTEXT))
            post += f" and {draw(st.sampled_from(['', 'not ']))}{atom}"
        if not count and agents and level > 1 and draw(st.integers(0, 4)) == 0:
            gripped.append(head)
        if kids:
            entries = ",\n".join(f"    ({h}, {r})" for h, _, r in kids)
            clauses[slot] = f"schema({head},\n  [\n{entries}\n  ],\n  {post})."
        else:
            clauses[slot] = f"schema({head}, [], {post})."
        return head, name

    node(1)
    lines = [f"% A task drawn by schemalog.testing.strategies.task_files: {depth} levels.",
             f"task({root}).", "", "object(cup).", "object(spoon).",
             *(f"initial({atom})." for atom in initial),
             *(f"agent({head}, gripper)." for head in gripped), "", *clauses, ""]
    return "\n".join(lines)


def tasks(**options):
    """`task_files(**options)` loaded with the public API: a `schemalog.Task` (its first task)."""
    def load(text: str):
        import schemalog

        return schemalog.loads(text, name="<task_files>").task()
    return task_files(**options).map(load)


@st.composite
def task_trees(draw, max_children=5, levels=3):
    """Trees whose siblings form chains, branches and cycles on shared objects and agents."""
    ids = iter(range(100_000))

    def node(level):
        n = next(ids)
        if level >= levels:
            kids = ()
        else:
            count = draw(st.integers(0, max_children))
            names = [f"b{next(ids)}" for _ in range(count)]
            kids = []
            for i, name in enumerate(names):
                child = node(level + 1)
                choice = draw(st.integers(0, 3))
                releaser = "true" if i == 0 or choice == 0 else f"{names[draw(st.integers(0, count - 1))]}.done"
                obj = draw(st.sampled_from(["cup", "cup", "spoon"]))
                agent = draw(st.sampled_from(["arm", "arm", "gripper"]))
                kids.append(Behaviour(label=parse_term(f"{name}({obj})"), agent=agent,
                                      objects=(parse_term(obj),),
                                      releaser=cond.from_term(parse_term(releaser)),
                                      post=cond.from_term(parse_term(f"{name}.done")),
                                      children=child.children))
            kids = tuple(kids)
        return Behaviour(label=parse_term(f"n{n}"), post=cond.from_term(parse_term(f"n{n}.done")), children=kids)
    return node(1)


@st.composite
def trees(draw, chains: int = 3, toggles: bool = True):
    """Depth 2-6, 1-4 children, at most ~40 behaviours: chains (a sibling's done), branches (two
    siblings released by one), toggling posts (hand.free) and releasers that read them.
    `chains` of 6 draws release a later sibling by an earlier one's done (3: half of them);
    without `toggles`, actions set only their own done (hand.free is still read)."""
    levels = draw(st.integers(2, 6))
    budget = [draw(st.integers(4, 40))]
    ids = iter(range(10_000))

    def node(level, releaser, n):
        name = f"b{n}"
        count = 0
        if level < levels and budget[0] > 0:
            count = min(draw(st.integers(0 if level > 1 else 1, 4)), budget[0])
            budget[0] -= count
        names = [next(ids) for _ in range(count)]
        kids = []
        for i in range(count):
            choice = draw(st.integers(0, chains + 2))
            if i and choice < chains:
                before = names[i - 1] if draw(st.booleans()) else draw(st.sampled_from(names[:i]))
                rel = f"b{before}.done"                                  # a chain, or a branch
            elif choice == chains:
                rel = "hand.free"
            elif choice == chains + 1:
                rel = "not hand.free"
            else:
                rel = "true"
            kids.append(node(level + 1, rel, names[i]))
        post = f"{name}.done"
        if not kids and toggles:
            post += draw(st.sampled_from(["", "", " and not hand.free", " and hand.free"]))
        obj = draw(st.sampled_from(["cup", "spoon"]))
        return Behaviour(label=parse_term(f"{name}({obj})" if level > 1 else name), objects=(parse_term(obj),),
                         releaser=_condition(releaser), post=_condition(post), children=tuple(kids))

    return node(1, "true", next(ids))


@st.composite
def starts(draw, tree):
    """One to three initial states: hand.free and a few done markers, some true."""
    leaves = sorted({lit.atom for n in _walk(tree) for lit in cond.literals(n.post)}, key=term_to_text)
    pool = [parse_term("hand.free"), *leaves[:6]]
    return draw(st.lists(st.lists(st.sampled_from(pool), max_size=3), min_size=1, max_size=3))


def _walk(tree):
    stack = [tree]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(n.children)


def _condition(text: str) -> cond.Condition:
    return cond.from_term(parse_term(text))
