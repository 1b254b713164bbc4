"""What changed in behaviour between two versions of a BT.CPP program, place by place, for a
reviewer (docs/behaviour_trees.md, "Reviewing a change: schemalog diff").

    Comparison = Comparison(verdict, direction, places, trees_added, trees_removed, main)
    Place    = Place(a, b, changes, effect, verdict)    one subtree pair where the programs differ
    Effect   = "changes behaviour" | "same behaviour" | "same behaviour here" | "undecided" | "not run"
    Direction= "equal" | "b within a" | "a within b" | "neither" | "unknown"

The places are the pairs of subtrees where the two programs part structurally, top-down: below
two nodes BT.CPP reads alike the children are compared pairwise, elsewhere the two nodes are a
place (bt/prove._parts, the units that verify proves by parts). A place's changes are its edits
in a reader's words, found by aligning the children of the two nodes on their structure
(attributes by name, as BT.CPP reads them): "B retries FollowPath 5 times instead of 6", "B
ticks GoalUpdated before ComputePathToPose". Each place is then decided on runs, never on text:

    same behaviour        the two subtrees are equal in every context their parent can make
                          (prove_equal contextual): the edit is a pure refactoring, anywhere
    same behaviour here   not so in every context, but the program with only this edit made
                          is proved equal to A: a refactoring in this program
    changes behaviour     the program with only this edit made is refuted against A: the
                          place's shortest run shows it (when it is the only place that can
                          differ, the whole pair's counterexample is that run, by congruence)
    undecided             a limit stopped the proof that would tell

The whole pair is proved as verify proves it (bt/prove.prove_by_parts); its verdict is the
answer (exit 0 equal, 1 different, 3 no proof), the places explain it. A direction is given where
one holds: every run of B is a run of A (B only removes behaviour: where A's node may answer
RUNNING, B's never does), or the converse, proved by trace inclusion (prove_equal subset).
Edits can mask or complete each other, so the places are each decided alone, and the whole
verdict stays the truth about the pair. `max_states` is one budget for all of it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

from schemalog.bt.model import Document, Node
from schemalog.bt.prove import (Verdict, _alike, _congruent, _context, _kind_differences, _part, _parts, describe,
                                prove_by_parts, prove_equal)
from schemalog.bt.semantics import Rule, _where

SAME, SAME_HERE, CHANGES, UNDECIDED = "same behaviour", "same behaviour here", "changes behaviour", "undecided"
NOT_RUN = "not run"                   # in a BehaviorTree the main tree does not reach: no run ticks it


@dataclass(frozen=True)
class Place:
    """A subtree of A and its counterpart in B where the programs part, what changed there, and
    what that does to the program's runs (`effect`, with the verdict that decided it)."""

    tree: str                            # the BehaviorTree ID it is in
    a: Node
    b: Node
    changes: tuple[str, ...]
    effect: str = UNDECIDED
    verdict: Verdict | None = None
    edit: Node | None = None             # what stands for `a` when this edit alone is made (else `b`):
                                         # B's node over A's children where B changes a node's own attributes

    @property
    def where(self) -> str:
        """The place on both sides, as "a.xml:12:5 / b.xml:12:5"."""
        return f"{_where(self.a) or '?'} / {_where(self.b) or '?'}"


@dataclass(frozen=True)
class Comparison:
    """Two programs compared: the whole pair's verdict, the direction that holds, the places
    where they part (behavioural first, in document order), trees only one side defines."""

    verdict: Verdict
    direction: str
    direction_verdict: Verdict | None
    places: tuple[Place, ...]
    trees_added: tuple[str, ...] = ()
    trees_removed: tuple[str, ...] = ()
    main: tuple[str, str] = ("", "")

    @property
    def equal(self) -> bool:
        return self.verdict.equal and self.verdict.complete

    @property
    def complete(self) -> bool:
        return self.verdict.complete

    @property
    def behavioural(self) -> tuple[Place, ...]:
        return tuple(p for p in self.places if p.effect == CHANGES)

    @property
    def refactorings(self) -> tuple[Place, ...]:
        return tuple(p for p in self.places if p.effect in (SAME, SAME_HERE))

    @property
    def undecided(self) -> tuple[Place, ...]:
        return tuple(p for p in self.places if p.effect == UNDECIDED)

    @property
    def not_run(self) -> tuple[Place, ...]:
        return tuple(p for p in self.places if p.effect == NOT_RUN)

    def first_divergence(self) -> tuple[str, str] | None:
        """The events (or root ends) where the whole pair's runs part, each side's node by
        file:line:col, as (a's, b's); None without a counterexample."""
        cex = self.verdict.counterexample
        if cex is None:
            return None
        return _last(cex.ticks_a), _last(cex.ticks_b)


def _last(ticks) -> str:
    if not ticks:
        return "nothing"
    t = ticks[-1]
    if t.status is None and not t.error and t.events:
        return describe(t.events[-1])
    if t.error:
        return f"the root tick throws: {t.error}"
    end = f"the root tick ends {t.status.value}" if t.status is not None else "the root tick stops"
    return (f"{describe(t.events[-1])}, then {end}" if t.events else end) + (" and asks to be ticked again at once"
                                                                            if t.woken else "")


def diff_documents(a: Document, b: Document, *, max_states: int, max_events_per_tick: int,
                   rules: Mapping[str, Rule] | None = None, halts: bool = True) -> Comparison:
    """Compare two documents: the whole pair proved as verify proves it, the places where they
    part described and each decided on runs, the direction that holds."""
    explore = dict(max_events_per_tick=max_events_per_tick, rules=rules)
    units = _units(a, b)
    places: list[Place] = []
    known: dict = {}                  # the places' proofs, which the whole pair's proof by parts reuses
    spent = 0
    reached = _reached(a) & _reached(b)
    for tree_id, na, nb, parent, shown in units:
        changes = tuple(changes_of(na, nb))
        if tree_id not in reached:
            # a tree no run of either main tree calls: the edit changes nothing a robot does
            # with these files, and is no refactoring either; said as such, proved nothing
            places.append(Place(tree_id, na, shown, changes, NOT_RUN, None, None if nb is shown else nb))
            continue
        v, k = _congruent(_part(a, na), _part(b, nb), max_states=max(max_states - spent, 0), **explore,
                          **_context(na is a.root, parent, rules, halts))
        spent += v.states
        if nb is shown:
            known[(id(na), id(nb))] = (v, k)
        effect = SAME if v.equal and v.complete else CHANGES if not v.equal else UNDECIDED
        places.append(Place(tree_id, na, shown, changes, effect, v, None if nb is shown else nb))
    order = _same_parts(a, b, rules, known) if all(p.effect != NOT_RUN for p in places) else None
    if order is not None:
        # verify's proof by parts proves exactly these parts, in this order, up to the first that
        # is not equal in every context: it takes those proofs (their states counted once)
        used: dict = {}
        for key in order:
            used[key] = known[key]
            if not (known[key][0].equal and known[key][0].complete):
                break
        credit = sum(v.states for v, _ in used.values())
        whole = prove_by_parts(a, b, max_states=max(max_states - spent + credit, 0), halts=halts, known=used,
                               **explore)
        spent += whole.states - credit
    else:
        whole = prove_by_parts(a, b, max_states=max(max_states - spent, 0), halts=halts, **explore)
        spent += whole.states
    # A place not equal in every context may still make no difference in this program, or make
    # the one the whole pair shows: decide it on the program with only this edit made
    open_ = [i for i, p in enumerate(places) if p.effect not in (SAME, NOT_RUN)]
    if len(open_) == 1 and whole.complete and (len(places) == 1 or all(p.edit is None for p in places)):
        # every other place is a subtree of A replaced by one of B, equal in every context: A
        # with this edit alone is B (congruence). (An edit of a node's own attributes is
        # proved over A's children, which B may have changed too: no such shortcut then, unless it
        # is the only place: then A with it alone is B.)
        i = open_[0]
        places[i] = replace(places[i], effect=SAME_HERE if whole.equal else CHANGES, verdict=whole)
    else:
        for i in open_:
            p = places[i]
            if spent >= max_states:
                places[i] = replace(p, effect=UNDECIDED,
                                    verdict=Verdict(True, False, 0, f"not decided: {max_states} states explored "
                                                                    f"(max_states) before this place's turn"))
                continue
            hybrid = _with(a, p.a, p.edit or p.b)
            v = prove_by_parts(a, hybrid, max_states=max_states - spent, halts=halts, **explore)
            spent += v.states
            effect = (SAME_HERE if v.equal and v.complete else CHANGES if not v.equal else UNDECIDED)
            places[i] = replace(p, effect=effect, verdict=v)
    direction, direction_verdict, spent = _direction(a, b, whole, spent, max_states, halts, explore)
    ids_a, ids_b = [t for t, _ in a.trees], [t for t, _ in b.trees]
    order = {CHANGES: 0, UNDECIDED: 1, SAME_HERE: 2, SAME: 3, NOT_RUN: 4}
    ranked = tuple(sorted(places, key=lambda p: order[p.effect]))
    total = replace(whole, states=spent)
    return Comparison(total, direction, direction_verdict, ranked,
                    tuple(t for t in ids_b if t not in ids_a), tuple(t for t in ids_a if t not in ids_b),
                    (a.main, b.main))


def _same_parts(a: Document, b: Document, rules, known: dict) -> list | None:
    """The subtree pairs bt/prove.prove_by_parts proves `a` and `b` through, in its order, when
    they are exactly those of `known` (by identity); else None."""
    if [i for i, _ in a.trees] != [i for i, _ in b.trees] or a.main != b.main or a.version != b.version \
            or _kind_differences(a, b, rules):
        return None
    parts = [(id(na), id(nb)) for (_, ra), (_, rb) in zip(a.trees, b.trees) for na, nb, _ in _parts(ra, rb, None, a, b)]
    return parts if len(parts) == len(known) and set(parts) == set(known) else None


def _direction(a: Document, b: Document, whole: Verdict, spent: int, max_states: int, halts: bool,
               explore: dict) -> tuple[str, Verdict | None, int]:
    """Which of the two holds, every run of B a run of A or the converse, with the verdict that
    shows it. Where the pair's first divergence is a different event or root end (not a node
    that may answer more outcomes on one side), its run is in one program and not in the other,
    both ways: neither holds, and that run shows it."""
    if whole.equal:
        return ("equal" if whole.complete else "unknown"), None, spent
    cex = whole.counterexample
    if cex is None or " may have " not in cex.difference:
        return "neither", None, spent
    found: list[tuple[str, Verdict]] = []
    for name, x, y in (("b within a", a, b), ("a within b", b, a)):
        if spent >= max_states:
            return "unknown", None, spent
        v = prove_equal(x, y, max_states=max_states - spent, halts=halts, subset=True, **explore)
        spent += v.states
        if v.equal and v.complete:
            return name, v, spent
        found.append((name, v))
    return ("neither" if all(not v.equal for _, v in found) else "unknown"), None, spent


def _reached(document: Document) -> set[str]:
    """The IDs of the trees a run of the main tree may tick: the main tree, and every tree a
    SubTree call reaches from it."""
    from schemalog.bt.model import walk
    from schemalog.bt.semantics import subtree_id

    trees = dict(document.trees)
    seen, todo = {document.main}, [document.main]
    while todo:
        root = trees.get(todo.pop())
        for n in walk(root) if root is not None else ():
            called = subtree_id(n)
            if called is not None and called not in seen:
                seen.add(called)
                todo.append(called)
    return seen


def _units(a: Document, b: Document) -> list[tuple[str, Node, Node, str | None]]:
    """The places where the documents part: the main trees' (compared whatever their IDs), then
    every other tree both define, by ID."""
    out = [(a.main, *p) for p in _places(a.root, b.root, None, a, b)]
    others_b = dict(b.trees)
    for tree_id, ra in a.trees:
        if tree_id in (a.main, b.main) or tree_id not in others_b:
            continue
        out.extend((tree_id, *p) for p in _places(ra, others_b[tree_id], None, a, b))
    return out


def _places(a: Node, b: Node, parent: str | None, da: Document,
            db: Document) -> list[tuple[Node, Node, str | None, Node]]:
    """bt/prove._parts, each as (A's node, what replaces it for the edit alone, parent type, B's
    node), but a node whose children B reorders is one place (its edits "B ticks X before Y"),
    not one per position the reordering moved something into; and a node whose own attributes B
    changes is a place of its own (B's node over A's children), its children compared apart."""
    same_shape = (a.type, a.form, len(a.children)) == (b.type, b.form, len(b.children))
    if not same_shape or _moves(a, b):
        return [(a, b, parent, b)]
    under = (a.type if not a.form else None) or "\0custom"      # a generic-form node is a custom one: opaque
    below = [p for ca, cb in zip(a.children, b.children) for p in _places(ca, cb, under, da, db)]
    if _alike(a, b, da, db):
        return below
    if not a.children:
        return [(a, b, parent, b)]
    own = Node(b.type, b.attrs, a.children, b.form, b.line, b.column, b.file)
    return [(a, own, parent, b), *below]


def _with(document: Document, old: Node, new: Node) -> Document:
    """`document` with the subtree `old` (by identity) replaced by `new`."""
    def swap(n: Node) -> Node:
        if n is old:
            return new
        if not n.children:
            return n
        kids = tuple(swap(c) for c in n.children)
        return n if all(k is c for k, c in zip(kids, n.children)) else n.with_children(kids)
    return replace(document, trees=tuple((i, swap(r)) for i, r in document.trees))


def _loose(n: Node) -> tuple:
    """A child as a reviewer recognises it across an edit: type, form, name, the tree a SubTree
    calls; not its other attributes or children (edited in place, it is still that child)."""
    return (n.type, n.form, n.attr("name"), n.attr("ID"))


def _moves(a: Node, b: Node) -> bool:
    """Whether B moves a child of `a`: one recognisable in both (_loose), out of their longest
    common order."""
    ka, kb = [_loose(c) for c in a.children], [_loose(c) for c in b.children]
    if ka == kb:
        return False
    kept = _lcs(ka, kb)
    left_a = {ka[i] for i in range(len(ka)) if i not in {i for i, _ in kept}}
    return any(kb[j] in left_a for j in range(len(kb)) if j not in {j for _, j in kept})


# ---------------------------------------------------------------------------------------------
# The edits at a place, in a reader's words

def _canon(n: Node) -> tuple:
    """A node and its subtree as BT.CPP reads them: attributes by name, in no order."""
    return (n.type, n.form, tuple(sorted(n.attrs)), tuple(_canon(c) for c in n.children))


def label(n: Node) -> str:
    """A node as a reviewer names it: its type, and its name where it has one ("RecoveryNode
    "NavigateRecovery""); a SubTree call by the tree it calls."""
    if n.type == "SubTree" and not n.form:
        head = f"SubTree {n.attr('ID')}"
    else:
        head = n.type
    name = n.attr("name")
    return f"{head} \"{name}\"" if name and name != n.type else head


def _child_label(n: Node) -> str:
    """What a decorator or control node acts on, for a sentence: its child (the first of several)."""
    return label(n.children[0]) if n.children else label(n)


def _times(v: str) -> str:
    return "without end" if v.strip() == "-1" else f"{v} time{'' if v.strip() == '1' else 's'}"


def _instead(new: str, old: str) -> str:
    """"5 times instead of 6", "without end instead of 3 times"."""
    if "-1" not in (new.strip(), old.strip()):
        return f"{_times(new)} instead of {old}"
    return f"{_times(new)} instead of {_times(old)}"


# Ports whose value a reviewer reads as a behaviour: (node type, port) -> sentence(node, old, new)
_PORT_WORDS = {
    ("RetryUntilSuccessful", "num_attempts"):
        lambda n, old, new: f"B tries {_child_label(n)} {_instead(new, old)}",
    ("Repeat", "num_cycles"):
        lambda n, old, new: f"B repeats {_child_label(n)} {_instead(new, old)}",
    ("RecoveryNode", "number_of_retries"):
        lambda n, old, new: f"B retries {_child_label(n)} {_instead(new, old)}",
    ("Timeout", "msec"):
        lambda n, old, new: f"B gives {_child_label(n)} {new} ms instead of {old} ms before halting it",
    ("Delay", "delay_msec"):
        lambda n, old, new: f"B waits {new} ms instead of {old} ms before ticking {_child_label(n)}",
    ("RateController", "hz"):
        lambda n, old, new: f"B ticks {_child_label(n)} at {new} Hz instead of {old} Hz",
    ("Parallel", "success_count"):
        lambda n, old, new: f"B's Parallel succeeds after {new} children succeed instead of {old}",
    ("Parallel", "failure_count"):
        lambda n, old, new: f"B's Parallel fails after {new} children fail instead of {old}",
}


def _attribute_changes(na: Node, nb: Node) -> list[str]:
    """The attributes of one node that B adds, drops or sets otherwise, in a reader's words."""
    old, new = dict(na.attrs), dict(nb.attrs)
    out = []
    for key in dict.fromkeys([*old, *new]):
        if old.get(key) == new.get(key):
            continue
        if key in old and key in new:
            words = _PORT_WORDS.get((na.type, key))
            out.append(words(na, old[key], new[key]) if words else
                       f"B sets {key}=\"{new[key]}\" on {label(na)} (A: \"{old[key]}\")")
        elif key in new:
            out.append(f"B adds {key}=\"{new[key]}\" to {label(na)}")
        else:
            out.append(f"B drops {key}=\"{old[key]}\" from {label(na)}")
    return out


def _lcs(xs: list, ys: list) -> list[tuple[int, int]]:
    """The index pairs of a longest common subsequence of xs and ys."""
    n, m = len(xs), len(ys)
    table = [[0] * (m + 1) for _ in range(n + 1)]
    for i in range(n - 1, -1, -1):
        for j in range(m - 1, -1, -1):
            table[i][j] = table[i + 1][j + 1] + 1 if xs[i] == ys[j] else max(table[i + 1][j], table[i][j + 1])
    out, i, j = [], 0, 0
    while i < n and j < m:
        if xs[i] == ys[j]:
            out.append((i, j))
            i, j = i + 1, j + 1
        elif table[i + 1][j] >= table[i][j + 1]:
            i += 1
        else:
            j += 1
    return out


_TICKING = {"Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory",
            "PipelineSequence", "RecoveryNode", "RoundRobin", "AsyncSequence", "AsyncFallback"}


def changes_of(na: Node, nb: Node, depth: int = 0) -> list[str]:
    """The edits that turn subtree `na` into `nb`, in a reader's words, each naming where."""
    if _canon(na) == _canon(nb):
        return []
    if (na.type, na.form) != (nb.type, nb.form):
        if len(nb.children) == 1 and _canon(nb.children[0]) == _canon(na):
            return [f"B wraps {label(na)} in {label(nb)}{_attrs_text(nb)}"]
        if len(na.children) == 1 and _canon(na.children[0]) == _canon(nb):
            return [f"B removes the {label(na)} around {label(nb)}"]
        if len(na.children) == len(nb.children) and all(_canon(x) == _canon(y) for x, y in
                                                        zip(na.children, nb.children)) and na.children:
            return [f"B has {label(nb)}{_attrs_text(nb)} where A has {label(na)}{_attrs_text(na)}, over the same "
                    f"children"]
        if na.type == nb.type:                          # <Action ID="X"/> and <Condition ID="X"/>
            return [f"B has <{nb.form or nb.type}> {label(nb)} where A has <{na.form or na.type}> {label(na)}"]
        return [f"B has {label(nb)}{_attrs_text(nb)} where A has {label(na)}{_attrs_text(na)}"]
    out = _attribute_changes(na, nb)
    ka, kb = [_canon(c) for c in na.children], [_canon(c) for c in nb.children]
    if ka == kb:
        return out
    if len(ka) == len(kb) and sorted(ka) != sorted(kb) and all(
            (x.type, x.form) == (y.type, y.form) for x, y in zip(na.children, nb.children)):
        # the same children, each edited in place
        for x, y in zip(na.children, nb.children):
            out.extend(changes_of(x, y, depth + 1))
        return out
    la, lb = [_loose(c) for c in na.children], [_loose(c) for c in nb.children]
    kept = _lcs(la, lb)
    kept_a, kept_b = {i for i, _ in kept}, {j for _, j in kept}
    for i, j in kept:                        # recognisable children in the common order: edited in place
        out.extend(changes_of(na.children[i], nb.children[j], depth + 1))
    gone = [i for i in range(len(la)) if i not in kept_a]
    new = [j for j in range(len(lb)) if j not in kept_b]
    verb = "ticks" if na.type in _TICKING else "puts"
    # a child in both, out of the common order: moved (and perhaps edited too)
    for j in list(new):
        match = next((i for i in gone if la[i] == lb[j]), None)
        if match is not None:
            gone.remove(match)
            new.remove(j)
            # said from what is now before it: A ticked it earlier ("B ticks GoalUpdated before
            # ComputePathToPose" where A ticks ComputePathToPose first)
            moved = label(nb.children[j])
            if j > 0:
                out.append(f"B {verb} {label(nb.children[j - 1])} before {moved}")
            else:
                out.append(f"B {verb} {moved} first in {label(nb)}")
            out.extend(changes_of(na.children[match], nb.children[j], depth + 1))
    # a child of the same type on both sides, or wrapped in one, in what is left: edited
    for j in list(new):
        match = next((i for i in gone if _related(na.children[i], nb.children[j])), None)
        if match is not None:
            gone.remove(match)
            new.remove(j)
            out.extend(changes_of(na.children[match], nb.children[j], depth + 1))
    for i in gone:
        out.append(f"B removes {label(na.children[i])} ({_where(na.children[i]) or 'A'}) from {label(na)}")
    for j in new:
        after = nb.children[j + 1] if j + 1 < len(kb) else None
        at = f"before {label(after)}" if after is not None else "at the end"
        out.append(f"B adds {label(nb.children[j])} ({_where(nb.children[j]) or 'B'}) to {label(nb)}, {at}")
    return out


def _related(x: Node, y: Node) -> bool:
    """Whether `y` is `x` edited: the same type, or `x` wrapped in `y` or unwrapped."""
    return ((x.type, x.form) == (y.type, y.form) or len(y.children) == 1 and _canon(y.children[0]) == _canon(x)
            or len(x.children) == 1 and _canon(x.children[0]) == _canon(y))


def _attrs_text(n: Node) -> str:
    shown = [(k, v) for k, v in n.attrs if k != "name"]
    return "".join(f" {k}=\"{v}\"" for k, v in shown)
