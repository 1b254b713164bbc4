"""`schemalog diff A.pl B.pl` for task knowledge: two versions of a task, or a task against its
compressed form, compared on runs (docs/compression.md, "Comparing two versions of a task").

    diff_tasks(a, b, **verify_options) -> TaskDiff    the verifier both ways, the edits by behaviour
    TaskDiff.text() / .markdown() / .as_json()        what `schemalog diff` prints

The runs are the verifier's (schemalog.verify): B's runs are within A's when every step B takes
from any reachable state A allows (soundness) and B can always still accomplish the task where A
can (completion). Two versions are the same when each is within the other; a compressed form
(B read from a file `schemalog compress` wrote, with its provenance) is proved against the
original it was compressed from, the one way a compression promises (its merged behaviours run
fewer interleavings). The places are the behaviours B adds, removes, or gives another releaser,
post-condition or children, found by label; for task knowledge they are not decided one by one
(only the whole pair is), and the report says so.
"""

from __future__ import annotations

from dataclasses import dataclass

EQUAL, DIFFERENT, UNDECIDED = 0, 1, 3


@dataclass(frozen=True)
class TaskDiff:
    """Two versions of a task compared: the verifier's reports (B against A, and A against B
    unless B is A's compressed form), the behaviours' edits, in a reader's words."""

    a_name: str
    b_name: str
    forward: object                   # api.report.Report: B against A
    backward: object | None           # A against B; None for a compressed form
    changes: tuple[tuple[str, str], ...]   # (where, what) per edit

    @property
    def compression(self) -> bool:
        return self.backward is None

    @property
    def equal(self) -> bool:
        """Proved the same: each within the other (a compression: sound and complete)."""
        return all(r.proved for r in self._reports())

    @property
    def complete(self) -> bool:
        """Every report exhaustive, and none vacuous: the answer is a proof or a refutation."""
        return all(r.exhaustive or r.verdict == "refuted" for r in self._reports()) and \
            not any(r.vacuous for r in self._reports())

    @property
    def direction(self) -> str:
        """"equal", "b within a", "a within b", "neither" or "unknown"."""
        if any(not r.exhaustive and r.verdict != "refuted" for r in self._reports()):
            return "unknown"
        b_in_a = self.forward.verdict != "refuted"
        a_in_b = self.backward is not None and self.backward.verdict != "refuted"
        if self.compression:
            return "b within a" if b_in_a else "neither"
        return {(True, True): "equal", (True, False): "b within a", (False, True): "a within b"}.get(
            (b_in_a, a_in_b), "neither")

    @property
    def exit_status(self) -> int:
        if self.equal:
            return EQUAL
        if any(r.verdict == "refuted" for r in self._reports()):
            return DIFFERENT
        return UNDECIDED

    def _reports(self) -> list:
        return [self.forward] + ([] if self.backward is None else [self.backward])

    def headline(self) -> str:
        what = {EQUAL: "same behaviour" if not self.compression else "a sound and complete compression",
                DIFFERENT: "behaviour changed", UNDECIDED: "NOT decided"}[self.exit_status]
        return f"{self.a_name} -> {self.b_name}: {what}"

    def text(self) -> str:
        """The report for a terminal: the verdict, the direction, the edits, then each failing
        direction's report as `schemalog verify` prints it."""
        lines = [self.headline(), f"direction: {_direction_words(self.direction, self.compression)}"]
        if self.changes:
            lines.append(f"{len(self.changes)} edit{'s' if len(self.changes) != 1 else ''} by behaviour (the whole "
                         f"pair is decided on runs; task knowledge's edits are not decided one by one):")
            lines += [f"  {where}: {what}" for where, what in self.changes]
        else:
            lines.append("no edit by behaviour: the two trees have the same behaviours, conditions and order")
        for title, r, first, second in (("B against A (are B's runs within A's?)", self.forward, "A", "B"),
                                         ("A against B (are A's runs within B's?)", self.backward, "B", "A")):
            if r is None or r.proved:
                continue
            # verify's report names its two trees "the original" and "the compressed tree"
            words = "" if self.compression else (f" (in verify's words, {first} is \"the original\" and {second} "
                                                 f"\"the compressed tree\")")
            lines += ["", f"{title}{words}:", *("  " + x if x else "" for x in r.text().rstrip("\n").splitlines())]
        return "\n".join(lines) + "\n"

    def markdown(self) -> str:
        from .tree_diff import _cell, _md

        out = [f"### schemalog diff: {self.headline().split(': ', 1)[1]}", "",
               f"`{_md(self.a_name)}` → `{_md(self.b_name)}`", "",
               f"**Direction:** {_md(_direction_words(self.direction, self.compression))}", ""]
        if self.changes:
            out += ["| where | what changed |", "| --- | --- |"]
            out += [f"| `{where}` | {_cell(what)} |" for where, what in self.changes]
            out.append("")
        for title, r in (("B against A", self.forward), ("A against B", self.backward)):
            if r is not None and not r.proved:
                out += [f"<details><summary>{title}: {r.verdict}</summary>", "", "```text",
                        *r.text().rstrip("\n").splitlines(), "```", "", "</details>", ""]
        return "\n".join(out)

    def as_json(self) -> dict:
        return {"a": self.a_name, "b": self.b_name, "kind": "compression" if self.compression else "versions",
                "equal": self.equal, "complete": self.complete, "direction": self.direction,
                "changes": [{"where": w, "what": t} for w, t in self.changes],
                "b_against_a": self.forward.as_json(),
                "a_against_b": None if self.backward is None else self.backward.as_json()}


def _direction_words(direction: str, compression: bool) -> str:
    words = {"equal": "equal: every run of each is a run of the other",
             "b within a": "every run of B is a run of A (B only removes behaviour)" +
                           ("" if compression else ", not the converse"),
             "a within b": "every run of A is a run of B (B only adds behaviour), not the converse",
             "neither": "neither: each has a run the other has not" if not compression else
                        "B has a run A has not",
             "unknown": "not decided (a limit stopped the proof, or the task cannot complete)"}
    return words[direction]


def changes_of(a, b) -> list[tuple[str, str]]:
    """The behaviours B adds, removes, or gives another releaser, post-condition or children
    order, by label, each with where it stands (B's place, else A's)."""
    from ..logic.terms import term_to_text
    from ..task import conditions as cond
    from ..task.tree import walk

    def where(n) -> str:
        s = n.source
        return f"{s.file}:{s.line}:{s.column}" if s is not None and s.line else term_to_text(n.label)

    def key(n) -> str:
        return term_to_text(n.label)

    first = {key(n): n for n in walk(a)}
    second = {key(n): n for n in walk(b)}
    # a releaser is written in the parent's schema/3 clause, beside the child's label
    parent_b = {key(c): n for n in walk(b) for c in n.children}
    out: list[tuple[str, str]] = []
    for k, nb in second.items():
        na = first.get(k)
        if na is None:
            out.append((where(nb), f"B adds {k} (released by {cond.to_text(nb.releaser)})"))
            continue
        if cond.to_text(na.releaser) != cond.to_text(nb.releaser):
            out.append((where(parent_b.get(k, nb)), f"B releases {k} on {cond.to_text(nb.releaser)} instead of "
                                                    f"{cond.to_text(na.releaser)}"))
        if cond.to_text(na.post) != cond.to_text(nb.post):
            out.append((where(nb), f"B's {k} achieves {cond.to_text(nb.post)} instead of {cond.to_text(na.post)}"))
        kids_a, kids_b = [key(c) for c in na.children], [key(c) for c in nb.children]
        if kids_a != kids_b and sorted(kids_a) == sorted(kids_b):
            out.append((where(nb), f"B orders {k}'s children {', '.join(kids_b)} (A: {', '.join(kids_a)})"))
    for k, na in first.items():
        if k not in second:
            out.append((where(na), f"B removes {k}"))
    return out


def diff_tasks(a, b, a_name: str = "A", b_name: str = "B", **verify_options) -> TaskDiff:
    """Compare two versions of a task (schemalog Tasks), or a task and its compressed form (B
    compressed, with provenance): the verifier B against A, and A against B for two versions."""
    import schemalog

    forward = schemalog.verify(a, b, **verify_options)
    backward = None if b.compressed else schemalog.verify(b, a, **verify_options)
    shown_b = b.original.tree if b.compressed else b.tree
    changes = [] if b.compressed else changes_of(a.tree, shown_b)
    if b.compressed:
        merged = [n for n in _walk(b.tree) if len(n.origins) > 1]
        from ..logic.terms import term_to_text

        changes = [(f"{n.source.file}:{n.source.line}:{n.source.column}" if n.source and n.source.line
                    else term_to_text(n.label),
                    f"B merges {', '.join(term_to_text(x) for x in n.merged_from)} into {term_to_text(n.label)}")
                   for n in merged]
    return TaskDiff(a_name, b_name, forward, backward, tuple(changes))


def _walk(tree):
    from ..task.tree import walk

    return walk(tree)
