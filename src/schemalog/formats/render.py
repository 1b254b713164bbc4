"""Task trees for people and programs: the terminal, Graphviz DOT, JSON, and knowledge text.

    tree_json(root)  -> {"label", "agent", "objects", "pre", "post", "releaser",
                         "importance", "k", "merged_from", "children"}
    show_json(task, root) -> {"task", "nodes", "depth", "tree"}

Colours follow the paper's figures: pre-conditions green where true in the state drawn (the
initial state), brown where false, in the terminal as in pictures; post-conditions blue. Pictures are laid out to be read whole on a 1920x1080 screen, or split.
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
from ..task.tree import Behaviour, Origin, count_nodes, depth, map_tree, walk, walk_with_depth

PRE_STYLE = "green"            # a pre-condition, true in the state the tree is shown in (or no state given)
FALSE_PRE_STYLE = "color(94)"  # ... false there: brown (xterm's 94, #875f00; yellow, the old brown, on 16 colours)
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


def rich_tree(root: Behaviour, title: str | None = None, first_id: int | None = None,
              state: frozenset | None = None) -> Tree:
    """A rich Tree with each behaviour's agent, objects and conditions (and, given
    `first_id`, its id as the query relations number it: pre-order from `first_id`); given
    a `state` (its true atoms), each pre-condition green where it holds there, brown where not."""
    number = itertools.count(first_id) if first_id is not None else None

    def text(node: Behaviour) -> Text:
        shown = _node_text(node, state)
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


def _node_text(node: Behaviour, state: frozenset | None = None) -> Text:
    text = Text()
    text.append(term_to_text(node.label), style="bold" if node.children else "")
    if node.agent != DEFAULT_AGENT:
        text.append(f" [{node.agent}]", style="magenta")
    if node.k > 1:
        text.append(f" k={node.k}", style="yellow")
    text.append("  pre: ", style="dim")
    true = state is None or cond.holds(node.pre, state)
    text.append(cond.to_text(node.pre), style=PRE_STYLE if true else FALSE_PRE_STYLE)
    text.append("  post: ", style="dim")
    text.append(cond.to_text(node.post), style=POST_STYLE)
    return text


def _dot_escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


# The paper's Figure 2: green (brown) text is a true (false) pre-condition, a green (brown)
# ellipse an active (inactive) behaviour, in the initial state; post-conditions blue. The paper's
# active there is what docs/semantics.md calls enabled: pre-condition true and post-condition
# false, for the behaviour and every ancestor (_live), so a leaf released by `true` under an
# inactive sub-task is outlined brown.
ACTIVE = "#2e7d32"
INACTIVE = "#8d6e63"
POST_COLOUR = "#1f4fbf"
ALIASED = "#d32f2f"
MERGED_FILL = "#fff3c4"
COMPOSITE_FILL = "#eef5ff"
CONDITION_POINTS = 9           # the smallest text of a picture: a post-condition, a page reference
MEASURED_NODES = 600           # a drawing of more behaviours cannot fit a screen: not laid out to see


@dataclass(frozen=True)
class Panel:
    """One tree of a picture: its cluster's name, its title, and the pre-order indices of the
    behaviours to mark as perceptually aliased; drawn from the behaviour at pre-order index
    `focus`, `depth` levels below it (None: all), a sub-task cut there drawn as one behaviour
    naming the picture its own is in (`pages`: pre-order index -> file name)."""

    key: str
    title: str
    tree: Behaviour
    aliased: frozenset[int] = frozenset()
    focus: int = 0
    depth: int | None = None
    pages: tuple[tuple[int, str], ...] = ()


@dataclass(frozen=True)
class Layout:
    """How a picture is laid out: `compact`, behaviours in rounded boxes and the leaves of a
    sub-task in a column under it, in order from the top; else the paper's ellipses, the
    leaves in a row; `short_titles`, panel titles on several lines. Panels are side by side, in
    order from the left."""

    compact: bool = False
    short_titles: bool = False      # a panel's title broken into lines at its `:`, `,` and `;`


# In order of preference: the paper's drawing first; the first one a screen can hold is drawn.
LAYOUTS = (Layout(), Layout(compact=True), Layout(compact=True, short_titles=True))


def _graph_header(name: str, layout: Layout) -> list[str]:
    if layout.compact:
        spacing, node = "nodesep=0.12, ranksep=0.2", 'shape=box, style=rounded, margin="0.06,0.03", fontsize=10'
    else:
        spacing, node = "nodesep=0.25, ranksep=0.4", "shape=ellipse, fontsize=11"
    return [f'digraph "{_dot_escape(name)}" {{',
            f'  graph [rankdir=TB, fontname="Helvetica", newrank=true, {spacing}, ordering=out];',
            f'  node [{node}, fontname="Helvetica"];',
            '  edge [arrowhead=none, color="#777777"];']


def to_dot(root: Behaviour, name: str = "task", initial: frozenset | None = None) -> str:
    """Graphviz DOT: behaviours as ellipses, pre-conditions green, post-conditions blue; given
    the `initial` state, coloured as the paper's Figure 2 (active or not, pre true or not),
    with a legend. A tree too wide for a screen is drawn compact (see choose_layout)."""
    return choose_layout(name, [Panel("tree", "", root)], initial)[0]


def figure2_panels(original: Behaviour, compressed: Behaviour, propagate: str,
                   initial: frozenset | None = None, aliasing: Behaviour | None = None,
                   aliased: frozenset[int] = frozenset(), merged_aliased: frozenset[int] = frozenset(),
                   searched: str = "") -> list[Panel]:
    """The panels of the paper's Figure 2 (see compare_dot)."""
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
    return panels


def compare_dot(original: Behaviour, compressed: Behaviour, name: str, propagate: str,
                initial: frozenset | None = None, aliasing: Behaviour | None = None,
                aliased: frozenset[int] = frozenset(), merged_aliased: frozenset[int] = frozenset(),
                searched: str = "") -> str:
    """The paper's Figure 2: the learned tree, the merge with perceptual aliasing (`aliasing`,
    compressed with --propagate none, its `aliased` behaviours marked) when given, and the
    merge with `propagate` (its own `merged_aliased` marked; `searched` says how far the
    search for aliasing went when it stopped short); coloured in the `initial` state, with a legend."""
    panels = figure2_panels(original, compressed, propagate, initial, aliasing, aliased, merged_aliased,
                            searched)
    return panels_dot(name, panels, initial)


def panels_dot(name: str, panels: list[Panel], initial: frozenset | None = None) -> str:
    """Trees side by side, each in its own cluster, in the first layout a screen can hold
    (choose_layout), and a legend."""
    return choose_layout(name, panels, initial)[0]


def page_dot(name: str, panels: list[Panel], initial: frozenset | None, layout: Layout) -> str:
    """One picture of `panels` laid out as `layout`: each titled panel in its own cluster,
    in order from the left, and a legend."""
    lines = _graph_header(name, layout)
    for i, panel in enumerate(panels):
        prefix = f"p{i}_" if panel.title else "n"
        body = dot_body(panel.tree, prefix, initial, panel.aliased, layout.compact, panel.focus, panel.depth,
                        dict(panel.pages))
        if panel.title:
            title = (f"<{_title_lines(panel.title)}>" if layout.short_titles
                     else f'"{_dot_escape(panel.title)}"')
            lines += [f"  subgraph cluster_{panel.key} {{",
                      f'    label={title}; labeljust=l; fontsize=12; color="#bbbbbb";']
            lines.extend("  " + line for line in body)
            lines.append("  }")
        else:
            lines.extend(body)
    legend = initial is not None or any(p.aliased for p in panels)
    if legend or any(p.pages for p in panels):
        lines.extend(_legend(initial, merged=any(n.k > 1 for p in panels for n in walk(p.tree)),
                             aliased=any(p.aliased for p in panels), cut=any(p.pages for p in panels)))
    lines.append("}")
    return "\n".join(lines) + "\n"


def _title_lines(title: str) -> str:
    """A panel's title as an HTML label, a line after each `: `, `, ` and `; `."""
    parts = title.replace(": ", ":\n").replace(", ", ",\n").replace("; ", ";\n").split("\n")
    return "".join(f'{_dot_escape(part)}<br align="left"/>' for part in parts)


def _shown(panel: Panel) -> list[int]:
    """The pre-order indices of the behaviours a panel draws."""
    nodes = list(walk(panel.tree))
    position = {id(node): i for i, node in enumerate(nodes)}
    shown, stack = [], [(nodes[panel.focus], 0)]
    while stack:
        node, level = stack.pop()
        shown.append(position[id(node)])
        if panel.depth is None or level < panel.depth:
            stack.extend((child, level + 1) for child in reversed(node.children))
    return shown


def _children(nodes: list[Behaviour], i: int) -> list[int]:
    """The pre-order indices of the children of the behaviour at pre-order index `i`."""
    found, j = [], i + 1
    for child in nodes[i].children:
        found.append(j)
        j += count_nodes(child)
    return found


def choose_layout(name: str, panels: list[Panel], initial: frozenset | None = None) -> tuple[str, bool]:
    """The DOT of `panels` in the first of LAYOUTS that a screen holds with its text readable
    (measured by dot: see graphviz.readable_on_screen), and True; else the one that shrinks
    least, and False. Without `dot` (DOT text only), or past MEASURED_NODES behaviours, the
    compact layout, unmeasured."""
    from .graphviz import drawing_size, readable_on_screen, screen_scale
    import shutil

    layouts = LAYOUTS
    drawn = sum(len(_shown(p)) for p in panels)
    if shutil.which("dot") is None or drawn > MEASURED_NODES:
        return page_dot(name, panels, initial, layouts[-1]), False
    best = None
    for layout in layouts:
        text = page_dot(name, panels, initial, layout)
        width, height = drawing_size(text)
        if readable_on_screen(width, height, CONDITION_POINTS):
            return text, True
        if best is None or screen_scale(width, height) > best[0]:
            best = (screen_scale(width, height), text)
    return best[1], False


@dataclass(frozen=True)
class Page:
    """One picture of a split drawing: its DOT text and what it shows."""

    dot: str
    what: str


def picture_pages(name: str, panels: list[Panel], initial: frozenset | None,
                  page_name) -> list[Page]:
    """The drawing of `panels` as pictures a screen can hold: one when it fits (choose_layout),
    else an overview and the pictures it names, `page_name(k)` the k-th (k >= 1): the overview
    draws each panel down to the deepest level at which it still fits, a sub-task cut there
    naming its picture; that picture is each panel whole when there are several, else each
    sub-task cut, split again the same way when it does not fit either."""
    pages: list[Page | None] = []

    def place(panels: list[Panel], what: str) -> int:
        k = len(pages)
        pages.append(None)
        text, fits = choose_layout(name, panels, initial)
        levels = max(depth(_subtree(p)) for p in panels)
        if fits or levels <= 2:
            pages[k] = Page(text, what)
            return k
        cut = 1
        while cut + 1 < levels - 1 and choose_layout(name, [_cut(p, cut + 1, {}, page_name(999)) for p in panels],
                                                     initial)[1]:
            cut += 1
        overview = []
        for panel in panels:
            if len(panels) > 1:           # the panel's title names the picture of it whole
                target = page_name(place([replace(panel, depth=None, pages=())], panel.title))
                overview.append(replace(_cut(panel, cut, {}, ""), title=f"{panel.title}; whole in {target}"))
                continue
            nodes = list(walk(panel.tree))
            targets = {}
            for i in _cut_points(panel, cut):
                node = nodes[i]
                head = panel.title.split(":")[0] + ", " if panel.title else ""
                title = f"{head}{term_to_text(node.label)}: {count_nodes(node)} behaviours"
                targets[i] = page_name(place([replace(panel, key=f"{panel.key}{i}", title=title, focus=i,
                                                      depth=None, pages=())], title))
            overview.append(_cut(panel, cut, targets, ""))
        pages[k] = Page(choose_layout(name, overview, initial)[0], "overview")
        return k

    place(panels, "")
    return pages


def _subtree(panel: Panel) -> Behaviour:
    return next(node for i, node in enumerate(walk(panel.tree)) if i == panel.focus)


def _cut_points(panel: Panel, cut: int) -> list[int]:
    """The pre-order indices of the sub-tasks `cut` levels below a panel's focus."""
    deeper = replace(panel, depth=cut)
    nodes = list(walk(panel.tree))
    focus_level = _levels(panel.tree)
    return [i for i in _shown(deeper) if nodes[i].children and focus_level[i] - focus_level[panel.focus] == cut]


def _levels(root: Behaviour) -> list[int]:
    return [level for _, level in walk_with_depth(root)]


def _cut(panel: Panel, cut: int, targets: dict[int, str], every: str) -> Panel:
    """The panel drawn `cut` levels deep, each sub-task cut there naming its picture (`targets`,
    else `every`)."""
    pages = tuple((i, targets.get(i, every)) for i in _cut_points(panel, cut))
    return replace(panel, depth=cut, pages=pages)


def _legend(initial: frozenset | None, merged: bool, aliased: bool, cut: bool = False) -> list[str]:
    """A legend node: what each colour and mark means."""
    state = ", ".join(sorted(term_to_text(a) for a in initial)) if initial else "nothing true"
    rows = [f'<tr><td colspan="2"><b>Legend</b> (colours in the initial state: {_dot_escape(state)})</td></tr>']
    if initial is not None:
        # What _live draws (docs/semantics.md, Enabling; the paper's Fig. 2 calls it active): a3(cup),
        # released by `true` under a sub-task whose pre-condition is false, is green text in a brown outline.
        rows += [f'<tr><td border="2" color="{ACTIVE}">  </td><td align="left" balign="left">enabled behaviour: active (its '
                 f'pre-condition holds, its<br/>post-condition does not), and so is every behaviour above it</td></tr>',
                 f'<tr><td border="2" color="{INACTIVE}">  </td><td align="left">not enabled: it or a behaviour '
                 f'above it is not active</td></tr>',
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
    if cut:
        rows.append('<tr><td><i>N below</i></td><td align="left">a sub-task whose N behaviours are drawn '
                    'in the picture named (dashed outline)</td></tr>')
    table = "".join(rows)
    # The graph's own label, so it sits below every panel instead of widening a rank.
    return [f'  label=<<table border="1" cellborder="0" cellspacing="4" color="#bbbbbb">{table}</table>>;',
            '  labelloc=b; labeljust=l; fontsize=12;']


def dot_body(root: Behaviour, prefix: str, initial: frozenset | None = None,
             aliased: frozenset[int] = frozenset(), compact: bool = False, focus: int = 0,
             depth: int | None = None, pages: dict[int, str] | None = None) -> list[str]:
    """The node and edge statements of a tree, ids `prefix` and the pre-order index; coloured
    in the `initial` state when given, the behaviours at the pre-order indices `aliased`
    marked; from the behaviour at index `focus`, `depth` levels down (None: all), a sub-task
    cut there drawn dashed, naming the picture its behaviours are in (`pages`). `compact`:
    the leaves of a sub-task in a column under it, in order from the top."""
    nodes = list(walk(root))
    live = _live(root, initial) if initial is not None else None
    position = {id(node): i for i, node in enumerate(nodes)}
    pages = pages or {}
    shown = _shown(Panel("", "", root, focus=focus, depth=depth))
    drawn = set(shown)
    statements: list[str] = []
    for i in shown:
        node = nodes[i]
        pre = cond.to_text(node.pre)
        pre_colour = "darkgreen" if initial is None else ACTIVE if cond.holds(node.pre, initial) else INACTIVE
        name = _dot_escape(term_to_text(node.label))
        title = f"<b>{name}</b>" if node.children else name
        if node.k > 1:
            title += f' <font color="#8a6d00">k={node.k}</font>'
        if i in aliased:
            title += f' <font color="{ALIASED}"><b>aliased</b></font>'
        label = (f"<{title}<br/><font color=\"{pre_colour}\">{_wrapped(pre)}</font>"
                 f"<br/><font color=\"{POST_COLOUR if initial is not None else 'blue'}\" "
                 f"point-size=\"{CONDITION_POINTS}\">{_wrapped(cond.to_text(node.post))}</font>")
        cut = node.children and not any(position[id(c)] in drawn for c in node.children)
        if cut:
            where = f": {_dot_escape(pages[i])}" if pages.get(i) else ""
            label += (f'<br/><font point-size="{CONDITION_POINTS}"><i>{count_nodes(node) - 1} below'
                      f'{where}</i></font>')
        attributes = [f"label={label}>"]
        fill = MERGED_FILL if node.k > 1 else COMPOSITE_FILL if node.children else None
        style = (["rounded"] if compact else []) + (["filled"] if fill else []) + (["dashed"] if cut else [])
        if style:
            attributes.append(f'style="{",".join(style)}"')
        if fill:
            attributes.append(f'fillcolor="{fill}"')
        if node.k > 1:
            attributes.append("peripheries=2")
        if i in aliased:
            attributes.append(f'color="{ALIASED}", penwidth=3')
        elif live is not None:
            attributes.append(f'color="{ACTIVE if live[i] else INACTIVE}", penwidth=2')
        statements.append(f"  {prefix}{i} [{', '.join(attributes)}];")
    for i in shown:
        children = [position[id(c)] for c in nodes[i].children if position[id(c)] in drawn]
        if compact and len(children) > 1 and not any(nodes[c].children for c in children):
            # A comb: a spine down from the sub-task, a short branch to each leaf, in order.
            above = f"{prefix}{i}"
            for k, child in enumerate(children):
                joint = f"{prefix}{i}_{k}"
                statements += [f'  {joint} [shape=point, width=0.03, height=0.03, color="#777777", label=""];',
                               f"  {{rank=same; {joint}; {prefix}{child};}}",
                               f"  {above} -> {joint}{' [tailport=s]' if k == 0 else ''};",
                               f"  {joint} -> {prefix}{child};"]
                above = joint
        else:
            statements.extend(f"  {prefix}{i} -> {prefix}{child};" for child in children)
    return statements


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


def distinct_labels(root: Behaviour) -> Behaviour:
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
    root = distinct_labels(root)
    schemas: dict[Term, SchemaDef] = {}
    order: list[Term] = []
    agents: dict[Term, str] = {}
    objects_of: dict[Term, tuple[Term, ...]] = {}
    all_objects: dict[Term, None] = {}       # in order met: an ordered set (a list's `in` was quadratic)
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
        all_objects.update(dict.fromkeys(node.objects))
    clauses: list[Clause] = [Clause(Struct("task", (root.label,)), TRUE, None)]
    clauses += [Clause(Struct("object", (o,)), TRUE, None) for o in all_objects]
    object_set = all_objects
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
           "panels_dot", "aliased_behaviours", "figure2_panels", "page_dot", "choose_layout", "picture_pages",
           "Page", "Layout", "LAYOUTS",
           "tree_document", "carried_clauses", "origin_term", "STRUCTURE"]
