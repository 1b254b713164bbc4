"""KnowledgeBase: clauses by predicate, argument indexes, and consult.

    KnowledgeBase.predicates : dict[(name, arity), Predicate]
    Predicate.clauses        : list[StoredClause]            in source order
    Predicate index          : dict[key, list[StoredClause]]  key = an argument's
                                                              principal functor

    KnowledgeBase.multifile  : set[(name, arity)]             declared multifile
    definitions              : Definitions                    which predicates files share

A call whose first argument is bound only tries the clauses with the same key or
a variable there; a call whose first argument is unbound uses the first other bound
argument, indexed just in time. A list a call may hold is never changed in place, so a
running call keeps its snapshot (the logical update view): assert and retract replace the
one bucket a clause's key names (a copy of that bucket, not a rebuild of the index), and
copy the clause list only when a call was handed it.

Several files make one program, as SWI-Prolog consults them, but a predicate is defined by
one file: a clause of it read from a second file is an error naming both places, unless the
predicate was declared `multifile` first. `Definitions` lets a language built on the engine
(the schema language) define some predicates per first argument, or let every file add to
them. Reading a file again replaces what it defined (a reconsult).

The knowledge base is the engine's `builtins.Database`; it sits above the engine because
consulting runs directives (`:- Goal.`) with it, and the engine never imports it back.
"""

from __future__ import annotations

import functools
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Iterator
from pathlib import Path

from .. import defaults
from ..cache import remembered
from ..errors import SchemalogError, SourcePos, unquoted
from ..inputs import missing
from . import dcg
from .compile import COMPILE_AFTER, activate_by_copy, activate_ground, compile_clause, compile_copy
from .engine import Engine, is_builtin
from .exceptions import PrologError, StepLimitExceeded
from .fastread import parse_text
from .parse import MAX_BYTES, Clause, Directive, grammar_text, lark_version, read_source
from .terms import TRUE, Atom, Float, Int, Str, Struct, Term, Var, conjuncts, indicator, is_ground, list_items, quote_atom, term_to_text, variable_names
from .unify import Bindings, rename

Key = tuple  # ("atom", name) | ("struct", name, arity) | ("int", v) | ...


_STRUCT_KEYS: dict[Key, Key] = {}   # a memo of immutable values, not state: see first_arg_key


def first_arg_key(term: Term) -> Key | None:
    """The index key of a (walked) first argument; None for a variable."""
    if isinstance(term, Var):
        return None
    if isinstance(term, Struct):
        # One tuple per functor, not per clause: a file of 100,000 schemas keys each twice.
        key = ("s", term.name, len(term.args))
        return _STRUCT_KEYS.setdefault(key, key)
    if isinstance(term, Atom):
        return ("a", term.name)
    if isinstance(term, Float):
        return ("Float", term.value.hex())      # NaN equals itself, as Float compares
    return (type(term).__name__, term.value)  # Int, Str


@dataclass(eq=False, slots=True)
class StoredClause:
    """A clause in the knowledge base; `source` is the file it was read from (resolved)."""

    head: Term
    body: Term
    pos: SourcePos | None = None
    library: bool = False
    source: Path | None = None
    key: Key | None = field(init=False)
    _copier: object = field(default=None, init=False, repr=False, compare=False)
    _activation: object = field(default=None, init=False, repr=False, compare=False)
    _by_copy: object = field(default=None, init=False, repr=False, compare=False)
    _calls: int = field(default=0, init=False, repr=False, compare=False)
    erased: bool = field(default=False, init=False, repr=False, compare=False)   # retracted

    def __post_init__(self) -> None:
        self.key = first_arg_key(self.head.args[0]) if isinstance(self.head, Struct) else None

    # The compiled copier and activations are code made with exec (compile.py), which pickle
    # cannot write, and a cache: an unpickled clause compiles them again when first called.
    _COMPILED = ("_copier", "_activation", "_by_copy", "_calls")

    def __getstate__(self) -> dict:
        """Its clause and where it came from, without the compiled code (a cache)."""
        return {name: getattr(self, name) for name in self.__slots__ if name not in self._COMPILED}

    def __setstate__(self, state: dict) -> None:
        for name in self._COMPILED:
            setattr(self, name, 0 if name == "_calls" else None)
        for name, value in state.items():
            setattr(self, name, value)

    def renamed(self) -> tuple[Term, Term]:
        """A copy of (head, body) with fresh variables; a clause without variables is its
        own copy (retract and clause/2 of a fact compile nothing)."""
        copy = self._copier
        if copy is None:
            if is_ground(self.head) and is_ground(self.body):
                copy = self._copier = False
            else:
                copy = self._copier = compile_copy(Struct(":-", (self.head, self.body)))
        if copy is False:
            return self.head, self.body
        pair = copy()
        return pair.args[0], pair.args[1]

    def activate(self, args: tuple, b, height: int, rest):
        """Unify a fresh copy of the head with a call of arguments `args` and return the goal
        list with the body's goals in front of `rest`, each cutting to `height`; False when the
        head does not match (the caller undoes the bindings). See compile.py."""
        activation = self._activation
        if activation is None:
            if is_ground(self.head) and is_ground(self.body):
                activation = self._activation = activate_ground(self.head, self.body)
            else:
                self._calls += 1
                if self._calls <= COMPILE_AFTER:
                    if self._by_copy is None:
                        self._by_copy = activate_by_copy(self.head, self.body)
                    return self._by_copy(args, b, height, rest)
                activation = self._activation = compile_clause(self.head, self.body)
        return activation(args, b, height, rest)

    def text(self) -> str:
        """The clause as Prolog text."""
        if self.body is TRUE:
            return term_to_text(self.head) + "."
        return term_to_text(Struct(":-", (self.head, self.body))) + "."


class Predicate:
    """The clauses of one predicate and their argument indexes.

    The first argument is indexed as clauses are called; another argument is indexed
    just in time, the first time a call leaves the first argument unbound but binds that
    one (SWI-Prolog's JIT indexing), so `parent(B2, P)` with P bound is a lookup, not a
    scan. An index is kept across assert and retract of a clause with a key there: the
    bucket of that key is replaced by a copy with the clause added or removed (a bucket
    may be held by a call). A clause with a variable there belongs in every bucket: adding
    or removing one drops the index, rebuilt on demand.

    The logical update view: a call goes on with the clauses it started with, whatever is
    asserted or retracted meanwhile. So once `clauses` has been handed to a call
    (`_shared`), adding or removing a clause replaces the list (one copy, in C) instead of
    changing it; until then assertz appends and retract deletes in place, and a directive
    asserting n facts costs O(n), not O(n^2).
    """

    __slots__ = ("clauses", "_index", "_unindexed", "_jit", "dynamic", "_shared", "_users")

    MIN_CLAUSES = 2  # one clause needs no index

    def __init__(self) -> None:
        self.clauses: list[StoredClause] = []
        self._index: dict[Key, list[StoredClause]] | None = None
        self._unindexed: list[StoredClause] = []
        self._jit: dict[int, tuple[dict[Key, list[StoredClause]], list[StoredClause]] | None] = {}
        self.dynamic = False
        self._shared = False   # `clauses` itself is held by a call in progress
        self._users = 0        # clauses not from the library

    def changed(self) -> None:
        self._index = None
        self._jit = {}

    def library_only(self) -> bool:
        """Whether every clause came from the prelude (a user file replaces such a predicate)."""
        return bool(self.clauses) and not self._users

    def add(self, clause: StoredClause, front: bool = False) -> None:
        """Add a clause last (first with `front`), keeping lists handed out unchanged."""
        if front:
            self.clauses = [clause, *self.clauses]
        elif self._shared:
            self.clauses = [*self.clauses, clause]
        else:
            self.clauses.append(clause)
        self._shared = False
        self._users += not clause.library
        if self._index is not None:
            if not _index_add(self._index, self._unindexed, clause, clause.key, front):
                self._index = None
        self._reindex_jit(clause, front)

    def remove(self, clause: StoredClause) -> None:
        """Remove one clause (retract); one already removed stays removed. The clause list
        is searched by identity (in C) and copied only when a call holds it; the indexes
        lose the clause from its key's bucket."""
        if clause.erased:
            return
        clauses = self.clauses
        try:
            position = clauses.index(clause)   # StoredClause compares by identity
        except ValueError:
            return
        if self._shared:
            self.clauses = clauses[:position] + clauses[position + 1:]
            self._shared = False
        else:
            del clauses[position]
        clause.erased = True
        self._users -= not clause.library
        if self._index is not None:
            if not _index_remove(self._index, self._unindexed, clause, clause.key):
                self._index = None
        self._reindex_jit(clause, None)

    def _reindex_jit(self, clause: StoredClause, front: bool | None) -> None:
        """Keep the just-in-time indexes after adding (`front` False or True) or removing
        (None) `clause`; one it cannot keep is dropped, rebuilt on demand."""
        if not self._jit:
            return
        for position, built in list(self._jit.items()):
            key = _arg_key(clause, position)
            if built is None:
                del self._jit[position]      # judged useless before: judged again when asked
            elif not (_index_add(built[0], built[1], clause, key, front) if front is not None
                      else _index_remove(built[0], built[1], clause, key)):
                del self._jit[position]

    def add_all(self, clauses: list[StoredClause]) -> None:
        """Add clauses last, in order."""
        self.clauses = [*self.clauses, *clauses]
        self._shared = False
        self._users += sum(not c.library for c in clauses)
        self.changed()

    def replace(self, clauses: list[StoredClause]) -> None:
        """Keep only `clauses` (retract, reconsult)."""
        self.clauses = clauses
        self._shared = False
        self._users = sum(not c.library for c in clauses)
        self.changed()

    def copies_on_add(self, front: bool = False) -> bool:
        """Whether adding a clause now copies the clause list (asserta, or a call holds it)."""
        return front or self._shared

    def candidates(self, first: Term | None) -> list[StoredClause]:
        if first is None or isinstance(first, Var) or len(self.clauses) < self.MIN_CLAUSES:
            self._shared = True
            return self.clauses
        if self._index is None:
            self._index, self._unindexed = _build_index(self.clauses, lambda c: c.key)
        return self._index.get(first_arg_key(first), self._unindexed)

    def select(self, args: tuple, b) -> list[StoredClause]:
        """The clauses that may match a call with these arguments (the engine's hot path:
        the first argument dereferenced and keyed inline; engine._run inlines the case of
        an index already built, so the two must key alike)."""
        clauses = self.clauses
        if len(clauses) < self.MIN_CLAUSES or not args:
            self._shared = True
            return clauses
        first = args[0]
        values = b.values
        while type(first) is Var:
            bound = values.get(first)
            if bound is None:
                if len(args) > 1:
                    return self.candidates_by(args, b.walk)
                self._shared = True
                return clauses
            first = bound
        index = self._index
        if index is None:
            index, self._unindexed = _build_index(clauses, lambda c: c.key)
            self._index = index
        if not index:   # no clause has a constant first argument (tak/4): no key to compute
            return self._unindexed
        kind = type(first)
        if kind is Struct:
            key = ("s", first.name, len(first.args))
        elif kind is Atom:
            key = ("a", first.name)
        elif kind is Int:
            key = ("Int", first.value)    # as first_arg_key keys an integer
        else:
            key = first_arg_key(first)
        return index.get(key, self._unindexed)

    def candidates_by(self, args: tuple, walk) -> list[StoredClause]:
        """The candidates of a call whose first argument is unbound: the bucket of the
        first other bound argument worth indexing on, else every clause."""
        if len(self.clauses) < self.MIN_CLAUSES:
            self._shared = True
            return self.clauses
        for position in range(1, len(args)):
            value = walk(args[position])
            if isinstance(value, Var):
                continue
            if position not in self._jit:
                self._jit[position] = _useful_index(self.clauses, position)
            built = self._jit[position]
            if built is not None:
                index, unindexed = built
                return index.get(first_arg_key(value), unindexed)
        self._shared = True
        return self.clauses


def _index_add(index: dict, unindexed: list, clause: StoredClause, key: Key | None, front: bool) -> bool:
    """Add `clause` to its key's bucket (a new list: the old one may be held by a call);
    False when the index cannot keep it (a variable there: it belongs in every bucket)."""
    if key is None:
        return False
    bucket = index.get(key, unindexed)
    index[key] = [clause, *bucket] if front else [*bucket, clause]
    return True


def _index_remove(index: dict, unindexed: list, clause: StoredClause, key: Key | None) -> bool:
    """Remove `clause` from its key's bucket (a new list); False as for _index_add."""
    if key is None:
        return False
    bucket = index.get(key)
    if bucket is not None:
        bucket = bucket.copy()
        try:
            bucket.remove(clause)            # by identity, in C
        except ValueError:
            return True
        if len(bucket) == len(unindexed):    # only the clauses with a variable there are left
            del index[key]
        else:
            index[key] = bucket
    return True


def _arg_key(clause: StoredClause, position: int) -> Key | None:
    head = clause.head
    return first_arg_key(head.args[position]) if isinstance(head, Struct) else None


def _build_index(clauses: list[StoredClause], key_of) -> tuple[dict[Key, list[StoredClause]],
                                                             list[StoredClause]]:
    """Buckets by key, in clause order; a clause with a variable there is in every bucket."""
    index: dict[Key, list[StoredClause]] = {}
    unindexed: list[StoredClause] = []
    for clause in clauses:
        key = key_of(clause)
        if key is None:
            unindexed.append(clause)
            for bucket in index.values():
                bucket.append(clause)
        else:
            bucket = index.get(key)
            if bucket is None:
                bucket = index[key] = list(unindexed)
            bucket.append(clause)
    return index, unindexed


def _useful_index(clauses: list[StoredClause], position: int):
    """An index on argument `position`, or None where it would not narrow calls down
    (fewer than two keys, or most clauses with a variable there)."""
    index, unindexed = _build_index(clauses, lambda c: _arg_key(c, position))
    if len(index) < 2 or 2 * len(unindexed) > len(clauses):
        return None
    return index, unindexed


@functools.lru_cache(maxsize=1)
def _prelude() -> tuple[Clause, ...]:
    """The library written in Prolog, parsed once per version of it and of its reader."""
    here = Path(__file__).resolve().parent
    text = (here / "prelude.pl").read_text(encoding="utf-8")
    # what the stored clauses are made of: the reader, the term and position classes, lark
    readers = [(path).read_text(encoding="utf-8") for path in
               (here / "terms.py", here / "parse.py", here / "fastread.py", here / "opread.py", here / "dcg.py",
                here.parent / "errors.py")]
    return remembered("prelude", [text, grammar_text(), *readers, lark_version()],
                      lambda: tuple(c for c in parse_text(text, "<prelude>") if isinstance(c, Clause)))


# SWI-Prolog 9's values of the flags ISO names (SWI-Prolog 9.0.4 is unbounded and has no
# max_integer/min_integer flags: current_prolog_flag(max_integer, X) fails there too).
INITIAL_FLAGS: dict[str, Term] = {
    "bounded": Atom("false"), "unknown": Atom("error"), "double_quotes": Atom("string"),
    "debug": Atom("false"), "char_conversion": Atom("false"),
    "max_arity": Atom("unbounded"), "occurs_check": Atom("false"),
}


def initial_operators() -> "OperatorTable":
    """The reader's operator table (terms.py), keyed (name, prefix | infix | postfix)."""
    from .terms import default_operator_table
    return default_operator_table()


@dataclass(frozen=True)
class Definitions:
    """Which predicates several files may define together (every other one is defined by
    one file, unless declared multifile).

    by_argument: defined per first argument: files may each have clauses, but not two
                 files clauses whose first arguments unify (the schema language's schema/3:
                 one sub-task, one file), unless that predicate, or the first argument's
                 own Name/Arity, is declared multifile.
    shared:      every file adds to them (declarations whose union is meant).
    by_unit:     by-argument predicates whose clash is best lifted by declaring the first
                 argument's Name/Arity multifile (a schema defines its sub-task; declaring
                 schema/3 would let every schema of every file overlap); for the others a
                 clash suggests declaring the predicate itself (`:- multifile(agent/2).`)."""

    by_argument: frozenset[tuple[str, int]] = frozenset()
    shared: frozenset[tuple[str, int]] = frozenset()
    by_unit: frozenset[tuple[str, int]] = frozenset()


PROLOG = Definitions()   # plain Prolog: every predicate belongs to one file


class _Defined:
    """The first arguments one file gave a by-argument predicate, indexed to find one that
    unifies with a new argument without scanning them all."""

    __slots__ = ("ground", "ground_keyed", "open_keyed", "variables")

    def __init__(self) -> None:
        self.ground: dict[Term, SourcePos] = {}
        # The ground ones by key, made only when a first argument with variables asks: a file
        # of 100,000 ground schema facts never needs it, and it would cost a list each.
        self.ground_keyed: dict[Key, list[tuple[Term, SourcePos]]] | None = None
        self.open_keyed: dict[Key, list[tuple[Term, SourcePos]]] = {}  # those with variables
        self.variables: list[tuple[Term, SourcePos]] = []

    def add(self, arg: Term, pos: SourcePos) -> None:
        key = first_arg_key(arg)
        if key is None:
            self.variables.append((arg, pos))
        elif is_ground(arg):
            if arg not in self.ground:
                self.ground[arg] = pos
                if self.ground_keyed is not None:
                    self.ground_keyed.setdefault(key, []).append((arg, pos))
        else:
            self.open_keyed.setdefault(key, []).append((arg, pos))

    def clash(self, arg: Term) -> tuple[Term, SourcePos] | None:
        """A first argument given here that unifies with `arg`, and where it was written."""
        key = first_arg_key(arg)
        if key is None:
            candidates = [*self.variables, *self.ground.items(),
                          *(e for entries in self.open_keyed.values() for e in entries)]
        elif is_ground(arg):
            if arg in self.ground:
                return arg, self.ground[arg]
            candidates = [*self.open_keyed.get(key, ()), *self.variables]
        else:
            if self.ground_keyed is None:
                self.ground_keyed = {}
                for term, pos in self.ground.items():
                    self.ground_keyed.setdefault(first_arg_key(term), []).append((term, pos))
            candidates = [*self.ground_keyed.get(key, ()), *self.open_keyed.get(key, ()), *self.variables]
        for term, pos in candidates:
            if Bindings().unify(arg, rename(term)):
                return term, pos
        return None


def _shown(term: Term) -> str:
    """A term as a message shows it: its variables by name, `_` for a fresh one."""
    return term_to_text(term, 999, variable_names([term]), spaced=True, next_argument=True)


class KnowledgeBase:
    """Clauses, consulted from files or added programmatically."""

    def __init__(self, prelude: bool = True, definitions: Definitions = PROLOG) -> None:
        self.predicates: dict[tuple[str, int], Predicate] = {}
        self.definitions = definitions
        self.multifile: set[tuple[str, int]] = set()
        # The file that defined each predicate first, and where; for a by-argument predicate,
        # the first arguments each file gave it.
        self._owners: dict[tuple[str, int], tuple[Path, SourcePos]] = {}
        self._arguments: dict[tuple[str, int], dict[Path, _Defined]] = {}
        self._read: set[Path] = set()   # files read (to the end or not): reading one again reloads it
        self._sources: list[Path] = []  # whose clauses are being read: the file, or the one including it
        self.warnings: list[str] = []
        self.files: list[str] = []  # every file read, consulted ones included
        # The files imported from SEED long-term memory: instantiation follows SEED where the
        # schema language differs (a sub-task with no schema is left out, not an error).
        self.seed_files: set[str] = set()
        self.max_bytes = MAX_BYTES  # the limit of a file consulted by a directive (--max-bytes)
        self.max_steps = defaults.MAX_STEPS  # the step limit each directive runs under (--max-steps)
        self._consulting: list[Path] = []
        # The Prolog flags (set_prolog_flag/2) and the operator table op/3 changes: the files
        # read after a change, queries and the writers follow it (docs/syntax.md, Operators).
        self.flags: dict[str, Term] = dict(INITIAL_FLAGS)
        self.operators = initial_operators()
        if prelude:
            for clause in _prelude():
                self._store(StoredClause(clause.head, clause.body, clause.pos, library=True))

    # -- reading --------------------------------------------------------------
    def candidates(self, name: str, arity: int, first: Term | None) -> list[StoredClause] | None:
        """The clauses that may match a call, or None if the predicate is unknown."""
        pred = self.predicates.get((name, arity))
        if pred is None:
            return None
        return pred.candidates(first)

    def clauses(self, name: str, arity: int) -> list[StoredClause]:
        """All clauses of `name/arity`, in order."""
        pred = self.predicates.get((name, arity))
        return list(pred.clauses) if pred else []

    def library_predicates(self) -> set[tuple[str, int]]:
        """The predicates defined only by the prelude (a user file may replace them, assert may not)."""
        return {key for key, p in self.predicates.items() if p.library_only()}

    def is_library(self, key: tuple[str, int]) -> bool:
        """Whether `key` (name, arity) is defined only by the prelude."""
        pred = self.predicates.get(key)
        return pred is not None and pred.library_only()

    def user_clauses(self) -> list[StoredClause]:
        """Every clause that did not come from the library, in predicate order."""
        return [c for p in self.predicates.values() for c in p.clauses if not c.library]

    # -- writing --------------------------------------------------------------
    def _store(self, clause: StoredClause, front: bool = False) -> None:
        ind = indicator(clause.head)
        pred = self.predicates.get(ind)
        if pred is None:
            pred = self.predicates[ind] = Predicate()
        elif not clause.library and pred.library_only():
            pred.replace([])  # a user definition replaces the library's
        pred.add(clause, front)

    def add_clause(self, head: Term, body: Term = TRUE, pos: SourcePos | None = None,
                   front: bool = False) -> None:
        """Add `head :- body`, checking that the head can be a clause head; a grammar rule
        `A --> B` read from a file is added as its clause (dcg.py)."""
        if pos is not None and dcg.is_rule(head, body):
            try:
                head, body = dcg.rule(*head.args)
            except dcg.DCGError as err:
                raise SchemalogError(f"grammar rule: {err}", pos) from None
        if isinstance(head, Var):
            raise SchemalogError("a clause head cannot be a variable", pos)
        if not isinstance(head, (Atom, Struct)):
            raise SchemalogError(f"a clause head must be an atom or compound term, not "
                                 f"{term_to_text(head)}", pos)
        name, arity = indicator(head)
        if is_builtin(name, arity) or (name, arity) in ((",", 2), (";", 2), ("->", 2)):
            raise SchemalogError(f"no permission to modify the built-in predicate {name}/{arity}", pos)
        # A clause written in a file being read (not one asserted while it is read) belongs to it.
        source = self._sources[-1] if pos is not None and self._sources else None
        if source is not None:
            self._check_definition(head, pos, source)
        self._store(StoredClause(head, body, pos, source=source), front=front)

    def _check_definition(self, head: Term, pos: SourcePos, source: Path) -> None:
        """Refuse a clause from `source` for what another file already defines (see Definitions)."""
        key = indicator(head)
        if key in self.definitions.shared:
            return
        if key in self.definitions.by_argument and isinstance(head, Struct):
            self._check_argument(key, head.args[0], pos, source)
            return
        owner = self._owners.get(key)
        if owner is None:
            self._owners[key] = (source, pos)
        elif owner[0] != source and key not in self.multifile:
            name, arity = key
            raise SchemalogError(
                f"{quote_atom(name)}/{arity} is defined in two files, here and at {owner[1]}: one file "
                f"defines a predicate; keep one definition, or, if both files are meant to add to it, "
                f"declare `:- multifile({quote_atom(name)}/{arity}).` before its first clause "
                f"(docs/syntax.md, Several files)", pos)

    def _check_argument(self, key: tuple[str, int], arg: Term, pos: SourcePos, source: Path) -> None:
        unit = indicator(arg) if isinstance(arg, (Atom, Struct)) else None
        files = self._arguments.setdefault(key, {})
        if key not in self.multifile and unit not in self.multifile:
            for other, defined in files.items():
                clash = defined.clash(arg) if other != source else None
                if clash is None:
                    continue
                name, arity = key
                predicate = f"{quote_atom(name)}/{arity}"
                declare = f"{quote_atom(unit[0])}/{unit[1]}" if unit is not None and key in \
                    self.definitions.by_unit else predicate
                rest = ", ..." if arity > 1 else ""
                raise SchemalogError(
                    f"{predicate} for {_shown(arg)} is defined in two files: {name}({_shown(arg)}{rest}) "
                    f"here and {name}({_shown(clash[0])}{rest}) at {clash[1]}; keep one, or, if both files "
                    f"are meant to define it, declare `:- multifile({declare}).` before this clause "
                    f"(docs/syntax.md, Several files)", pos)
        defined = files.get(source)
        if defined is None:
            defined = files[source] = _Defined()
        defined.add(arg, pos)

    def add_facts(self, facts: list[Term]) -> None:
        """Add many ground facts at once (a task tree's relations): one list per predicate
        instead of a copy per clause, so loading n facts costs O(n)."""
        grouped: dict[tuple[str, int], list[StoredClause]] = {}
        for fact in facts:
            key = indicator(fact)
            if is_builtin(*key):
                raise SchemalogError(f"no permission to modify the built-in predicate {key[0]}/{key[1]}")
            grouped.setdefault(key, []).append(StoredClause(fact, TRUE))
        for key, clauses in grouped.items():
            pred = self.predicates.get(key)
            if pred is None:
                pred = self.predicates[key] = Predicate()
            elif pred.library_only():
                pred.replace([])
            pred.add_all(clauses)

    def add_term(self, term: Term, front: bool = False) -> None:
        """Add a clause given as one term (`H :- B` or a fact), as assertz/asserta do."""
        if isinstance(term, Struct) and term.name == ":-" and len(term.args) == 2:
            self.add_clause(term.args[0], term.args[1], front=front)
        else:
            self.add_clause(term, front=front)

    def remove(self, clause: StoredClause) -> None:
        """Remove one stored clause (retract): no scan of the predicate's other clauses
        in Python, no rebuilt index (Predicate.remove)."""
        pred = self.predicates.get(indicator(clause.head))
        if pred is not None:
            pred.remove(clause)

    def remove_all(self, clauses: list[StoredClause]) -> None:
        """Remove these stored clauses, of one predicate (retractall): one pass."""
        if not clauses:
            return
        if len(clauses) < 8:
            for clause in clauses:
                self.remove(clause)
            return
        pred = self.predicates.get(indicator(clauses[0].head))
        if pred is not None:
            gone = {id(c) for c in clauses}
            for clause in clauses:
                clause.erased = True
            pred.replace([c for c in pred.clauses if id(c) not in gone])

    def forget_file(self, file: str | Path) -> None:
        """Remove the clauses read from `file`, and what it defined (before it is read again)."""
        key = Path(file).resolve()
        name = str(file)
        for pred in self.predicates.values():
            kept = [c for c in pred.clauses if c.source != key
                    and not (c.source is None and c.pos is not None and c.pos.file == name)]
            if len(kept) != len(pred.clauses):
                pred.replace(kept)
        self._owners = {k: owner for k, owner in self._owners.items() if owner[0] != key}
        for files in self._arguments.values():
            files.pop(key, None)

    def abolish(self, name: str, arity: int) -> None:
        """Forget `name/arity` whole, clauses and dynamic declaration (abolish/1)."""
        self.predicates.pop((name, arity), None)

    def declare_dynamic(self, name: str, arity: int) -> None:
        """Make `name/arity` known, so calling it without clauses fails instead of raising."""
        pred = self.predicates.setdefault((name, arity), Predicate())
        pred.dynamic = True

    # -- consulting -----------------------------------------------------------
    def consult_text(self, text: str, file: str = "<string>", base: Path | None = None,
                     run_directives: bool = True, via: str | None = None) -> None:
        """Add every clause of `text`; directives declare, include or run goals. `via` says how
        a file the command line does not name was reached: what is not Prolog text in it is
        then placed, never quoted (the file may be any the process can read)."""
        try:
            items = parse_text(text, file, self.operators)
        except SchemalogError as err:
            if via is None:
                raise
            raise unquoted(err.pos or SourcePos(file, 1, 1), "not Prolog text schemalog reads", via) from None
        for item in items:
            if isinstance(item, Clause):
                self.add_clause(item.head, item.body, item.pos)
            elif run_directives:
                self.run_directive(item, base)

    @contextmanager
    def reading(self, path: str | Path, pos: SourcePos | None = None,
                included: bool = False) -> Iterator[None]:
        """Mark `path` as being read while the block runs: a file that consults itself,
        directly or through others, is an error naming the chain. Its clauses are its own,
        and replace those it gave before; `included` ones belong to the file including it
        (`:- include(F).`, as in SWI-Prolog)."""
        key = Path(path).resolve()
        if key in self._consulting:
            chain = " -> ".join(str(f) for f in (*self._consulting, key))
            raise SchemalogError(f"consult cycle: {chain}", pos)
        if included and self._sources:
            source = self._sources[-1]
        else:
            if key in self._read:
                self.forget_file(key)    # read again: its new clauses replace its old ones
            self._read.add(key)
            source = key
        self.files.append(str(path))
        self._consulting.append(key)
        self._sources.append(source)
        try:
            yield
        finally:
            self._consulting.pop()
            self._sources.pop()

    def consult(self, path: str | Path, max_bytes: int = MAX_BYTES, pos: SourcePos | None = None,
                max_steps: int | None = None, included: bool = False) -> None:
        """Load a knowledge file; its directives (and those of the files it consults) run
        under `max_steps` each (default: the knowledge base's `max_steps`)."""
        if max_steps is not None:
            self.max_steps = max_steps
        p = Path(path)
        how = "included" if included else "consulted"
        with self.reading(p, pos, included):
            self.consult_text(read_source(p, max_bytes), str(path), base=p.parent,
                              via=f"it is {how} at {pos}" if pos is not None else f"it is {how} by consult/1")

    def run_directive(self, d: Directive, base: Path | None = None) -> None:
        """Declare (dynamic), include (consult) or run the goal of a directive."""
        goal = d.goal
        if isinstance(goal, Struct) and goal.name in ("dynamic", "discontiguous", "multifile") \
                and len(goal.args) == 1:
            for spec in conjuncts(goal.args[0]):
                items, _ = list_items(spec)
                for s in items or [spec]:
                    if not (isinstance(s, Struct) and s.name == "/" and isinstance(s.args[0], Atom)
                            and isinstance(s.args[1], Int)):
                        raise SchemalogError(f"{goal.name} expects Name/Arity, not {term_to_text(s)}", d.pos)
                    if goal.name == "dynamic":
                        self.declare_dynamic(s.args[0].name, s.args[1].value)
                    elif goal.name == "multifile":
                        self.multifile.add((s.args[0].name, s.args[1].value))
            return
        if isinstance(goal, Struct) and goal.name == "table" and len(goal.args) == 1:
            raise SchemalogError(f":- {term_to_text(goal)}: tabling is not supported by schemalog's engine "
                                 f"(docs/syntax.md); without the directive the predicate runs untabled, "
                                 f"which may not end where tabling would", d.pos)
        if isinstance(goal, Struct) and goal.name in ("consult", "include", "ensure_loaded") \
                or isinstance(goal, Struct) and goal.name == "[|]":
            targets = list_items(goal)[0] if goal.name == "[|]" else [goal.args[0]]
            for target in targets:
                name = target.name if isinstance(target, Atom) else (
                    target.value if isinstance(target, Str) else None)
                if name is None:
                    raise SchemalogError(f"cannot consult {term_to_text(target)}", d.pos)
                path = (base or Path(".")) / name
                if missing(path) and path.suffix == "":
                    path = path.with_suffix(".pl")
                if missing(path):
                    raise SchemalogError(f"consult: no such file {name!r}", d.pos)
                if goal.name == "ensure_loaded" and path.resolve() in self._read:
                    continue             # loaded already: ensure_loaded does not read it again
                try:
                    self.consult(path, self.max_bytes, pos=d.pos, included=goal.name == "include")
                except SchemalogError as err:
                    if err.pos is not None:      # placed in the file read: its own place
                        raise
                    # The file could not be read at all (a directory, a name too long): the
                    # directive that named it is where the user can act.
                    raise SchemalogError(f"{goal.name}: {err.message}", d.pos) from None
            return
        if isinstance(goal, Struct) and goal.name in ("initialization", "module", "use_module") \
                or isinstance(goal, Atom) and goal.name == "use_module":
            self.warnings.append(f"{d.pos}: warning: directive {term_to_text(goal)} ignored")
            return
        try:
            if Engine(self, max_steps=self.max_steps).first(goal) is None:
                self.warnings.append(f"{d.pos}: warning: directive failed: {term_to_text(goal)}")
        except PrologError as err:
            self.warnings.append(f"{d.pos}: warning: directive raised {err}")
        except StepLimitExceeded:
            # Stopped, as a failing directive is reported: the clauses it asserted stay.
            self.warnings.append(f"{d.pos}: warning: directive exceeded the step limit of "
                                 f"{self.max_steps:,} steps: {term_to_text(goal)} "
                                 f"(raise it with --max-steps N)")



__all__ = ["KnowledgeBase", "StoredClause", "Predicate", "Definitions", "PROLOG", "first_arg_key"]
