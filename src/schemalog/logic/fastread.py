"""The reader's fast path: lark's own terminals, matched by two regexes, and a small
operator-precedence parser for the grammar's clauses; lark reads any clause it does not.

    parse_text(text, file, operators) -> list[Clause | Directive]    what parse_text_slowly returns

lark's contextual lexer matches, in each parser state, the terminals that state accepts, in
lark's priority order. Every state of the grammar accepts either terms' first tokens
(operand mode) or what may follow a term (operator mode; `(` after a functor aside), so two
alternations of the compiled terminals, in lark's order, give the tokens lark gives. The
parser below follows grammar/schemalog.lark rule by rule and builds the terms the
transformer in parse.py builds, with the same `arrange`. Whatever it does not take as the
grammar does (a syntax error, a priority clash, a bad escape, nesting past MAX_NESTING) it
hands to lark for that one clause, so every error is lark's, with its file:line:column
(where lark finds no reading either, opread.py, the table-driven reader, may: `X = +a`).
A text with an `op/3` directive is read clause by clause, the directive changing the table
for the clauses after it; while the table differs from the grammar's, opread.py reads them.
"""

from __future__ import annotations

import functools
import hashlib
import re

from ..errors import SchemalogError, SourcePos
from .parse import (_LAYOUT, MAX_NESTING, Clause, Directive, _atom_name, _BadEscape, _LineIndex, _Operand,
                    _reader, _unescape, arrange, clause_item, float_of_token, int_of_token, lark_clause)
from .opread import _clause_goals, declare, module_goal, read_clause
from .terms import DEFAULT_OPERATORS, INFIX_OPS, NIL, Atom, Int, OperatorTable, Str, Struct, Var, \
    conjuncts, default_operator_table, make_list

# Terminal names of grammar/schemalog.lark (lark names "(" LPAR, and so on).
OPERAND_TERMINALS = frozenset({"PREFIX", "NAME", "QATOM", "SYMATOM", "VAR", "INT", "FLOAT", "STRING",
                               "FUNCTOR", "SYMFUNCTOR", "LPAR", "LSQB", "LBRACE", "RSQB", "RBRACE"})
OPERATOR_TERMINALS = frozenset({"INFIX", "DOT", "COMMA", "END", "RPAR", "RSQB", "RBRACE", "VBAR"})

# What the parser is inside: a clause, ( ), { }, a functor's arguments, a list, a list's tail.
_TOP, _PAREN, _CURLY, _ARGS, _LIST, _TAIL = range(6)


class _Fallback(Exception):
    """This clause is lark's to read."""


def _give_up(token, name):
    return _Fallback()


# Runs of tokens matched at once in operand mode, without layout inside: `name(word)`
# (a behaviour and its object, `b3(cup)`) and `word.word` (a condition, `cup.taken`). Token
# by token, with lark's terminals as below, `f(a)` is FUNCTOR, then NAME (or SYMATOM for an
# operator word: the same atom), then RPAR; `a.b` is NAME, DOT, NAME unless a word is a
# prefix operator (then PREFIX) or the second is followed by "(" (FUNCTOR): both left out.
# And a schema's entry `(name(word), word)` or `(name(word), word.word)`, with white space
# (layout, no comment) between its tokens: LPAR, the first run, COMMA, NAME or SYMATOM (a
# word before ")" is an atom) or the second run, RPAR.
_WORD = r"[a-z][A-Za-z0-9_]*"
_PREFIX_WORD = r"(?:dynamic|discontiguous|multifile|initialization|table|not)(?![A-Za-z0-9_])"
LANES = (rf"(?P<ENTRY>\(\s*(?P<entry_name>{_WORD})\((?P<entry_arg>{_WORD})\)\s*,\s*"
         rf"(?:(?!{_PREFIX_WORD})(?P<entry_left>{_WORD})\.)?(?P<entry_right>{_WORD})\s*\))",
         rf"(?P<CALL>(?P<call_name>{_WORD})\((?P<call_arg>{_WORD})\))",
         rf"(?P<DOTTED>(?!{_PREFIX_WORD})(?P<dot_left>{_WORD})\.(?!{_PREFIX_WORD})(?P<dot_right>{_WORD})"
         rf"(?![A-Za-z0-9_(]))")
# That argument rests on lark's terminals (which may start at a letter, at "." or at ")", and in
# which order): the lanes are used only while the grammar compiles to the very terminals it was
# made for, this fingerprint of their names and regexes in lark's order. Should the grammar
# change, they are left out (tests/logic/test_fastread.py then asks to check them again).
LANES_GRAMMAR = "6c1774ed9993790c"


def _fingerprint(terminals) -> str:
    return hashlib.sha256(repr([(t.name, t.pattern.to_regexp()) for t in terminals]).encode()).hexdigest()[:16]


@functools.lru_cache(maxsize=None)
def scanners() -> tuple[re.Pattern, re.Pattern] | None:
    """The operand-mode and operator-mode token regexes, built from the terminals of lark's
    compiled grammar (None if lark's lexer does something they would not: then lark reads all)."""
    lexer = _reader("start").lark.parser.lexer
    root = getattr(lexer, "root_lexer", None)
    if root is None or any(cb for cb in getattr(root, "callback", {}).values()
                           if type(cb).__name__ == "UnlessCallback"):
        return None
    ordered = root.terminals  # lark's order: priority, then width, then length, then name
    layout = "|".join(f"(?:{t.pattern.to_regexp()})" for t in ordered if t.name in root.ignore_types)

    def scanner(names: frozenset, lanes: tuple[str, ...] = ()) -> re.Pattern:
        alternatives = "|".join([*lanes, *(f"(?P<{t.name}>{t.pattern.to_regexp()})"
                                           for t in ordered if t.name in names)])
        # Layout is skipped first, never backtracked into: a lookahead group is atomic, and
        # lark tries the ignored terminals where no token may start.
        return re.compile(f"(?=(?P<_layout>(?:{layout})*))(?P=_layout)(?:{alternatives})", root.g_regex_flags)

    lanes = LANES if _fingerprint(ordered) == LANES_GRAMMAR else ()
    return scanner(OPERAND_TERMINALS, lanes), scanner(OPERATOR_TERMINALS)


def parse_text(text: str, file: str = "<string>", operators: OperatorTable | None = None) -> list[Clause | Directive]:
    """Parse program text into clauses and directives, lark reading the clauses this does not.

    `operators` is the operator table the text starts with (default: the grammar's); an
    `op/3` directive changes it for the clauses after it, which opread.py then reads."""
    table = operators.copy() if operators is not None and operators.view() is not DEFAULT_OPERATORS else None
    if table is not None or _declares_operators(text):
        return _parse_with_operators(text, file, table)
    found = scanners()
    line_at = _LineIndex(text)
    if found is None:
        return _all_by_lark(text, file, line_at)
    operand, operator = found[0].match, found[1].match
    items: list[Clause | Directive] = []
    # One Atom per name, one str per name, one compound per functor and atomic arguments
    # (b3(cup), b3.done), for the whole text: a file of 100,000 schemas names each sub-task
    # twice and repeats a few names (schema, true, done, its objects) a million times. Terms
    # are immutable, so what is equal may be one object.
    atoms: dict[str, Atom] = {"[]": NIL}  # by name; `[]` is NIL itself, as `[ ]` is
    quoted: dict[str, Atom] = {}      # by token, for a quoted or symbol atom
    names: dict[str, str] = {}
    shared: dict[tuple, Struct] = {}  # see _shared
    offset, size = 0, len(text)
    while True:
        start = _LAYOUT.match(text, offset).end()
        if start == size:
            return items
        try:
            term, offset = _read_term(text, start, operand, operator, atoms, quoted, names, shared)
        except (_Fallback, _BadEscape, ValueError, OverflowError):
            read, offset = _lark_or_opread(text, offset, file, line_at, DEFAULT_OPERATORS)
            items.extend(read)
            if not read:
                return items
            continue
        items.append(clause_item(term, SourcePos(file, *line_at(start))))


# Where a text may declare operators: `op(` in a directive. Only such texts need the
# table-following loop below; the others keep the fast path whole.
_OP_DIRECTIVE = re.compile(r"(?<![A-Za-z0-9_'])op\s*\(")


def _declares_operators(text: str) -> bool:
    return _OP_DIRECTIVE.search(text) is not None


def parse_text_slowly(text: str, file: str = "<string>") -> list[Clause | Directive]:
    """Parse program text as parse_text does, without its fast path: what it must agree with."""
    return _parse_with_operators(text, file, None, fast=False)


def _parse_with_operators(text: str, file: str, table: OperatorTable | None,
                          fast: bool = True) -> list[Clause | Directive]:
    """Read clause by clause, following the `op/3` directives: while the table is the
    grammar's, a clause is read as parse_text reads it, else by opread."""
    line_at = _LineIndex(text)
    found = scanners() if fast else None
    items: list[Clause | Directive] = []
    offset, size = 0, len(text)
    caches: tuple = ({"[]": NIL}, {}, {}, {})
    while True:
        start = _LAYOUT.match(text, offset).end()
        if start == size:
            return items
        if table is not None and table.view() is not DEFAULT_OPERATORS:
            try:
                term, offset = read_clause(text, start, file, line_at, table.view())
            except SchemalogError as err:
                raise left_open(err, text, start, file, line_at) from None
            read = [clause_item(term, SourcePos(file, *line_at(start)))]
        else:
            try:
                if found is None:
                    raise _Fallback
                term, offset = _read_term(text, start, found[0].match, found[1].match, *caches)
                read = [clause_item(term, SourcePos(file, *line_at(start)))]
            except (_Fallback, _BadEscape, ValueError, OverflowError):
                read, offset = _lark_or_opread(text, start, file, line_at, DEFAULT_OPERATORS)
        for item in read:
            if isinstance(item, Directive):        # `:- op(...).`, `:- op(...), op(...).`
                for goal in conjuncts(item.goal):
                    if isinstance(goal, Struct) and goal.name == "op":
                        changed = table if table is not None else default_operator_table()
                        if declare(changed, goal):
                            table = changed
        items.extend(read)
        if not read:
            return items


def _lark_or_opread(text: str, offset: int, file: str, line_at: _LineIndex, ops) -> tuple[list, int]:
    """The clause lark reads from `offset`, or, where lark finds none, opread's reading of it
    with `ops` (`X = =..(a, [b])`, `X = +a`); lark's error when neither reads it."""
    try:
        return lark_clause(text, offset, file, line_at)
    except SchemalogError as lark_error:
        try:
            term, end = read_clause(text, offset, file, line_at, ops)
        except SchemalogError:
            raise left_open(lark_error, text, offset, file, line_at) from None
        if term is None:
            return [], end
        if "modules are not supported" in lark_error.message and module_goal(_clause_goals(term)):
            raise lark_error from None
        start = _LAYOUT.match(text, offset).end()
        return [clause_item(term, SourcePos(file, *line_at(start)))], end


def left_open(err: SchemalogError, text: str, offset: int, file: str, line_at: _LineIndex) -> SchemalogError:
    """A syntax error met where a new clause seems to begin (at a line's first column, or at
    the end of the file) while the clause read since an earlier line is still open: that one
    most likely lacks its `)` or its final `.`, and the error, found only at the next clause,
    names where the open one began."""
    if err.pos is None or err.pos.file != file:
        return err
    start = _LAYOUT.match(text, offset).end()
    line, column = line_at(min(start, len(text)))
    at_end = err.message.startswith("unexpected end of file")
    if err.pos.line <= line or not (at_end or err.pos.column == 1):
        return err
    began = SourcePos(file, line, column)
    hint = (f"the clause from {began} is still open" if at_end else
            f"the clause from {began} is still open here (a missing ')' or final '.' there?)")
    return SchemalogError(f"{err.message}; {hint}", err.pos, err.source_line, err.exit_code)


def _all_by_lark(text: str, file: str, line_at: _LineIndex) -> list[Clause | Directive]:
    items, offset = [], 0
    while True:
        read, offset = _lark_or_opread(text, offset, file, line_at, DEFAULT_OPERATORS)
        if not read:
            return items
        items.extend(read)


def _shared(name: str, args: tuple, shared: dict) -> Struct:
    """Struct(name, args), the one already made if its arguments are atoms or integers.

    Keyed by the atoms' identities (the reader makes one Atom per name) and the integers'
    values, in a tuple Python hashes itself: hashing a Struct calls Struct.__hash__ and each
    Atom's dataclass __hash__, which cost more than the rest of the look-up."""
    if len(args) == 1:
        arg = args[0]
        kind = type(arg)
        if kind is Atom:
            key = (name, id(arg))
        elif kind is Int:
            key = (name, (arg.value,))
        else:
            return Struct(name, args)
    else:
        parts = [name]
        for arg in args:
            kind = type(arg)
            if kind is Atom:
                parts.append(id(arg))
            elif kind is Int:
                parts.append((arg.value,))
            else:
                return Struct(name, args)
        key = tuple(parts)
    made = shared.get(key)
    if made is None:
        made = shared[key] = Struct(name, args)
    return made


def _finish(run: list, shared: dict):
    """The term of a run `operand (infix operand)*`, as the transformer's `expr` and `arg`."""
    if len(run) == 1:
        item = run[0]
        if type(item) is not _Operand:
            return item
    elif len(run) == 3 and type(run[0]) is not _Operand and type(run[2]) is not _Operand:
        return _shared(run[1], (run[0], run[2]), shared)  # two primaries (priority 0) fit any operator
    elif len(run) == 5 and type(run[0]) is not _Operand and type(run[2]) is not _Operand \
            and type(run[4]) is not _Operand:
        # Three primaries, two operators (`b3(cup), b2.done`): what arrange does with them.
        # Either the first operator binds first (its priority fits the second's left
        # argument), or the second does, and its priority must fit the first's right argument.
        left, first, middle, second, right = run
        p1, kind1 = INFIX_OPS[first]
        p2, kind2 = INFIX_OPS[second]
        if p1 <= (p2 if kind2 == "yfx" else p2 - 1):
            return _shared(second, (_shared(first, (left, middle), shared), right), shared)
        if p2 > (p1 if kind1 == "xfy" else p1 - 1):
            raise _Fallback      # a priority clash: lark's error
        return _shared(first, (left, _shared(second, (middle, right), shared)), shared)
    return arrange(run, _give_up)[0]


def _read_term(text: str, pos: int, operand, operator, atoms: dict, quoted: dict, names: dict, shared: dict):
    """The clause term from `pos` to its final "." and the offset after it (else _Fallback)."""
    varmap: dict[str, Var] = {}
    stack: list[tuple] = []
    kind, run, prefixes, args, name = _TOP, [], None, None, None
    depth = 0
    while True:
        # Operand mode: prefix operators, then a primary (or an opening bracket).
        m = operand(text, pos)
        if m is None:
            raise _Fallback
        typ = m.lastgroup
        pos = m.end()
        if typ == "NAME":
            token = m[typ]
            value = atoms.get(token)
            if value is None:
                value = atoms[token] = Atom(names.setdefault(token, token))
        elif typ == "ENTRY":  # "(" FUNCTOR "(" NAME ")" "," NAME [DOT NAME] ")" (see LANES)
            if depth + 2 > MAX_NESTING:
                raise _Fallback
            token = m["entry_arg"]
            arg = atoms.get(token)
            if arg is None:
                arg = atoms[token] = Atom(names.setdefault(token, token))
            token = m["entry_name"]
            behaviour = _shared(names.setdefault(token, token), (arg,), shared)
            token = m["entry_right"]
            releaser = atoms.get(token)
            if releaser is None:
                releaser = atoms[token] = Atom(names.setdefault(token, token))
            token = m["entry_left"]
            if token is not None:
                left = atoms.get(token)
                if left is None:
                    left = atoms[token] = Atom(names.setdefault(token, token))
                releaser = _shared(names.setdefault(".", "."), (left, releaser), shared)
            value = _shared(names.setdefault(",", ","), (behaviour, releaser), shared)
        elif typ == "CALL":  # FUNCTOR "(" NAME ")" (see LANES)
            if depth >= MAX_NESTING:
                raise _Fallback
            token = m["call_arg"]
            arg = atoms.get(token)
            if arg is None:
                arg = atoms[token] = Atom(names.setdefault(token, token))
            token = m["call_name"]
            value = _shared(names.setdefault(token, token), (arg,), shared)
        elif typ == "DOTTED":  # NAME DOT NAME (see LANES): the left one and "." join the run here
            token = m["dot_left"]
            left = atoms.get(token)
            if left is None:
                left = atoms[token] = Atom(names.setdefault(token, token))
            if prefixes is not None:
                run.append(_Operand([*prefixes, left]))
                prefixes = None
            else:
                run.append(left)
            run.append(names.setdefault(".", "."))
            token = m["dot_right"]
            value = atoms.get(token)
            if value is None:
                value = atoms[token] = Atom(names.setdefault(token, token))
        elif typ == "VAR":
            var_name = m[typ]
            if var_name == "_":
                value = Var("_")
            else:
                value = varmap.get(var_name)
                if value is None:
                    value = varmap[var_name] = Var(var_name)
        elif typ == "FUNCTOR" or typ == "SYMFUNCTOR":
            depth += 1  # the "(" its lookahead saw
            if depth > MAX_NESTING:
                raise _Fallback
            token = m[typ]
            stack.append((kind, run, prefixes, args, name))
            kind, run, prefixes, args = _ARGS, [], None, []
            name = _atom_name(token) if token[0] == "'" else names.setdefault(token, token)
            pos += 1
            continue
        elif typ == "LSQB" or typ == "LPAR" or typ == "LBRACE":
            depth += 1
            if depth > MAX_NESTING:
                raise _Fallback
            stack.append((kind, run, prefixes, args, name))
            kind = _LIST if typ == "LSQB" else _PAREN if typ == "LPAR" else _CURLY
            run, prefixes, args = [], None, [] if typ == "LSQB" else None
            continue
        elif typ == "PREFIX":
            if prefixes is None:
                prefixes = []
            prefixes.append(m[typ])
            continue
        elif typ == "INT":
            value = int_of_token(m[typ])
            if value is None:
                raise _Fallback
        elif typ == "QATOM" or typ == "SYMATOM":
            token = m[typ]
            value = quoted.get(token)
            if value is None:
                atom_name = _atom_name(token)
                value = atoms.get(atom_name)
                if value is None:
                    value = atoms[atom_name] = Atom(names.setdefault(atom_name, atom_name))
                quoted[token] = value
        elif typ == "FLOAT":
            value = float_of_token(m[typ])
        elif typ == "STRING":
            value = Str(_unescape(m[typ][1:-1], '"'))
        elif (typ == "RSQB" and kind == _LIST or typ == "RBRACE" and kind == _CURLY) \
                and not run and not args and prefixes is None:
            value = NIL if typ == "RSQB" else Atom("{}")  # `[ ]`, `{ }`
            depth -= 1
            kind, run, prefixes, args, name = stack.pop()
        else:
            raise _Fallback
        if prefixes is not None:
            run.append(_Operand([*prefixes, value]))
            prefixes = None
        else:
            run.append(value)
        # Operator mode: an infix operator, a separator, or the end of what is open.
        while True:
            m = operator(text, pos)
            if m is None:
                raise _Fallback
            typ = m.lastgroup
            pos = m.end()
            if typ == "COMMA":
                if kind == _ARGS or kind == _LIST:
                    args.append(_finish(run, shared))
                    run = []
                    break
                if kind == _TAIL:
                    raise _Fallback
                run.append(",")
                break
            if typ == "INFIX" or typ == "DOT":
                token = m[typ]
                run.append(names.setdefault(token, token))
                break
            if typ == "END":
                if kind != _TOP:
                    raise _Fallback
                return _finish(run, shared), pos
            if typ == "VBAR":
                if kind != _LIST:
                    raise _Fallback
                args.append(_finish(run, shared))
                kind, run = _TAIL, []
                break
            if typ == "RPAR" and kind == _ARGS:
                args.append(_finish(run, shared))
                value = _shared(name, tuple(args), shared)
            elif typ == "RPAR" and kind == _PAREN:
                value = _finish(run, shared)
            elif typ == "RSQB" and kind == _LIST:
                args.append(_finish(run, shared))
                value = make_list(args)
            elif typ == "RSQB" and kind == _TAIL:
                value = make_list(args, _finish(run, shared))
            elif typ == "RBRACE" and kind == _CURLY:
                value = Struct("{}", (_finish(run, shared),))
            else:
                raise _Fallback
            depth -= 1
            kind, run, prefixes, args, name = stack.pop()
            if prefixes is not None:
                run.append(_Operand([*prefixes, value]))
                prefixes = None
            else:
                run.append(value)
