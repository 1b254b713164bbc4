"""Compression of behaviour trees under BT.CPP 4's semantics: rewrites that leave every
leaf tick, halt, script and root status as it was (docs/semantics.md, "Behaviour trees").

    compress(document) -> Compressed(document, rewrites)
    Rewrite = (rule, type, name, line, column)   one rewrite, where it was made in the original

The rules (each proved on real trees by bt/prove.py; compress is not trusted without it):

    flatten      Sequence(.., Sequence(a, b), ..)  ->  Sequence(.., a, b, ..)
                 the same for ReactiveSequence, Fallback, ReactiveFallback (not for
                 SequenceWithMemory, which yields after each child that started and succeeded):
                 a composite inside one of the same type resumes, restarts and skips as the
                 outer one would at the same place (BT.CPP src/controls/*_node.cpp)
    single       Sequence(a) -> a, Fallback(a) -> a (any of those five composites): the
                 status of the only child is the composite's
    inverters    Inverter(Inverter(a)) -> a
    forced       ForceSuccess(ForceSuccess(a)) -> ForceSuccess(a), and the other three pairs
                 of ForceSuccess/ForceFailure: the outer one decides every status but RUNNING

A node is rewritten only when its type is one of those above and it carries no `_`-attribute
(a pre- or post-condition belongs to that node: `_skipIf`, `_onSuccess`, ...). Two contexts
the rules cannot see make two more exceptions, both refuted by the prover otherwise
(tests/bt/test_review_soundness.py): `single` and `inverters` keep the node when the child
that would take its place has a pre-condition (BT.CPP checks it only from IDLE, and a parent
such as WhileDoElse or PipelineSequence ticks a finished child again without resetting it:
the removed node's reset made the check run); `flatten` keeps an inner Sequence or Fallback
when a child of it may return SKIPPED (their skipped_count_ is reset only on completion or
from IDLE, so flattened under such a parent it would count skips across ticks). Its `name` goes
with it: BT.CPP's traces and Groot2 show it, but it does nothing. Custom nodes, opaque ones
and everything else are kept as they are, ports and remapping included.
"""

from __future__ import annotations

from dataclasses import dataclass

from .model import Document, Node

COMPOSITES = frozenset({"Sequence", "SequenceWithMemory", "ReactiveSequence", "Fallback", "ReactiveFallback"})
# SequenceWithMemory hands the tick back after a child that started this tick succeeds
# (requiresWakeUp, src/controls/sequence_with_memory_node.cpp); nested, the inner one's last
# success does not, so flattening it moves a RUNNING: the prover refutes it (tests/bt/test_prove_by_parts.py).
FLATTENED = COMPOSITES - {"SequenceWithMemory"}
FORCES = frozenset({"ForceSuccess", "ForceFailure"})


@dataclass(frozen=True)
class Rewrite:
    """One rewrite: the rule, and the node it removed (type, name, where it stood)."""

    rule: str
    type: str
    name: str
    line: int
    column: int
    file: str = ""

    def __str__(self) -> str:
        place = f"{self.file}:" if self.file else ""
        where = f"{place}{self.line}:{self.column}: " if self.line else ""
        named = f" {self.name!r}" if self.name != self.type else ""
        return f"{where}{self.rule}: removed {self.type}{named}"


@dataclass(frozen=True)
class Compressed:
    """A compressed document and the rewrites that made it, in the order made."""

    document: Document
    rewrites: tuple[Rewrite, ...]


def _plain(node: Node, types: frozenset[str]) -> bool:
    """Whether `node` is of one of `types`, in its own element form, with no `_`-attribute."""
    return node.type in types and not node.form and not any(k.startswith("_") for k, _ in node.attrs)


PRECONDITIONS = frozenset({"_skipIf", "_successIf", "_failureIf", "_while"})
SKIPPING = frozenset({"_skipIf", "_while"})


def _guarded(node: Node) -> bool:
    """Whether `node` has a pre-condition. BT.CPP checks those only when the node is IDLE or
    SKIPPED (TreeNode::checkPreConditions): moved up to a parent that does not reset it between
    ticks (WhileDoElse's condition, PipelineSequence's finished children), it would be ticked
    with its last status kept and skip the check its removed parent's reset made it run."""
    return any(k in PRECONDITIONS for k, _ in node.attrs)


def _may_skip(node: Node) -> bool:
    """Whether `node` may return SKIPPED: a `_skipIf`/`_while`, or anything below it that may
    (a SubTree or an opaque node passes it up as far as we know)."""
    return any(k in SKIPPING for k, _ in node.attrs) or any(_may_skip(c) for c in node.children) \
        or node.type == "SubTree" or node.form == "SubTree"


def _removed(rule: str, node: Node) -> Rewrite:
    return Rewrite(rule, node.type, node.name, node.line, node.column, node.file)


def compress_node(node: Node, log: list[Rewrite], keep: frozenset[int] = frozenset(),
                  origin: dict[int, tuple[Node, Node]] | None = None) -> Node:
    """`node` with the rules applied bottom-up, each rewrite appended to `log`; a node of the
    original whose id() is in `keep` is never removed (a rewrite the prover refuted there)."""
    # id(a node made here) -> (that node, kept alive so that its id is not reused; the original)
    origin = {} if origin is None else origin

    def removable(n: Node) -> bool:
        return id(origin[id(n)][1] if id(n) in origin else n) not in keep

    children = tuple(compress_node(c, log, keep, origin) for c in node.children)
    if node.type in FLATTENED and not node.form:
        flat: list[Node] = []
        for child in children:
            # Sequence and Fallback count their SKIPPED children in a member reset only when they
            # complete or start IDLE (skipped_count_, src/controls/sequence_node.cpp): flattened
            # under a parent that keeps their FAILURE status, the count would run across ticks
            if _plain(child, frozenset({node.type})) and child.children and removable(child) \
                    and not (node.type in ("Sequence", "Fallback") and any(_may_skip(c) for c in child.children)):
                log.append(_removed("flatten", child))
                flat.extend(child.children)
            else:
                flat.append(child)
        children = tuple(flat)
    made = node.with_children(children)
    origin[id(made)] = (made, node)
    if id(node) in keep:
        return made
    if _plain(made, COMPOSITES) and len(children) == 1 and not _guarded(children[0]):
        log.append(_removed("single", made))
        return children[0]
    if _plain(made, frozenset({"Inverter"})) and len(children) == 1 and _plain(children[0], frozenset({"Inverter"})) \
            and len(children[0].children) == 1 and removable(children[0]) and not _guarded(children[0].children[0]):
        log.append(_removed("inverters", made))
        log.append(_removed("inverters", children[0]))
        return children[0].children[0]
    if made.type in FORCES and not made.form and len(children) == 1 and _plain(children[0], FORCES) \
            and len(children[0].children) == 1 and removable(children[0]):
        log.append(_removed("forced", children[0]))
        forced = made.with_children(children[0].children)
        origin[id(forced)] = (forced, node)
        return forced
    return made


def compress(document: Document, keep: frozenset[int] = frozenset()) -> Compressed:
    """Apply the rules to every behaviour tree of `document`, removing no node whose id() is in
    `keep` (bt/prove.py's compress_proved keeps there the nodes of a part it refuted)."""
    log: list[Rewrite] = []
    trees = tuple((tree_id, compress_node(root, log, keep)) for tree_id, root in document.trees)
    return Compressed(document.with_trees(trees), tuple(log))
