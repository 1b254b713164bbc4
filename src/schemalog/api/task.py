"""A task: one tree of behaviours instantiated from knowledge, original or compressed.

    Task        = (tree: Behaviour, knowledge, original: Task, compression | None)
    Compression = the paper's figures of one application of Algorithm 1 (Bi, Bm, D, RD)

A Task is immutable: compress() returns a new Task whose `original` is the one compressed.
Its methods print nothing; what the command line would say as a note is in `notes`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterable

from .. import defaults
from ..errors import SchemalogError, UsageError, readable_name
from ..logic.terms import Term, term_to_text
from ..task.tree import Behaviour, count_nodes, depth

from .limits import DEFAULT, within
from .arguments import Count, Path, Seconds, Size, Times, checked, read_scene_for, refuse_overwriting, state_atoms

if TYPE_CHECKING:
    from ..run.scene import Scene
    from ..run.world import World
    from .execution import Run
    from .knowledge import Knowledge
    from .report import Report

# -o's suffix, save()'s too: the format written.
SUFFIX_FORMATS = {".json": "json", ".dot": "dot", ".gv": "dot", ".pl": "pl", ".yaml": "yaml", ".yml": "yaml",
                  ".prolog": "seed", ".xml": "btcpp", ".py": "py_trees", ".png": "png", ".svg": "svg",
                  ".pdf": "pdf"}
PICTURES = ("png", "svg", "pdf")


@dataclass(frozen=True)
class Compression:
    """What one compression did: the paper's figures (equation 1) and the notes it made."""

    propagate: str
    nodes_before: int
    nodes_after: int
    depth_before: int
    depth_after: int
    reduction_degree: float
    notes: tuple[str, ...] = ()
    conditions_simplified: int = 0
    conditions_needing_sympy: int = 0

    def figures(self) -> str:
        """`Bi = 12, Bm = 6, D = 3, RD = (Bi - Bm) / (Bi - D) = 0.67`, as compress prints it."""
        return (f"Bi = {self.nodes_before}, Bm = {self.nodes_after}, D = {self.depth_before}, "
                f"RD = (Bi - Bm) / (Bi - D) = {self.reduction_degree:.2f}")


class Task:
    """One task's tree of behaviours, with the knowledge it came from."""

    __slots__ = ("tree", "knowledge", "compression", "notes", "_original")

    def __init__(self, tree: Behaviour, knowledge: Knowledge, original: Task | None = None,
                 compression: Compression | None = None, notes: Iterable[str] = ()) -> None:
        self.tree = tree
        self.knowledge = knowledge
        self.compression = compression
        self.notes: tuple[str, ...] = tuple(notes)
        self._original = original

    @classmethod
    def instantiated(cls, knowledge: Knowledge, task: Term, max_depth: int = defaults.MAX_DEPTH,
                     max_nodes: int = defaults.MAX_NODES, read: dict | None = None, provenance: bool = True) -> Task:
        """The task's tree from its schemas (a compressed file's tree keeps its provenance;
        provenance False: the tree as read, its original not rebuilt, as show prints it)."""
        from ..task.compress import original_of
        from ..task.tree import Instantiator

        instantiator = Instantiator(knowledge._kb, max_depth=max_depth, max_nodes=max_nodes, read=read)
        tree = instantiator.instantiate(task)
        notes = tuple(instantiator.warnings)
        if not provenance:
            return cls(tree, knowledge, notes=notes)
        before = original_of(tree)
        original = None if before is tree else cls(before, knowledge, notes=notes)
        return cls(tree, knowledge, original, notes=notes)

    # -- what it is ------------------------------------------------------------------
    @property
    def name(self) -> str:
        """The task's label as text: `prepareboth`."""
        return term_to_text(self.tree.label)

    @property
    def label(self) -> Term:
        return self.tree.label

    def __len__(self) -> int:
        """The number of behaviours (Bi of an original, Bm of a compressed tree)."""
        return count_nodes(self.tree)

    @property
    def depth(self) -> int:
        return depth(self.tree)

    @property
    def original(self) -> Task:
        """The uncompressed task: itself, or the one this was compressed from (rebuilt from
        provenance for a file written by `schemalog compress`)."""
        return self._original if self._original is not None else self

    @property
    def compressed(self) -> bool:
        return self._original is not None

    @property
    def provenance(self) -> bool:
        """Whether the tree carries origins/2 (written by `schemalog compress`), here or below."""
        from ..task.tree import walk

        return any(n.origins for n in walk(self.tree))

    @property
    def kind(self) -> str:
        """`original`, `compressed (propagate full)`, or `compressed` (a compressed file's)."""
        if self._original is None:
            return "original"
        return f"compressed (propagate {self.compression.propagate})" if self.compression else "compressed"

    def __repr__(self) -> str:
        return f"<Task {self.name}: {self.kind}, {len(self)} behaviours, depth {self.depth}>"

    # -- what it does ------------------------------------------------------------------
    @checked
    def compress(self, propagate: str = "full", *, sympy_budget: Times = defaults.SYMPY_BUDGET,
                 timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Task:
        """Merge sequential behaviours (Definition 1, Algorithm 1) into a new Task."""
        from ..task.compress import compress, protected_labels
        from ..task.conditions import Simplifier

        if propagate not in defaults.PROPAGATE_MODES:
            raise UsageError(f"propagate {propagate!r}: choose {', '.join(defaults.PROPAGATE_MODES)}")
        if not 0 <= sympy_budget <= defaults.MAX_SYMPY_BUDGET:
            raise UsageError(f"sympy_budget {sympy_budget}: at most {defaults.MAX_SYMPY_BUDGET} "
                             f"(its cost doubles per variable)")
        kb = self.knowledge._kb
        with within(timeout, max_memory):
            result = compress(self.tree, propagate, protected_labels(kb, self.tree),
                              Simplifier(sympy_budget=sympy_budget))
        figures = Compression(result.propagate, result.nodes_before, result.nodes_after, result.depth_before,
                              result.depth_after, result.reduction_degree, tuple(result.notes),
                              result.simplifier.calls, result.simplifier.sympy_calls)
        # a compressed task compressed again still stands for the tree it was compressed from
        return Task(result.tree, self.knowledge, self.original, figures, tuple(f"note: {n}" for n in result.notes))

    def decompress(self) -> Task:
        """The original tree rebuilt from the provenance (origins/2) a compressed file carries;
        a tree without it is itself (said in `notes`)."""
        from ..task.compress import decompress

        notes = () if self.tree.origins else \
            (f"note: {self.name} carries no provenance (origins/2): it is shown as it is",)
        return Task(decompress(self.tree), self.knowledge, notes=notes)

    @checked
    def verify(self, compressed: Task | None = None, *, timeout: Seconds | None = None, max_memory: Size | None = DEFAULT, **options) -> Report:
        """Prove `compressed` (default: this task if it is compressed, else this task
        compressed with propagate full) against this task's original: schemalog.verify's options."""
        from .report import verify

        with within(timeout, max_memory):
            if compressed is None:
                compressed = self if self.compressed else self.compress()
            return verify(self.original, compressed, **options)

    @checked
    def run(self, scene: Path | None = None, *, seed: int | None = None, jitter: float | None = None,
            state: str | Iterable[str] | None = None, selector: str = "incremental", fail: Iterable[str] = (),
            fail_times: Count | None = None, retries: Times = defaults.RETRIES, recovery: str = defaults.RECOVERIES[0],
            max_decisions: Count | None = None, timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> Run:
        """Execute with the attentional executive against an emulated robot, to the end."""
        with within(timeout, max_memory):
            run = self.start(scene, seed=seed, jitter=jitter, state=state, selector=selector, fail=fail,
                             fail_times=fail_times, retries=retries, recovery=recovery, max_decisions=max_decisions)
            run.finish()
        return run

    @checked
    def start(self, scene: Path | None = None, *, seed: int | None = None, jitter: float | None = None,
              state: str | Iterable[str] | None = None, selector: str = "incremental", fail: Iterable[str] = (),
              fail_times: Count | None = None, retries: Times = defaults.RETRIES,
              recovery: str = defaults.RECOVERIES[0], max_decisions: Count | None = None) -> Run:
        """A run not yet started: iterate it for its decisions as the executive takes them."""
        from .execution import start_run

        return start_run(self, scene, seed, jitter, state, selector, tuple(fail), fail_times, retries, recovery,
                         max_decisions)

    # -- what it is written as ---------------------------------------------------------
    def to_prolog(self) -> str:
        """Schema text that loads back into this tree (with origins/2 when compressed)."""
        return self.text("pl")

    def to_yaml(self) -> str:
        return self.text("yaml")

    def to_seed(self) -> str:
        """The authors' SEED long-term memory format."""
        return self.text("seed")

    def to_json(self) -> str:
        return self.text("json")

    def to_dot(self) -> str:
        """The tree as a Graphviz graph, coloured in the initial state."""
        return self.text("dot")

    @checked
    def to_btcpp(self, state: str | Iterable[str] | bool | None = None, *, retries: Times = defaults.RETRIES,
                 node_types: dict | Path | None = None) -> str:
        """BehaviorTree.CPP v4 XML that runs this tree, each failed action retried `retries`
        times; the robot writes the state (default), or the first tick writes `state` (True:
        initial/1). `node_types`: functor -> NodeType (or a YAML file, read_node_types)."""
        return self.text("btcpp", state, retries=retries, node_types=node_types)

    @checked
    def to_py_trees(self, state: str | Iterable[str] | bool | None = None, *, retries: Times = defaults.RETRIES) -> str:
        """A Python module that builds and runs this tree in py_trees (INITIAL: `state`, printed by
        `python module.py`; True: initial/1)."""
        return self.text("py_trees", state, retries=retries)

    @checked
    def text(self, fmt: str, state: str | Iterable[str] | bool | None = None, *, header: str | None = None,
             retries: Times = defaults.RETRIES, node_types: dict | Path | None = None) -> str:
        """This task written in one format: pl, yaml, seed, json, dot, btcpp, py_trees
        (header: the comment pl and seed start with, default header())."""
        from ..formats.render import carried_clauses, show_json, to_dot, tree_document

        kb = self.knowledge._kb
        if fmt in ("pl", "yaml", "seed"):
            return written(tree_document(self.tree, carried=carried_clauses(kb)), fmt,
                           self.header() if header is None else header)
        if fmt == "json":
            import json
            return json.dumps(show_json(self.tree.label, self.tree), indent=2) + "\n"
        if fmt == "dot":
            return to_dot(self.tree, self.name, self.initial_atoms())
        if fmt in ("btcpp", "py_trees"):
            return self._exported(fmt, state, retries, node_types)
        raise UsageError(f"no text format {fmt!r}: choose pl, yaml, seed, json, dot, btcpp or py_trees")

    @checked
    def save(self, path: Path, format: str | None = None) -> str:
        """Write this task to `path` atomically (format: from the suffix), never over a file
        the knowledge was read from; the format written."""
        from ..formats.documents import write_atomically

        name = os.fspath(path)
        fmt = format or SUFFIX_FORMATS.get(os.path.splitext(name)[1].lower())
        if fmt is None:
            raise UsageError(f"{readable_name(name)}: say the format (its suffix is none of "
                             f"{', '.join(sorted(SUFFIX_FORMATS))})")
        refuse_overwriting(name, self.knowledge.files)
        if fmt in PICTURES:
            from ..formats.graphviz import render
            write_atomically(name, render(self.to_dot(), fmt))
        else:
            write_atomically(name, self.text(fmt))
        return fmt

    def header(self) -> str:
        """The comment a written file starts with: where it came from, and its figures."""
        files = ", ".join(map(readable_name, self.knowledge.files)) or "text"
        if self.compression is None:
            return f"Task {self.name} from {files}, written by schemalog."
        return (f"Compressed by schemalog (Algorithm 1, propagate {self.compression.propagate}) from "
                f"{files}, task {self.name}.\n{self.compression.figures()}.\n"
                f"`schemalog decompress` restores the original tree from the origins/2 facts.")

    def initial_atoms(self) -> frozenset:
        """The settled initial state of the knowledge's initial/1."""
        from ..run.world import World, initial_state

        return World(self.tree, initial_state(self.knowledge._kb)).atoms

    def _exported(self, target: str, state, retries: int, node_types) -> str:
        from ..formats.quoting import Unquotable
        from ..run.world import World, initial_state

        if node_types is not None and target != "btcpp":
            raise UsageError("node types are for BehaviorTree.CPP exports (a py_trees action is called by its label)")
        if isinstance(node_types, (str, os.PathLike)):
            from .behaviour_trees import read_node_types
            node_types = read_node_types(node_types)
        atoms = None                  # the robot writes the state before the first tick
        if state is not None and state is not False:
            initial = initial_state(self.knowledge._kb) if state is True else state_atoms(state, "state")
            # The world settles the initial state (a composite whose parts hold is accomplished),
            # and the runtime starts from what the world starts from.
            atoms = sorted(World(self.original.tree, initial).atoms, key=term_to_text)
        files = ", ".join(map(readable_name, self.knowledge.files)) or "text"
        title = f"{self.name} from {files}: {self.kind} tree of {len(self)} behaviours, exported by schemalog"
        try:
            if target == "btcpp":
                from ..formats.btcpp import export_btcpp
                nodes = bt_nodes(self.knowledge._kb)
                try:
                    return export_btcpp(self.tree, atoms, title, retries, node_types, nodes)
                except ValueError as err:
                    raise UsageError(f"node types: {err}") from None
            from ..formats.pytrees import export_pytrees
            return export_pytrees(self.tree, atoms, title, retries)
        except Unquotable as err:
            raise Unquotable(f"cannot export {self.name} to {target}: {err.message}") from None

    # -- notebooks ----------------------------------------------------------------------
    def _repr_svg_(self) -> str | None:
        """The tree drawn by Graphviz, sized for a notebook (a compressed task beside its
        original when both fit, its aliased behaviours marked); None without `dot`."""
        from .notebook import task_svg

        return task_svg(self)

    def _repr_html_(self) -> str | None:
        """The tree as text, for a notebook without Graphviz (None with it: the picture shows,
        since notebooks prefer HTML to SVG)."""
        import html

        from .notebook import have_dot

        if have_dot():
            return None
        return f"<pre>{html.escape(self.tree_text())}</pre>"

    @checked
    def tree_text(self, width: Count = 120) -> str:
        """The tree as `schemalog show` prints it to a file."""
        from ..formats.render import rich_tree

        return rendered(rich_tree(self.tree, f"{self.name}: {len(self)} behaviours, depth {self.depth}"), width)


def rendered(renderable, width: int = 120) -> str:
    """A rich renderable as plain text."""
    import io

    from rich.console import Console

    buffer = io.StringIO()
    Console(file=buffer, width=width, no_color=True).print(renderable)
    return buffer.getvalue()


def written(doc, fmt: str, header: str) -> str:
    """A tree's knowledge as text: schema text (pl), YAML, or SEED long-term memory."""
    from ..formats.documents import to_pl, to_yaml

    if fmt == "seed":
        from ..formats.seed import seed_text
        return seed_text(list(doc.items), header=header)
    return to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc)


def bt_nodes(kb) -> dict:
    """The knowledge's bt_node(Label, 'NodeType', [port = value, ...]) facts (written by `convert
    tree.xml`): label -> (node type, ((port, value text), ...)); a malformed one is an error at its clause."""
    from ..logic.terms import NIL, Atom, Struct, indicator, list_items

    out: dict = {}
    for clause in kb.user_clauses():
        if indicator(clause.head) != ("bt_node", 3):
            continue
        label, ident, ports = clause.head.args
        try:
            items, tail = list_items(ports)
            if not isinstance(ident, Atom) or tail != NIL:
                raise ValueError
            pairs = []
            for item in items:
                if not (isinstance(item, Struct) and item.name == "=" and len(item.args) == 2
                        and isinstance(item.args[0], Atom)):
                    raise ValueError
                value = item.args[1]
                pairs.append((item.args[0].name, value.name if isinstance(value, Atom) else term_to_text(value)))
        except ValueError:
            raise SchemalogError("bt_node/3 reads bt_node(Label, 'NodeType', [port = value, ...])",
                                 clause.pos) from None
        out.setdefault(label, (ident.name, tuple(pairs)))
    return out
