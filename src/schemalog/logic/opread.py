"""A Prolog reader driven by an operator table: what lark's fixed grammar does not read.

    read_clause(text, offset, file, line_at, ops) -> (Term | None, offset after its ".")
    read_term(text, file, ops) -> Term              one term, its final "." optional

    ops: terms.Operators (prefix, infix, postfix: name -> (priority, type))

grammar/schemalog.lark has its operators in its terminals, so it reads only the default table.
After an `op/3` directive (or where lark finds no reading: `=..(a, [b])`, `X = +a`), clauses are
read here: the same tokens as the grammar's (names, variables, numbers, quoted items, runs of
symbol characters, punctuation), and any name the table holds is an operator, looked up as the
term is read (ISO 13211-1, 6.3.4). As in SWI-Prolog: a name directly followed by `(` is a
functor whatever its operator status; `-` touching a number is its sign; a prefix operator
before `,` `)` `]` `}` `|`, the end, or an infix operator is an atom. Runs of operators are
arranged by priority without recursion (shunting-yard), brackets on an explicit stack, so deep
terms read as the other readers read them. Errors are SchemalogErrors at file:line:column.
"""

from __future__ import annotations

import re

from ..errors import SchemalogError, SourcePos
from .parse import MAX_NESTING, _LAYOUT, _atom_name, _BadEscape, _LineIndex, _source_line, _unescape, \
    float_of_token, int_of_token
from .parse import parse_term as lark_parse_term
from .terms import DEFAULT_OPERATORS, NIL, Atom, Int, Operators, OperatorTable, Str, Struct, Term, Var, list_items, make_list, \
    operator_kind

_QUOTED_BODY = r"[^{q}\\\n]*(?:(?:\\x[0-9a-fA-F]+(?:\\|(?![0-9a-fA-F\\]))|\\x(?![0-9a-fA-F])|\\[0-7]+" \
               r"(?:\\|(?![0-7\\]))|\\\n|\\[^x0-7\n]|{q}{q})[^{q}\\\n]*)*"
# The grammar's terminals (grammar/schemalog.lark), numbers without their sign (a `-` touching
# a number is read as its sign by the parser, where a term may start), and every run of symbol
# characters one name, a "." in it only where it does not end the clause.
_TOKEN = re.compile("|".join((
    r"(?P<FLOAT>\d+\.\d+Inf|\d+\.\d+NaN|\d+\.\d+(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+)",
    r"(?P<INT>0x[0-9a-fA-F]+|0o[0-7]+|0b[01]+|0'(?:\\.|''|[^\\'\n])|\d+)",
    r"(?P<NAME>[a-z][A-Za-z0-9_]*)",
    r"(?P<VAR>[A-Z_][A-Za-z0-9_]*)",
    "(?P<QATOM>'" + _QUOTED_BODY.format(q="'") + "')",
    '(?P<STRING>"' + _QUOTED_BODY.format(q='"') + '")',
    r"(?P<END>\.(?=\s|%|/\*|\Z))",
    r"(?P<SYM>[+\-*/\\^<>=~:?@#&$.]+)",
    r"(?P<SOLO>[!;])",
    r"(?P<PUNCT>[()\[\]{},|])",
)))

_BAR = (1100, "xfy")        # `|` as an infix operator, which op/3 may not change below 1001
_END_AFTER = re.compile(r"\s|%|/\*|\Z")

# What a frame on the stack is: a clause, ( ), { }, a functor's arguments, a list, a list's tail.
_TOP, _PAREN, _CURLY, _ARGS, _LIST, _TAIL = range(6)
_CLOSERS = {")": (_PAREN, _ARGS), "]": (_LIST, _TAIL), "}": (_CURLY,)}
# After these an operator name is an atom, not a prefix operator.
_TERMINATORS = frozenset({")", "]", "}", ",", "|"})


class _Token:
    __slots__ = ("type", "text", "start", "end")

    def __init__(self, type_: str, text: str, start: int, end: int) -> None:
        self.type, self.text, self.start, self.end = type_, text, start, end


class _Item:
    """An operator in a run: its name, class (prefix, infix, postfix) and token."""

    __slots__ = ("name", "kind", "token")

    def __init__(self, name: str, kind: str, token: _Token) -> None:
        self.name, self.kind, self.token = name, kind, token


class _Reader:
    """One text, its tokens read on demand, and where errors are reported."""

    def __init__(self, text: str, file: str, line_at: _LineIndex, ops: Operators) -> None:
        self.text, self.file, self.line_at, self.ops = text, file, line_at, ops
        self.peeked: _Token | None = None

    # -- tokens -----------------------------------------------------------------
    def error(self, message: str, offset: int) -> SchemalogError:
        line, column = self.line_at(offset)
        # lark's reader says the nesting limit without "syntax error", as a limit, not a mistake
        said = message if message.startswith("brackets nested") else f"syntax error: {message}"
        return SchemalogError(said, SourcePos(self.file, line, column), _source_line(self.text, line))

    def next(self, pos: int) -> _Token:
        """The token after layout from `pos` (type EOF at the end of the text)."""
        text = self.text
        start = _LAYOUT.match(text, pos).end()
        if start == len(text):
            return _Token("EOF", "", start, start)
        if text.startswith("/*", start):
            raise self.error("a block comment is not closed (missing */)", start)
        m = _TOKEN.match(text, start)
        if m is None:
            char = text[start]
            what = "a quote is not closed" if char in "'\"`" else f"unexpected character {char!r}"
            raise self.error(what, start)
        end = m.end()
        if m.lastgroup == "SYM" and text[end - 1] == "." and _END_AFTER.match(text, end):
            # `=..` before layout is the operator, `a+.` is `+` and the clause's end (as lark
            # reads them): a final "." ends the clause unless the whole run is an operator.
            ops = self.ops
            name = m.group()
            if name not in ops.infix and name not in ops.prefix and name not in ops.postfix:
                end -= 1
        return _Token(m.lastgroup, text[start:end], start, end)

    def name_of(self, token: _Token) -> str | None:
        """The atom a token names, or None if it is no name."""
        if token.type in ("NAME", "SYM", "SOLO"):
            return token.text
        if token.type == "QATOM":
            try:
                return _atom_name(token.text)
            except _BadEscape as bad:
                raise self.error(bad.message, token.start + 1 + bad.offset) from None
        return None

    def starts_term(self, token: _Token) -> bool:
        """Whether `token` may begin a term (not a closing bracket, separator or the end)."""
        return token.type not in ("END", "EOF") and token.text not in _TERMINATORS

    # -- terms ------------------------------------------------------------------
    def read(self, pos: int, want_end: bool) -> tuple[Term | None, int]:
        """The term from `pos` to its final "." (or the end of the text, if not `want_end`),
        and the offset after it; None when only layout is left."""
        text, ops = self.text, self.ops
        varmap: dict[str, Var] = {}
        stack: list[tuple] = []
        kind, run, args, name, opener = _TOP, [], None, None, None
        first = self.next(pos)
        if first.type == "EOF":
            return None, first.end
        token = first
        while True:
            # Operand mode: prefix operators, then a primary or an opening bracket.
            typ = token.type
            value: Term | None = None
            after = token.end
            if typ == "VAR":
                if token.text == "_":
                    value = Var("_")
                else:
                    value = varmap.get(token.text)
                    if value is None:
                        value = varmap[token.text] = Var(token.text)
            elif typ == "INT" or typ == "FLOAT":
                value = self.number(token, "")
            elif typ == "STRING":
                try:
                    value = Str(_unescape(token.text[1:-1], '"'))
                except _BadEscape as bad:
                    raise self.error(bad.message, token.start + 1 + bad.offset) from None
            elif typ == "PUNCT" and token.text in "([{":
                nxt = self.next(after)
                if token.text == "{" and nxt.text == "}" and text.startswith("(", nxt.end):
                    # {}(x): '{}' as a functor, as SWI-Prolog reads it (and write_canonical writes it)
                    if len(stack) >= MAX_NESTING:
                        raise self.error(f"brackets nested deeper than {MAX_NESTING} levels", token.start)
                    stack.append((kind, run, args, name, opener))
                    kind, run, args, name, opener = _ARGS, [], [], "{}", token
                    token = self.next(nxt.end + 1)
                    continue
                if token.text != "(" and nxt.text == ("]" if token.text == "[" else "}") and nxt.type == "PUNCT":
                    value, after = (NIL if token.text == "[" else Atom("{}")), nxt.end
                else:
                    if len(stack) >= MAX_NESTING:
                        raise self.error(f"brackets nested deeper than {MAX_NESTING} levels", token.start)
                    stack.append((kind, run, args, name, opener))
                    kind = {"(": _PAREN, "[": _LIST, "{": _CURLY}[token.text]
                    run, args, name, opener = [], [] if token.text == "[" else None, None, token
                    token = nxt
                    continue
            else:
                atom = self.name_of(token)
                if atom is None:
                    raise self.error(f"unexpected {_shown(token)}; expected a term", token.start)
                if text.startswith("(", after):        # a functor, whatever its operator status
                    if len(stack) >= MAX_NESTING:
                        raise self.error(f"brackets nested deeper than {MAX_NESTING} levels", after)
                    stack.append((kind, run, args, name, opener))
                    kind, run, args, name, opener = _ARGS, [], [], atom, token
                    token = self.next(after + 1)
                    continue
                nxt = self.next(after)
                if atom == "-" and typ != "QATOM" and nxt.type in ("INT", "FLOAT") and nxt.start == after:
                    value, after = self.number(nxt, "-"), nxt.end
                elif atom in ops.prefix and typ != "QATOM" and self.starts_term(nxt) \
                        and not self.infix_next(atom, nxt):
                    run.append(_Item(atom, "prefix", token))
                    token = nxt
                    continue
                else:
                    value = Atom(atom)
                    self.peeked = nxt
            run.append(value)
            # Operator mode: infix and postfix operators, separators, closing brackets.
            while True:
                token = self.peeked if self.peeked is not None else self.next(after)
                self.peeked = None
                after = token.end
                typ, tok = token.type, token.text
                if typ == "PUNCT" and tok == ",":
                    if kind == _ARGS or kind == _LIST:
                        args.append(self.finish(run, 1200))
                        run = []
                        break
                    if kind == _TAIL:
                        raise self.error("unexpected ','; expected ']' after a list's tail", token.start)
                    run.append(_Item(",", "infix", token))
                    break
                if typ == "PUNCT" and tok == "|" and kind == _LIST:
                    args.append(self.finish(run, 1200))
                    kind, run = _TAIL, []
                    break
                if typ == "PUNCT" and tok == "|" and kind != _TAIL:
                    # Outside a list, `a | b` is '|'(a, b) at 1100 xfy, as in SWI-Prolog 7
                    # (a grammar rule's body reads it as `;`).
                    run.append(_Item("|", "infix", token))
                    break
                if typ == "PUNCT" and tok in _CLOSERS:
                    if kind not in _CLOSERS[tok]:
                        raise self.error(f"unexpected {tok!r}{self.expected(kind)}", token.start)
                    if kind == _ARGS:
                        args.append(self.finish(run, 1200))
                        value = Struct(name, tuple(args))
                    elif kind == _PAREN:
                        value = self.finish(run, 1200)
                    elif kind == _LIST:
                        args.append(self.finish(run, 1200))
                        value = make_list(args)
                    elif kind == _TAIL:
                        value = make_list(args, self.finish(run, 1200))
                    else:
                        value = Struct("{}", (self.finish(run, 1200),))
                    kind, run, args, name, opener = stack.pop()
                    run.append(value)
                    continue
                if typ == "END" or typ == "EOF":
                    if kind != _TOP:
                        raise self.error(f"unexpected {'end of file' if typ == 'EOF' else repr('.')}"
                                         f"{self.expected(kind)}", token.start)
                    if typ == "EOF" and want_end:
                        raise self.error("unexpected end of file: a clause is not finished (missing the "
                                         "final '.'?)", token.start)
                    return self.finish(run, 1200), after
                op = self.name_of(token)
                if op is not None and op in ops.infix:
                    if op in ops.postfix and not self.starts_term(self.next(after)):
                        run.append(_Item(op, "postfix", token))
                        continue
                    run.append(_Item(op, "infix", token))
                    break
                if op is not None and op in ops.postfix:
                    run.append(_Item(op, "postfix", token))
                    continue
                raise self.error(f"unexpected {_shown(token)}; expected an operator{self.expected(kind, True)}",
                                 token.start)
            token = self.next(after)

    def infix_next(self, prefix: str, token: _Token) -> bool:
        """Whether the prefix operator `prefix` before `token` is an atom: `token` is an infix
        or postfix operator that cannot start a term itself, with a term after it, whose left
        argument the atom fits (its priority is the operator's), as SWI-Prolog reads them:
        `- = a` is =(-, a), `- * a` *(-, a); `\\+ is - 1` is \\+((is)-1), `:- is` :-(is),
        `- - a` and `- (a)` -(...)."""
        op = self.name_of(token) if token.type in ("NAME", "SYM", "SOLO") else None
        if op is None or op not in self.ops.infix and op not in self.ops.postfix:
            return False
        if op in self.ops.prefix or self.text.startswith("(", token.end):
            return False
        priority, typ = self.ops.infix.get(op) or self.ops.postfix[op]
        if self.ops.prefix[prefix][0] > (priority if typ[0] == "y" else priority - 1):
            return False
        return op in self.ops.postfix or self.starts_term(self.next(token.end))

    @staticmethod
    def expected(kind: int, separator: bool = False) -> str:
        wanted = {_PAREN: "')'", _ARGS: "',' or ')'", _LIST: "',', '|' or ']'", _TAIL: "']'",
                  _CURLY: "'}'", _TOP: "'.' (end of clause)"}[kind]
        return f" or {wanted}" if separator else f"; expected {wanted}"

    def number(self, token: _Token, sign: str) -> Term:
        try:
            if token.type == "FLOAT":
                return float_of_token(sign + token.text)
            value = int_of_token(sign + token.text)
        except _BadEscape as bad:
            raise self.error(bad.message, token.start + 2 + bad.offset) from None
        if value is None:
            raise self.error(f"{token.text} is not one character", token.start)
        return value

    def finish(self, run: list, max_priority: int) -> Term:
        """The term of a run of operands and operators, arranged by priority."""
        if len(run) == 1 and not isinstance(run[0], _Item):
            return run[0]
        if not run:   # pragma: no cover - a run always has an operand
            raise SchemalogError("syntax error: empty term")
        term, priority = self.arrange(run)
        if priority > max_priority:
            token = next(i.token for i in run if isinstance(i, _Item))
            raise self.error(f"operator priority clash: a term of priority {priority} where at most "
                             f"{max_priority} is allowed (put it in parentheses)", token.start)
        return term

    def arrange(self, run: list) -> tuple[Term, int]:
        """Shunting-yard over `run`: operands (priority 0) and _Items by the table's priorities."""
        ops = self.ops
        out: list[tuple[Term, int]] = []
        pending: list[tuple[_Item, int, int, int]] = []   # (operator, priority, left max, right max)

        def clash(item: _Item) -> SchemalogError:
            return self.error(f"operator priority clash at {item.name!r} (put the operands in parentheses)",
                              item.token.start)

        def reduce() -> None:
            item, priority, left_max, right_max = pending.pop()
            right, right_p = out.pop()
            if right_p > right_max:
                raise clash(item)
            if item.kind == "prefix":
                out.append((Struct(item.name, (right,)), priority))
                return
            left, left_p = out.pop()
            if left_p > left_max:
                raise clash(item)
            out.append((Struct(item.name, (left, right)), priority))

        for item in run:
            if not isinstance(item, _Item):
                out.append((item, 0))
            elif item.kind == "prefix":
                priority, typ = ops.prefix[item.name]
                pending.append((item, priority, -1, priority if typ == "fy" else priority - 1))
            else:
                table = ops.infix if item.kind == "infix" else ops.postfix
                priority, typ = table.get(item.name) or _BAR
                left_max = priority if typ[0] == "y" else priority - 1
                while pending and pending[-1][1] <= left_max:
                    reduce()
                if item.kind == "infix":
                    pending.append((item, priority, left_max, priority if typ == "xfy" else priority - 1))
                    continue
                operand, operand_p = out.pop()
                if operand_p > left_max:
                    raise clash(item)
                out.append((Struct(item.name, (operand,)), priority))
        while pending:
            reduce()
        return out[0]


def _shown(token: _Token) -> str:
    if token.type == "EOF":
        return "end of file"
    return repr(token.text if len(token.text) < 40 else token.text[:37] + "...")


_OP_TYPES = frozenset({"xfx", "xfy", "yfx", "fy", "fx", "xf", "yf"})


def declare(table: OperatorTable, goal: Term) -> bool:
    """Apply a directive `op(Priority, Type, Names)` to the reader's `table`, if `goal` is one
    whose arguments op/3 accepts (others are left to op/3 itself, which says what is wrong
    when the directive runs); whether it was one."""
    if not (isinstance(goal, Struct) and goal.name == "op" and len(goal.args) == 3):
        return False
    priority, typ, names = goal.args
    if not (isinstance(priority, Int) and 0 <= priority.value <= 1200 and isinstance(typ, Atom)
            and typ.name in _OP_TYPES):
        return False
    items, tail = list_items(names)
    items = [names] if isinstance(names, Atom) and names != NIL else items if tail == NIL else []
    if not items or not all(isinstance(i, Atom) and i.name not in (",", "|", "[]", "{}") for i in items):
        return False
    for item in items:
        key = (item.name, operator_kind(typ.name))
        if priority.value == 0:
            table.pop(key, None)
        else:
            table[key] = (priority.value, typ.name)
    return True


def read_clause(text: str, offset: int, file: str, line_at: _LineIndex, ops: Operators) -> tuple[Term | None, int]:
    """The clause term from `offset` to its final "." (None if only layout is left), and the
    offset after it."""
    return _Reader(text, file, line_at, ops).read(offset, True)


def read_term(text: str, file: str, ops: Operators) -> Term:
    """One term, as parse.parse_term reads one (a final "." optional)."""
    reader = _Reader(text, file, _LineIndex(text), ops)
    term, end = reader.read(0, False)
    if term is None:
        raise reader.error("unexpected end of file; expected a term", len(text))
    rest = reader.next(end)
    if rest.type != "EOF":
        raise reader.error(f"unexpected {_shown(rest)} after the term", rest.start)
    return term


_CONTROL = frozenset({(",", 2), (";", 2), ("->", 2), ("*->", 2), ("\\+", 1), ("not", 1), ("call", 1),
                      ("findall", 3), ("forall", 2), ("once", 1), ("ignore", 1)})


def module_goal(goal: Term) -> bool:
    """Whether `goal` calls a module-qualified goal (`lists:append(X, Y, Z)`) through its
    control constructs: schemalog has no modules (docs/queries.md), so such a query or clause
    keeps the reader's message saying so, where `X = a:b` reads as the term `:(a, b)`."""
    stack = [goal]
    while stack:
        g = stack.pop()
        if isinstance(g, Struct):
            if g.name == ":" and len(g.args) == 2:
                return True
            if (g.name, len(g.args)) in _CONTROL:
                stack.extend(g.args)
    return False


def _clause_goals(term: Term) -> Term:
    """The goals a clause term runs: a rule's body, a directive's goal (a fact runs none)."""
    if isinstance(term, Struct) and term.name in (":-", "?-") and len(term.args) in (1, 2):
        return term.args[-1]
    return Atom("true")


def parse_term(text: str, file: str = "<argument>", operators: OperatorTable | None = None,
               goal: bool = False) -> Term:
    """One term (a query, term_to_atom/2's text) read with `operators` (default: the
    grammar's table): by lark while the table is the grammar's, else, or where lark finds no
    reading, by this reader; lark's error when neither reads it. A `goal` (a query) that
    calls a module-qualified goal keeps lark's message that modules are not supported."""
    ops = operators.view() if operators is not None else DEFAULT_OPERATORS
    if ops is not DEFAULT_OPERATORS:
        return read_term(text, file, ops)
    try:
        return lark_parse_term(text, file)
    except SchemalogError as lark_error:
        try:
            term = read_term(text, file, ops)
        except SchemalogError:
            raise lark_error from None
        if goal and "modules are not supported" in lark_error.message and module_goal(term):
            raise lark_error from None
        return term
