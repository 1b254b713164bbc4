"""Import the authors' SEED long-term memory (LTM.prolog) into the paper's schema form.

    SEED:  schema(Name, [[Sub, Importance, [Releaser, ...]], ...]).   goal(Name, [Literal, ...]).
    ours:  schema(Name, [(Sub, Releaser), (Sub, Releaser, Importance), ...], Post).

A schema takes its post-condition from the first `goal/2` whose head unifies with
its name; a generic schema (`schema(subtask(_, _), [])`) gets one specialised copy per
goal it unifies with, then keeps its generic form with the default post
`Name.done`. Rule schemas keep their bodies. `schema(object(O), [])` also declares
`object(O)`. Gripper commands are declared to the gripper agent. The SEED server
code (getSemantics/1, updateSchema/4, ...) and its directives are not task
knowledge: they are skipped, and said so.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from ..task import conditions as cond
from ..errors import SchemalogError
from ..logic.parse import Clause, Directive
from ..task.schema import Entry, SchemaDef, read_entry, schema_term
from ..logic.terms import NIL, TRUE, Atom, Float, Int, Struct, Term, Var, iter_vars, list_items, term_to_text
from ..logic.unify import Bindings, rename, variant


@dataclass
class SeedImport:
    """The clauses in our form, and what was left out."""

    clauses: list[Clause] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def is_seed(clauses: list[Clause | Directive]) -> bool:
    """Whether parsed text is SEED knowledge (schema/2 and no schema/3)."""
    heads = [c.head for c in clauses if isinstance(c, Clause)]
    has2 = any(isinstance(h, Struct) and h.name == "schema" and len(h.args) == 2 for h in heads)
    has3 = any(isinstance(h, Struct) and h.name == "schema" and len(h.args) == 3 for h in heads)
    return has2 and not has3


def default_post(label: Term) -> cond.Condition:
    """`Label.done`: the post-condition of a behaviour with no goal."""
    return cond.Lit(Struct(".", (label, Atom("done"))))


def import_seed(items: list[Clause | Directive]) -> SeedImport:
    """Translate parsed SEED text into schema/3 clauses."""
    out = SeedImport()
    goals = [c for c in items if isinstance(c, Clause) and _is(c.head, "goal", 2)]
    skipped: Counter[str] = Counter()
    grippers: dict[str, Term] = {}
    objects: list[Term] = []
    for item in items:
        if isinstance(item, Directive):
            skipped[f":- {term_to_text(item.goal)}"] += 1
            continue
        head = item.head
        if _is(head, "goal", 2):
            continue
        if not _is(head, "schema", 2):
            skipped[f"{head.name}/{len(head.args)}" if isinstance(head, Struct) else term_to_text(head)] += 1
            continue
        name, subs = head.args
        where = f"SEED schema {term_to_text(name)}"
        items_, tail = list_items(subs)
        if tail != NIL:
            raise SchemalogError(f"{where}: the sub-task list must be a list, not {term_to_text(subs)}", item.pos)
        try:
            entries = tuple(read_entry(e, where) for e in items_)
        except SchemalogError as err:
            raise SchemalogError(err.message, item.pos) from None
        for e in entries:
            _note_gripper(e.behaviour, grippers)
        if not entries:
            _note_gripper(name, grippers)
        if isinstance(name, Struct) and name.name == "object" and len(name.args) == 1 and not entries:
            objects.append(name.args[0])
        for specialised_name, specialised_entries, body, post, general in _with_goals(
                name, entries, item.body, goals):
            s = SchemaDef(specialised_name, specialised_entries, post, body, item.pos)
            out.clauses.append(Clause(schema_term(s), body, item.pos))
            if general:
                break
    for obj in objects:
        out.clauses.append(Clause(Struct("object", (obj,)), TRUE, None))
    for pattern in grippers.values():
        out.clauses.append(Clause(Struct("agent", (pattern, Atom("gripper"))), TRUE, None))
    if skipped:
        listing = ", ".join(f"{k} (x{n})" if n > 1 else k for k, n in sorted(skipped.items()))
        out.notes.append(f"skipped what is not task knowledge: {listing}")
    return out


def _with_goals(name: Term, entries: tuple[Entry, ...], body: Term, goals: list[Clause]):
    """Yield (name, entries, body, post, covers_all) for each goal that fits, then the default."""
    for g in goals:
        b = Bindings()
        pair = rename(Struct("-", (g.head, g.body)))
        g_head, g_body = pair.args
        if g_body != TRUE or not b.unify(g_head.args[0], name):
            continue
        resolved = b.resolve(Struct("s", (name, g_head.args[1], body, *[_entry_struct(e) for e in entries])))
        s_name, g_list, s_body, *s_entries = resolved.args
        try:
            post = cond.from_term(g_list)
        except cond.NotACondition as err:
            raise SchemalogError(f"goal of {term_to_text(s_name)} is not a condition: {err}", g.pos) from None
        # A goal that does not narrow the schema's name covers it: no default copy after it.
        general = variant(s_name, name)
        yield s_name, tuple(_entry_back(e) for e in s_entries), s_body, post, general
        if general:
            return
    yield name, entries, body, default_post(name), True


def _entry_struct(e: Entry) -> Term:
    return Struct("e", (e.behaviour, cond.to_term(e.releaser), _weight(e.importance)))


def _entry_back(t: Struct) -> Entry:
    weight = t.args[2]
    return Entry(t.args[0], cond.from_term(t.args[1]), weight.value)


def _weight(w: int | float) -> Term:
    return Int(w) if isinstance(w, int) else Float(w)


def _note_gripper(label: Term, grippers: dict[str, Term]) -> None:
    """Declare behaviours that command the gripper (`kuka(gripper(open))`) to the gripper agent."""
    if _mentions_gripper(label):
        pattern = _generalise_gripper(label)
        key = term_to_text(pattern, names={v: "_" for v in iter_vars(pattern)})  # _G12 == _G40
        grippers.setdefault(key, pattern)


def _mentions_gripper(t: Term) -> bool:
    stack = [t]
    while stack:
        x = stack.pop()
        if isinstance(x, Struct):
            if x.name == "gripper" and len(x.args) == 1:
                return True
            stack.extend(x.args)
    return False


def _generalise_gripper(t: Term) -> Term:
    if isinstance(t, Struct):
        if t.name == "gripper" and len(t.args) == 1:
            return Struct("gripper", (Var("_"),))
        return Struct(t.name, tuple(_generalise_gripper(a) if _mentions_gripper(a) else a for a in t.args))
    return t


def _is(term: Term, name: str, arity: int) -> bool:
    return isinstance(term, Struct) and term.name == name and len(term.args) == arity
