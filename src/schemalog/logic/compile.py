"""Clauses compiled to Python: the head's unification and the body's goals, in one function.

    activate(args, b, height, rest) -> Goals | False     args: the call's arguments;
                                                           False: the head does not match
    Goals = (Goal, cut_barrier, rest) | None               the engine's goal list (engine.py)
    Goal  = Term | Call | UserCall | Or | IfThenElse | IfThen | Not
    Call  = (Builtin, args)                                a deterministic built-in, found when
                                                           the clause was compiled
    UserCall = ((name, arity), args)                       any other predicate's call, its key
                                                           made once, no goal term built
    Or(left, right), IfThenElse(cond, then, otherwise), IfThen(cond, then), Not(goal)
                                                           a control construct (engine.py), each
                                                           part a tuple of Goals

Calling a clause unifies its head with the goal and pushes its body's goals. Compiled, that is
one Python function per clause (the WAM's get and put instructions, in effect):

- a head variable's first occurrence names the goal's argument; a constant is compared or
  bound; a compound is taken apart where the goal has one, built where the goal has an unbound
  variable; nothing of the head is copied;
- the body's conjunction is flattened into the goal list, so `(A, B, C)` costs three goals,
  not five; a variable goal G is call(G), as ISO converts a clause body (its cut is local);
- a built-in that is not a control construct is resolved now, into a `Call`, so the engine
  calls it without looking it up (an engine's own relations cannot override it, as for a
  built-in); a user predicate's call becomes a `UserCall`, its key made now and its
  arguments built, with no goal term for the engine to take apart again;
  `X is Y - 1` and the comparisons of integer sums, differences and products are computed in
  Python, falling back to the general `is` (with its errors, floats and big numbers) for
  anything else; `X = Y` binds an unbound side itself;
- `;`, `->`, `*->` with an else-branch, `\\+` and `not` become the engine's Or, IfThenElse,
  IfThen and Not with their parts compiled the same way (their cuts reach as interpreted: the
  condition's is local, a branch's cuts the clause); `*->` without else stays a term;
- the first body goals, while they are comparisons of integers, type tests or `V is Expr` of
  a new variable over known integers (tak's `X =< Y`, then its three `is`), are made in the
  activation: a failing test fails the clause as a head would, with no choicepoint left for
  the next clause only to fail at once, and a computed value names V (no variable made, bound
  or trailed, no goal pushed). On anything but integers that goal and those after it stay in
  the body, in order, with their errors;
- `arg(N, T, A)` with N an integer when the clause is entered calls the deterministic
  arg_bound (no choicepoint); a repeated head variable is bound or compared inline.

Heads and bodies past a size bound, and a clause's first calls (`COMPILE_AFTER`: compiling
costs an `exec`, worth it only for a clause called again and again), copy the clause and unify.
"""

from __future__ import annotations

import re
from typing import Callable

from .builtins import body_calls
from .engine import BUILTINS, CONTROL, NONDET_BUILTINS, IfThen, IfThenElse, Not, Or, SoftIfThenElse
from .library import arg_bound
from .terms import TRUE, Atom, Float, Int, Struct, Term, Var, iter_vars, is_ground
from .unify import rename

Activation = Callable  # (args, bindings, height, rest) -> Goals | False

COMPILE_AFTER = 2   # calls of a clause before it is compiled


def compile_copy(term: Term, max_nodes: int = 2_000, max_depth: int = 60):
    """A function returning a copy of `term` with fresh variables, compiled to one Python
    expression: `rename` walks the term on every call, this builds it directly, sharing
    ground sub-terms. Very large or deep terms fall back to `rename`."""
    variables: dict[Var, str] = {}
    constants: list[Term] = []
    nodes = 0

    def expr(t: Term, depth: int) -> str:
        nonlocal nodes
        nodes += 1
        if nodes > max_nodes or depth > max_depth:
            raise OverflowError
        if isinstance(t, Var):
            name = variables.get(t)
            if name is None:
                name = variables[t] = f"v{len(variables)}"
            return name
        if isinstance(t, Struct) and not is_ground(t):
            args = ", ".join(expr(a, depth + 1) for a in t.args)
            constants.append(t.name)
            return f"S(c[{len(constants) - 1}], ({args},))"
        constants.append(t)
        return f"c[{len(constants) - 1}]"

    try:
        body = expr(term, 0)
    except OverflowError:
        return lambda: rename(term)
    fresh = "".join(f"    {name} = V('_')\n" for name in variables.values())
    source = f"def copy():\n{fresh}    return {body}\n"
    scope = {"S": Struct, "V": Var, "c": tuple(constants)}
    exec(source, scope)
    return scope["copy"]


def body_goals(body: Term) -> list[Term]:
    """The goals of a clause body's conjunction, nested conjunctions flattened, in order;
    `true` alone is none. The body has its variable goals written call(G) already."""
    out: list[Term] = []
    stack = [body]
    while stack:
        t = stack.pop()
        if isinstance(t, Struct) and t.name == "," and len(t.args) == 2:
            stack.append(t.args[1])
            stack.append(t.args[0])
        else:
            out.append(t)
    return [] if out == [TRUE] else out


def push_goals(goals: list[Term], height: int, rest):
    """The goal list with `goals` in front of `rest`, each cutting to `height`."""
    for goal in reversed(goals):
        rest = (goal, height, rest)
    return rest


def activate_by_copy(head: Term, body: Term) -> Activation:
    """An activation that copies the clause and unifies (no exec): a clause's first calls,
    and clauses too large to compile."""
    clause = Struct(":-", (head, body_calls(body)))
    copy = compile_copy(clause)

    def activate(args: tuple, b, height: int, rest):
        fresh_head, fresh_body = copy().args
        if args and not b.unify(fresh_head, Struct(fresh_head.name, args)):
            return False
        return push_goals(body_goals(fresh_body), height, rest)
    return activate


def activate_ground(head: Term, body: Term) -> Activation:
    """A clause without variables (a fact of a task tree, fib's `fib(0, 0) :- !.`) needs no
    copy: its arguments are matched with the call's one by one, an unbound one bound, an
    atomic one compared, a compound one unified (no goal term built for the unification)."""
    goals = body_goals(body)
    pattern = head.args if isinstance(head, Struct) else ()

    def activate(args: tuple, b, height: int, rest):
        if pattern:
            values = b.values
            get = values.get
            for p, x in zip(pattern, args):
                while type(x) is Var:
                    y = get(x)
                    if y is None:
                        break
                    x = y
                if x is p:
                    continue
                if type(x) is Var:
                    values[x] = p
                    b.trail.append(x)
                elif type(p) is Struct:
                    if not b.unify(p, x):
                        return False
                elif type(x) is not type(p) or x != p:
                    return False
        if not goals:
            return rest
        return push_goals(goals, height, rest)
    return activate


# Integer arithmetic computed inline: a binary or unary operator over integers, whose result
# (within _SMALL) needs neither the big-number limit nor a float. `//` truncates toward
# zero and `rem` takes the dividend's sign (SWI-Prolog's defaults), `mod` the divisor's
# (Python's %); a zero divisor or a negative shift raises in Python, and the goal is then
# the general built-in's, with its error.
_INLINE_BINARY = {"+": "+", "-": "-", "*": "*", "mod": "%", "/\\": "&", "\\/": "|", ">>": ">>",
                  "//": "TDIV", "rem": "TREM"}
_RAISING = frozenset({"mod", ">>", "//", "rem"})


def _truncating_div(x: int, y: int) -> int:
    """x // y rounded toward zero (ZeroDivisionError for y = 0)."""
    q = x // y
    if q < 0 and q * y != x:
        q += 1
    return q


def _truncating_rem(x: int, y: int) -> int:
    return x - y * _truncating_div(x, y)
_COMPARISONS = {"<": "<", ">": ">", "=<": "<=", ">=": ">=", "=:=": "==", "=\\=": "!="}
_SMALL = 1 << 62
# Type tests a compiled clause makes itself when they are its first goal, on a head variable
# (walked into x): as the built-ins of builtins.py decide them.
_TYPE_TESTS = {"var": "type({x}) is V", "nonvar": "type({x}) is not V",
               "atomic": "type({x}) is not V and type({x}) is not S", "atom": "type({x}) is A",
               "integer": "type({x}) is I", "compound": "type({x}) is S",
               "callable": "type({x}) is S or type({x}) is A", "number": "type({x}) is I or type({x}) is F"}
# Control constructs compiled into engine.Or and the like (`*->` alone stays a term: rare).
_COMPILED_CONTROL = frozenset({(";", 2), ("->", 2), ("\\+", 1), ("not", 1)})


def _inline_expression(t: Term, depth: int = 0) -> bool:
    """Whether `t` is an integer expression the compiler computes inline."""
    if depth > 8:
        return False
    if isinstance(t, (Var, Int)):
        return True
    if isinstance(t, Struct) and len(t.args) == 2 and t.name in _INLINE_BINARY:
        return all(_inline_expression(a, depth + 1) for a in t.args)
    if isinstance(t, Struct) and len(t.args) == 1 and t.name == "-":
        return _inline_expression(t.args[0], depth + 1)
    return False


def _expression_code(t: Term, local: dict[Var, str]) -> str:
    """Python code computing the inline expression `t` (`_inline_expression`), each variable
    read as the Int bound to the local it names: `X + 1` is `(x3.value + 1)`."""
    if isinstance(t, Var):
        return f"{local[t]}.value"
    if isinstance(t, Int):
        return repr(t.value)
    if len(t.args) == 1:
        return f"(-{_expression_code(t.args[0], local)})"
    op = _INLINE_BINARY[t.name]
    left, right = _expression_code(t.args[0], local), _expression_code(t.args[1], local)
    if op.isalpha():
        return f"{op}({left}, {right})"
    return f"({left} {op} {right})"


def _raises(t: Term) -> bool:
    """Whether the inline expression `t` has an operation Python may refuse (x // 0)."""
    return isinstance(t, Struct) and (t.name in _RAISING and len(t.args) == 2 or any(_raises(a) for a in t.args))


def _int_now(x, get) -> bool:
    """Whether `x` is bound to an integer now."""
    while type(x) is Var:
        x = get(x)
        if x is None:
            return False
    return type(x) is Int


def unify_goal(e, a: tuple, b) -> bool:
    """`X = Y` as a compiled body calls it: an unbound side is bound at once, without the
    general unification's set-up; anything else is the general unification."""
    x, y = a
    get = b.values.get
    while type(x) is Var:
        bound = get(x)
        if bound is None:
            break
        x = bound
    while type(y) is Var:
        bound = get(y)
        if bound is None:
            break
        y = bound
    if x is y:
        return True
    if type(x) is Var:   # the side bound first, as Bindings.unify binds it
        b.values[x] = y
        b.trail.append(x)
        return True
    if type(y) is Var:
        b.values[y] = x
        b.trail.append(y)
        return True
    return b.unify(x, y)


def compile_clause(head: Term, body: Term, max_nodes: int = 300, max_depth: int = 12,
                   max_goals: int = 200) -> Activation:
    """Compile `head :- body` into an activation (see the module's docstring)."""
    body = body_calls(body)
    names: dict[Var, str] = {}          # every variable of the clause, named up front
    for v in (*iter_vars(head), *iter_vars(body)):
        names.setdefault(v, f"v{len(names)}")
    seen: set[Var] = set()              # the variables the code so far has given a value
    constants: list = []
    lines: list[str] = []
    helpers: list[str] = []             # module-level functions: the inline arithmetic
    counter = iter(range(1 << 30))
    nodes = 0

    def const(t) -> str:
        # a global of the generated code: one look-up where `c[k]` takes two
        constants.append(t)
        return f"c{len(constants) - 1}"

    def build(t: Term, var=None) -> str:
        """An expression building `t` from the named variables (or `var(v)` for a variable)."""
        if isinstance(t, Var):
            return var(t) if var else names[t]
        if isinstance(t, Struct) and not is_ground(t):
            return f"S({const(t.name)}, ({', '.join(build(a, var) for a in t.args)},))"
        return const(t)

    def create(t: Term, pad: str, known: set[Var]) -> None:
        """Fresh variables for those of `t` with no value yet."""
        for v in dict.fromkeys(iter_vars(t)):
            if v not in known:
                known.add(v)
                lines.append(f"{pad}{names[v]} = V('_')")

    def walk(x: str, pad: str, out: list[str]) -> None:
        out.append(f"{pad}while type({x}) is V:")
        out.append(f"{pad}    y = get({x})")
        out.append(f"{pad}    if y is None: break")
        out.append(f"{pad}    {x} = y")

    def unify_with(p: Term, x: str, pad: str, depth: int) -> None:
        """Code unifying the head pattern `p` with the term named `x` (walked unless `p` is
        a variable's first occurrence, which just names it)."""
        nonlocal nodes
        nodes += 1
        if nodes > max_nodes or depth > max_depth:
            raise OverflowError
        if isinstance(p, Var):
            if p in seen:
                # a repeated head variable (app/3's H, `app(X, X, Y)`): an unbound side bound
                # here, as Bindings.unify would bind it; two bound ones unified
                y = f"u{next(counter)}"
                lines.append(f"{pad}{y} = {names[p]}")
                walk(y, pad, lines)
                walk(x, pad, lines)
                lines.append(f"{pad}if {y} is {x}: pass")
                lines.append(f"{pad}elif type({y}) is V: values[{y}] = {x}; trail.append({y})")
                lines.append(f"{pad}elif type({x}) is V: values[{x}] = {y}; trail.append({x})")
                lines.append(f"{pad}elif type({y}) is S or type({x}) is S:")
                lines.append(f"{pad}    if not b.unify({y}, {x}): return False")
                lines.append(f"{pad}elif type({y}) is not type({x}) or {y} != {x}: return False")
            else:
                seen.add(p)
                lines.append(f"{pad}{names[p]} = {x}")
            return
        walk(x, pad, lines)
        if not isinstance(p, Struct) or is_ground(p):
            c = const(p)
            lines.append(f"{pad}if type({x}) is V: values[{x}] = {c}; trail.append({x})")
            test = f"not b.unify({x}, {c})" if isinstance(p, Struct) else f"type({x}) is not type({c}) or {x} != {c}"
            lines.append(f"{pad}elif {test}: return False")
            return
        # A compound with variables: built for an unbound goal variable, else taken apart;
        # both branches leave the same variables named.
        lines.append(f"{pad}if type({x}) is V:")
        create(p, pad + "    ", set(seen))
        lines.append(f"{pad}    values[{x}] = {build(p)}; trail.append({x})")
        args = f"a{next(counter)}"
        lines.append(f"{pad}elif type({x}) is S and {x}.name == {const(p.name)} and len({args} := {x}.args) == {len(p.args)}:")
        unpack(p.args, args, pad + "    ", depth + 1)
        lines.append(f"{pad}else: return False")
        seen.update(iter_vars(p))

    def unpack(patterns: tuple, source: str, pad: str, depth: int) -> None:
        """Code unifying each of `patterns` with the items of the tuple named `source`, taken
        in one assignment: `v0, x3, = a1` names a variable's first occurrence at once."""
        targets, pending = [], []
        for sub in patterns:
            if isinstance(sub, Var) and sub not in seen:
                seen.add(sub)
                targets.append(names[sub])
            else:
                item = f"x{next(counter)}"
                targets.append(item)
                pending.append((sub, item))
        lines.append(f"{pad}{', '.join(targets)}, = {source}")
        for sub, item in pending:
            unify_with(sub, item, pad, depth)

    def arithmetic(goal: Term) -> str | None:
        """A `Call` computing `goal` (is/2 or a comparison) inline, or None."""
        if not isinstance(goal, Struct) or len(goal.args) != 2:
            return None
        name = goal.name
        if name == "is":
            if not _inline_expression(goal.args[1]) or isinstance(goal.args[1], (Var, Int)):
                return None
            exprs = [goal.args[1]]
        elif name in _COMPARISONS:
            if not all(_inline_expression(a) for a in goal.args):
                return None
            exprs = list(goal.args)
        else:
            return None
        if name == "is" and not isinstance(goal.args[0], Var):
            return None   # `3 is X + 1`: rare; the general built-in
        operands = list(dict.fromkeys(v for e in exprs for v in iter_vars(e)))
        slot = {v: f"a[{i + (name == 'is')}]" for i, v in enumerate(operands)}
        fn = f"f{next(counter)}"
        out = [f"def {fn}(e, a, b):", "    get = b.values.get"]
        local = {}
        for v in operands:
            x = local[v] = f"x{next(counter)}"
            out.append(f"    {x} = {slot[v]}")
            walk(x, "    ", out)
        test = " and ".join(f"type({x}) is I" for x in local.values()) or "True"

        def value(t: Term) -> str:
            return _expression_code(t, local)

        general = build(goal, var=lambda v: slot[v] if v in slot else "a[0]")
        builtin = const(BUILTINS[(name, 2)])
        out.append(f"    if {test}:")
        pad = "        "
        if any(_raises(x) for x in exprs):   # x // 0 and the like: the general built-in's error
            out.append("        try:")
            pad = "            "
        if name == "is":
            out.append(f"{pad}r = {value(exprs[0])}")
            if pad != "        ":
                out.append("        except (ZeroDivisionError, ValueError): pass")
                out.append("        else:")
            out.append(f"{pad}if -{_SMALL} < r < {_SMALL}:")
            out.append(f"{pad}    t = a[0]")
            out.append(f"{pad}    while type(t) is V:")
            out.append(f"{pad}        y = get(t)")
            out.append(f"{pad}        if y is None:")
            out.append(f"{pad}            b.values[t] = I(r); b.trail.append(t); return True")
            out.append(f"{pad}        t = y")
            out.append(f"{pad}    return type(t) is I and t.value == r")
        else:
            out.append(f"{pad}return {value(exprs[0])} {_COMPARISONS[name]} {value(exprs[1])}")
            if pad != "        ":
                out.append("        except (ZeroDivisionError, ValueError): pass")
        # anything else (a float, an unbound variable, a big result): the general built-in
        out.append(f"    return {builtin}(e, {general}.args, b)")
        helpers.append("\n".join(out))
        target = [names[goal.args[0]]] if name == "is" else []
        return f"({fn}, ({', '.join(target + [names[v] for v in operands])},))"

    def prefix_goal(goal: Term, k: int) -> bool:
        """Code making the body's k-th goal in the activation, when the goals before it were
        made there too (`st == k`): a type test of a known variable (boyer's
        `rewrite(A, A) :- atomic(A), !.`), a comparison of integer expressions (tak's
        `X =< Y`, queens' two `=\\=`), or `V is Expr` of a variable first met there, its value
        computed now and named, with no variable made or bound (tak's three `is`). A test that
        fails makes the clause fail as its head would: no choicepoint is left for the next
        clause only to fail at once. Where the operands are not integers (floats, unbound
        variables, errors to raise) `st` stays k: this goal and the rest stay in the body,
        in order. False when the goal is none of these (the prefix ends there)."""
        if not isinstance(goal, Struct):
            return False
        if (len(goal.args) == 1 and goal.name in _TYPE_TESTS and isinstance(goal.args[0], Var)
                and goal.args[0] in seen):
            x = f"g{next(counter)}"
            lines.append(f"    if st == {k}:")
            lines.append(f"        {x} = {names[goal.args[0]]}")
            walk(x, "        ", lines)
            lines.append(f"        if not ({_TYPE_TESTS[goal.name].format(x=x)}): return False")
            lines.append(f"        st = {k + 1}")
            return True
        if len(goal.args) != 2:
            return False
        if goal.name in _COMPARISONS:
            exprs = list(goal.args)
        elif (goal.name == "is" and isinstance(goal.args[0], Var) and goal.args[0] not in seen
              and not isinstance(goal.args[1], (Var, Int))):
            exprs = [goal.args[1]]
        else:
            return False
        if not (all(_inline_expression(e) for e in exprs) and not any(_raises(e) for e in exprs)
                and {v for e in exprs for v in iter_vars(e)} <= seen):
            return False
        lines.append(f"    if st == {k}:")
        local = {}
        for v in dict.fromkeys(v for e in exprs for v in iter_vars(e)):
            x = local[v] = f"g{next(counter)}"
            lines.append(f"        {x} = {names[v]}")
            walk(x, "        ", lines)
        known = " and ".join(f"type({x}) is I" for x in local.values()) or "True"

        def value(t: Term) -> str:
            return _expression_code(t, local)

        if goal.name == "is":
            target = goal.args[0]
            lines.append(f"        if {known}:")
            lines.append(f"            g = {value(exprs[0])}")
            lines.append(f"            if -{_SMALL} < g < {_SMALL}: {names[target]} = I(g); st = {k + 1}")
            seen.add(target)
            computed.append((k, target))
        else:
            lines.append(f"        if {known}:")
            lines.append(f"            if not {value(exprs[0])} {_COMPARISONS[goal.name]} {value(exprs[1])}:"
                         " return False")
            lines.append(f"            st = {k + 1}")
        return True

    def branch(t: Term, depth: int) -> str:
        """A tuple of the goal list entries of a control construct's part."""
        return "(" + "".join(goal_code(g, depth) + ", " for g in body_goals(t)) + ")"

    def control(goal: Struct, depth: int) -> str:
        """A compiled control construct (engine.Or and the like) with its parts compiled."""
        if depth > max_depth:
            raise OverflowError
        depth += 1
        if goal.name == ";":
            left, right = goal.args
            if isinstance(left, Struct) and len(left.args) == 2 and left.name in ("->", "*->"):
                kind = "ITE" if left.name == "->" else "SITE"
                return (f"{kind}({branch(left.args[0], depth)}, {branch(left.args[1], depth)}, "
                        f"{branch(right, depth)})")
            return f"OR({branch(left, depth)}, {branch(right, depth)})"
        if goal.name == "->":
            return f"IT({branch(goal.args[0], depth)}, {branch(goal.args[1], depth)})"
        return f"NOT({branch(goal.args[0], depth)})"

    def goal_code(goal: Term, depth: int = 0) -> str:
        """The goal list entry of one body goal: a Call, a UserCall, a compiled control
        construct, or the goal's instance (the other control constructs, nondeterministic
        built-ins)."""
        if not isinstance(goal, (Struct, Atom)):
            return build(goal)
        args = goal.args if isinstance(goal, Struct) else ()
        key = (goal.name, len(args))
        if key in _COMPILED_CONTROL:
            return control(goal, depth)
        if key == ("=", 2):
            return f"(U, ({build(args[0])}, {build(args[1])},))"
        if key == ("arg", 3):
            # arg(N, T, A) with N an integer when the clause is entered (a binding made
            # then stays while this goal list lives): the deterministic arg_bound, which
            # leaves no choicepoint; else the nondeterministic arg/3
            n = build(args[0])
            call = f"(ARG, ({n}, {build(args[1])}, {build(args[2])},))"
            return f"({call} if INT_NOW({n}, get) else {build(goal)})"
        if key in CONTROL or key in NONDET_BUILTINS or goal.name == "call":   # call/9 and past too
            return build(goal)
        built = "(" + "".join(build(a) + ", " for a in args) + ")"
        fn = BUILTINS.get(key)
        if fn is not None:
            inline = arithmetic(goal)
            return inline if inline is not None else f"({const(fn)}, {built})"
        return f"({const(key)}, {built})"

    try:
        if isinstance(head, Struct):   # an atom head (`go :- ...`) has nothing to unify
            unpack(head.args, "goal_args", "    ", 0)
        goals = body_goals(body)
        if len(goals) > max_goals:
            raise OverflowError
        # The goals the activation makes itself (prefix_goal), while they are such goals.
        computed: list[tuple[int, Var]] = []      # (k, V) of each `V is Expr` among them
        made = 0
        if goals and len(goals) <= 64:
            lines.append("    st = 0")
            while made < len(goals) and prefix_goal(goals[made], made):
                made += 1
            if not made:
                lines.pop()
            for k, v in computed:                 # not computed: a variable, as ever
                lines.append(f"    if st <= {k}: {names[v]} = V('_')")
        for goal in goals:
            create(goal, "    ", seen)
        # The goal list is built last goal first, one statement each: Python's parser
        # refuses more than 200 nested parentheses.
        lines.append("    r = rest")
        for goal in reversed(goals[made:]):
            lines.append(f"    r = ({goal_code(goal)}, height, r)")
        for k in reversed(range(made)):           # those not made here, in order
            lines.append(f"    if st <= {k}: r = ({goal_code(goals[k])}, height, r)")
    except (OverflowError, RecursionError):
        return activate_by_copy(head, body)
    code = "\n".join(lines)
    # only the look-ups the code uses: a clause of variables alone (tak/4) needs none
    uses = {word for word in ("values", "trail", "get") if re.search(rf"\b{word}\b", code)}
    prologue = ("    values = b.values\n" if "values" in uses else "") + (
        "    trail = b.trail\n" if "trail" in uses else "") + (
        ("    get = values.get\n" if "values" in uses else "    get = b.values.get\n") if "get" in uses else "")
    source = ("\n\n".join(helpers) + "\n\n" if helpers else "") + (
        "def activate(goal_args, b, height, rest):\n" + prologue + code + "\n    return r\n")
    scope = {"S": Struct, "V": Var, "I": Int, "A": Atom, "F": Float, "T": TRUE, "OR": Or, "ITE": IfThenElse,
             "SITE": SoftIfThenElse, "IT": IfThen, "NOT": Not, "U": unify_goal,
             "TDIV": _truncating_div, "TREM": _truncating_rem, "ARG": arg_bound, "INT_NOW": _int_now,
             **{f"c{k}": constant for k, constant in enumerate(constants)}}
    try:
        exec(source, scope)
    except (SyntaxError, RecursionError, MemoryError):   # a body term too deep for Python's parser
        return activate_by_copy(head, body)
    return scope["activate"]


__all__ = ["COMPILE_AFTER", "activate_by_copy", "activate_ground", "body_goals", "compile_clause",
           "compile_copy", "push_goals", "unify_goal"]
