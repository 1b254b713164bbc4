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
from dataclasses import dataclass, replace

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


# The paper's Figure 2: green (brown) text is a true (false) pre-condition, a green (brown)
# ellipse an active (inactive) behaviour, in the initial state; post-conditions blue.
ACTIVE = "#2e7d32"
INACTIVE = "#8d6e63"
POST_COLOUR = "#1f4fbf"
ALIASED = "#d32f2f"
MERGED_FILL = "#fff3c4"
COMPOSITE_FILL = "#eef5ff"
LEFT_TO_RIGHT_LEAVES = 16      # a tree with more leaves than this is drawn left to right


@dataclass(frozen=True)
class Panel:
    """One tree of a picture: its cluster's name, its title, and the pre-order indices of the
    behaviours to mark as perceptually aliased."""

    key: str
    title: str
    tree: Behaviour
    aliased: frozenset[int] = frozenset()


def _leaves(root: Behaviour) -> int:
    return sum(1 for n in walk(root) if not n.children)


def _graph_header(name: str, rankdir: str) -> list[str]:
    return [f'digraph "{_dot_escape(name)}" {{',
            f'  graph [rankdir={rankdir}, fontname="Helvetica", newrank=true, nodesep=0.25, ranksep=0.4, ordering=out];',
            '  node [shape=ellipse, fontname="Helvetica", fontsize=11];',
            '  edge [arrowhead=none, color="#777777"];']


def to_dot(root: Behaviour, name: str = "task", initial: frozenset | None = None) -> str:
    """Graphviz DOT: behaviours as ellipses, pre-conditions green, post-conditions blue; given
    the `initial` state, coloured as the paper's Figure 2 (active or not, pre true or not),
    with a legend. A tree of many leaves is drawn left to right, a cluster per sub-task."""
    rankdir = "LR" if _leaves(root) > LEFT_TO_RIGHT_LEAVES else "TB"
    lines = _graph_header(name, rankdir)
    lines.extend(dot_body(root, "n", initial, clusters=rankdir == "LR"))
    if initial is not None:
        lines.extend(_legend(initial, merged=any(n.k > 1 for n in walk(root)), aliased=False))
    lines.append("}")
    return "\n".join(lines) + "\n"


def compare_dot(original: Behaviour, compressed: Behaviour, name: str, propagate: str,
                initial: frozenset | None = None, aliasing: Behaviour | None = None,
                aliased: frozenset[int] = frozenset(), merged_aliased: frozenset[int] = frozenset(),
                searched: str = "") -> str:
    """The paper's Figure 2: the learned tree, the merge with perceptual aliasing (`aliasing`,
    compressed with --propagate none, its `aliased` behaviours marked) when given, and the
    merge with `propagate` (its own `merged_aliased` marked; `searched` says how far the
    search for aliasing went when it stopped short); coloured in the `initial` state, with a legend."""
    panels = [Panel("original", f"(a) Learned symbolic representation: {count_nodes(original)} behaviours",
                    original)]
    if aliasing is not None:
        panels.append(Panel("aliased", f"(b) Merged with perceptual aliasing (propagate none): "
                                       f"{count_nodes(aliasing)} behaviours, {len(aliased)} aliased",
                            aliasing, aliased))
    shown = (f", {len(merged_aliased)} aliased" if merged_aliased or propagate == "none"
             else f", no perceptual aliasing {searched}" if searched
             else ", no perceptual aliasing" if initial is not None else "")
    panels.append(Panel("merged", f"({chr(ord('a') + len(panels))}) Merged Symbolic Representation "
                                  f"(propagate {propagate}): {count_nodes(compressed)} behaviours{shown}",
                        compressed, merged_aliased))
    return panels_dot(name, panels, initial)


def panels_dot(name: str, panels: list[Panel], initial: frozenset | None = None) -> str:
    """Trees side by side (top to bottom when large), each in its own cluster, and a legend."""
    large = any(_leaves(p.tree) > LEFT_TO_RIGHT_LEAVES for p in panels)
    lines = _graph_header(name, "LR" if large else "TB")
    for i, panel in reversed(list(enumerate(panels))) if large else enumerate(panels):   # (a) on top
        lines += [f"  subgraph cluster_{panel.key} {{",
                  f'    label="{_dot_escape(panel.title)}"; labeljust=l; fontsize=14; color="#bbbbbb";']
        lines.extend("  " + line for line in dot_body(panel.tree, f"p{i}_", initial, panel.aliased, clusters=large))
        lines.append("  }")
    if initial is not None or any(p.aliased for p in panels):
        lines.extend(_legend(initial, merged=any(n.k > 1 for p in panels for n in walk(p.tree)),
                             aliased=any(p.aliased for p in panels)))
    lines.append("}")
    return "\n".join(lines) + "\n"


def _legend(initial: frozenset | None, merged: bool, aliased: bool) -> list[str]:
    """A legend node: what each colour and mark means."""
    state = ", ".join(sorted(term_to_text(a) for a in initial)) if initial else "nothing true"
    rows = [f'<tr><td colspan="2"><b>Legend</b> (colours in the initial state: {_dot_escape(state)})</td></tr>']
    if initial is not None:
        rows += [f'<tr><td border="2" color="{ACTIVE}">  </td><td align="left">active behaviour: its '
                 f'pre-condition holds and its post-condition does not</td></tr>',
                 f'<tr><td border="2" color="{INACTIVE}">  </td><td align="left">inactive behaviour</td></tr>',
                 f'<tr><td><font color="{ACTIVE}">pre</font></td><td align="left">pre-condition, true</td></tr>',
                 f'<tr><td><font color="{INACTIVE}">pre</font></td><td align="left">pre-condition, false</td></tr>']
    rows.append(f'<tr><td><font color="{POST_COLOUR}">post</font></td><td align="left">post-condition</td></tr>')
    if merged:
        rows.append(f'<tr><td bgcolor="{MERGED_FILL}">k=N</td><td align="left">merged behaviour standing '
                    f'for N original ones (double outline)</td></tr>')
    if aliased:
        rows.append(f'<tr><td border="3" color="{ALIASED}"><font color="{ALIASED}">aliased</font></td>'
                    f'<td align="left">perceptual aliasing: enabled in a state where the original task '
                    f'enables none of its actions</td></tr>')
    table = "".join(rows)
    # The graph's own label, so it sits below every panel instead of widening a rank.
    return [f'  label=<<table border="1" cellborder="0" cellspacing="4" color="#bbbbbb">{table}</table>>;',
            '  labelloc=b; labeljust=l; fontsize=12;']


def dot_body(root: Behaviour, prefix: str, initial: frozenset | None = None,
             aliased: frozenset[int] = frozenset(), clusters: bool = False) -> list[str]:
    """The node and edge statements of a tree, ids starting with `prefix`; coloured in the
    `initial` state when given, the behaviours at the pre-order indices `aliased` marked,
    and with `clusters`, each sub-task of the root in a cluster of its own."""
    nodes = list(walk(root))
    live = _live(root, initial) if initial is not None else None
    ids = {id(node): f"{prefix}{i}" for i, node in enumerate(nodes)}
    statements: list[str] = []
    for i, node in enumerate(nodes):
        pre = cond.to_text(node.pre)
        pre_colour = "darkgreen" if initial is None else ACTIVE if cond.holds(node.pre, initial) else INACTIVE
        name = _dot_escape(term_to_text(node.label))
        title = f"<b>{name}</b>" if node.children else name
        if node.k > 1:
            title += f' <font color="#8a6d00">k={node.k}</font>'
        if i in aliased:
            title += f' <font color="{ALIASED}"><b>aliased</b></font>'
        label = (f"<{title}<br/><font color=\"{pre_colour}\">{_wrapped(pre)}</font>"
                 f"<br/><font color=\"{POST_COLOUR if initial is not None else 'blue'}\" point-size=\"9\">"
                 f"{_wrapped(cond.to_text(node.post))}</font>>")
        attributes = [f"label={label}"]
        fill = MERGED_FILL if node.k > 1 else COMPOSITE_FILL if node.children else None
        if fill:
            attributes.append(f'style=filled, fillcolor="{fill}"')
        if node.k > 1:
            attributes.append("peripheries=2")
        if i in aliased:
            attributes.append(f'color="{ALIASED}", penwidth=3')
        elif live is not None:
            attributes.append(f'color="{ACTIVE if live[i] else INACTIVE}", penwidth=2')
        statements.append(f"  {prefix}{i} [{', '.join(attributes)}];")
    if clusters and root.children:
        # Each sub-task of the root in its own box, so a wide task reads one part at a time.
        member = {id(root): None}
        for k, child in enumerate(root.children):
            for node in walk(child):
                member[id(node)] = k
        lines = [statements[0]]
        for k, child in reversed(list(enumerate(root.children))):
            lines.append(f"  subgraph cluster_{prefix}{k} {{")
            lines.append(f'    label="{_dot_escape(term_to_text(child.label))}"; style=dashed; color="#cccccc";')
            lines.extend("  " + statements[i] for i, node in enumerate(nodes) if member[id(node)] == k)
            lines.append("  }")
    else:
        lines = statements
    for node in nodes:
        # Left to right, dot stacks a node's children from the bottom up: give them in reverse
        # so the first sub-task reads at the top, as it comes first in the task.
        for child in (reversed(node.children) if clusters else node.children):
            lines.append(f"  {ids[id(node)]} -> {ids[id(child)]};")
    return lines


def aliased_behaviours(original: Behaviour, compressed: Behaviour, initial: frozenset,
                       max_states: int = 2_000) -> tuple[frozenset[int], bool]:
    """The pre-order indices of the compressed tree's leaves that perceptual aliasing enables:
    in some state the original task reaches from `initial` (breadth first, up to `max_states`
    states), the leaf is enabled but the action it would run first (its first constituent
    not yet accomplished) is not an enabled action of the original; and whether every
    reachable state was looked at (False: the search stopped at `max_states`)."""
    from ..run.execute import Plan, enabled_indices
    from ..run.world import World

    world = World(original, initial)
    o_plan, c_plan = Plan.of(original), Plan.of(compressed)
    start = world.atoms
    seen, frontier, marked = {start}, [start], set()
    complete = True
    while frontier:
        state = frontier.pop(0)
        o_enabled = [o_plan.nodes[i] for i in enabled_indices(o_plan, state)]
        allowed = {leaf.label for leaf in o_enabled}
        for i in enabled_indices(c_plan, state):
            first = next((label for label, post in c_plan.steps[i] if not cond.holds(post, state)), None)
            if first is not None and first not in allowed:
                marked.add(i)
        for leaf in o_enabled:
            after = world.successor(state, leaf.post)
            if after not in seen:
                if len(seen) >= max_states:
                    complete = False
                    continue
                seen.add(after)
                frontier.append(after)
    return frozenset(marked), complete


def _wrapped(text: str, width: int = 28) -> str:
    """A condition escaped for an HTML label, broken into lines after `and`/`or` past `width`."""
    words = text.split(" ")
    lines, line = [], ""
    for word in words:
        if line and len(line) + 1 + len(word) > width and line.split(" ")[-1] in ("and", "or"):
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    lines.append(line)
    return "<br/>".join(_dot_escape(part) for part in lines)


def _live(root: Behaviour, atoms: frozenset) -> list[bool]:
    """Each behaviour (pre-order) active in `atoms`: it and its ancestors pre true, post false."""
    live: list[bool] = []
    stack: list[tuple[Behaviour, bool]] = [(root, True)]
    while stack:
        node, up = stack.pop()
        on = up and cond.holds(node.pre, atoms) and not cond.holds(node.post, atoms)
        live.append(on)
        stack.extend((c, on) for c in reversed(node.children))
    return live


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


__all__ = ["node_json", "tree_json", "show_json", "rich_tree", "to_dot", "dot_body", "compare_dot", "Panel",
           "panels_dot", "aliased_behaviours",
           "tree_document", "carried_clauses", "origin_term", "STRUCTURE"]
