"""Task trees for people and programs: the terminal, Graphviz DOT, JSON, and knowledge text.

    tree_json(root)  -> {"label", "agent", "objects", "pre", "post", "releaser",
                         "importance", "k", "merged_from", "children"}
    show_json(task, root) -> {"task", "nodes", "depth", "tree"}

Colours follow the paper's figures: pre-conditions green, post-conditions blue.
"""

from __future__ import annotations

import itertools

from rich.text import Text
from rich.tree import Tree

from ..task import conditions as cond
from .documents import Document
from ..errors import SchemalogError
from ..logic.parse import Clause
from dataclasses import replace

from ..task.schema import DEFAULT_AGENT, Entry, SchemaDef, schema_term
from ..logic.terms import TRUE, Atom, Float, Int, Struct, Term, is_ground, make_list, term_to_text
from ..task.tree import Behaviour, Origin, count_nodes, depth, map_tree, walk

PRE_STYLE = "green"
POST_STYLE = "blue"


def node_json(node: Behaviour) -> dict:
    """One behaviour's fields, without children."""
    return {
        "label": term_to_text(node.label),
        "agent": node.agent,
        "objects": [term_to_text(o) for o in node.objects],
        "pre": cond.to_text(node.pre),
        "releaser": cond.to_text(node.releaser),
        "post": cond.to_text(node.post),
        "importance": node.importance,
        "k": node.k,
        "merged_from": [term_to_text(m) for m in node.merged_from],
    }


def tree_json(root: Behaviour) -> dict:
    """The tree as nested JSON-ready dicts (iterative: deep trees are fine)."""
    out = {**node_json(root), "children": []}
    stack = [(root, out)]
    while stack:
        node, record = stack.pop()
        for child in node.children:
            child_record = {**node_json(child), "children": []}
            record["children"].append(child_record)
            stack.append((child, child_record))
    return out


def show_json(task: Term, root: Behaviour) -> dict:
    """The `show --json` object."""
    return {"task": term_to_text(task), "nodes": count_nodes(root), "depth": depth(root),
            "tree": tree_json(root)}


def rich_tree(root: Behaviour, title: str | None = None, first_id: int | None = None) -> Tree:
    """A rich Tree with each behaviour's agent, objects and conditions (and, given
    `first_id`, its id as the query relations number it: pre-order from `first_id`)."""
    number = itertools.count(first_id) if first_id is not None else None

    def text(node: Behaviour) -> Text:
        shown = _node_text(node)
        return Text.assemble((f"{next(number)} ", "cyan"), shown) if number is not None else shown

    if title:
        top = Tree(Text(title, style="bold"))
        stack = [(root, top)]
    else:
        top = Tree(text(root))
        stack = [(child, top) for child in reversed(root.children)]
    while stack:                      # pre-order, so the ids count as tree_facts numbers them
        node, parent = stack.pop()
        branch = parent.add(text(node))
        stack.extend((child, branch) for child in reversed(node.children))
    return top


def _node_text(node: Behaviour) -> Text:
    text = Text()
    text.append(term_to_text(node.label), style="bold" if node.children else "")
    if node.agent != DEFAULT_AGENT:
        text.append(f" [{node.agent}]", style="magenta")
    if node.k > 1:
        text.append(f" k={node.k}", style="yellow")
    text.append("  pre: ", style="dim")
    text.append(cond.to_text(node.pre), style=PRE_STYLE)
    text.append("  post: ", style="dim")
    text.append(cond.to_text(node.post), style=POST_STYLE)
    return text


def _dot_escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def to_dot(root: Behaviour, name: str = "task") -> str:
    """Graphviz DOT: behaviours as ellipses, pre-conditions green, post-conditions blue."""
    lines = [f'digraph "{_dot_escape(name)}" {{',
             '  graph [rankdir=TB, fontname="Helvetica"];',
             '  node [shape=ellipse, fontname="Helvetica", fontsize=11];',
             '  edge [arrowhead=none];']
    lines.extend(dot_body(root, "n"))
    lines.append("}")
    return "\n".join(lines) + "\n"


def compare_dot(original: Behaviour, compressed: Behaviour, name: str, propagate: str) -> str:
    """Before and after side by side, like the paper's Figure 2."""
    lines = [f'digraph "{_dot_escape(name)}" {{',
             '  graph [rankdir=TB, fontname="Helvetica", newrank=true];',
             '  node [shape=ellipse, fontname="Helvetica", fontsize=11];',
             '  edge [arrowhead=none];',
             '  subgraph cluster_original {',
             '    label="Initial Symbolic Representation";']
    lines.extend("  " + line for line in dot_body(original, "o"))
    lines.append("  }")
    lines.append("  subgraph cluster_merged {")
    lines.append(f'    label="Merged Symbolic Representation (propagate {_dot_escape(propagate)})";')
    lines.extend("  " + line for line in dot_body(compressed, "m"))
    lines.append("  }")
    lines.append("}")
    return "\n".join(lines) + "\n"


def dot_body(root: Behaviour, prefix: str) -> list[str]:
    """The node and edge statements of a tree, ids starting with `prefix`."""
    lines: list[str] = []
    ids: dict[int, str] = {}
    for i, node in enumerate(walk(root)):
        ids[id(node)] = f"{prefix}{i}"
        label = (f"<<b>{_dot_escape(term_to_text(node.label))}</b>"
                 f"<br/><font color=\"darkgreen\">{_dot_escape(cond.to_text(node.pre))}</font>"
                 f"<br/><font color=\"blue\">{_dot_escape(cond.to_text(node.post))}</font>>")
        style = ', style=filled, fillcolor="#eef5ff"' if node.children else ""
        lines.append(f"  {prefix}{i} [label={label}{style}];")
    for node in walk(root):
        for child in node.children:
            lines.append(f"  {ids[id(node)]} -> {ids[id(child)]};")
    return lines


# ---------------------------------------------------------------------------
# A tree as knowledge text: the schemas that instantiate to exactly this tree.
#
# An entry's releaser is the behaviour's whole pre-condition (its propagated context
# folded in, as Algorithm 1 writes it), and a compressed tree's provenance is written
# per entry: origins(Parent, [OriginsOfChild1, ...]) and task_origins(Task, Origins),
# each origin as origin(Label, Releaser, Post, Importance, Position, Slot).

def origin_term(o: Origin) -> Term:
    """An origin as the term origin(Label, Releaser, Post, Importance, Position, Slot)."""
    weight = Int(o.importance) if isinstance(o.importance, int) else Float(o.importance)
    return Struct("origin", (o.label, cond.to_term(o.releaser), cond.to_term(o.post), weight,
                             Int(o.position), Int(o.slot)))


def _signature(node: Behaviour) -> tuple:
    return (tuple((c.label, c.pre, c.importance, c.origins) for c in node.children), node.post,
            node.agent, node.objects)


def _distinct_labels(root: Behaviour) -> Behaviour:
    """Rename (name_2, name_3, ...) a behaviour whose label another, different one has."""
    seen: dict[Term, tuple] = {}
    used: set[Term] = {b.label for b in walk(root)}

    def settle(node: Behaviour, _position: int) -> Behaviour:
        sig = _signature(node)
        known = seen.get(node.label)
        if known is None or known == sig:
            seen[node.label] = sig
            return node
        n = 2
        while True:
            name = f"{node.label.name}_{n}" if isinstance(node.label, (Atom, Struct)) else f"b_{n}"
            label = Struct(name, node.label.args) if isinstance(node.label, Struct) else Atom(name)
            if label not in used and label not in seen:
                break
            n += 1
        used.add(label)
        seen[label] = sig
        return replace(node, label=label)
    return map_tree(root, settle)


# What a written tree states itself; every other clause of its source is carried over.
STRUCTURE = frozenset({("schema", 3), ("schema", 2), ("goal", 2), ("task", 1), ("object", 1),
                       ("objects", 2), ("agent", 2), ("behaviour", 1), ("origins", 2),
                       ("task_origins", 2)})


def carried_clauses(kb) -> list[Clause]:
    """The source's clauses that are not tree structure: initial/1, no_merge/1, rules..."""
    from ..logic.terms import indicator
    return [Clause(c.head, c.body, c.pos) for c in kb.user_clauses()
            if indicator(c.head) not in STRUCTURE]


def tree_document(root: Behaviour, file: str = "<tree>", carried: list[Clause] = ()) -> Document:
    """Ground schema knowledge whose task (the root's label) instantiates to `root` again,
    followed by the `carried` clauses of its source (initial state, no_merge/1, rules)."""
    root = _distinct_labels(root)
    schemas: dict[Term, SchemaDef] = {}
    order: list[Term] = []
    agents: dict[Term, str] = {}
    objects_of: dict[Term, tuple[Term, ...]] = {}
    all_objects: list[Term] = []
    provenance: dict[Term, Term] = {}
    with_origins = bool(root.origins)
    for node in walk(root):
        if not is_ground(node.label):
            raise SchemalogError(f"cannot write {term_to_text(node.label)} as knowledge: it is not ground")
        if node.label not in schemas:
            entries = tuple(Entry(c.label, c.pre, c.importance) for c in node.children)
            schemas[node.label] = SchemaDef(node.label, entries, node.post)
            order.append(node.label)
            if with_origins and node.children:
                provenance[node.label] = make_list(
                    [make_list([origin_term(o) for o in c.origins]) for c in node.children])
        if node.agent != DEFAULT_AGENT:
            agents[node.label] = node.agent
        objects_of[node.label] = node.objects
        for o in node.objects:
            if o not in all_objects:
                all_objects.append(o)
    clauses: list[Clause] = [Clause(Struct("task", (root.label,)), TRUE, None)]
    clauses += [Clause(Struct("object", (o,)), TRUE, None) for o in all_objects]
    object_set = set(all_objects)
    for label in order:
        derived = tuple(a for a in (label.args if isinstance(label, Struct) else ()) if a in object_set)
        if derived != objects_of[label]:
            clauses.append(Clause(Struct("objects", (label, make_list(objects_of[label]))), TRUE, None))
    clauses += [Clause(Struct("agent", (label, Atom(agent))), TRUE, None) for label, agent in agents.items()]
    clauses += [Clause(schema_term(schemas[label]), TRUE, None) for label in order]
    if with_origins:
        clauses.append(Clause(Struct("task_origins", (root.label, make_list(
            [origin_term(o) for o in root.origins]))), TRUE, None))
        clauses += [Clause(Struct("origins", (label, terms)), TRUE, None) for label, terms in provenance.items()]
    clauses += list(carried)
    return Document(tuple(clauses), file)


__all__ = ["node_json", "tree_json", "show_json", "rich_tree", "to_dot", "dot_body", "compare_dot",
           "tree_document", "carried_clauses", "origin_term", "STRUCTURE"]
