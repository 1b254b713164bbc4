"""The authors' SEED long-term memory (LTM.prolog), both ways: imported into the paper's
schema form, and a task tree written back as SEED knowledge.

    SEED:  schema(Name, [[Sub, Importance, [Releaser, ...]], ...]).   goal(Name, [Literal, ...]).
    ours:  schema(Name, [(Sub, Releaser), (Sub, Releaser, Importance), ...], Post).

Import. A schema takes its post-condition from the first `goal/2` whose head unifies with
its name; a generic schema (`schema(subtask(_, _), [])`) gets one specialised copy per
goal it unifies with, then keeps its generic form with the default post `Name.done`.
Rule schemas keep their bodies; when a body calls `schema/2` or `goal/2` (SEED's rules
ask the memory itself) the SEED clauses are kept as well, and so is every helper
predicate a body reaches; their bodies call ECLiPSe's term_string/2, atom_string/2 and
split_string/4 (logic/eclipse.py), where SWI-Prolog's differ. A sub-task that no schema can
name is left out with a warning, as SEED's "no semantic for ..." does (one that no rule
schema's body accepts, at instantiation: task/tree.py). `schema(object(O), [])` also declares `object(O)`;
gripper commands are declared to the gripper agent. The SEED server code
(getSemantics/1, updateSchema/4, ...) and its directives are not task knowledge: they
are skipped, and said so. SWI-Prolog's `listing/1` of such a memory reads the same: the
`[hand|free]` cells of SWI-Prolog 7, the `'.'(hand, free, A)` body goals of SWI-Prolog 9.

Export (`seed_text`). A task tree becomes ground SEED knowledge: one schema/2 and one
goal/2 per behaviour. Literals are written `[Obj|prop]`, which is the term ECLiPSe reads
for SEED's `Obj.prop` (its list cell is '.'/2), and which SWI-Prolog 9 reads without
turning it into a dict call. A releaser SEED cannot say, a disjunction, is written as one
entry per disjunct (SEED releases a behaviour when any node of its instance is
released), with an `exact_releaser(Parent, Index, Copies, Releaser)` fact that SEED
never asks and the importer reads back (also written where the lists hold the releaser only
up to equivalence, `x and not x` as `["FALSE"]`). Provenance, agents, objects and the initial state
are facts SEED ignores, written with `,` `;` `-` only; the ECLiPSe built-ins are written by
their ECLiPSe names again.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from ..task import conditions as cond
from ..errors import SchemalogError, SourcePos
from ..logic.eclipse import RENAMED
from ..logic.opread import parse_term
from ..logic.parse import Clause, Directive
from ..task.schema import DEFAULT_AGENT, Entry, SchemaDef, read_entry, schema_term
from ..logic.terms import (CONS, NIL, TRUE, Atom, Float, Int, Str, Struct, Term, Var, conjuncts, indicator,
                           iter_vars, list_items, make_list, term_to_text, variable_names)
from ..logic.unify import Bindings, rename, variant

# Predicates of schemalog's own knowledge: a SEED file that carries them (an export does)
# keeps them; SEED never asks for them.
VOCABULARY = frozenset({("task", 1), ("object", 1), ("objects", 2), ("agent", 2), ("initial", 1),
                        ("constraint", 1), ("no_merge", 1), ("behaviour", 1), ("origins", 2),
                        ("task_origins", 2)})
EXACT_RELEASER = ("exact_releaser", 4)


@dataclass
class SeedImport:
    """The clauses in our form, what was left out (notes), and sub-tasks dropped (warnings)."""

    clauses: list[Clause | Directive] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def is_seed(clauses: list[Clause | Directive]) -> bool:
    """Whether parsed text is SEED knowledge (schema/2 and no schema/3)."""
    heads = [c.head for c in clauses if isinstance(c, Clause)]
    has2 = any(isinstance(h, Struct) and h.name == "schema" and len(h.args) == 2 for h in heads)
    has3 = any(isinstance(h, Struct) and h.name == "schema" and len(h.args) == 3 for h in heads)
    return has2 and not has3


def default_post(label: Term) -> cond.Condition:
    """`Label.done`: the post-condition of a behaviour with no goal."""
    return cond.Lit(Struct(".", (label, Atom("done"))))


# ---------------------------------------------------------------------------
# Import

def import_seed(items: list[Clause | Directive]) -> SeedImport:
    """Translate parsed SEED text into schema/3 clauses."""
    out = SeedImport()
    items = [_eclipse_clause(_without_dict_calls(i)) if isinstance(i, Clause) else i for i in items]
    clauses = [c for c in items if isinstance(c, Clause)]
    seed_clauses = [c for c in clauses if _is(c.head, "schema", 2) or _is(c.head, "goal", 2)]
    goals = [c for c in clauses if _is(c.head, "goal", 2)]
    schema_heads = [c.head.args[0] for c in clauses if _is(c.head, "schema", 2)]
    disjunctions = _disjunctions(clauses)
    reached = _reached(seed_clauses + [c for c in clauses if indicator(c.head) in VOCABULARY], clauses)
    keep_seed = ("schema", 2) in reached or ("goal", 2) in reached
    skipped: Counter[str] = Counter()
    grippers: dict[str, Term] = {}
    objects: list[Term] = []
    for item in items:
        if isinstance(item, Directive):
            if _declares_kept(item.goal, reached | VOCABULARY, keep_seed):
                out.clauses.append(item)
            else:
                skipped[f":- {term_to_text(item.goal)}"] += 1
            continue
        head = item.head
        if _is(head, "goal", 2):
            continue
        if not _is(head, "schema", 2):
            ind = indicator(head)
            if ind in VOCABULARY or ind in reached:
                out.clauses.append(item)
            elif ind != EXACT_RELEASER:
                skipped[f"{ind[0]}/{ind[1]}" if ind else term_to_text(head)] += 1
            continue
        name, subs = head.args
        where = f"SEED schema {term_to_text(name)}"
        items_, tail = list_items(subs)
        if tail != NIL:
            raise SchemalogError(f"{where}: the sub-task list must be a list, not {term_to_text(subs)}", item.pos)
        try:
            entries = [read_entry(_strings_read(e, item.pos), where) for e in items_]
        except SchemalogError as err:
            raise SchemalogError(err.message, err.pos or item.pos) from None
        entries = _collapse(name, entries, disjunctions)
        kept = []
        for e in entries:
            if any(Bindings().unify(rename(h), e.behaviour) for h in schema_heads):
                kept.append(e)
            else:
                out.warnings.append(f"{item.pos}: warning: no semantic for {term_to_text(e.behaviour)} "
                                    f"(a sub-task of {term_to_text(name)}): left out, as SEED does")
        entries = tuple(kept)
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
    if keep_seed:
        # A rule asks SEED's memory itself (`schema(speech(A), _)`): it gets it, as written.
        out.clauses.extend(seed_clauses)
        out.notes.append("kept the schema/2 and goal/2 clauses too: a rule's body asks for them")
    for obj in objects:
        out.clauses.append(Clause(Struct("object", (obj,)), TRUE, None))
    for pattern in grippers.values():
        out.clauses.append(Clause(Struct("agent", (pattern, Atom("gripper"))), TRUE, None))
    if skipped:
        listing = ", ".join(f"{k} (x{n})" if n > 1 else k for k, n in sorted(skipped.items()))
        out.notes.append(f"skipped what is not task knowledge: {listing}")
    return out


# Control constructs and meta-calls, and which of their arguments are goals.
_GOAL_ARGS = {(",", 2): (0, 1), (";", 2): (0, 1), ("->", 2): (0, 1), ("*->", 2): (0, 1), ("\\+", 1): (0,),
              ("not", 1): (0,), ("call", 1): (0,), ("once", 1): (0,), ("ignore", 1): (0,),
              ("forall", 2): (0, 1), ("findall", 3): (1,), ("findall", 4): (1,), ("bagof", 3): (1,),
              ("setof", 3): (1,), ("aggregate_all", 3): (1,), ("catch", 3): (0, 2), ("^", 2): (1,)}


def _renamed_goals(body: Term, names: dict[tuple[str, int], str]) -> Term:
    """`body` with each goal whose predicate `names` maps called by its new name, inside
    control constructs and meta-calls too (a goal built at run time is not seen)."""
    def goal(g: Term) -> Term:
        if not isinstance(g, Struct):
            return g
        key = (g.name, len(g.args))
        if key in names:
            return Struct(names[key], g.args)
        places = _GOAL_ARGS.get(key)
        if places is None:
            return g
        if key == (",", 2):   # a long conjunction is a loop, not a recursion
            parts = [goal(c) for c in conjuncts(g)]
            result = parts[-1]
            for part in reversed(parts[:-1]):
                result = Struct(",", (part, result))
            return result
        return Struct(g.name, tuple(goal(a) if i in places else a for i, a in enumerate(g.args)))
    return goal(body)


def _eclipse_clause(c: Clause) -> Clause:
    """A SEED clause whose body calls ECLiPSe's term_string/2, atom_string/2, split_string/4."""
    if c.body == TRUE:
        return c
    return Clause(c.head, _renamed_goals(c.body, RENAMED), c.pos)


def _without_dict_calls(c: Clause) -> Clause:
    """Undo SWI-Prolog 9's reading of `hand.free` in a schema/2 or goal/2 clause: its listing
    shows `[A] :- '.'(hand, free, A)`; the literal goes back where A stood."""
    if not (_is(c.head, "schema", 2) or _is(c.head, "goal", 2)) or c.body == TRUE:
        return c
    b = Bindings()
    rest = []
    for g in conjuncts(c.body):
        if isinstance(g, Struct) and g.name == "." and len(g.args) == 3 and isinstance(b.walk(g.args[2]), Var):
            b.unify(g.args[2], Struct(".", g.args[:2]))
        else:
            rest.append(g)
    if len(rest) == len(conjuncts(c.body)):
        return c
    body = TRUE
    for g in reversed(rest):
        body = g if body == TRUE else Struct(",", (g, body))
    return Clause(b.resolve(c.head), b.resolve(body), c.pos)


def _strings_read(entry: Term, pos: SourcePos | None) -> Term:
    """An entry `[Sub, Importance, Releasers]` with its releasers' strings read."""
    items, tail = list_items(entry)
    if tail != NIL or len(items) != 3:
        return entry
    return make_list([items[0], items[1], _read_strings(items[2], pos)])


def _read_strings(releasers: Term, pos: SourcePos | None) -> Term:
    """SEED names a releaser by its text: `"hand.free"` is the literal hand.free."""
    def read(t: Term) -> Term:
        if isinstance(t, Str) and t.value.upper() not in ("TRUE", "FALSE"):
            try:
                read_term = parse_term(t.value)
            except SchemalogError as err:
                raise SchemalogError(f"the releaser {term_to_text(t)} does not read as a literal: "
                                     f"{err.message.splitlines()[0]}", pos) from None
            if any(True for _ in iter_vars(read_term)):
                # SEED takes a string's text as the name of a working-memory variable, as written:
                # its `Obj` is never the schema's Obj.
                raise SchemalogError(f"the releaser {term_to_text(t)} names a variable inside a string, "
                                     f"which SEED never instantiates; write it without the quotes", pos)
            return read_term
        return t
    items, tail = list_items(releasers)
    if tail == NIL and isinstance(releasers, Struct):
        return make_list([read(i) for i in items])
    return read(releasers)


def _disjunctions(clauses: list[Clause]) -> dict[tuple[Term, int], tuple[int, cond.Condition]]:
    """The exact_releaser/4 facts of an export: (parent, index) -> (copies, releaser)."""
    found = {}
    for c in clauses:
        if indicator(c.head) == EXACT_RELEASER and c.body == TRUE:
            parent, index, copies, releaser = c.head.args
            if not (isinstance(index, Int) and isinstance(copies, Int) and copies.value >= 1):
                raise SchemalogError("exact_releaser(Parent, Index, Copies, Releaser) needs whole "
                                     "numbers for Index and Copies", c.pos)
            try:
                found[(parent, index.value)] = (copies.value, cond.from_term(releaser))
            except cond.NotACondition as err:
                raise SchemalogError(f"exact_releaser: {err}", c.pos) from None
    return found


def _collapse(name: Term, entries: list[Entry], disjunctions) -> list[Entry]:
    """Read back the entries an export wrote for one sub-task (a disjunction: one per disjunct)."""
    if not disjunctions:
        return entries
    out, i = [], 0
    while i < len(entries):
        found = disjunctions.get((name, i))
        if found is None:
            out.append(entries[i])
            i += 1
            continue
        copies, releaser = found
        out.append(Entry(entries[i].behaviour, releaser, entries[i].importance))
        i += copies
    return out


def _calls(body: Term) -> list[tuple[str, int]]:
    """The predicates a body may call (control constructs and meta-calls looked into)."""
    found, stack = [], [body]
    while stack:
        g = stack.pop()
        if isinstance(g, Struct) and g.name in (",", ";", "->", "*->") and len(g.args) == 2:
            stack.extend(g.args)
        elif isinstance(g, Struct) and g.name in ("\\+", "call", "once", "ignore", "forall", "findall",
                                                   "bagof", "setof", "aggregate_all"):
            found.append((g.name, len(g.args)))
            stack.extend(a for a in g.args if isinstance(a, (Atom, Struct)))
        elif isinstance(g, (Atom, Struct)):
            found.append(indicator(g))
    return found


def _reached(roots: list[Clause], clauses: list[Clause]) -> set[tuple[str, int]]:
    """Every predicate the bodies of `roots` reach through the file's own clauses."""
    by_pred: dict[tuple[str, int], list[Clause]] = {}
    for c in clauses:
        by_pred.setdefault(indicator(c.head), []).append(c)
    reached: set[tuple[str, int]] = set()
    stack = [ind for c in roots for ind in _calls(c.body)]
    while stack:
        ind = stack.pop()
        if ind in reached:
            continue
        reached.add(ind)
        for c in by_pred.get(ind, ()):
            stack.extend(_calls(c.body))
    return reached


def _declares_kept(goal: Term, kept: set, keep_seed: bool) -> bool:
    """Whether a directive is `dynamic` for predicates kept (schema/2 and goal/2 only when kept)."""
    if not (isinstance(goal, Struct) and goal.name == "dynamic" and len(goal.args) == 1):
        return False
    specs = []
    for t in conjuncts(goal.args[0]):
        items, tail = list_items(t)
        specs.extend(items if tail == NIL and isinstance(t, Struct) and t.name == CONS else [t])
    for s in specs:
        if not (isinstance(s, Struct) and s.name == "/" and len(s.args) == 2 and isinstance(s.args[0], Atom)
                and isinstance(s.args[1], Int)):
            return False
        ind = (s.args[0].name, s.args[1].value)
        if ind in (("schema", 2), ("goal", 2)):
            if not keep_seed:
                return False
        elif ind not in kept:
            return False
    return True


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
            post = cond.from_term(_read_strings(g_list, g.pos))
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


# ---------------------------------------------------------------------------
# Export

SEED_PROLOGUE = (":- op(500, xfy, .).", ":- op(600, fx, -).", ":- dynamic schema/2.", ":- dynamic goal/2.")


def seed_text(document_clauses: list[Clause], header: str | None = None) -> str:
    """SEED long-term memory for the ground knowledge of `formats.render.tree_document`
    (schema/3 facts, task/1, object/1, objects/2, agent/2, origins, carried clauses)."""
    schemas = [c for c in document_clauses if _is(c.head, "schema", 3)]
    labels = [c.head.args[0] for c in schemas]
    agents = {c.head.args[0] for c in document_clauses if _is(c.head, "agent", 2)}
    lines = [f"% {line}".rstrip() for line in (header or "").splitlines()]
    lines += ["" if lines else None, *SEED_PROLOGUE, ""]
    lines = [x for x in lines if x is not None]
    markers: list[Term] = []
    goals: list[str] = []
    for c in schemas:
        label, subs, post = c.head.args
        entries = [read_entry(e, f"schema {term_to_text(label)}") for e in list_items(subs)[0]]
        seed_entries: list[str] = []
        for e in entries:
            disjuncts = _disjuncts(e.releaser, label, e.behaviour)
            if len(disjuncts) > 1 or cond.conjoin(list(disjuncts[0])) != e.releaser:
                # SEED's lists say it only up to equivalence: the exact releaser goes beside them.
                markers.append(Struct("exact_releaser", (label, Int(len(seed_entries)), Int(len(disjuncts)),
                                                               _safe_condition(e.releaser))))
            for lits in disjuncts:
                releasers = make_list([_literal_term(x) for x in lits]) if lits else make_list([Str("TRUE")])
                seed_entries.append(_text(make_list([e.behaviour, _weight(e.importance), releasers])))
        if seed_entries:
            inner = ",\n".join(f"\t{x}" for x in seed_entries)
            lines.append(f"schema({_text(label)}, [\n{inner}\n\t]).")
        else:
            lines.append(f"schema({_text(label)}, []).")
        post_c = cond.from_term(post)
        literals = post_c.items if isinstance(post_c, cond.And) else () if post_c == cond.TRUE else (post_c,)
        goals.append(f"goal({_text(label)}, {_text(make_list([_literal_term(x) for x in literals]))}).")
    lines += ["", *goals, ""]
    # What SEED never asks for: schemalog's own facts, read back by the importer.
    for c in document_clauses:
        if _is(c.head, "schema", 3):
            continue
        lines.append(_text(_safe_clause(c), 1200) + ".")
    for label in labels:
        if _mentions_gripper(label) and label not in agents:
            lines.append(_text(Struct("agent", (label, Atom(DEFAULT_AGENT)))) + ".")  # not the gripper
    for m in markers:
        lines.append(_text(m) + ".")
    return "\n".join(lines).rstrip("\n") + "\n"


def _disjuncts(releaser: cond.Condition, label: Term, sub: Term) -> list[tuple[cond.Lit, ...]]:
    """The releaser as SEED's lists: one conjunction of literals per disjunct."""
    dnf = cond.to_dnf(releaser)
    if dnf is None:
        raise SchemalogError(f"cannot write {term_to_text(label)} as SEED: the releaser of {term_to_text(sub)} "
                             f"has more than {cond.DEFAULT_DNF_LIMIT} disjuncts (SEED's releasers are "
                             f"conjunctions of literals)")
    if not dnf:
        return [(cond.FALSE,)]  # SEED's working memory holds FALSE = 0: ["FALSE"] is never released
    order: dict[cond.Lit, int] = {}
    for lit in cond.literals(cond.nnf(releaser)):  # disjuncts and literals in the order written
        order.setdefault(lit, len(order))
    ranked = cond.from_dnf(dnf, order)
    parts = ranked.items if isinstance(ranked, cond.Or) else (ranked,)
    return [tuple(p.items) if isinstance(p, cond.And) else () if p == cond.TRUE else (p,) for p in parts]


def _cell(atom: Term) -> Term:
    """`Obj.prop` as the cell [Obj|prop]: ECLiPSe's reading of SEED's dot, and no dict for SWI."""
    if isinstance(atom, Struct) and atom.name == "." and len(atom.args) == 2:
        obj, prop = atom.args
        if (isinstance(prop, Struct) and prop.name in (".", CONS)) or prop == NIL:
            raise SchemalogError(f"cannot write the literal {term_to_text(atom)} for SEED: its property "
                                 f"is not an atom or a simple term")
        return Struct(CONS, (_cell(obj), prop))
    return atom


def _literal_term(lit: cond.Condition) -> Term:
    if lit == cond.FALSE:
        return Str("FALSE")
    assert isinstance(lit, cond.Lit)
    return _cell(lit.atom) if lit.positive else Struct("-", (_cell(lit.atom),))


def _safe_condition(c: cond.Condition) -> Term:
    """A condition in words both ECLiPSe and SWI-Prolog read: `,` `;` `-` `\\+` and cells."""
    if isinstance(c, cond.Const):
        return Atom("true" if c.value else "false")
    if isinstance(c, cond.Lit):
        return _literal_term(c)
    if isinstance(c, cond.Not):
        return Struct("\\+", (_safe_condition(c.item),))
    op = "," if isinstance(c, cond.And) else ";"
    result = _safe_condition(c.items[-1])
    for item in reversed(c.items[:-1]):
        result = Struct(op, (_safe_condition(item), result))
    return result


def _safe_clause(c: Clause) -> Term:
    """A fact or rule to write in the SEED file; conditions inside schemalog's facts made safe."""
    head = c.head
    if _is(head, "initial", 1) or _is(head, "constraint", 1):
        try:
            head = Struct(head.name, (_safe_condition(cond.from_term(head.args[0])),))
        except cond.NotACondition:
            pass
    elif _is(head, "origins", 2) or _is(head, "task_origins", 2):
        def origin(t: Term) -> Term:
            label, releaser, post, *rest = t.args
            return Struct("origin", (label, _safe_condition(cond.from_term(releaser)),
                                     _safe_condition(cond.from_term(post)), *rest))
        value = head.args[1]
        if head.name == "origins":
            value = make_list([make_list([origin(o) for o in list_items(g)[0]]) for g in list_items(value)[0]])
        else:
            value = make_list([origin(o) for o in list_items(value)[0]])
        head = Struct(head.name, (head.args[0], value))
    if c.body == TRUE:
        return head
    return Struct(":-", (head, _renamed_goals(c.body, {(new, arity): old for (old, arity), new in RENAMED.items()})))


def _text(t: Term, priority: int = 1199) -> str:
    return term_to_text(t, priority, variable_names([t]), next_argument=True)


__all__ = ["SeedImport", "is_seed", "import_seed", "default_post", "seed_text", "VOCABULARY"]
