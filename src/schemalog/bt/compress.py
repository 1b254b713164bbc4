"""Compression of behaviour trees under BT.CPP 4's semantics: rewrites that leave every
leaf tick, halt, script and root status as it was (docs/semantics.md, "Behaviour trees").

    compress(document, keep_names=True) -> Compressed(document, rewrites, kept)
    Rewrite = (rule, type, name, line, column)   one rewrite, where it was made in the original;
                                                 in `kept`, a named node that rule would remove

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
from IDLE, so flattened under such a parent it would count skips across ticks). Custom nodes,
opaque ones and everything else are kept as they are, ports and remapping included.

A node that carries a `name` attribute is never removed (issue 48, item 4), whatever the name,
one equal to its type included: a name is part of the tree's interface. BT.CPP's substitution
rules match a node by its name or its path (BehaviorTreeFactory::instantiateTreeNode: `filter ==
name`, or a wildcard over `config.path`, the SubTree instances above it and its name), and so
do Groot2, loggers and monitors. BT.CPP's own t15 example substitutes the Sequence `counting`
with a TestNode; flattened away, that rule matches nothing and the three SaySomething below it
run. The node a rule removes, kept when named: `flatten` the inner composite; `single` the
composite; `inverters` both Inverters (the pair is kept when either is named); `forced` the
inner one, except that of two of the same type with the outer unnamed and without a
`_`-attribute, the outer goes instead (they do the same). `Compressed.kept` lists each named
node kept so, with the rule that would have removed it; `keep_names=False` removes them as
before (`--drop-names`).
"""

from __future__ import annotations

import json
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

    @property
    def node(self) -> str:
        """The node as a person finds it: `file:line:column Type "name"` (the name quoted as
        JSON quotes it, so a control character in it cannot drive the terminal)."""
        place = f"{self.file}:" if self.file else ""
        where = f"{place}{self.line}:{self.column} " if self.line else ""
        return f"{where}{self.type} {json.dumps(self.name, ensure_ascii=False)}"


@dataclass(frozen=True)
class Compressed:
    """A compressed document, the rewrites that made it in the order made, and the named nodes a
    rewrite would have removed, kept (each with that rule), in the order met."""

    document: Document
    rewrites: tuple[Rewrite, ...]
    kept: tuple[Rewrite, ...] = ()


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


def named(node: Node) -> bool:
    """Whether `node` carries a `name` attribute (BT.CPP names it after its type only without one)."""
    return node.attr("name") is not None


def compress_node(node: Node, log: list[Rewrite], keep: frozenset[int] = frozenset(),
                  origin: dict[int, tuple[Node, Node]] | None = None, kept: dict[int, Rewrite] | None = None) -> Node:
    """`node` with the rules applied bottom-up, each rewrite appended to `log`; a node of the
    original whose id() is in `keep` is never removed (a rewrite the prover refuted there). With
    `kept` (a dict), a node with a `name` attribute is never removed either, and `kept` maps the
    id() of each such node of the original to the rewrite that would have removed it (the first
    rule met); with None, named nodes go as any other."""
    # id(a node made here) -> (that node, kept alive so that its id is not reused; the original)
    origin = {} if origin is None else origin

    def original(n: Node) -> Node:
        return origin[id(n)][1] if id(n) in origin else n

    def removable(n: Node) -> bool:
        return id(original(n)) not in keep

    def spared(rule: str, n: Node) -> bool:
        """Whether `n`, which `rule` would remove, stays for its name (and say so in `kept`)."""
        if kept is None or not named(n):
            return False
        kept.setdefault(id(original(n)), _removed(rule, n))
        return True

    children = tuple(compress_node(c, log, keep, origin, kept) for c in node.children)
    if node.type in FLATTENED and not node.form:
        flat: list[Node] = []
        for child in children:
            # Sequence and Fallback count their SKIPPED children in a member reset only when they
            # complete or start IDLE (skipped_count_, src/controls/sequence_node.cpp): flattened
            # under a parent that keeps their FAILURE status, the count would run across ticks
            if _plain(child, frozenset({node.type})) and child.children and removable(child) \
                    and not (node.type in ("Sequence", "Fallback") and any(_may_skip(c) for c in child.children)) \
                    and not spared("flatten", child):
                log.append(_removed("flatten", child))
                flat.extend(child.children)
            else:
                flat.append(child)
        children = tuple(flat)
    made = node.with_children(children)
    origin[id(made)] = (made, node)
    if id(node) in keep:
        return made
    if _plain(made, COMPOSITES) and len(children) == 1 and not _guarded(children[0]) and not spared("single", made):
        log.append(_removed("single", made))
        return children[0]
    if _plain(made, frozenset({"Inverter"})) and len(children) == 1 and _plain(children[0], frozenset({"Inverter"})) \
            and len(children[0].children) == 1 and removable(children[0]) and not _guarded(children[0].children[0]):
        # the pair goes together or stays together: either one's name keeps both
        outer, inner = spared("inverters", made), spared("inverters", children[0])
        if outer or inner:
            return made
        log.append(_removed("inverters", made))
        log.append(_removed("inverters", children[0]))
        return children[0].children[0]
    if made.type in FORCES and not made.form and len(children) == 1 and _plain(children[0], FORCES) \
            and len(children[0].children) == 1 and removable(children[0]):
        if kept is not None and named(children[0]):
            if children[0].type == made.type and _plain(made, FORCES) and not named(made):
                # two of one type do the same: the unnamed outer one goes, the named one stays
                log.append(_removed("forced", made))
                return children[0]
            spared("forced", children[0])
            return made
        log.append(_removed("forced", children[0]))
        forced = made.with_children(children[0].children)
        origin[id(forced)] = (forced, node)
        return forced
    return made


def compress(document: Document, keep: frozenset[int] = frozenset(), keep_names: bool = True) -> Compressed:
    """Apply the rules to every behaviour tree of `document`, removing no node whose id() is in
    `keep` (bt/prove.py's compress_proved keeps there the nodes of a part it refuted), and, with
    `keep_names`, no node that carries a `name` attribute (listed in `kept`)."""
    log: list[Rewrite] = []
    kept: dict[int, Rewrite] | None = {} if keep_names else None
    trees = tuple((tree_id, compress_node(root, log, keep, None, kept)) for tree_id, root in document.trees)
    return Compressed(document.with_trees(trees), tuple(log), tuple(kept.values()) if kept else ())
