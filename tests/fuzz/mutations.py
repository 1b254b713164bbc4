"""Hypothesis strategies for the fuzz suite: mutated knowledge, scenes and demonstrations,
Prolog queries over built-ins with odd arguments, and odd command lines.

Inputs are bytes (a file's content) or tuples of strings (an argv). A mutation is drawn
as a small list of edits to a shipped seed file (flip a byte, delete, duplicate or splice a
span, insert a token from the dictionaries below), each at a drawn position, mostly at a
delimiter so that the edit lands where the reader makes decisions. `long=True` opens up
the inputs whose only problem is that they are slow (very deep nesting, very wide tasks):
the fast profile keeps away from them so CI does not time out on known slowness.
"""

from __future__ import annotations

from hypothesis import strategies as st

from harness import COFFEE, KITCHEN, MIX, MIX_SCENE, ROOT, SEED, STRUCTURE

KNOWLEDGE_SEEDS = {p.name: p.read_bytes() for p in (MIX, COFFEE, STRUCTURE, SEED)}
SCENE_SEEDS = {p.name: p.read_bytes() for p in (KITCHEN, MIX_SCENE)}


def nest(open_: str, inner: str, close: str, depth: int) -> bytes:
    return (open_ * depth + inner + close * depth).encode()


def prolog_tokens(long: bool) -> list[bytes]:
    """Tokens that have broken readers: numbers, escapes, unicode, operators, nesting."""
    depths = [20, 200, 900] + ([5_000, 50_000] if long else [])
    tokens = [
        # huge and odd numbers
        b"1" + b"0" * 400, b"1" + b"0" * 20_000, b"1.0e400", b"-1.0e-400", b"1.0Inf", b"1.5NaN", b"-0.0",
        b"0x" + b"f" * 200, b"0b102", b"0o9", b"0'", b"0''", b"0'''", b"1_000_000", b"1 000", b"123456789012345678901234567890",
        b"9" * 4000 + b".0", b"0'\\z", b"0'\\x110000\\", b"0'\\", b"0'\\n", b"2'abc", b"36'ZZZ", b"37'1",
        # escapes in quoted text
        b'"\\x1b[2J"', b"'\\x1b[2J'", b"'\\u0000'", b"'\\U0010FFFF'", b"'\\U00110000'", b'"\\777777777\\"',
        b"'\\c\n  x'", b"'\\z'", b"'\\x'", b"'\\", b"\"", b"`back`", b"'a\nb'", b"'\\e\\a\\b\\f\\v\\0\\'",
        # unicode and bytes that are not UTF-8
        "é".encode(), "\u202e".encode(), "日本語".encode(), "\ufeff".encode(), b"\xff\xfe", b"\x00", b"\xc3",
        "𝓍".encode(), "e\u0301".encode(), "\u2028".encode(), "ℵ(x)".encode(), b"\r", b"\r\n", b"\t", b"\x0c",
        # operators and odd syntax
        b":- op(700, xfx, ===>).\n", b":- op(0, xfx, is).\n", b":- op(1201, fx, foo).\n", b":- op(200, xfy, '.').\n",
        b":- op(9, yfx, '|').\n", b":- op(100, fy, schema).\n", b":- op(1200, xfx, ',').\n", b":- op(-1, xfx, a).\n",
        b"a:-b:-c", b"- (1)", b"- 1", b"a- -1", b"[a|b|c]", b"{a}", b"'|'", b"(,)", b"(;)", b"||", b"[]()", b"{}(x)",
        b"f(,)", b"f()", b"X = f(X)", b"_", b"_X", b"\\+", b"..", b"...", b"a.b.c.d.e.f", b"not not not",
        b"- - - - - a", b"\\+ \\+ \\+ a", b",", b";", b"|", b"(", b")", b"[", b"]", b"{", b"}",
        # comments and clause ends
        b"/*", b"*/", b"%", b".", b". ", b"\n.\n", b"end_of_file.\n", b"?- true.\n",
        # directives and schemas that stress the engine and the instantiation
        b":- initialization(halt).\n", b":- include('/etc/passwd').\n", b":- consult(nowhere).\n",
        b":- ensure_loaded(library(lists)).\n", b":- repeat, fail.\n", b":- X is 2**100000, true.\n",
        b":- length(L, L).\n", b":- atom_length(A, B).\n", b":- throw(ball).\n", b":- X = f(X), write(X).\n",
        b"schema(t, [(a, true)], t.done).\n", b"schema(a, [(a, true)], x).\n", b"schema(X, [], Y).\n",
        b"schema(r(N), [(r(s(N)), true)], r.done).\n", b"task(a).\n", b"task(X).\n", b"task(1).\n",
        b"initial(X).\n", b"initial(not a).\n", b"object(_).\n", b"constraint(foo).\n", b"agent(X, Y).\n",
        b"schema(s, [(t, true)|T], p).\n", b"schema(s, \"abc\", p).\n", b"schema(s, [(t, 1.5)], 3).\n",
    ]
    for depth in depths:
        tokens += [nest("f(", "x", ")", depth), nest("[", "", "]", depth), nest("(", "a", ")", depth),
                   nest("- ", "a", "", depth), nest("{", "a", "}", depth), nest("not ", "a.b", "", depth),
                   nest("[a|", "[]", "]", depth), ("a" + ".b" * depth).encode()]
    if long:
        children = ", ".join(f"(w{i}, true)" for i in range(10_000))
        tokens.append(f"schema(wide, [{children}], wide.done).\n".encode())
    return tokens


YAML_TOKENS = [
    b"*a", b"&a [1, 2, 3]", b"!!python/object/apply:os.system ['echo pwned']", b"!!binary aGk=", b".nan", b".inf",
    b"-.inf", b"1e999", b"-1", b"[1, 2]", b"[1, 2, 3, 4]", b"[]", b"{}", b"null", b"~", b"? ", b"- ", b"\t",
    b"---\n", b"...\n", b"<<: *a", b"0x10", b"1_000", b"yes", b"'", b'"', b"\"\\x1b[2J\"", b"\xff", "é".encode(),
    b"%YAML 9.9\n", b"!tag", b"|\n  x", b">\n", b"[" * 200 + b"]" * 200, b"{a: " * 200 + b"1" + b"}" * 200,
    b"objects:\n", b"objects: 3\n", b"end_effector: [nan, 0, 0]\n", b"end_effector: [1e308, 0, 0]\n",
    b"  spoon: [0.1, 0.2]\n", b"  cup: cup\n", b"  '': [0, 0, 0]\n", b"  f(x: [0, 0, 0]\n", b"name: [1]\n",
]

LAUGHS = (b"a: &a [x, x, x, x, x, x, x, x, x]\n" + b"".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join(['*' + chr(97 + i)] * 9)}]\n".encode() for i in range(8))
    + b"objects: *i\n")

DEMO_VALUES = [b"nan", b"inf", b"-inf", b"1e308", b"-1e308", b"-1", b"0", b"", b" ", b"close", b"open", b"shut",
               b"1" * 400, b"1,2", b"\"", b"0x10", b"1e-320", b"NaN", b"+1", b"1.5.5", "é".encode(), b"\xff"]


# Whole clauses, inserted between two clauses so that they are read as such: they reach the
# schema checks, the instantiation and its limits instead of stopping at a syntax error.
CLAUSES = [
    b"task(r(0)).\nschema(r(N), [(r(s(N)), true)], r.done).\n",          # unbounded depth: --max-depth
    b"task(w).\nschema(w, [(v, true), (v, true), (v, true)], w.done).\nschema(v, [(w, true)], v.done).\n",
    b"task(b).\nschema(b, [(c(X), true)], b.done).\nschema(c(_), [], c.done).\n",   # a variable sub-task
    b"task(t).\nschema(t, [(t, true)], t.done).\n", b"task(1.5).\n", b"task([]).\n", b"task(\"s\").\n",
    b"schema(a1(spoon), [], a1.done).\n" * 3, b"schema(a1(spoon), [], not a1.done).\n",
    b"schema(a1(spoon), [], (a1.done ; x.y)).\n", b"schema(a1(spoon), [], \\+ \\+ a.b).\n",
    b"schema(a1(spoon), [(a9, true)], a1.done).\n", b"initial(a1.done).\n", b"initial(spoon.used and hand.free).\n",
    b"constraint(false).\n", b"constraint(not hand.free and hand.free).\n", b"constraint(X).\n",
    b"agent(_, arm).\nagent(_, gripper).\n", b"object(X) :- object(X).\n", b"schema(X, Y, Z) :- schema(X, Y, Z).\n",
    b"task(T) :- task(T).\n", b"schema(s(N), [], s.done) :- N > 0, M is N - 1, schema(s(M), _, _).\n",
    b":- dynamic(schema/3).\n", b":- discontiguous(schema/3).\n", b":- op(700, xfx, schema).\n",
    b":- set_prolog_flag(double_quotes, codes).\n", b":- retractall(schema(_, _, _)).\n",
    b":- assertz(schema(z, [], z.done)).\n", b":- forall(between(1, 2000, I), assertz(f(I))).\n",
]
# Only in the long profile: 100,000 assertz/1 in a directive take minutes (20,000: 2.6 s CPU).
LONG_CLAUSES = [b":- forall(between(1, 100000, I), assertz(f(I))).\n",
                b"task(g).\nschema(g, [" + b", ".join(b"(h%d, true)" % i for i in range(10_000)) + b"], g.done).\n"]


@st.composite
def edited(draw, seeds: dict[str, bytes], tokens: list[bytes], delimiters: bytes = b"(),[] .\n:", clauses=()):
    """(seed name, mutated bytes): 1-4 edits to one seed file."""
    name = draw(st.sampled_from(sorted(seeds)))
    data = bytearray(seeds[name])
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(["flip", "delete", "duplicate", "splice", "token", "token", "token", "truncate"]
                                  + ["clause"] * (3 if clauses else 0)))
        if op == "clause":
            ends = [i + 2 for i in range(len(data) - 1) if data[i:i + 2] == b".\n"] or [len(data)]
            at = ends[draw(st.integers(0, len(ends) - 1))]
            data[at:at] = draw(st.sampled_from(clauses))
            continue
        if draw(st.booleans()) and data:
            spots = [i for i, b in enumerate(data) if b in delimiters] or [0]
            pos = spots[draw(st.integers(0, len(spots) - 1))]
        else:
            pos = draw(st.integers(0, len(data)))
        span = draw(st.integers(1, 200))
        if op == "flip" and data:
            pos = min(pos, len(data) - 1)
            data[pos] ^= 1 << draw(st.integers(0, 7))
        elif op == "delete":
            del data[pos:pos + span]
        elif op == "duplicate":
            data[pos:pos] = data[pos:pos + span] * draw(st.integers(1, 3))
        elif op == "splice":
            other = seeds[draw(st.sampled_from(sorted(seeds)))]
            start = draw(st.integers(0, max(0, len(other) - 1)))
            data[pos:pos] = other[start:start + span]
        elif op == "truncate":
            del data[pos:]
        else:
            data[pos:pos] = draw(st.sampled_from(tokens))
    return name, bytes(data)


def knowledge(long: bool = False):
    """Mutated task knowledge: (seed name, bytes)."""
    return edited(KNOWLEDGE_SEEDS, prolog_tokens(long), clauses=CLAUSES + (LONG_CLAUSES if long else []))


@st.composite
def scenes(draw, long: bool = False):
    """Mutated scenes: bytes of YAML, or now and then a whole hostile document. Unclosed
    flow nesting costs PyYAML superlinear time (2,000 `{` 2.7 s, 5,000 10 s): the fast
    profile stays at 1,000."""
    if draw(st.integers(0, 9)) == 0:
        deep = [b"{" * 5000, b"[" * 20000] if long else [b"{" * 1000]
        return draw(st.sampled_from([LAUGHS, b"", b"\xff\xfe", b"[]", b"- 1\n- 2\n", b"objects: {}\n",
                                     b"!!python/object/apply:os.system ['true']\n", *deep]))
    return draw(edited(SCENE_SEEDS, YAML_TOKENS, delimiters=b"[],:\n "))[1]


@st.composite
def demonstrations(draw, csv: bytes):
    """A demonstration CSV with rows deleted, duplicated, swapped, cut, or fields replaced."""
    lines = csv.split(b"\n")
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(["field", "field", "field", "delete", "duplicate", "swap", "cut", "bytes", "column"]))
        if not lines:            # an earlier cut or delete left nothing: an empty recording
            break
        i = draw(st.integers(0, len(lines) - 1))
        if op == "field":
            fields = lines[i].split(b",")
            j = draw(st.integers(0, max(0, len(fields) - 1)))
            fields[j] = draw(st.sampled_from(DEMO_VALUES))
            lines[i] = b",".join(fields)
        elif op == "delete":
            del lines[i:i + draw(st.integers(1, 50))]
        elif op == "duplicate":
            lines[i:i] = [lines[i]] * draw(st.integers(1, 3)) if lines else []
        elif op == "swap" and len(lines) > 1:
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        elif op == "cut":
            lines = lines[:i]
        elif op == "column":
            lines = [line + (b",extra" if k == 2 else b",1") for k, line in enumerate(lines)]
        elif lines:
            data = bytearray(lines[i])
            if data:
                data[draw(st.integers(0, len(data) - 1))] ^= 1 << draw(st.integers(0, 7))
            lines[i] = bytes(data)
    return b"\n".join(lines)


# Built-ins and the odd arguments to give them (docs/queries.md, docs/syntax.md).
BUILTINS = {
    1: ["atom", "number", "var", "is_list", "ground", "callable", "atomic", "compound", "string", "write", "print",
        "writeq", "write_canonical", "msort", "halt", "tab", "nl", "throw", "call", "once", "ignore", "forall_",
        "length_", "atom_to_term_", "succ_or_zero", "char_code_", "number_vars", "term_variables_", "abs_", "\\+",
        "retract", "assertz", "asserta", "retractall", "abolish", "consult", "read_term_", "tab", "garbage_collect"],
    2: ["atom_length", "atom_codes", "atom_chars", "char_code", "number_codes", "number_chars", "atom_number",
        "atom_string", "string_chars", "string_codes", "string_to_atom", "string_length", "number_string",
        "term_to_atom", "upcase_atom", "downcase_atom", "length", "msort", "sort", "keysort", "last", "sum_list",
        "max_list", "min_list", "list_to_set", "reverse", "nb_getval", "b_getval", "nb_setval", "copy_term",
        "succ", "=..", "is", "=:=", "<", "@<", "==", "\\=", "=", "tab", "format", "char_type", "code_type",
        "atomic_list_concat", "term_variables", "sumlist", "exclude_", "numbervars_", "split_", "findall_", "writeq_",
        "setof_", "string_code_", "plus_", "between_", "nth0_", "functor_", "arg_", "sub_atom_"],
    3: ["functor", "arg", "between", "succ_", "plus", "nth0", "nth1", "atom_concat", "string_concat", "findall",
        "bagof", "setof", "format", "atomic_list_concat", "numbervars", "sub_string_", "split_string_", "char_type_",
        "string_code", "sort_", "msort_", "numlist", "catch", "forall", "aggregate_all", "select", "memberchk",
        "member_", "append", "exclude", "include", "maplist", "foldl_", "nb_setval_", "term_string", "format_atom"],
    4: ["sort", "sub_atom_", "split_string", "foldl", "maplist", "atomic_list_concat_", "aggregate_all_"],
    5: ["sub_atom", "sub_string", "foldl", "maplist"],
}

ODD_ARGS = [
    "_", "X", "Y", "0", "1", "-1", "3", "1.5", "-0.0", "1.0e308", "1.0Inf", "-1.0Inf", "nan", "inf", "1.5NaN",
    "1000000000000000000000000000000", "-1000000000000000000000000000000", "0'a", "0' ", "1114111", "1114112",
    "-5", "55296", "a", "'A b'", "''", "[]", "'[]'", "\"\"", "\"abc\"", "\"\\x1b[2J\"", "f(x)", "f(X, Y)", "[a, b]",
    "[a|b]", "[a|_]", "[X, Y|Z]", "[1, 2, 3]", "[0'a, -1]", "[a, 1, f(x)]", "\"abc\"", "{a}", "(a, b)", "(a :- b)",
    "X-Y", "a-1", "[a-1, b-2]", "1 + a", "foo(bar)", "\\+ a", "'\\u0000'", "'é'", "'日本'", "~w", "\"~*c\"",
    "\"~a~w~q~p~e~f~d~s~n~c~r~8|~t~30|~i~+\"", "\"~\"", "\"~99999999c\"", "\"~e\"", "[100000000, 0'x]",
    "[[[[[[[[[[a]]]]]]]]]]", "(X = f(X), X)", "2**100", "2**10000000", "9**9**9", "msb(-1)", "1 rdiv 0",
    "max(1, a)", "1 / 0", "1.0 / 0", "0 ** -1", "cot(0)", "sqrt(-1)", "log(0)", "random(0)", "1 << 100000000",
    "- (1)", "- 1", "a.b", "spoon.taken", "schema(T, S, P)", "true", "fail", "!", "call", "atom", "user",
    "E", "error(type_error(T, V), _)", "\"\\777777\\\"",
]


def _builtin_goal(name: str, args: list[str]) -> str:
    name = name.rstrip("_")
    if name in ("=..", "is", "=:=", "<", "@<", "==", "\\=", "=") and len(args) == 2:
        return f"({args[0]} {name} {args[1]})"
    if name == "\\+":
        return f"(\\+ {args[0]})"
    return f"{name}({', '.join(args)})"


# Arguments whose oddity is in the reader (escapes, 0'c): kept apart so that a reader bug
# does not stop a hypothesis run before it reaches the built-ins.
READER_ARGS = [a for a in ODD_ARGS if "\\" in a.replace("\\+", "")]
BUILTIN_ARGS = [a for a in ODD_ARGS if a not in READER_ARGS] + ["97", "[97, 98]", "[-1]", "[1114112]", "[0]"]
ESCAPES = ["\\x1b[2J", "\\x41\\", "\\x110000\\", "\\z", "\\u0000", "\\U0010FFFF", "\\U00110000", "\\777\\",
           "\\0\\", "\\e", "\\s", "\\c", "\\\n", "\\N", "\\", "\\'", "''", "\\x\\", "\\xg\\", "é"]


@st.composite
def reader_queries(draw):
    """A query whose text stresses the reader: escapes in quoted atoms, strings, 0'c."""
    escape = draw(st.sampled_from(ESCAPES))
    form = draw(st.sampled_from(["X = '{}'", 'X = "{}"', "X = 0'{}", "atom_length('{}', N)", "X = `{}`",
                                 "atom_codes(A, \"{}\")", "X = 0'{} + 1", "writeq('{}')", "X = [0'{}]"]))
    return form.replace("{}", escape)


@st.composite
def queries(draw):
    """A Prolog query: one to three built-in calls with odd arguments, sometimes shared
    variables, sometimes inside catch/3 or findall/3."""
    goals = []
    for _ in range(draw(st.integers(1, 3))):
        arity = draw(st.sampled_from(sorted(BUILTINS)))
        name = draw(st.sampled_from(BUILTINS[arity]))
        # a fresh variable for three arguments in ten: most built-ins convert one way or the other
        args = [draw(st.sampled_from(BUILTIN_ARGS)) if draw(st.integers(0, 9)) > 2 else f"V{len(goals)}{i}"
                for i in range(arity)]
        goals.append(_builtin_goal(name, args))
    goal = ", ".join(goals)
    wrap = draw(st.sampled_from(["", "", "catch", "findall", "cyclic", "once"]))
    if wrap == "catch":
        goal = f"catch(({goal}), E, true)"
    elif wrap == "findall":
        goal = f"findall(X, ({goal}), L)"
    elif wrap == "cyclic":
        goal = f"X = f(X), Y = [a|Y], {goal}"
    elif wrap == "once":
        goal = f"once(({goal}))"
    return goal


# Option values that have broken argument parsing and the code behind it.
ODD_VALUES = ["-1", "0", "1", "-0", "2", "1e309", "nan", "NaN", "inf", "-inf", "", " ", "99999999999999999999",
              "1e-320", "0x10", "1_000", " 3", "3.5", "-3.5", "1e3", "abc", "é", "\x1b[2J", "-", "--", "'",
              "a.b, c", "not", "f(", "X", "_", "2147483648", "9223372036854775808"]


def odd_values(paths: list[str]):
    return st.sampled_from(ODD_VALUES + paths)


# Pieces of file names that have broken commands: past NAME_MAX, bytes that are not UTF-8 (as
# os.fsdecode gives them: lone surrogates), a leading dash, layout and control characters,
# quotes and what ends a comment or a docstring in a written file, backslash escapes.
NAME_PIECES = ["x" * 300, "\udcff", "\udcfe\udcc3", "-", "--", "\n", "\r", "\t", " ", "'", '"', '"""', "`",
               "\\", "\\N", "\\x", "\x1b[2J", "\x7f", "\x01", "%", "<!--", "-->", "é", "日本", "\u202e", "$(x)", ";",
               "*", "?", "[", "]", "{", "}", "#", ":", ",", "=", "."]


@st.composite
def file_names(draw, suffix: str = ".pl", long: bool = False):
    """A hostile file name ending in `suffix`: pieces of NAME_PIECES around a stem, never `/` or
    NUL (no file can have them) nor a leading `.` (the harness takes those for leftovers)."""
    pieces = st.sampled_from(NAME_PIECES)
    if long:
        pieces = st.one_of(pieces, st.text(st.characters(blacklist_characters="/\x00",
                                                         blacklist_categories=("Cs",)), max_size=8),
                           st.binary(min_size=1, max_size=4).map(lambda b: b.decode("utf-8", "surrogateescape")))
    parts = draw(st.lists(pieces, min_size=1, max_size=4 if long else 3))
    name = "".join(parts[:1]) + "n" + "".join(parts[1:]) + suffix
    name = name.replace("/", "_").replace("\x00", "_")
    return "_" + name if name.startswith(".") else name


# --- behaviour trees (BT.CPP XML), their models and semantics files, sweep grids -------------

_CORPUS = ROOT / "tests" / "bt" / "corpus"
BT_SEEDS = {p.name: p.read_bytes() for p in (
    _CORPUS / "nav2" / "follow_point.xml", _CORPUS / "nav2" / "navigate_to_pose_w_replanning_and_recovery.xml",
    _CORPUS / "nav2" / "navigate_w_replanning_and_round_robin_recovery.xml",
    _CORPUS / "btcpp" / "tutorials" / "t09_scripting.xml", _CORPUS / "btcpp" / "tutorials" / "t14_subtree_model_1.xml")}
NODES_SEED = (_CORPUS / "nav2" / "nav2_tree_nodes.xml").read_bytes()
SECRET_MARKER = "S3CRETMARKER0123"      # in secret.txt beside every tree: never shown (tests/fuzz/test_secrets.py)

XML_TOKENS = [
    b'<include path="secret.txt"/>', b'<include path="/etc/passwd"/>', b'<include path="/proc/self/environ"/>',
    b'<include path="t.xml"/>', b'<include path="missing.xml"/>', b'<include ros_pkg="x" path="y"/>', b"<include/>",
    b'&#x1;', b'&#xD800;', b'&#0;', b'&#x110000;', b'&#99999999999999999999;', b"&amp;&&", b"&lt;", b"&bogus;",
    b'<SubTree ID="MainTree"/>', b'<SubTree ID="nowhere"/>', b'<SubTree ID="x" _autoremap="maybe"/>',
    b'<BehaviorTree ID="x"><AlwaysSuccess/></BehaviorTree>', b'<BehaviorTree>', b"</BehaviorTree>", b"</root>",
    b'<root BTCPP_format="3">', b'<root BTCPP_format="4" main_tree_to_execute="nowhere">', b"<TreeNodesModel/>",
    b'<!DOCTYPE r [<!ENTITY a "aaaaaaaa">]>', b'<?xml version="1.0"?>', b"<!-- -- -->", b"<![CDATA[x]]>",
    b'num_attempts="-1"', b'num_attempts="99999999999999999999"', b'num_cycles="2.9"', b'msec="-1"', b'msec="1e400"',
    b'name=""', b'ID=""', b'_skipIf="x &gt; 1"', b'_while="{a}"', b'code="x := 1"', b'code="{c}"', b'port="{}"',
    b"<Sequence>", b"</Sequence>", b"<Inverter>", b"</Inverter>", b"<Fallback/>", b"<ReactiveSequence>",
    b"<Action ID=\"A\"/>", b"<Condition ID=\"C\"/>", b"<Control ID=\"K\"/>", b"<Decorator ID=\"D\"/>",
    b"<RetryUntilSuccessful num_attempts=\"-1\">", b"<Repeat>", b"<SequenceStar>", b"<Switch2 case_1=\"1\"/>",
    b"\x00", b"\xff", "é".encode(), b"\x1b[2J", b"\r", b"\t", b" " * 10, b'"', b"'", b"<", b">", b"/>", b"=",
    nest("<Inverter>", "<AlwaysSuccess/>", "</Inverter>", 100), nest("<Sequence>", "<AlwaysSuccess/>", "</Sequence>", 300),
]

SEMANTICS_SEED = b"MyRecovery: RecoveryNode\nIsBatteryOk: Condition\nMyAction: StatefulAction\n"
SEMANTICS_TOKENS = [b"Fallback: Sequence\n", b"Sequence: Sequence\n", b"X: Nothing\n", b"X: RecoveryNode\n",
                    b"MyRecovery: Condition\n", b"- a\n", b"[a, b]\n", b"a: [1]\n", b"a: {b: c}\n", b"? x\n", b"\xff",
                    b"*a", b"&a b", b"x: !!python/object/apply:os.system ['true']\n", b"\t", b"'", b'"', b":", b"\n"]

GRID_SEEDS = {"small.yaml": b"name: small\nshapes: [3x2, [2, 3]]\nreductions: [0, 0.5]\nseeds: [1, 2]\n"
                            b"propagate: [full, none]\nmeasures: [compress, prove]\nlimits:\n  max_states: 200\n"
                            b"  cell_seconds: 2\n",
              "timed.yaml": b"shapes: [3x2]\nreductions: [0.5]\nmeasures: [time, runtimes]\nruns: 1\nticks: 1\n"
                            b"selectors: [incremental, scan]\ncoffee: false\n"}
GRID_TOKENS = [b"9" * 5000, "\u0663x\u0662".encode(), b"999999999999x2", b"1e400", b"-1",
               b"nan", b"inf", b"0x10", b"[]", b"{}", b"~", b"4x2", b"12x10", b"[64, 2]", b"coffee: true\n",
               b"sizes: [6x4]\n", b"seeds: [4294967296]\n", b"runs: 0\n", b"name: ../../x\n", b"name: \"\"\n",
               b"measures: [plot]\n", b"limits: {max_states: 0}\n", b"shapes: 3x2\n", b"\xff", b"\t", b"'", b"- ",
               b"&a [1]", b"*a", b"x: !!python/name:os.system\n"] + YAML_TOKENS


def bt_trees():
    """Mutated BT.CPP documents: (seed name, bytes)."""
    return edited(BT_SEEDS, XML_TOKENS, delimiters=b'<>"= /\n')


def bt_nodes():
    """A mutated TreeNodesModel file (Nav2's): bytes."""
    return edited({"nav2_tree_nodes.xml": NODES_SEED}, XML_TOKENS, delimiters=b'<>"= /\n').map(lambda d: d[1])


def semantics_files():
    """A mutated --semantics YAML: bytes."""
    return edited({"semantics.yaml": SEMANTICS_SEED}, SEMANTICS_TOKENS, delimiters=b": \n").map(lambda d: d[1])


def grids():
    """Mutated sweep grids: (seed name, bytes)."""
    return edited(GRID_SEEDS, GRID_TOKENS, delimiters=b"[],:\n x")
