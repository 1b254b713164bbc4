"""Task trees in and out of BehaviorTree.CPP v4 XML, and runs in its real runtime.

    export_btcpp(tree, initial) -> str            a <root BTCPP_format="4"> document
    import_btcpp(text, file)    -> Imported       (tree, initial state) from such a document
    run_btcpp(xml, original, initial, failures) -> BtRun   ticked in BT.CPP (behaviortreepy) against
                                                  the World, the robot failing `failures`

The exported document (docs/formats.md, BehaviorTree.CPP):

    schemalog_run            the main tree: a Script of `acted`, the failure counters and (when
                             asked) the initial state; else the robot writes the state before the
                             first tick. Then KeepRunningUntilFailure over one *decision* per
                             tick, the task under ForceSuccess (a failed action is a decision
                             too), then a ScriptCondition on the task's post-condition
    a composite behaviour    <SubTree ID=.. name="label" _while="PRE" _skipIf="acted || (POST)"
                             importance=".." agent=".."/> over a BehaviorTree holding a Sequence
                             of its children
    a leaf                   <functor name="label" _while="PRE" _skipIf="acted || (POST) ||
                             failures__N > R" _onSuccess="acted := true; failures__N := 0"
                             _onFailure="acted := true; failures__N += 1"/>, an action the
                             runtime registers: retried R times, then inhibited (the executive's rule)
    a merged leaf            <Sequence name="label" ...> of its constituents, each an original
                             action <a name=".." _while="PREVIOUS POST" _skipIf="POST"/> with its
                             own failure counter
    a literal obj.prop       the boolean blackboard entry obj__prop (others: q__ + hex of the text)

`acted` is set by the leaf that acts and reset before each decision, so every tick takes
exactly one decision: the first enabled leaf in tree order (docs/formats.md says why that
order is sound). Metadata BT.CPP has no use for is kept in `_`-attributes it ignores:
`_importance`, `_agent`, `_objects`, `_origins` (provenance, origin/6 terms), `_releaser` and
`_context` (when a propagated context makes the pre-condition more than the releaser).

Import reads that form back exactly, and besides it the part of BT.CPP with a schema meaning
(Sequence, SequenceWithMemory, ReactiveSequence, Parallel, conditions, Precondition, `_while`,
SubTree with literal ports, Script boolean assignments, the post-condition pattern
Fallback(conditions..., behaviour)); everything else is refused with the element's line and
column. Either way each action's node type and ports are kept (Imported.nodes), for an export
to give them back. XML is parsed with defusedxml (no entities, no external references).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from .. import defaults
from ..errors import SchemalogError, SourcePos, unquoted, visible
from ..logic.terms import Atom, Float, Int, Str, Struct, Term, is_ground, list_items, make_list, quote_atom, term_to_text
from ..task import conditions as cond
from ..task.conditions import Condition
from ..task.schema import DEFAULT_AGENT, DEFAULT_IMPORTANCE
from ..task.tree import Behaviour, Origin, walk
from .quoting import Unquotable, xml_attribute, xml_comment

MAIN_TREE = "schemalog_run"
ACTED = "acted"
MAX_XML_ELEMENTS = 50_000      # Nav2's largest trees have about a hundred; beyond this is not a tree file
MAX_XML_NESTING = defaults.MAX_DEPTH

# Node types of BT.CPP an action must not be named after.
BUILTIN_NODES = frozenset({
    "Sequence", "SequenceWithMemory", "ReactiveSequence", "Parallel", "ParallelAll", "Fallback",
    "ReactiveFallback", "Recovery", "RecoveryNode", "PipelineSequence", "RoundRobin", "Retry",
    "RetryUntilSuccessful", "Repeat", "Inverter", "ForceSuccess", "ForceFailure", "KeepRunningUntilFailure",
    "RunOnce", "Timeout", "Delay", "Precondition", "Script", "ScriptCondition", "SetBlackboard", "SubTree",
    "Sleep", "AlwaysSuccess", "AlwaysFailure", "Switch2", "Switch3", "Switch4", "Switch5", "Switch6",
    "IfThenElse", "WhileDoElse", "Action", "Condition", "Control", "Decorator", "BehaviorTree",
    "UnsetBlackboard", "AsyncSequence", "LoopInt", "LoopDouble", "LoopString", "LoopBool", "TryCatch",
    "ManualSelector", "SkipUnlessUpdated", "WaitValueUpdate", "WasEntryUpdated", "EntryUpdated",
    "ParallelFirst", "ReactiveParallel", "LatchedSequence", "LatchedFallback", "Finally", "root",
    "TreeNodesModel", "include"})
REFUSED = {
    "Fallback": "a Fallback tries alternatives after a failure; schemas have no failure to recover from",
    "ReactiveFallback": "a Fallback tries alternatives after a failure; schemas have no failure to recover from",
    "Recovery": "a recovery node reacts to failure, which schemas do not model",
    "RecoveryNode": "a recovery node reacts to failure, which schemas do not model",
    "PipelineSequence": "a PipelineSequence re-ticks finished children, which schemas do not model",
    "RoundRobin": "a RoundRobin rotates between alternatives, which schemas do not model",
    "Retry": "retrying after a failure is the executive's job (run --fail), not the task's",
    "RetryUntilSuccessful": "retrying after a failure is the executive's job (run --fail), not the task's",
    "Repeat": "a schema behaviour is accomplished once; repetition has no schema meaning",
    "KeepRunningUntilFailure": "repetition has no schema meaning (outside schemalog's own run tree)",
    "Inverter": "inverting a status has no schema meaning",
    "ForceSuccess": "forcing a status has no schema meaning (outside schemalog's own run tree)",
    "ForceFailure": "forcing a status has no schema meaning",
    "Timeout": "time limits have no schema meaning", "Delay": "delays have no schema meaning",
    "RunOnce": "running once has no schema meaning (a behaviour already runs until accomplished)",
    "IfThenElse": "an else-branch is an alternative, which schemas do not model",
    "WhileDoElse": "an else-branch is an alternative, which schemas do not model",
    "Switch2": "a Switch chooses among alternatives, which schemas do not model",
    "Switch3": "a Switch chooses among alternatives, which schemas do not model",
    "Switch4": "a Switch chooses among alternatives, which schemas do not model",
    "SetBlackboard": "SetBlackboard copies values; only Script assignments of booleans have a schema meaning",
    "AsyncSequence": "use Sequence", "TryCatch": "failures have no schema meaning",
}


# ---------------------------------------------------------------------------
# Literals as blackboard keys, conditions as BT.CPP scripts

_PIECE = re.compile(r"[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)*")
_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_RESERVED_KEYS = {ACTED, "true", "false"}
FAILURES = "failures__"          # failures__N: how often action element N failed in a row (an int)
# BT.CPP 4.8's script reads a name that starts with a keyword (`truex`, `true__done`, `falsey`) as
# the keyword and then a stray name, a parse error: such entries take the q__ form too
_RESERVED_PREFIXES = ("q__", FAILURES, "true", "false")


def _pieces(atom: Term) -> list[str] | None:
    """`hand.free` -> [hand, free]: the names of a right-nested `.` of plain atoms, else None."""
    out = []
    while isinstance(atom, Struct) and atom.name == "." and len(atom.args) == 2 and isinstance(atom.args[0], Atom):
        out.append(atom.args[0].name)
        atom = atom.args[1]
    if not isinstance(atom, Atom):
        return None
    out.append(atom.name)
    return out if all(_PIECE.fullmatch(p) for p in out) else None


def _dotted(pieces: list[str]) -> Term:
    term: Term = Atom(pieces[-1])
    for name in reversed(pieces[:-1]):
        term = Struct(".", (Atom(name), term))
    return term


def literal_key(atom: Term) -> str:
    """The blackboard entry of an atom: `hand.free` -> hand__free; others q__ + hex of the text."""
    pieces = _pieces(atom)
    if pieces is not None:
        key = "__".join(pieces)
        if key not in _RESERVED_KEYS and not key.startswith(_RESERVED_PREFIXES):
            return key
    return "q__" + term_to_text(atom).encode().hex()


def key_atom(key: str) -> Term:
    """The atom a blackboard entry stands for (the inverse of literal_key; `door_open` -> door_open)."""
    from ..logic.opread import parse_term

    if key.startswith("q__"):
        try:
            return parse_term(bytes.fromhex(key[3:]).decode(), "<key>")
        except (ValueError, SchemalogError):
            pass
    pieces = key.split("__")
    return _dotted(pieces) if all(_PIECE.fullmatch(p) for p in pieces) else Atom(key)


def to_script(c: Condition) -> str:
    """A condition in BT.CPP's scripting language, every compound operand parenthesised."""
    if isinstance(c, cond.Const):
        return "true" if c.value else "false"
    if isinstance(c, cond.Lit):
        return literal_key(c.atom) if c.positive else "!" + literal_key(c.atom)
    if isinstance(c, cond.Not):
        return "!(" + to_script(c.item) + ")"
    joiner = " && " if isinstance(c, cond.And) else " || "
    return joiner.join(_operand(i) for i in c.items)


def _operand(c: Condition) -> str:
    text = to_script(c)
    return f"({text})" if isinstance(c, (cond.And, cond.Or, cond.Not)) else text


_TOKEN = re.compile(r"\s*(?:(&&|\|\||!=|!|\(|\)|:=|==|=|;)|([A-Za-z_@][A-Za-z0-9_]*)|(\S))")
_ARITHMETIC = "it compares or computes values; only boolean entries joined by &&, || and ! have a schema meaning"


class ScriptError(ValueError):
    """A script outside the boolean subset; the message says why."""


def _tokens(text: str) -> list[str]:
    out = []
    for m in _TOKEN.finditer(text):
        op, name, other = m.groups()
        if other is not None:
            raise ScriptError(f"{other!r} in {text!r}: {_ARITHMETIC}")
        out.append(op or name)
    return out


def parse_script_condition(text: str, acted: bool = False) -> Condition:
    """Read a boolean script (`a__b && !(c || d)`) back into a condition, structure intact.

    With `acted`, the entry `acted` reads as the literal ACTED_LIT (schemalog's decision flag)."""
    tokens = _tokens(text)
    if not tokens:
        raise ScriptError("an empty script has no condition")
    pos = [0]

    def peek():
        return tokens[pos[0]] if pos[0] < len(tokens) else None

    def take():
        pos[0] += 1
        return tokens[pos[0] - 1]

    def chain(op: str, sub, kind):
        items = [sub()]
        while peek() == op:
            take()
            items.append(sub())
        return items[0] if len(items) == 1 else kind(tuple(items))

    def disjunction():
        return chain("||", conjunction, cond.Or)

    def conjunction():
        return chain("&&", unary, cond.And)

    def unary():
        t = peek()
        if t == "!":
            take()
            inner = unary()
            if isinstance(inner, cond.Lit):
                return inner.negate()
            if isinstance(inner, cond.Const):
                raise ScriptError(f"!{to_script(inner)} in {text!r}: write the constant itself")
            return cond.Not(inner)
        if t == "(":
            take()
            inner = disjunction()
            if take() != ")" if peek() is not None else True:
                raise ScriptError(f"unbalanced parentheses in {text!r}")
            return inner
        if t is None:
            raise ScriptError(f"{text!r} ends where a condition should follow")
        if t in ("==", "!=", "=", ":=", ";", ")", "&&", "||"):
            raise ScriptError(f"{t!r} in {text!r}: {_ARITHMETIC}" if t in ("==", "!=", "=", ":=")
                              else f"unexpected {t!r} in {text!r}")
        take()
        if t == "true":
            return cond.TRUE
        if t == "false":
            return cond.FALSE
        if t.startswith("@"):
            t = t[1:]
        if acted and t == ACTED:
            return ACTED_LIT
        return cond.Lit(key_atom(t))

    result = disjunction()
    if peek() is not None:
        t = peek()
        raise ScriptError(f"{t!r} in {text!r}: {_ARITHMETIC}" if t in ("==", "!=", "=", ":=")
                          else f"unexpected {t!r} in {text!r}")
    return result


ACTED_LIT = cond.Lit(Atom("$acted"))
_COUNTER_RESET = re.compile(r"\s*" + FAILURES + r"\d+\s*:=\s*0\s*")
_INHIBITED = re.compile(r"(?:\s*\|\|\s*" + FAILURES + r"\d+\s*>\s*\d+)+\s*$")


def parse_assignments(text: str) -> list[tuple[Term, bool]]:
    """Read `a := true; b := false` into (atom, value) pairs; anything else is a ScriptError."""
    out = []
    for statement in [s.strip() for s in text.split(";")]:
        if not statement:
            continue
        m = re.fullmatch(r"@?([A-Za-z_][A-Za-z0-9_]*)\s*(:=|=)\s*(true|false)", statement)
        if not m:
            raise ScriptError(f"{statement!r}: only assignments of true or false have a schema meaning "
                              f"(the post-condition of a Script, or the initial state)")
        out.append((m.group(1), m.group(3) == "true"))
    return out


# ---------------------------------------------------------------------------
# Export

GENERIC_ACTION = "SchemalogAction"


@dataclass(frozen=True)
class NodeType:
    """The BT.CPP node type a functor's actions run as, and its input ports, one per argument
    in order (`a1: {type: PickUp, ports: [object]}`: `a1(spoon)` is `<PickUp object="spoon">`)."""

    type: str
    ports: tuple[str, ...]


NodeTypes = dict      # functor name -> NodeType
LabelNodes = dict     # action label -> (node type, ((port, value), ...)): bt_node/3 facts

_PORT = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def check_node_types(types: NodeTypes) -> None:
    """Refuse a node type or port BT.CPP would not take (ValueError, naming it)."""
    for functor, t in types.items():
        if not _KEY.fullmatch(t.type) or t.type in BUILTIN_NODES or t.type in (ACTED, MAIN_TREE, GENERIC_ACTION):
            raise ValueError(f"{functor}: {t.type!r} cannot be a node type (an identifier that is not "
                             f"one of BT.CPP's own node types, nor {GENERIC_ACTION})")
        for port in t.ports:
            if not _PORT.fullmatch(port) or port in ("name", "ID"):
                raise ValueError(f"{functor}: {port!r} cannot be a port name (an identifier not starting "
                                 f"with _, nor name or ID)")
        if len(set(t.ports)) != len(t.ports):
            raise ValueError(f"{functor}: a port is named twice in {list(t.ports)}")


def default_node(label: Term) -> tuple[str, tuple[tuple[str, str], ...]]:
    """The node type and ports an export gives action `label` when nothing maps it."""
    args = label.args if isinstance(label, Struct) else ()
    values = [_port_value(a) for a in args]
    ports = () if None in values else tuple((f"arg{k}", v) for k, v in enumerate(values, 1))
    return action_id(label), ports


def _port_value(arg: Term) -> str | None:
    """An argument as a literal port value, or None where BT.CPP would read it as something else
    (`{x}`: a blackboard entry; `=`: the entry of the port's own name)."""
    text = term_to_text(arg)
    core = text.strip(" ")
    if core == "=" or (core.startswith("{") and core.endswith("}")):
        return None
    return text


def action_id(label: Term) -> str:
    """The node type of an action: its functor when that is a BT.CPP name, else SchemalogAction
    (`'Ω'`, `'a&b'`, `SubTree`: the name attribute keeps the label exactly)."""
    name = label.name if isinstance(label, (Atom, Struct)) else ""
    return name if _KEY.fullmatch(name or "") and name not in BUILTIN_NODES and name != ACTED else GENERIC_ACTION


def agent_text(agent: str) -> str:
    """An agent name as an attribute: itself, or quoted as an atom when it would not read back
    as itself (`'my arm'` stays; a name with a control character or a leading quote is quoted)."""
    return agent if agent.isprintable() and not agent.startswith("'") else quote_atom(agent)


def agent_of(text: str) -> str:
    """The agent name an attribute holds (the inverse of agent_text)."""
    if text.startswith("'"):
        from ..logic.opread import parse_term
        try:
            term = parse_term(text, "<agent>")
        except SchemalogError:
            return text
        if isinstance(term, Atom):
            return term.name
    return text


def steps_of(leaf: Behaviour) -> tuple[tuple[Term, Condition], ...]:
    """The original actions a leaf performs, in order (the executive's rule)."""
    if len(leaf.origins) > 1:
        return tuple((o.label, o.post) for o in leaf.origins)
    return ((leaf.origins[0].label if leaf.origins else leaf.label, leaf.post),)


def atoms_of(tree: Behaviour) -> list[Term]:
    """Every atom a condition of the tree reads or writes, in order of appearance."""
    seen: dict[Term, None] = {}
    for node in walk(tree):
        parts = [node.context, node.releaser, node.post]
        for o in node.origins:
            parts += [o.releaser, o.post]
        for part in parts:
            for lit in cond.literals(part):
                seen.setdefault(lit.atom, None)
    return list(seen)


def _number(value) -> str:
    return term_to_text(Int(value) if isinstance(value, int) else Float(value))


def _meta(node: Behaviour, port_style: bool) -> list[tuple[str, str]]:
    """Importance and agent (SubTree literal ports, else `_`-attributes), objects, provenance."""
    out = []
    prefix = "" if port_style else "_"
    if node.importance != DEFAULT_IMPORTANCE:
        out.append((prefix + "importance", _number(node.importance)))
    if node.agent != DEFAULT_AGENT:
        out.append((prefix + "agent", agent_text(node.agent)))
    out.append(("_objects", term_to_text(make_list(node.objects))))
    if node.context != cond.TRUE:
        out.append(("_context", to_script(node.context)))
        out.append(("_releaser", to_script(node.releaser)))
    if node.origins:
        from .render import origin_term
        out.append(("_origins", term_to_text(make_list([origin_term(o) for o in node.origins]))))
    return out


def _attrs(pairs: list[tuple[str, str]]) -> str:
    return "".join(f" {k}={xml_attribute(v)}" for k, v in pairs)


class _Exporter:
    def __init__(self, tree: Behaviour, retries: int, node_types: NodeTypes, nodes: LabelNodes) -> None:
        self.trees: dict[str, str] = {}        # body -> BehaviorTree ID
        self.bodies: list[tuple[str, str]] = []
        self.actions: dict[str, dict[str, str]] = {}    # node type -> its ports -> a description
        self.retries = retries
        self.counters: list[str] = []          # failures__1 ... one per action element
        self.node_types = node_types
        self.nodes = nodes
        self.mapped_owner: dict[str, tuple] = {}       # a mapped node type -> (functor, ports)
        # A mapped type may not be the node type another functor already gets by default
        # (`a1` mapped to `a2` beside an action a2(cup, x)): the robot's a2 has its own ports.
        defaults_of = {action_id(action): action.name for node in walk(tree) if not node.children
                       for action, _ in steps_of(node) if isinstance(action, (Atom, Struct))
                       and action.name not in node_types}
        for functor, t in node_types.items():
            if t.type in defaults_of and defaults_of[t.type] != functor:
                raise Unquotable(f"the node types map gives {functor} the node type {t.type}, which the "
                                 f"action {defaults_of[t.type]} already has")
        # BT.CPP refuses a BehaviorTree ID that names a registered node: a built-in one
        # (a task called SubTree) or one of this document's actions (a sub-task pick(x)
        # beside an action pick_x)
        self.used_ids: set[str] = {MAIN_TREE, GENERIC_ACTION, *BUILTIN_NODES, *(
            self.action(action)[0] for node in walk(tree) if not node.children for action, _ in steps_of(node))}
        self.actions.clear()

    def action(self, label: Term) -> tuple[str, list[tuple[str, str]]]:
        """The node type of an action and its ports: one per argument, `argK` unless the node
        types map names them (no ports when an argument would read as a blackboard entry)."""
        functor = label.name if isinstance(label, (Atom, Struct)) else None
        args = label.args if isinstance(label, Struct) else ()
        mapped = self.node_types.get(functor) if functor is not None else None
        written = self.nodes.get(label)
        if written is not None and mapped is None:        # bt_node/3: as the imported tree had it
            ident, ports = written
            declared = self.actions.setdefault(ident, {})
            for name, _ in ports:
                declared.setdefault(name, f"a port of {ident}")
            return ident, list(ports)
        if mapped is not None:
            other = self.mapped_owner.setdefault(mapped.type, (functor, mapped.ports))
            if other[0] != functor and other[1] != mapped.ports:
                raise Unquotable(f"the node types map gives {mapped.type} to {other[0]} (ports {', '.join(other[1]) or 'none'}) "
                                 f"and to {functor} (ports {', '.join(mapped.ports) or 'none'})")
            if len(args) > len(mapped.ports):
                raise Unquotable(f"the node types map gives {mapped.type} {len(mapped.ports)} port(s), "
                                 f"and {term_to_text(label)} has {len(args)} argument(s)")
            ident, names = mapped.type, mapped.ports
        else:
            ident, names = action_id(label), tuple(f"arg{k}" for k in range(1, len(args) + 1))
        values = [_port_value(a) for a in args]
        ports = [] if None in values else list(zip(names, values))
        declared = self.actions.setdefault(ident, {})
        for k, name in enumerate(names[:len(args)], 1):
            declared.setdefault(name, f"argument {k} of {ident}")
        return ident, ports

    def _tree_id(self, label: Term) -> str:
        base = re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9_]", "_", term_to_text(label))).strip("_") or "task"
        if not re.match(r"[A-Za-z_]", base):
            base = "t_" + base
        name, n = base, 1
        while name in self.used_ids:
            n += 1
            name = f"{base}_{n}"
        self.used_ids.add(name)
        return name

    def guards(self, node: Behaviour, counters: tuple[str, ...] = ()) -> list[tuple[str, str]]:
        """`_while="PRE" _skipIf="acted || (POST) || failures__N > R ..."`: active, not yet
        acted this tick, and none of its actions inhibited (failed more than R times in a row)."""
        inhibited = "".join(f" || {c} > {self.retries}" for c in counters)
        return [("_while", to_script(node.pre)), ("_skipIf", f"{ACTED} || {_operand(node.post)}{inhibited}")]

    def counter(self) -> str:
        self.counters.append(f"{FAILURES}{len(self.counters) + 1}")
        return self.counters[-1]

    def element(self, node: Behaviour, indent: str) -> list[str]:
        """The lines of the element that stands for `node` where its parent lists it."""
        label = term_to_text(node.label)
        if node.children:
            tree_id = self.subtree(node)
            pairs = [("ID", tree_id), ("name", label), ("_autoremap", "true"), *self.guards(node),
                     *_meta(node, port_style=True)]
            return [f"{indent}<SubTree{_attrs(pairs)}/>"]
        steps = steps_of(node)
        # A leaf that acts, succeeding or failing, is this tick's decision (`acted`); a failure
        # counts against the action that failed and the next tick retries it (the executive's
        # rule), until it has failed more than R times in a row: then it is skipped (inhibited).
        if steps == ((node.label, node.post),):
            ident, ports = self.action(node.label)
            n = self.counter()
            pairs = [("name", label), *ports, *self.guards(node, (n,)), ("_onSuccess", f"{ACTED} := true; {n} := 0"),
                     ("_onFailure", f"{ACTED} := true; {n} += 1"), *_meta(node, port_style=False)]
            return [f"{indent}<{ident}{_attrs(pairs)}/>"]
        counters = tuple(self.counter() for _ in steps)
        decided = [("_onSuccess", f"{ACTED} := true"), ("_onFailure", f"{ACTED} := true")]
        lines = [f"{indent}<Sequence{_attrs([('name', label), *self.guards(node), *decided, *_meta(node, False)])}>"]
        previous = None
        for (action, post), n in zip(steps, counters):
            ident, ports = self.action(action)
            # A constituent runs only once the one before it holds its post-condition
            # (`_while`), so a robot that reports success without achieving it does not
            # run the next action; the merged leaf ends and is tried again. An inhibited
            # constituent is skipped by itself (`_skipIf`), and with it those that wait for
            # its post-condition: all skipped, the Sequence is SKIPPED and did not act. Its
            # post-condition may still come from elsewhere (another merged leaf sharing the
            # action), and then the rest runs: the executive's split leaf, after `decompress`.
            after = [] if previous is None else [("_while", to_script(previous))]
            pairs = [("name", term_to_text(action)), *ports, *after,
                     ("_skipIf", f"{_operand(post)} || {n} > {self.retries}"),
                     ("_onSuccess", f"{n} := 0"), ("_onFailure", f"{n} += 1")]
            lines.append(f"{indent}  <{ident}{_attrs(pairs)}/>")
            previous = post
        lines.append(f"{indent}</Sequence>")
        return lines

    def subtree(self, node: Behaviour) -> str:
        """The ID of the BehaviorTree holding `node`'s children (shared by identical ones)."""
        body = ["    <Sequence>"]
        for child in node.children:
            body += self.element(child, "      ")
        body.append("    </Sequence>")
        text = "\n".join(body)
        found = self.trees.get(text)
        if found is None:
            found = self.trees[text] = self._tree_id(node.label)
            self.bodies.append((found, text))
        return found


def export_btcpp(tree: Behaviour, initial=None, title: str = "", retries: int = defaults.RETRIES,
                 node_types: NodeTypes | None = None, nodes: LabelNodes | None = None) -> str:
    """A BT.CPP v4 document that runs `tree` (original or compressed), its failed actions retried
    `retries` times, parsed back before it is returned: it must import as `tree` and `initial`
    (Unquotable: refused). `initial` None: the robot writes the state (every literal's blackboard
    entry) before the first tick; atoms: the tree's first tick writes that state itself.
    `node_types`: functor -> NodeType, the node type and port names of its actions; `nodes`:
    label -> (node type, ports), an action's own node as an imported tree wrote it (bt_node/3),
    unless node_types maps its functor."""
    node_types = dict(node_types or {})
    check_node_types(node_types)
    nodes = dict(nodes or {})
    check_node_types({term_to_text(k): NodeType(t, tuple(p for p, _ in ports)) for k, (t, ports) in nodes.items()})
    text = _document(tree, initial, title, retries, node_types, nodes)
    try:
        back = import_btcpp(text, "<export>")
    except SchemalogError as err:
        raise Unquotable(f"the document does not read back: {err.message}") from None
    if back.tree != tree or set(back.initial) != set(initial or ()):
        raise Unquotable("the document does not read back as the tree exported")
    return text


def state_keys(tree: Behaviour) -> list[tuple[str, Term]]:
    """The blackboard entries the robot writes for `tree`: (key, atom), in order of appearance."""
    return [(literal_key(a), a) for a in atoms_of(tree)]


def _document(tree: Behaviour, initial, title: str, retries: int, node_types: NodeTypes, nodes: LabelNodes) -> str:
    """The text of export_btcpp's document."""
    if not isinstance(retries, int) or isinstance(retries, bool) or retries < 0:
        raise ValueError(f"retries must be an int, 0 or more, not {retries!r}")
    exporter = _Exporter(tree, retries, node_types, nodes)
    task = exporter.element(tree, "            ")
    assignments = [f"{ACTED} := false"] + [f"{c} := 0" for c in exporter.counters]
    if initial is not None:
        true_atoms = set(initial)
        atoms = list(dict.fromkeys([*atoms_of(tree), *initial]))
        assignments += [f"{literal_key(a)} := {'true' if a in true_atoms else 'false'}" for a in atoms]
    keys = ", ".join(f"{k} = {term_to_text(a)}" for k, a in state_keys(tree))
    perception = ("the robot writes these boolean blackboard entries before the first tick, "
                  "and again whenever they change: " + (keys or "none") if initial is None else
                  "the initial state is written by the first tick (the Script \"initial state\"); "
                  "the robot then keeps these boolean entries current: " + (keys or "none"))
    lines = ['<?xml version="1.0" encoding="UTF-8"?>']
    if title:
        lines.append(xml_comment(title))
    lines += [xml_comment(perception),
              f'<root BTCPP_format="4" main_tree_to_execute="{MAIN_TREE}">',
              f'  <BehaviorTree ID="{MAIN_TREE}">',
              '    <Sequence name="run">',
              f'      <Script name="initial state" code={xml_attribute("; ".join(assignments))}/>',
              '      <ForceSuccess name="until no decision is taken">',
              '        <KeepRunningUntilFailure name="one decision per tick">',
              '          <Sequence name="decision">',
              f'            <Script name="decide" code="{ACTED} := false"/>',
              '            <ForceSuccess name="a failed action is a decision too">',
              *["  " + t for t in task],
              '            </ForceSuccess>',
              f'            <ScriptCondition name="decided" code="{ACTED}"/>',
              '          </Sequence>',
              '        </KeepRunningUntilFailure>',
              '      </ForceSuccess>',
              f'      <ScriptCondition name="accomplished" code={xml_attribute(to_script(tree.post))}/>',
              '    </Sequence>',
              '  </BehaviorTree>']
    for tree_id, body in exporter.bodies:
        lines += [f'  <BehaviorTree ID="{tree_id}">', body, '  </BehaviorTree>']
    lines.append('  <TreeNodesModel>')
    for ident, ports in exporter.actions.items():
        if not ports:
            lines.append(f'    <Action ID="{ident}"/>')
            continue
        lines.append(f'    <Action ID="{ident}">')
        lines += [f'      <input_port name="{port}" type="std::string">{text}</input_port>'
                  for port, text in ports.items()]
        lines.append('    </Action>')
    lines += ['  </TreeNodesModel>', '</root>', '']
    return "\n".join(lines)


def action_ids(xml: str) -> list[str]:
    """The action node types an exported document declares (what a runtime must register)."""
    return re.findall(r'<Action ID="([^"]+)"/?>', xml.split("<TreeNodesModel>", 1)[-1])


def without_ports(xml: str) -> str:
    """An exported document with its actions' ports taken out, for a runtime that can register
    actions but not declare their ports (behaviortreepy 0.1.4): BT.CPP refuses an XML port its
    node type does not provide. The action's name still holds the label, arguments included."""
    body, marker, model = xml.partition("  <TreeNodesModel>")
    ports = set(re.findall(r'<input_port name="([^"]+)"', model))
    if not ports:
        return xml
    types = set(action_ids(xml))

    def strip(m: re.Match) -> str:
        # `<Type a="..." b='...' .../>`: attribute by attribute, each value in its own quotes
        # (quoteattr writes '...' when the value holds a "), so no value is looked inside
        if m.group(1) not in types:
            return m.group(0)
        kept = [a.group(0) for a in _ATTRIBUTE.finditer(m.group(2)) if a.group(1) not in ports]
        return f"<{m.group(1)}{''.join(kept)}{m.group(3)}>"

    model = re.sub(r'<input_port [^>]*>[^<]*</input_port>\s*', "", model)
    model = re.sub(r'<Action ID="([^"]+)">\s*</Action>', r'<Action ID="\1"/>', model)
    return _ELEMENT.sub(strip, body) + marker + model


_ATTRIBUTE = re.compile(r'\s+([^\s=/>]+)=("[^"]*"|\'[^\']*\')')
_ELEMENT = re.compile(r'<([A-Za-z_][A-Za-z0-9_]*)((?:\s+[^\s=/>]+=(?:"[^"]*"|\'[^\']*\'))*)\s*(/?)>')


# ---------------------------------------------------------------------------
# Parsing XML safely, with positions

@dataclass
class XNode:
    """One XML element: tag, attributes, children, where it starts."""

    tag: str
    attrs: dict[str, str]
    line: int
    column: int
    children: list["XNode"] = field(default_factory=list)
    file: str = ""

    @property
    def pos(self) -> SourcePos:
        return SourcePos(self.file, self.line, self.column)


class _Target:
    def __init__(self, parser_ref: list, file: str) -> None:
        self.ref, self.file = parser_ref, file
        self.stack: list[XNode] = []
        self.root: XNode | None = None
        self.count = 0

    def start(self, tag, attrs):
        p = self.ref[0].parser
        node = XNode(tag, dict(attrs), p.CurrentLineNumber, p.CurrentColumnNumber + 1, file=self.file)
        self.count += 1
        where = SourcePos(self.file, node.line, node.column)
        if self.count > MAX_XML_ELEMENTS:
            raise SchemalogError(f"the XML has more than {MAX_XML_ELEMENTS:,} elements: not a behaviour "
                                 f"tree schemalog imports (Nav2's largest trees have about a hundred)", where)
        if len(self.stack) >= MAX_XML_NESTING:
            raise SchemalogError(f"the XML nests deeper than {MAX_XML_NESTING} elements", where)
        if self.stack:
            self.stack[-1].children.append(node)
        else:
            self.root = node
        self.stack.append(node)

    def end(self, tag):
        self.stack.pop()

    def data(self, data):
        pass

    def close(self):
        return self.root


class MalformedXML(SchemalogError):
    """Text that is not well-formed XML; `reason` is expat's, which quotes nothing of the text."""

    def __init__(self, message: str, reason: str, pos: SourcePos, source_line: str | None = None) -> None:
        super().__init__(message, pos, source_line)
        self.reason = reason


def parse_xml(text: str, file: str) -> XNode:
    """Parse XML with defusedxml: entities and external references refused, positions kept."""
    from defusedxml import DefusedXmlException
    from defusedxml.ElementTree import DefusedXMLParser
    from xml.etree.ElementTree import ParseError

    ref: list = []
    target = _Target(ref, file)
    parser = DefusedXMLParser(target=target, forbid_dtd=False, forbid_entities=True, forbid_external=True)
    ref.append(parser)
    try:
        parser.feed(text)
        root = parser.close()
    except ParseError as err:
        line, column = err.position
        if not text.strip():
            raise MalformedXML("the file is empty: no XML element", "the file is empty",
                               SourcePos(file, 1, 1)) from None
        lines = text.splitlines()
        reason = _expat_reason(str(err))
        # expat's reasons are fixed words, but ElementTree's "undefined entity &name;" quotes the text
        bare = "undefined entity" if reason.startswith("undefined entity") else reason
        raise MalformedXML(f"malformed XML: {reason}", bare, SourcePos(file, line, column + 1),
                           source_line=lines[line - 1] if 0 < line <= len(lines) else None) from None
    except DefusedXmlException as err:
        p = parser.parser
        what = f"the entity {getattr(err, 'name', '')}" if getattr(err, "name", None) else "a DTD"
        raise SchemalogError(f"the XML declares {what}: entities are refused (they can expand without "
                             f"bound or read other files)",
                             SourcePos(file, p.CurrentLineNumber, p.CurrentColumnNumber + 1)) from None
    if root is None:
        raise SchemalogError("the XML has no element", SourcePos(file, 1, 1))
    return root


def read_included(parse, text: str, file: str, path: str, via: SourcePos):
    """The root that `parse(text, file)` makes of a file an <include path=...> at `via` names,
    or an error that gives its place and what it is not, never its text: BT.CPP follows any
    path, so the file may be any the process can read. Once it is a <root> document, it is a
    behaviour tree, and messages about it quote it as they quote any tree."""
    try:
        root = parse(text, file)
    except MalformedXML as err:
        pos, what = err.pos, f"not XML ({err.reason})"
    except SchemalogError as err:
        pos, what = err.pos, "not XML as BT.CPP reads it"
    else:
        if root.tag == "root":
            return root
        pos, what = root.pos, "XML, but not a BT.CPP document (its root element is not <root>)"
    raise unquoted(pos or SourcePos(file, 1, 1), what,
                   f"it is read through <include path=\"{visible(path)}\"> at {via}") from None


def _expat_reason(text: str) -> str:
    return re.sub(r": line \d+, column \d+$", "", text)


# ---------------------------------------------------------------------------
# Import

@dataclass(frozen=True)
class Imported:
    """A task tree read from BT.CPP XML, with the initial state its Script sets."""

    tree: Behaviour
    initial: tuple[Term, ...] = ()
    notes: tuple[str, ...] = ()
    includes: tuple[str, ...] = ()     # the files read through <include>, in the order read
    # Each action's node type and ports as the document wrote them, by (label, post-condition):
    # what an export needs to give the robot its own nodes back (`bt_node/3` in converted knowledge).
    nodes: dict[tuple[Term, Condition], tuple[str, tuple[tuple[str, str], ...]]] = field(default_factory=dict)


def import_btcpp(text: str, file: str = "<xml>", read=None) -> Imported:
    """Read a BT.CPP v4 document into a task tree (see the module docstring for what has a meaning);
    `read(path) -> str` reads the files it includes (<include path="...">), relative to `file`."""
    return _Importer(parse_xml(text, file), file, read).run()


def _snake(name: str) -> str:
    s = re.sub(r"(?<=[a-z0-9])([A-Z])", r"_\1", name)
    s = re.sub(r"(?<=[A-Z])([A-Z][a-z])", r"_\1", s)
    return re.sub(r"[^a-z0-9_]", "_", s.lower()).strip("_") or "node"


def _value_term(value: str) -> Term:
    from ..logic.opread import parse_term

    try:
        t = parse_term(value, "<port>")
        if isinstance(t, (Atom, Int, Float)):
            return t
    except SchemalogError:
        pass
    return Str(value) if not re.fullmatch(r"[a-z][A-Za-z0-9_]*", value) else Atom(value)


class _Importer:
    def __init__(self, root: XNode, file: str, read=None) -> None:
        self.root, self.file, self.read = root, file, read
        self.trees: dict[str, XNode] = {}
        self.where: dict[str, SourcePos] = {}
        self.conditions: set[str] = set()
        self.on_path: list[str] = []
        self.used_posts: dict[Term, int] = {}
        self.count = 0
        self.includes: list[str] = []
        self.nodes: dict = {}
        self.model_ports: dict[str, set[str]] = {}     # node type -> the ports its TreeNodesModel declares

    def _record(self, label: Term, post: Condition, node: XNode, skip: set[str] = frozenset()) -> None:
        """Keep the node type and literal ports an action was written with."""
        ident = node.attrs.get("ID", node.tag) if node.tag == "Action" else node.tag
        ports = tuple((k, v) for k, v in node.attrs.items()
                      if not (k in skip or k.startswith("_") or k in ("name", "ID")))
        self.nodes.setdefault((label, post), (ident, ports))

    def pos(self, node: XNode) -> SourcePos:
        return SourcePos(node.file or self.file, node.line, node.column)

    def fail(self, node: XNode, message: str):
        raise SchemalogError(message, self.pos(node))

    def run(self) -> Imported:
        root = self.root
        self._collect(root, self.file, [self.file])
        if not self.trees:
            self.fail(root, "the document defines no <BehaviorTree>")
        main = root.attrs.get("main_tree_to_execute") or next(iter(self.trees))
        if main not in self.trees:
            self.fail(root, f"main_tree_to_execute=\"{main}\" names no BehaviorTree of the file")
        body = self.trees[main].children[0]
        scaffold = self._scaffold(body) if main == MAIN_TREE else None
        if scaffold is not None:
            state_script, task_node = scaffold
            initial = tuple(self._assignments(state_script, want_initial=True))
            self.on_path.append(main)
            tree = self.exported(task_node)
            return Imported(tree, initial, includes=tuple(self.includes), nodes=self.nodes)
        self.on_path.append(main)
        tree = self.plain(body, cond.TRUE, None)
        return Imported(tree, (), includes=tuple(self.includes), nodes=self.nodes)

    def _collect(self, root: XNode, file: str, chain: list[str]) -> None:
        """Register the BehaviorTrees of `root` (a document read from `file`) and of its includes."""
        fail = self.fail
        if root.tag != "root":
            fail(root, f"a BT.CPP document starts with <root BTCPP_format=\"4\">, not <{root.tag}>")
        version = root.attrs.get("BTCPP_format")
        if version not in (None, "4"):
            fail(root, f"BTCPP_format=\"{version}\": schemalog reads version 4")
        for child in root.children:
            if child.tag == "BehaviorTree":
                tree_id = child.attrs.get("ID")
                if not tree_id:
                    fail(child, "a <BehaviorTree> needs an ID")
                if tree_id in self.trees:
                    fail(child, f"BehaviorTree {tree_id} is defined twice (first at {self.where[tree_id]})")
                if len(child.children) != 1:
                    fail(child, f"BehaviorTree {tree_id} must hold exactly one node, not {len(child.children)}")
                self.trees[tree_id] = child
                self.where[tree_id] = self.pos(child)
            elif child.tag == "TreeNodesModel":
                for model in child.children:
                    if model.tag == "Condition" and model.attrs.get("ID"):
                        self.conditions.add(model.attrs["ID"])
                    if model.attrs.get("ID"):
                        self.model_ports.setdefault(model.attrs["ID"], set()).update(
                            p.attrs["name"] for p in model.children if p.attrs.get("name"))
            elif child.tag == "include":
                path = child.attrs.get("path")
                if not path:
                    fail(child, "an <include> needs path=\"...\"")
                if "ros_pkg" in child.attrs:
                    fail(child, "<include ros_pkg=...>: schemalog finds no ROS packages; give a path")
                if self.read is None:
                    fail(child, f"<include path={path!r}>: includes are read only from files")
                import os

                from ..inputs import not_regular
                target = os.path.normpath(os.path.join(os.path.dirname(file), path))
                if target in chain:
                    fail(child, f"recursive include: {' -> '.join([*chain, target])}")
                what = not_regular(target)
                if what is not None:            # a FIFO would wait for a writer without end
                    fail(child, f"<include path={path!r}>: names {what}, not a file: BT.CPP includes files")
                self.includes.append(target)
                try:
                    text = self.read(target)
                except SchemalogError as err:
                    fail(child, f"<include path={path!r}>: {err.message}")
                self._collect(read_included(parse_xml, text, target, path, self.pos(child)), target,
                              [*chain, target])
            else:
                fail(child, f"unknown element <{child.tag}> under <root>")

    # -- schemalog's own form -----------------------------------------------------
    def _scaffold(self, body: XNode):
        """(initial-state Script, task element) of an exported run tree, else None."""
        try:
            script, forced, accomplished = body.children
            (loop,) = forced.children
            (decision,) = loop.children
            reset, task, decided = decision.children
            if task.tag == "ForceSuccess" and task.attrs.get("name") == "a failed action is a decision too":
                (task,) = task.children
        except ValueError:
            return None
        shape = [(body, "Sequence"), (script, "Script"), (forced, "ForceSuccess"),
                 (loop, "KeepRunningUntilFailure"), (decision, "Sequence"), (reset, "Script"),
                 (decided, "ScriptCondition"), (accomplished, "ScriptCondition")]
        if any(n.tag != tag for n, tag in shape):
            return None
        return script, task

    def _assignments(self, script: XNode, want_initial: bool) -> list[Term]:
        code = script.attrs.get("code", "")
        if want_initial:                     # `failures__1 := 0; ...`: the runtime's counters
            code = ";".join(s for s in code.split(";") if not _COUNTER_RESET.fullmatch(s))
        try:
            pairs = parse_assignments(code)
        except ScriptError as err:
            self.fail(script, f"Script: {err}")
        return [key_atom(k) for k, v in pairs if v and k != ACTED] if want_initial else pairs

    def _cond(self, node: XNode, attr: str, acted: bool = False) -> Condition:
        try:
            return parse_script_condition(node.attrs[attr], acted)
        except ScriptError as err:
            self.fail(node, f"{attr}: {err}")

    def _label(self, node: XNode, text: str) -> Term:
        from ..logic.opread import parse_term

        try:
            return parse_term(text, "<name>")
        except SchemalogError as err:
            self.fail(node, f"name={text!r} is not a term: {err.message}")

    def _origins(self, node: XNode) -> tuple[Origin, ...]:
        from ..logic.opread import parse_term

        text = node.attrs.get("_origins")
        if text is None:
            return ()
        try:
            items, _ = list_items(parse_term(text, "<origins>"))
            return tuple(_origin(t) for t in items)
        except (SchemalogError, ValueError, cond.NotACondition) as err:
            self.fail(node, f"_origins: {getattr(err, 'message', err)}")

    def _common(self, node: XNode, port_style: bool) -> dict:
        from ..logic.opread import parse_term

        a = node.attrs
        if "name" not in a or "_while" not in a or "_skipIf" not in a:
            self.fail(node, f"<{node.tag}> in a schemalog run tree needs name, _while and _skipIf")
        # `acted || (POST) || failures__3 > 2 || ...`: the failure counters are the runtime's
        skip_text = _INHIBITED.sub("", a["_skipIf"])
        try:
            skip = parse_script_condition(skip_text, acted=True)
        except ScriptError as err:
            self.fail(node, f"_skipIf: {err}")
        if not (isinstance(skip, cond.Or) and len(skip.items) == 2 and skip.items[0] == ACTED_LIT):
            self.fail(node, f"_skipIf must read \"{ACTED} || POST\", not {a['_skipIf']!r}")
        pre = self._cond(node, "_while")
        releaser, context = pre, cond.TRUE
        if "_context" in a:
            context, releaser = self._cond(node, "_context"), self._cond(node, "_releaser")
        prefix = "" if port_style else "_"
        weight = a.get(prefix + "importance")
        importance = DEFAULT_IMPORTANCE
        if weight is not None:
            t = _value_term(weight)
            if not isinstance(t, (Int, Float)):
                self.fail(node, f"importance={weight!r} is not a number")
            importance = t.value
        try:
            objects = tuple(list_items(parse_term(a.get("_objects", "[]"), "<objects>"))[0])
        except SchemalogError as err:
            self.fail(node, f"_objects: {err.message}")
        return dict(label=self._label(node, a["name"]), agent=agent_of(a.get(prefix + "agent", DEFAULT_AGENT)),
                    objects=objects, releaser=releaser, post=skip.items[1], context=context,
                    importance=importance, origins=self._origins(node), source=self.pos(node))

    def exported(self, node: XNode) -> Behaviour:
        self._count(node)
        if node.tag == "SubTree":
            tree_id = node.attrs.get("ID", "")
            body = self._subtree_body(node, tree_id)
            if body.tag != "Sequence":
                self.fail(body, f"BehaviorTree {tree_id} of a schemalog run tree holds a Sequence")
            children = tuple(self.exported(c) for c in body.children)
            self.on_path.pop()
            return Behaviour(children=children, **self._common(node, port_style=True))
        if node.tag == "Sequence":
            fields = self._common(node, port_style=False)
            for step in node.children:
                self._count(step)
            labels = [self._label(s, s.attrs.get("name", "")) for s in node.children]
            if labels != [o.label for o in fields["origins"]]:
                self.fail(node, "a merged behaviour's actions must be its provenance (_origins), in order")
            for step, origin in zip(node.children, fields["origins"]):
                self._record(origin.label, origin.post, step)
            return Behaviour(**fields)
        if node.tag in BUILTIN_NODES:
            self.fail(node, f"<{node.tag}> is not part of a schemalog run tree")
        fields = self._common(node, port_style=False)
        origins = fields["origins"]
        self._record(origins[0].label if len(origins) == 1 else fields["label"], fields["post"], node)
        return Behaviour(**fields)

    def _subtree_body(self, node: XNode, tree_id: str) -> XNode:
        if tree_id not in self.trees:
            self.fail(node, f"SubTree {tree_id!r} is never defined (no <BehaviorTree ID=\"{tree_id}\">)")
        if len(self.on_path) > MAX_XML_NESTING:
            self.fail(node, f"SubTrees nest deeper than {MAX_XML_NESTING} levels")
        if tree_id in self.on_path:
            cycle = " -> ".join([*self.on_path[self.on_path.index(tree_id):], tree_id])
            self.fail(node, f"recursive SubTree: {cycle}")
        self.on_path.append(tree_id)
        return self.trees[tree_id].children[0]

    def _count(self, node: XNode) -> None:
        self.count += 1
        if self.count > MAX_XML_ELEMENTS:
            self.fail(node, f"the tree has more than {MAX_XML_ELEMENTS:,} nodes once its SubTrees are expanded")

    # -- anyone's BT.CPP ----------------------------------------------------------
    def _post_of(self, label: Term) -> Condition:
        """`label.done`; a label used again gets done2, done3 ... so each occurrence is its own."""
        n = self.used_posts.get(label, 0) + 1
        self.used_posts[label] = n
        prop = Atom("done" if n == 1 else f"done{n}")
        return cond.Lit(Struct(".", (label, prop)))

    def _ports(self, node: XNode, skip: set[str]) -> list[Term]:
        args = []
        for k, v in node.attrs.items():
            if k in skip or k.startswith("_") or k == "name" or k == "ID":
                continue
            if "{" in v:
                self.fail(node, f"port {k}=\"{v}\" is remapped to a blackboard entry: only literal ports have "
                                f"a schema meaning (a sub-task's arguments)")
            args.append(_value_term(v))
        return args

    def _plain_label(self, node: XNode, ident: str, skip: set[str] = frozenset(),
                     meta: set[str] = frozenset({"importance", "agent"})) -> Term:
        args = self._ports(node, skip | meta)
        name = node.attrs.get("name")
        if name:
            from ..logic.opread import parse_term
            try:
                t = parse_term(name, "<name>")
                if not args and isinstance(t, (Atom, Struct)) and is_ground(t):
                    return t
            except SchemalogError:
                pass
        functor = _snake(ident)
        return Struct(functor, tuple(args)) if args else Atom(functor)

    def _guard(self, node: XNode) -> Condition:
        """What `_while` and `_skipIf` add to a node's releaser."""
        parts = []
        if "_while" in node.attrs:
            parts.append(self._cond(node, "_while"))
        if "_skipIf" in node.attrs:
            parts.append(cond.negate(self._cond(node, "_skipIf")))
        for attr in ("_successIf", "_failureIf", "_onSuccess", "_onFailure", "_onHalted", "_post"):
            if attr in node.attrs:
                self.fail(node, f"{attr} on an imported node: only _while and _skipIf (releasers) have a "
                                f"schema meaning outside schemalog's own run tree")
        return cond.conjoin(parts) if parts else cond.TRUE

    def _condition_of(self, node: XNode) -> Condition | None:
        """The condition a condition node checks, or None when `node` is not one."""
        if node.tag == "ScriptCondition":
            return self._cond(node, "code")
        ident = node.attrs.get("ID") if node.tag == "Condition" else node.tag
        if node.tag == "Condition" or ident in self.conditions:
            if node.children:
                self.fail(node, f"condition {ident} has children")
            return cond.Lit(self._plain_label(node, ident or "condition"))
        return None

    def plain(self, node: XNode, releaser: Condition, weight_node: XNode | None) -> Behaviour:
        """A node of anyone's tree as a behaviour released by `releaser` (and its own guards)."""
        self._count(node)
        tag = node.tag
        releaser = cond.conjoin([releaser, self._guard(node)])
        if tag in ("Fallback", "ReactiveFallback"):
            return self._post_condition_pattern(node, releaser)
        if tag in REFUSED:
            self.fail(node, f"<{tag}> has no schema meaning: {REFUSED[tag]}")
        if tag == "Precondition":
            if "else" in node.attrs and node.attrs["else"] not in ("SKIPPED", "FAILURE"):
                self.fail(node, f"Precondition else=\"{node.attrs['else']}\": only SKIPPED or FAILURE (not released) "
                                f"have a schema meaning")
            if "if" not in node.attrs or len(node.children) != 1:
                self.fail(node, "a Precondition needs if=\"...\" and exactly one child")
            return self.plain(node.children[0], cond.conjoin([releaser, self._cond(node, "if")]), None)
        if tag == "SubTree":
            tree_id = node.attrs.get("ID", "")
            body = self._subtree_body(node, tree_id)
            named = "name" in node.attrs or self._ports(node, {"_autoremap", "importance", "agent"})
            inner = self.plain(body, cond.TRUE, None)
            self.on_path.pop()
            if named or "name" not in body.attrs:
                # The SubTree names the behaviour (its name, or its ID and literal ports).
                return self._with(inner, self._plain_label(node, tree_id, {"_autoremap"}), releaser, node)
            from dataclasses import replace
            return replace(inner, releaser=releaser, importance=self._weight(node),
                           agent=agent_of(node.attrs["agent"]) if "agent" in node.attrs else inner.agent, source=self.pos(node))
        if tag in ("Sequence", "SequenceWithMemory", "ReactiveSequence", "Parallel", "ParallelAll"):
            if not node.children:
                self.fail(node, f"<{tag}> needs at least one child")
            for k, v in node.attrs.items():
                if not k.startswith("_") and k != "name" and tag.startswith("Parallel") and \
                        k in ("success_count", "failure_count", "max_failures"):
                    if k == "success_count" and v not in ("-1", str(len(node.children))):
                        self.fail(node, f"Parallel {k}=\"{v}\": a schema behaviour is accomplished when all its "
                                        f"sub-behaviours are (success_count=-1)")
            label = self._plain_label(node, tag.lower() if "name" not in node.attrs else node.attrs["name"],
                                      {"success_count", "failure_count", "max_failures"})
            children: list[Behaviour] = []
            guard = cond.TRUE      # conditions met so far (a ReactiveSequence re-checks them)
            previous = cond.TRUE   # the previous sibling's post (Sequence order)
            for child in node.children:
                c = self._condition_of(child)
                if c is not None:
                    guard = cond.conjoin([guard, c, self._guard(child)])
                    continue
                own = cond.conjoin([guard, previous]) if not tag.startswith("Parallel") else guard
                built = self.plain(child, own, None)
                children.append(built)
                if not tag.startswith("Parallel"):
                    previous = built.post
            if not children:
                self.fail(node, f"<{tag}> holds only conditions: nothing for them to release")
            return Behaviour(label=label, objects=_objects(label), releaser=releaser, post=self._post_of(label),
                             children=tuple(children), importance=self._weight(node), agent=agent_of(node.attrs.get("agent", DEFAULT_AGENT)),
                             source=self.pos(node))
        if tag == "Script":
            try:
                pairs = parse_assignments(node.attrs.get("code", ""))
            except ScriptError as err:
                self.fail(node, f"Script: {err}")
            lits = [cond.Lit(key_atom(k), v) for k, v in pairs]
            label = self._label(node, node.attrs["name"]) if "name" in node.attrs else \
                Struct("script", (Int(node.line),))
            return Behaviour(label=label, objects=(), releaser=releaser,
                             post=cond.conjoin(lits) if lits else cond.TRUE, source=self.pos(node))
        c = self._condition_of(node)
        if c is not None:
            self.fail(node, "a condition must come before the behaviours it releases in a Sequence")
        if tag in BUILTIN_NODES:
            self.fail(node, f"<{tag}> has no schema meaning here")
        if node.children:
            self.fail(node, f"unknown node type <{tag}> with children: schemalog reads Sequence, "
                            f"SequenceWithMemory, ReactiveSequence, Parallel, Precondition and SubTree")
        ident = node.attrs.get("ID", tag) if tag == "Action" else tag
        # `importance` and `agent` are the schema's, unless the node's model declares them as
        # its own ports (a robot's `agent` port): then they are ports like any other.
        meta = {"importance", "agent"} - self.model_ports.get(ident, set())
        label = self._plain_label(node, ident, meta=meta)
        post = self._post_of(label)
        self._record(label, post, node, meta)
        return Behaviour(label=label, objects=_objects(label), releaser=releaser, post=post,
                         importance=self._weight(node) if "importance" in meta else DEFAULT_IMPORTANCE,
                         agent=agent_of(node.attrs.get("agent", DEFAULT_AGENT)) if "agent" in meta else DEFAULT_AGENT,
                         source=self.pos(node))

    def _post_condition_pattern(self, node: XNode, releaser: Condition) -> Behaviour:
        """`<Fallback><IsDoorOpen/><OpenDoor/></Fallback>`: conditions first, then one behaviour,
        is that behaviour with the conditions (any of them) as its post-condition: it runs
        only while they do not hold, the schema's "active while its goal is not achieved"."""
        conditions = []
        for child in node.children:
            c = self._condition_of(child)
            if c is None:
                break
            conditions.append(cond.conjoin([c, self._guard(child)]))
        rest = node.children[len(conditions):]
        if not conditions or len(rest) != 1:
            self.fail(node, f"<{node.tag}> has a schema meaning only as the post-condition pattern, conditions "
                            f"then one behaviour (<{node.tag}><IsDoorOpen/><OpenDoor/></{node.tag}>); "
                            f"otherwise it tries alternatives after a failure, which schemas do not model")
        from dataclasses import replace
        inner = self.plain(rest[0], releaser, None)
        goal = cond.Or(tuple(conditions)) if len(conditions) > 1 else conditions[0]
        if (inner.label, inner.post) in self.nodes:           # the action keeps its node under its new goal
            self.nodes.setdefault((inner.label, goal), self.nodes[(inner.label, inner.post)])
        return replace(inner, post=goal, source=self.pos(node))

    def _weight(self, node: XNode):
        v = node.attrs.get("importance")
        if v is None:
            return DEFAULT_IMPORTANCE
        t = _value_term(v)
        if not isinstance(t, (Int, Float)):
            self.fail(node, f"importance={v!r} is not a number")
        return t.value

    def _with(self, inner: Behaviour, label: Term, releaser: Condition, node: XNode) -> Behaviour:
        from dataclasses import replace
        post = self._post_of(label)
        return replace(inner, label=label, objects=_objects(label), releaser=releaser, post=post,
                       importance=self._weight(node), agent=agent_of(node.attrs["agent"]) if "agent" in node.attrs else inner.agent, source=self.pos(node))


def _objects(label: Term) -> tuple[Term, ...]:
    """What an imported behaviour acts on: its atom arguments (a port `angle="60"` is no object)."""
    return tuple(a for a in (label.args if isinstance(label, Struct) else ()) if isinstance(a, Atom))


def _origin(t: Term) -> Origin:
    if not (isinstance(t, Struct) and t.name == "origin" and len(t.args) == 6):
        raise ValueError(f"expected origin(Label, Releaser, Post, Importance, Position, Slot), not {term_to_text(t)}")
    label, releaser, post, weight, position, slot = t.args
    if not (isinstance(weight, (Int, Float)) and isinstance(position, Int) and isinstance(slot, Int)):
        raise ValueError(f"importance, position and slot must be numbers in {term_to_text(t)}")
    return Origin(label, cond.from_term(releaser), cond.from_term(post), weight.value, position.value, slot.value)


# ---------------------------------------------------------------------------
# Running in BehaviorTree.CPP

def action_posts(original: Behaviour) -> dict[str, tuple[Term, list[Condition]]]:
    """Each action's text -> its label and the posts of its occurrences in `original`, in order."""
    out: dict[str, tuple[Term, list[Condition]]] = {}
    for node in walk(original):
        if not node.children:
            entry = out.setdefault(node.name, (node.label, []))
            if node.post not in entry[1]:
                entry[1].append(node.post)
    return out


def performed(by_name, text: str, world) -> tuple[Term, Condition]:
    """The label and post-condition of the action a runtime performs by name. An action used with
    several post-conditions (an imported `OpenGripper` done four times) performs its first
    occurrence not yet accomplished: a runtime's callback knows the name, the world knows the rest."""
    label, posts = by_name[text]
    return label, next((p for p in posts if not world.holds(p)), posts[0])


@dataclass
class BtRun:
    """A run of an exported tree in BT.CPP: how it ended, the actions, the ticks."""

    status: str             # "completed", "stuck" or "tick limit"
    trace: list[Term]       # the actions performed, in order
    ticks: int
    seconds: float = 0.0            # ticking, the actions' callbacks included
    action_seconds: float = 0.0     # of which in the callbacks (the emulated robot and world)
    tick_seconds: tuple[float, ...] = ()   # each tick's own work, its callbacks left out
    failed: list[Term] = field(default_factory=list)   # the commands the robot failed, in order

    @property
    def control_seconds(self) -> float:
        """The runtime's own work: ticking the tree, its guards and scripts."""
        return self.seconds - self.action_seconds


def run_btcpp(xml: str, original: Behaviour, initial=(), max_ticks: int | None = None,
              failures: dict[Term, int | None] | None = None) -> BtRun:
    """Tick `xml` in BT.CPP to the end; each action performs in the World of `original`, whose
    state the robot writes to the blackboard before the first tick and after each action.
    `failures`: the robot fails these actions' commands that many times (None: always)."""
    import time

    import behaviortreepy as bt

    from ..run.execute import RobotManager
    from ..run.world import World

    world = World(original, initial)
    robot = RobotManager(failures=failures)
    by_name = action_posts(original)
    trace: list[Term] = []
    failed: list[Term] = []
    factory = bt.BehaviorTreeFactory()
    board: list = []

    spent = [0.0]

    def perform(node) -> object:
        began = time.perf_counter()
        label, post = performed(by_name, node.name(), world)
        if not robot.command(label, None):
            failed.append(label)
            spent[0] += time.perf_counter() - began
            return bt.NodeStatus.FAILURE
        change = world.perform(post)
        trace.append(label)
        bb = board[0]
        for atom in change.added:
            bb.set_bool(literal_key(atom), True)
        for atom in change.removed:
            bb.set_bool(literal_key(atom), False)
        spent[0] += time.perf_counter() - began
        return bt.NodeStatus.SUCCESS

    for ident in action_ids(xml):
        factory.register_simple_action(ident, perform)
    tree = factory.create_tree_from_text(without_ports(xml))
    board.append(tree.root_blackboard())
    for atom in dict.fromkeys([*atoms_of(original), *world.atoms]):     # the robot's perception
        board[0].set_bool(literal_key(atom), atom in world)
    limit = max_ticks if max_ticks is not None else 4 * sum(1 for n in walk(original) if not n.children) + 8
    limit += (defaults.RETRIES + 1) * sum((v if v is not None else 1) for v in (failures or {}).values())
    started = time.perf_counter()
    status = bt.NodeStatus.RUNNING
    ticks = 0
    each = []
    while status == bt.NodeStatus.RUNNING and ticks < limit:
        before, began = spent[0], time.perf_counter()
        status = tree.tick_once()
        each.append(time.perf_counter() - began - (spent[0] - before))
        ticks += 1
    seconds = time.perf_counter() - started
    outcome = ("completed" if status == bt.NodeStatus.SUCCESS else
               "stuck" if status == bt.NodeStatus.FAILURE else "tick limit")
    return BtRun(outcome, trace, ticks, seconds, spent[0], tuple(each), failed)


__all__ = ["export_btcpp", "import_btcpp", "run_btcpp", "state_keys", "NodeType", "without_ports", "Imported", "BtRun", "literal_key", "key_atom",
           "to_script", "parse_script_condition", "parse_assignments", "ScriptError", "parse_xml",
           "action_id", "action_ids", "steps_of", "atoms_of", "MAIN_TREE"]
