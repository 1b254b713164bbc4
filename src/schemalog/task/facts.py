"""A task tree as Prolog facts, so rules such as kb/compression.pl can be queried over it.

    node(Id, Label)   parent(Id, ParentId)   child(ParentId, Id)   depth(Id, Level)
    agent(Id, Agent)  objects(Id, [O, ...])  k(Id, K)              leaf(Id)
    pre(Id, C)        entry(Id, C)           post(Id, C)           kind(Id, action | subtask)

Ids are pre-order positions from `first` (the root; 0 by default); the root's level is 1;
conditions are canonical terms, so two equal conditions unify.
"""

from __future__ import annotations

from . import conditions as cond
from ..logic.kb import KnowledgeBase
from ..shipped import shipped_text
from ..logic.terms import Atom, Int, Struct, Term, make_list
from .tree import Behaviour


def tree_facts(root: Behaviour, first: int = 0) -> list[Term]:
    """The facts describing every behaviour of `root`, numbered from `first` in pre-order."""
    facts: list[Term] = []
    stack: list[tuple[Behaviour, int | None, int]] = [(root, None, 1)]
    next_id = first
    while stack:
        node, parent, level = stack.pop()
        me = Int(next_id)
        next_id += 1
        facts.append(Struct("node", (me, node.label)))
        if parent is not None:
            facts.append(Struct("parent", (me, Int(parent))))
            facts.append(Struct("child", (Int(parent), me)))
        facts.append(Struct("depth", (me, Int(level))))
        facts.append(Struct("agent", (me, Atom(node.agent))))
        facts.append(Struct("objects", (me, make_list(node.objects))))
        for name, c in (("pre", node.pre), ("entry", node.entry), ("post", node.post)):
            facts.append(Struct(name, (me, cond.to_term(cond.canonical(c)))))
        facts.append(Struct("k", (me, Int(node.k))))
        facts.append(Struct("kind", (me, Atom("subtask" if node.children else "action"))))
        if not node.children:
            facts.append(Struct("leaf", (me,)))
        stack.extend((child, me.value, level + 1) for child in reversed(node.children))
    return facts


def compression_kb(root: Behaviour, user: KnowledgeBase | None = None) -> KnowledgeBase:
    """kb/compression.pl with the facts of `root` (and the user's no_merge/1 clauses)."""
    kb = KnowledgeBase()
    kb.consult_text(shipped_text("kb/compression.pl"), "kb/compression.pl")
    kb.add_facts(tree_facts(root))
    if user is not None:
        for clause in user.clauses("no_merge", 1):
            kb.add_clause(clause.head, clause.body, clause.pos)
    return kb
