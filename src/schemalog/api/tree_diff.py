"""`schemalog diff A B` for BT.CPP programs: what changed in behaviour, for a terminal, a tool, a
pull-request comment and a picture (docs/behaviour_trees.md, "Reviewing a change").

    diff_trees(a, b, max_states, rules, run_once) -> TreeDiff    bt/diff.py's comparison
    TreeDiff.text() / .markdown() / .as_json() / .dot()           the four outputs

A report names each side by what was read (a file, several, a folder) and states what its
verdict covers, as verify's does.
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import defaults
from .behaviour_trees import EVENTS_PER_TICK

EQUAL, DIFFERENT, UNDECIDED = 0, 1, 3          # the exit statuses of `schemalog diff`


@dataclass(frozen=True)
class TreeDiff:
    """Two BT.CPP programs compared (bt/diff.Comparison), with the names of what was read."""

    diff: object                        # bt.diff.Comparison
    a_name: str
    b_name: str
    covers: str = ""                    # what the verdict covers of what the XML leaves open
    under: str = ""                     # " with the nav2 profile", ...
    note: str = ""                      # the BT.CPP versions the sides were read under, where it matters

    @property
    def equal(self) -> bool:
        """Whether the two programs are proved to behave alike."""
        return self.diff.equal

    @property
    def complete(self) -> bool:
        """Whether the whole pair's search was exhausted (a proof or a refutation, not a limit)."""
        return self.diff.verdict.complete

    @property
    def direction(self) -> str:
        """"equal", "b within a", "a within b", "neither" or "unknown" (bt/diff.py)."""
        return self.diff.direction

    @property
    def places(self) -> tuple:
        """Every place where the programs part (bt/diff.Place: a, b, changes, effect, verdict),
        those that change behaviour first."""
        return self.diff.places

    @property
    def refactorings(self) -> tuple:
        """The places that make no behavioural difference (in every context, or in this program)."""
        return self.diff.refactorings

    @property
    def exit_status(self) -> int:
        """0 proved equal, 1 different (a run tells them apart), 3 neither proved nor refuted."""
        v = self.diff.verdict
        return EQUAL if v.equal and v.complete else DIFFERENT if not v.equal else UNDECIDED

    # -- text -------------------------------------------------------------------------------
    def headline(self) -> str:
        v = self.diff.verdict
        if v.equal and v.complete:
            what = "same behaviour"
        elif v.equal:
            what = "NOT decided"
        else:
            what = "behaviour changed"
        return f"{self.a_name} -> {self.b_name}: {what}{self.under}"

    def text(self) -> str:
        """The report for a terminal."""
        from ..bt.prove import explain

        d, v = self.diff, self.diff.verdict
        lines = [f"{self.headline()}: {_verdict_line(v)}"]
        first = d.first_divergence()
        if first is not None:
            ticks = max(len(v.counterexample.ticks_a), len(v.counterexample.ticks_b))
            lines += [f"first divergence (root tick {ticks}):", f"  a: {first[0]}", f"  b: {first[1]}"]
        lines.append(f"direction: {_direction_words(d.direction)}")
        if d.main[0] != d.main[1]:
            lines.append(f"main tree: A runs {d.main[0]}, B runs {d.main[1]}")
        behavioural, same, undecided = d.behavioural, d.refactorings, d.undecided
        if behavioural:
            lines.append(f"{_count(len(behavioural), 'place')} {'changes' if len(behavioural) == 1 else 'change'} "
                         f"behaviour:")
            for k, p in enumerate(behavioural, 1):
                lines.append(f"  {k}. {_place_head(p)}")
                lines += [f"     {c}" for c in p.changes or ("(the subtrees differ only as BT.CPP resolves them)",)]
                if p.verdict is not None and p.verdict.counterexample is not None:
                    lines.append("     shortest run that shows it:")
                    lines += [f"       {x}" for x in explain(p.verdict).splitlines()[1:]]
        if undecided:
            lines.append(f"{_count(len(undecided), 'place')} not decided (a limit stopped the proof; raise "
                         f"--max-states):")
            lines += [f"  - {_place_head(p)}: {'; '.join(p.changes)}" for p in undecided]
        if d.not_run:
            lines.append(f"{_count(len(d.not_run), 'change')} in BehaviorTrees the main tree does not reach (no run "
                         f"ticks {'it' if len(d.not_run) == 1 else 'them'}; with another --task, they may matter):")
            lines += [f"  - {_place_head(p)} in {p.tree}: {'; '.join(p.changes) or 'resolved alike'}" for p in d.not_run]
        if same:
            lines.append(f"{_count(len(same), 'structural change')} with no behavioural difference (a pure "
                         f"refactoring):")
            for p in same:
                scope = "in every context" if p.effect == "same behaviour" else "in this program, not in every context"
                lines.append(f"  - {_place_head(p)}: {'; '.join(p.changes) or 'resolved alike'} ({scope})")
        if not d.places and not d.trees_added and not d.trees_removed and d.main[0] == d.main[1]:
            lines.append("no structural change: the trees are the same to BT.CPP (attributes by name, each "
                         "SubTree call as it resolves)")
        if d.trees_added or d.trees_removed:
            lines.append("trees: " + "; ".join([*(f"B adds BehaviorTree {t}" for t in d.trees_added),
                                                 *(f"B removes BehaviorTree {t}" for t in d.trees_removed)]))
        if self.covers:
            lines.append(self._covers() + ".")
        if self.note:
            lines.append(f"note: {self.note}.")
        return "\n".join(lines) + "\n"

    def _covers(self) -> str:
        """What the verdict covers ("It covers ..."), or the registration its run needs ("Shown on a
        run with X registered as a StatefulActionNode")."""
        return f"It {self.covers}" if self.diff.verdict.equal else f"Shown on {self.covers}"

    # -- markdown ---------------------------------------------------------------------------
    def markdown(self) -> str:
        """The report as a pull-request comment (GitHub-flavoured Markdown)."""
        from ..bt.prove import explain

        d, v = self.diff, self.diff.verdict
        icon = {EQUAL: "same behaviour", DIFFERENT: "behaviour changed", UNDECIDED: "not decided"}[self.exit_status]
        out = [f"### schemalog diff: {icon}", "",
               f"`{_md(self.a_name)}` → `{_md(self.b_name)}`{_md(self.under)}: {_md(_verdict_line(v))}", ""]
        first = d.first_divergence()
        if first is not None:
            out += ["**First divergence**", "", f"- A: {_md(first[0])}", f"- B: {_md(first[1])}", ""]
        out += [f"**Direction:** {_md(_direction_words(d.direction))}", ""]
        if d.places:
            out += ["| # | A | B | what changed | effect |", "| --- | --- | --- | --- | --- |"]
            for k, p in enumerate(d.places, 1):
                effect = f"**{p.effect}**" if p.effect == "changes behaviour" else p.effect
                out.append(f"| {k} | {_side(p.a)} | {_side(p.b)} | "
                           f"{_cell('; '.join(p.changes) or 'resolved alike')} | {effect} |")
            out.append("")
            for k, p in enumerate(d.places, 1):
                if p.effect == "changes behaviour" and p.verdict is not None and p.verdict.counterexample:
                    out += [f"<details><summary>Place {k}: the shortest run that shows it</summary>", "", "```text",
                            *explain(p.verdict).splitlines()[1:], "```", "", "</details>", ""]
        else:
            out += ["No structural change: the trees are the same to BT.CPP.", ""]
        if d.trees_added or d.trees_removed:
            out += ["**Trees:** " + _md("; ".join([*(f"B adds {t}" for t in d.trees_added),
                                                    *(f"B removes {t}" for t in d.trees_removed)])), ""]
        if self.covers:
            out += [f"<sub>{_md(self._covers())}.</sub>", ""]
        if self.note:
            out += [f"<sub>Note: {_md(self.note)}.</sub>", ""]
        return "\n".join(out)

    # -- JSON -------------------------------------------------------------------------------
    def as_json(self) -> dict:
        """The report as JSON (docs/formats.md)."""
        from ..bt.prove import explain

        d, v = self.diff, self.diff.verdict
        first = d.first_divergence()
        return {
            "a": self.a_name, "b": self.b_name, "equal": v.equal, "complete": v.complete,
            "proved": v.equal and v.complete, "states": v.states, "reason": v.reason, "covers": self.covers,
            "note": self.note,
            "direction": d.direction,
            "first_divergence": None if first is None else {"a": first[0], "b": first[1]},
            "counterexample": None if v.counterexample is None else explain(v).splitlines()[1:],
            "main": {"a": d.main[0], "b": d.main[1]},
            "places": [{"tree": p.tree, "a": _node_json(p.a), "b": _node_json(p.b), "changes": list(p.changes),
                        "effect": p.effect, "reason": p.verdict.reason if p.verdict else "",
                        "run": (explain(p.verdict).splitlines()[1:] if p.verdict is not None
                                and p.verdict.counterexample is not None and p.effect == "changes behaviour"
                                else None)}
                       for p in d.places],
            "trees_added": list(d.trees_added), "trees_removed": list(d.trees_removed),
        }

    # -- picture ----------------------------------------------------------------------------
    def dot(self, a_document, b_document) -> str:
        """Both programs side by side as Graphviz DOT: each place's nodes marked by its effect,
        the path to the first divergence in bold."""
        from ..bt.model import walk
        from ..bt.semantics import _where

        d = self.diff
        fill = {"changes behaviour": "#f6b2b2", "undecided": "#f8e08e", "same behaviour here": "#cfe3f7",
                "same behaviour": "#d8efd8", "not run": "#e4e4e4"}
        from ..bt.diff import _canon

        # in a place, a node is marked unless the other side's place holds it, subtree and all
        marked: dict[int, str] = {}
        for p in d.places:
            for root, other in ((p.a, p.b), (p.b, p.a)):
                there = {_canon(m) for m in walk(other)}
                for n in walk(root):
                    if n is root or _canon(n) not in there:
                        marked.setdefault(id(n), fill[p.effect])
        first = d.first_divergence()
        targets = set()
        cex = d.verdict.counterexample
        if cex is not None:
            for ticks in (cex.ticks_a, cex.ticks_b):
                if ticks and ticks[-1].events:
                    targets.add(ticks[-1].events[-1].where)
        lines = ["digraph diff {", "  rankdir=TB; newrank=true; node [shape=box, style=\"rounded,filled\", "
                 "fillcolor=white, fontname=\"Helvetica\", fontsize=10]; edge [arrowhead=none];"]
        for side, doc, title in (("a", a_document, self.a_name), ("b", b_document, self.b_name)):
            lines.append(f"  subgraph cluster_{side} {{ label={_q(('A: ' if side == 'a' else 'B: ') + title)}; "
                         f"fontname=\"Helvetica\";")
            counter = 0
            for tree_id, root in sorted(doc.trees, key=lambda t: t[0] != doc.main):
                ids: dict[int, str] = {}
                parent_of: dict[int, object] = {}
                for n in walk(root):
                    counter += 1
                    ids[id(n)] = f"{side}{counter}"
                    for c in n.children:
                        parent_of[id(c)] = n
                on_path: set[int] = set()
                for n in walk(root):
                    if _where(n) and _where(n) in targets:
                        x = n
                        while x is not None:
                            on_path.add(id(x))
                            x = parent_of.get(id(x))
                tree_label = f"{side}_tree_{counter}"
                lines.append(f"    {tree_label} [shape=plaintext, style=\"\", label={_q('BehaviorTree ' + tree_id)}];")
                lines.append(f"    {tree_label} -> {ids[id(root)]} [style=dotted];")
                for n in walk(root):
                    from ..bt.diff import label
                    attrs = [f"label={_q(label(n) + (chr(10) + _where(n) if _where(n) else ''))}"]
                    if id(n) in marked:
                        attrs.append(f"fillcolor=\"{marked[id(n)]}\"")
                    if id(n) in on_path:
                        attrs.append("penwidth=3, color=\"#b00000\"")
                    lines.append(f"    {ids[id(n)]} [{', '.join(attrs)}];")
                    for c in n.children:
                        bold = " [penwidth=3, color=\"#b00000\"]" if id(c) in on_path and id(n) in on_path else ""
                        lines.append(f"    {ids[id(n)]} -> {ids[id(c)]}{bold};")
            lines.append("  }")
        legend = ("red: changes behaviour; yellow: undecided; blue: same behaviour in this program; green: "
                  "same behaviour in every context; grey: in a tree no run reaches" + ("; bold: the path to the first divergence" if first else ""))
        lines.append(f"  label={_q(self.headline() + chr(10) + legend)}; labelloc=t; fontname=\"Helvetica\";")
        lines.append("}")
        return "\n".join(lines) + "\n"


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _verdict_line(v) -> str:
    if v.equal and v.complete:
        return f"proved equal: {v.reason}"
    if v.equal:
        return f"NOT proved: {v.reason}"
    return f"refuted after {v.states:,} states: {v.reason}"


def _direction_words(direction: str) -> str:
    return {"equal": "equal: every run of each is a run of the other",
            "b within a": "every run of B is a run of A (B only removes behaviour), not the converse",
            "a within b": "every run of A is a run of B (B only adds behaviour), not the converse",
            "neither": "neither: each has a run the other has not",
            "unknown": "not decided (a limit stopped the proof)"}[direction]


def _count(n: int, word: str) -> str:
    return f"{n:,} {word}{'' if n == 1 else 's'}"


def _place_head(p) -> str:
    from ..bt.diff import label

    head = label(p.a) if label(p.a) == label(p.b) else f"{label(p.a)} / {label(p.b)}"
    return f"{head} at {p.where}"


def _side(n) -> str:
    from ..bt.diff import label
    from ..bt.semantics import _where

    return f"`{_where(n).replace('`', chr(39))}` {_cell(label(n))}" if _where(n) else _cell(label(n))


def _node_json(n) -> dict:
    return {"type": n.type, "name": n.attr("name"), "file": n.file, "line": n.line, "column": n.column}


def _md(text: str) -> str:
    """Text made safe in Markdown: HTML and the characters that start formatting escaped."""
    return (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace("*", "\\*")
            .replace("_", "\\_").replace("`", "\\`"))


def _cell(text: str) -> str:
    return _md(text).replace("|", "\\|").replace("\n", " ")


def diff_trees(a, b, max_states: int = defaults.MAX_STATES, rules=None, *, run_once: bool = False,
               a_name: str = "A", b_name: str = "B", under: str = "") -> TreeDiff:
    """Compare two BT.CPP documents (read_tree) under BT.CPP 4 semantics: the whole pair proved
    as verify proves it, every place where they part described and decided on runs, the
    direction that holds (bt/diff.py). `rules`, `run_once`: as prove_trees."""
    from ..bt.diff import diff_documents
    from .behaviour_trees import _readings, _under, version_words

    # each reading BT.CPP allows (behaviour_trees._readings: an unmarked file under 4 and 3.8
    # where they may run it apart); the report shows the first that is no proof, else the first
    pairs = _readings(a, b, rules)
    diffs = [diff_documents(x, y, max_states=max_states, max_events_per_tick=EVENTS_PER_TICK, rules=rules,
                            halts=not run_once) for x, y in pairs]
    pick = next((k for k, d in enumerate(diffs) if not d.equal), 0)
    d, (x, y) = diffs[pick], pairs[pick]
    words = _under(x, y)
    notes = []
    if x.version != y.version:
        notes.append("the two sides are read under two BT.CPP versions: a node written alike may run apart, "
                     "which the whole verdict covers and the places, found in the text, do not name")
    if len(pairs) > 1:
        said = " and ".join(version_words(p[0].version) for p in pairs)
        notes.append(f"the files have no BTCPP_format: compared under {said}, as each loads them; this report "
                     f"is under {version_words(x.version)}")
    if words:
        under = f" under {words} semantics{under}"
    return TreeDiff(d, a_name, b_name, d.verdict.assumed, under, "; ".join(notes))
