"""Task trees for people and programs: the terminal, Graphviz DOT, JSON, and knowledge text.

    tree_json(root)  -> {"label", "agent", "objects", "pre", "post", "releaser",
                         "importance", "k", "merged_from", "children"}
    show_json(task, root) -> {"task", "nodes", "depth", "tree"}

Colours follow the paper's figures: pre-conditions green, post-conditions blue.
"""

from __future__ import annotations

from rich.text import Text
from rich.tree import Tree

from . import conditions as cond
from .documents import Document
from .errors import SchemalogError
from .parse import Clause
from .schema import DEFAULT_AGENT, Entry, SchemaDef, schema_term
from .terms import TRUE, Atom, Struct, Term, is_ground, make_list, term_to_text
from .tree import Behaviour, count_nodes, depth, walk

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


def rich_tree(root: Behaviour, title: str | None = None) -> Tree:
    """A rich Tree with each behaviour's agent, objects and conditions."""
    top = Tree(Text(title, style="bold") if title else _node_text(root))
    start = top if not title else top.add(_node_text(root))
    stack = [(root, start)]
    while stack:
        node, branch = stack.pop()
        added = [(child, branch.add(_node_text(child))) for child in node.children]
        stack.extend(reversed(added))
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

def tree_document(task: Term, root: Behaviour, file: str = "<tree>") -> Document:
    """Ground schema knowledge whose `task` instantiates to `root` again."""
    schemas: dict[Term, SchemaDef] = {}
    order: list[Term] = []
    agents: dict[Term, str] = {}
    objects_of: dict[Term, tuple[Term, ...]] = {}
    all_objects: list[Term] = []
    for node in walk(root):
        if not is_ground(node.label):
            raise SchemalogError(f"cannot write {term_to_text(node.label)} as knowledge: it is not ground")
        entries = tuple(Entry(c.label, c.releaser, c.importance) for c in node.children)
        s = SchemaDef(node.label, entries, node.post)
        known = schemas.get(node.label)
        if known is None:
            schemas[node.label] = s
            order.append(node.label)
        elif (known.entries, known.post) != (entries, node.post):
            raise SchemalogError(f"two behaviours labelled {term_to_text(node.label)} differ; "
                                 f"they cannot be written as one schema")
        if node.agent != DEFAULT_AGENT:
            agents[node.label] = node.agent
        objects_of[node.label] = node.objects
        for o in node.objects:
            if o not in all_objects:
                all_objects.append(o)
    clauses: list[Clause] = [Clause(Struct("task", (task,)), TRUE, None)]
    clauses += [Clause(Struct("object", (o,)), TRUE, None) for o in all_objects]
    object_set = set(all_objects)
    for label in order:
        derived = tuple(a for a in (label.args if isinstance(label, Struct) else ()) if a in object_set)
        if derived != objects_of[label]:
            clauses.append(Clause(Struct("objects", (label, make_list(objects_of[label]))), TRUE, None))
    clauses += [Clause(Struct("agent", (label, Atom(agent))), TRUE, None) for label, agent in agents.items()]
    clauses += [Clause(schema_term(schemas[label]), TRUE, None) for label in order]
    return Document(tuple(clauses), file)


__all__ = ["node_json", "tree_json", "show_json", "rich_tree", "to_dot", "dot_body", "tree_document"]
