"""BehaviorTree.CPP 4's tick semantics as a small-step interpreter over immutable configurations
(docs/semantics.md, "Behaviour trees (BT.CPP 4 semantics)").

    Program = program(document, rules)      the main tree with every SubTree expanded: PNodes
    PNode   = PNode(node, rule, kids, context, path)  a node, the table key of its rule, its
                                            children, the SubTree calls above it, its address
    Config  = Config(memory, pending, kinds)  between events: what the nodes remember, the
                                            outcomes the environment chose so far in this root
                                            tick, and the registrations decided so far
    kinds   = ((type, "re-ticked" | "stateful"), ...)  how an action type is registered, once a run
                                            has needed to know (see ACTION below)
    memory  = ((path, status, vars), ...)   sorted by path; only nodes that are not IDLE or keep a
                                            variable (a Sequence's child index, a Retry's count)
    Event   = Event(kind, node, outcome, label, where, ports)  kind: "tick" | "halt" | "check" | "script" |
                                            "time" | "choose"; node = (context, identity), where
                                            context is the tuple of SubTree identities above it
    Step    = Await(event, options, config) | RootTicked(status, error, node_ticks, config)

`step(program, config)` replays the current root tick from `config.memory` with the outcomes in
`config.pending` and stops at the next event (Await: the event without its outcome and the
outcomes the environment may choose; `advance(config, outcome)` is the configuration after it)
or at the end of the root tick (RootTicked: the root's status and the memory the next root tick
starts from). Events with no choice (a script, a halt) also stop, with the single option None.
Nothing else is nondeterministic: blackboard values are not interpreted, so the environment
answering the i-th event is any function of the events before it.

Node rules live in one table, RULES (type -> Rule). A user passes more in `rules=`; a type the
table does not define is opaque (docs). Each rule cites the BT.CPP 4 or Nav2 source it follows.
A document read under BT.CPP 3.8 (Document.version 3) runs under RULES_V3 (the section "BT.CPP 3.8" at the end)
instead, which reuses these rules where 3.8 behaves alike, and ticks without 4's pre- and
post-conditions (3.8's TreeNode::executeTick has none).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from enum import Enum
from types import MappingProxyType

from schemalog.bt.model import Document, Node, subtree_ports
from schemalog.bt.ports import TYPE_NAMES, convert, is_port_name
from schemalog.errors import SchemalogError


class Status(Enum):
    """A node's status as BT.CPP 4 names it (include/behaviortree_cpp/basic_types.h)."""

    IDLE = "IDLE"
    """Not ticked since its last reset: a node's resting state, never the result of a tick."""
    RUNNING = "RUNNING"
    """Still working: tick it again."""
    SUCCESS = "SUCCESS"
    """Done, and it achieved its goal."""
    FAILURE = "FAILURE"
    """Done, and it did not."""
    SKIPPED = "SKIPPED"
    """Not executed: a pre-condition (`_skipIf`, `_while`) said so; the node stays IDLE."""


IDLE, RUNNING, SUCCESS, FAILURE, SKIPPED = (Status.IDLE, Status.RUNNING, Status.SUCCESS,
                                            Status.FAILURE, Status.SKIPPED)
COMPLETED = (SUCCESS, FAILURE)
PRE_CONDITIONS = ("_failureIf", "_successIf", "_skipIf", "_while")   # PreCond's order, tree_node.h
ACTION_OUTCOMES = (SUCCESS, FAILURE, RUNNING)
CONDITION_OUTCOMES = (SUCCESS, FAILURE)


class TreeError(SchemalogError):
    """What BT.CPP throws while ticking (a child count a node refuses, an IDLE it cannot handle)."""


class NodeTickLimit(TreeError):
    """One root tick ticked more nodes than the limit (a loop that no event interrupts)."""


@dataclass(frozen=True)
class Event:
    """One observable thing a tick does: its kind, the node (context, identity), the outcome."""

    kind: str
    node: tuple
    outcome: object = None
    label: str = field(default="", compare=False)     # the node's name, for people
    where: str = field(default="", compare=False)     # file:line:column of the node, for people
    ports: tuple = field(default=(), compare=False)   # its ports in its element's order, for people


@dataclass(frozen=True)
class Config:
    """Where a run is between two events: the nodes' memory, the outcomes chosen in this tick."""

    memory: tuple = ()
    pending: tuple = ()
    kinds: tuple = ()                     # ((type, "re-ticked" | "stateful"), ...), sorted

    def with_kind(self, node_type: str, kind: str) -> "Config":
        """This configuration with `node_type`'s registration decided."""
        return Config(self.memory, self.pending, tuple(sorted(dict(self.kinds, **{node_type: kind}).items())))


@dataclass(frozen=True)
class Await:
    """The run stopped at `event` (outcome None); the environment picks one of `options`."""

    event: Event
    options: tuple
    config: Config
    key: object = field(default=None, compare=False)   # the interrupted tick as data, or None


@dataclass(frozen=True)
class RootTicked:
    """The root tick ended with `status` (or BT.CPP threw `error`), next tick from `config`."""

    status: Status | None
    error: str
    node_ticks: int
    config: Config
    events: tuple = ()
    limited: bool = False                      # error is max_node_ticks, a limit, not BT.CPP's
    kept: Config | None = None                 # completed: the memory with the root's status kept
                                               # (a parent that does not reset it: WhileDoElse's
                                               # condition, PipelineSequence's finished children)
    woken: bool = False                        # a node emitted the wake-up signal in this tick
                                               # (Tree::tickOnce then ticks the root again at once)


@dataclass(frozen=True)
class Rule:
    """How a node type ticks and halts; `literal` names the ports that must be literal numbers
    or statuses (a blackboard reference makes the node opaque)."""

    tick: Callable[["_Run", "PNode"], Status]
    halt: Callable[["_Run", "PNode"], None] | None = None
    literal: tuple[str, ...] = ()
    visit: Callable[["_Run", "PNode"], None] | None = None   # haltTree's visit, where not haltNode's


@dataclass(frozen=True)
class PNode:
    """A node of the expanded program: its rule's key, its children, the SubTree calls above it."""

    node: Node
    rule: str
    kids: tuple["PNode", ...]
    context: tuple
    path: tuple[int, ...]
    decorator: bool = False         # a BT.CPP DecoratorNode: its executeTick resets a completed child

    @property
    def identity(self) -> tuple:
        """What events record of this node: the SubTree calls above it and its own identity."""
        return (self.context, self.node.identity)


@dataclass(frozen=True)
class Program:
    """A document's main tree ready to run: expanded SubTrees and the rule table it runs with."""

    root: PNode
    rules: Mapping[str, Rule]
    passing: frozenset = frozenset()    # paths of sequences whose passed children are never ticked again
    version: int = 4                    # the BT.CPP whose executeTick runs it: 3 (3.8) or 4
    skips: bool = True                  # an opaque node may return SKIPPED (4; not 3.8, nor a 4 tree
                                        # proved against a 3.8 one: its custom nodes are 3.8's, ported)


class _Stop(Exception):
    def __init__(self, event: Event, options: tuple) -> None:
        self.event, self.options = event, options


# ---------------------------------------------------------------------------------------------
# The run of one root tick (a replay from the tick's start memory, private to step())

class _Run:
    """The mutable scratch state of one replay; step() is pure because each call makes its own."""

    def __init__(self, program: Program, config: Config, max_node_ticks: int) -> None:
        self.program = program
        self.mem: dict[tuple, list] = {p: [Status(s), dict(v)] for p, s, v in config.memory}
        self.pending = config.pending
        self.kinds = dict(config.kinds)
        self.pos = 0
        self.woken = False               # emitWakeUpSignal (src/tree_node.cpp) in this tick
        self.events: list[Event] = []
        self.node_ticks = 0
        self.max_node_ticks = max_node_ticks

    # memory
    def _slot(self, n: PNode) -> list:
        return self.mem.setdefault(n.path, [IDLE, {}])

    def status(self, n: PNode) -> Status:
        """The node's status (IDLE when never ticked or reset)."""
        return self.mem[n.path][0] if n.path in self.mem else IDLE

    def set_status(self, n: PNode, status: Status) -> None:
        """Set the node's status (TreeNode::setStatus / resetStatus)."""
        self._slot(n)[0] = status

    def get(self, n: PNode, key: str, default=0):
        """A variable the node's rule keeps between ticks."""
        return self.mem[n.path][1].get(key, default) if n.path in self.mem else default

    def put(self, n: PNode, key: str, value) -> None:
        """Keep a variable; a falsy value is the initial one and is dropped (canonical memory)."""
        slot = self._slot(n)[1]
        if value in (0, None, False, ()) and not isinstance(value, Status):
            slot.pop(key, None)
        else:
            slot[key] = value

    def freeze(self) -> tuple:
        """The memory as a canonical tuple, without what no later tick can read (Program.passing)."""
        passed = {p: v["idx"] for p in self.program.passing if p in self.mem
                  for v in (self.mem[p][1],) if v.get("idx")}
        return tuple(sorted((p, s.value, tuple(sorted(v.items()))) for p, (s, v) in self.mem.items()
                            if (s is not IDLE or v) and not (passed and _behind(p, passed))))

    def after(self) -> Config:
        """The configuration the next root tick starts from: memory and registrations."""
        return Config(self.freeze(), (), tuple(sorted(self.kinds.items())))

    def registration(self, n: PNode) -> str:
        """How the leaf's type is registered, "re-ticked" or "stateful": decided once per run, by the
        environment when no rule and no earlier event decided it (see ACTION)."""
        kind = self.kinds.get(n.node.type)
        if kind is None:
            kind = self.event("registration", n, KINDS, ("registration", n.node.type))
            self.kinds[n.node.type] = kind
        return kind

    # events
    def event(self, kind: str, n: PNode, options: tuple, identity=None):
        """Record an event of node `n`; return the environment's outcome (None for no choice)."""
        node = (() if kind == "registration" else n.context, identity if identity is not None else n.node.identity)
        shown = n.node.ports if identity is None else ()
        if self.pos < len(self.pending):
            outcome = self.pending[self.pos]
            if outcome not in options:
                raise SchemalogError(f"outcome {outcome!r} is not one of {options!r}")
            self.pos += 1
            self.events.append(Event(kind, node, outcome, n.node.name, _where(n.node), shown))
            return outcome
        raise _Stop(Event(kind, node, None, n.node.name, _where(n.node), shown), options)

    def script(self, n: PNode, code: str, key: str) -> None:
        """Execute a script: an event without a choice."""
        self.event("script", n, (None,), (key, code))

    def check(self, n: PNode, code: str, key: str) -> bool:
        """Evaluate a script condition: the environment says true or false."""
        return self.event("check", n, (True, False), (key, code))

    # TreeNode::executeTick, haltNode; ControlNode::haltChild, resetChildren
    def tick(self, n: PNode) -> Status:
        """executeTick (src/tree_node.cpp): pre-conditions, the rule's tick, post-conditions."""
        self.node_ticks += 1
        if self.node_ticks > self.max_node_ticks:
            raise NodeTickLimit(f"more than {self.max_node_ticks} node ticks in one root tick "
                            f"(a loop without an event, e.g. Repeat num_cycles=-1 over AlwaysSuccess)")
        if self.program.version == 3:
            # TreeNode::executeTick (3.8, src/tree_node.cpp): tick(), setStatus; the C++
            # pre/post-condition callbacks are no part of the XML. DecoratorNode::executeTick
            # (3.8, src/decorator_node.cpp) resets a completed child as 4's does.
            new = self.program.rules[n.rule].tick(self, n)
            self.set_status(n, new)
            if n.decorator and self.status(n.kids[0]) in COMPLETED:
                self.set_status(n.kids[0], IDLE)
            return new
        new = self._pre_conditions(n)
        if new is None:
            new = self.program.rules[n.rule].tick(self, n)
        if new in COMPLETED:                                  # checkPostConditions
            key = "_onSuccess" if new is SUCCESS else "_onFailure"
            for k in (key, "_post"):
                code = n.node.attr(k)
                if code is not None:
                    self.script(n, code, k)
        if new is not SKIPPED:                               # preserve IDLE if skipped
            self.set_status(n, new)
        if n.decorator and self.status(n.kids[0]) in COMPLETED:
            # DecoratorNode::executeTick (src/decorator_node.cpp): after the tick, a child that
            # completed is reset (resetStatus: no halt), whatever the decorator's own tick did,
            # so Nav2's RateController or a custom decorator never leaves a finished child
            self.set_status(n.kids[0], IDLE)
        return new

    def _pre_conditions(self, n: PNode) -> Status | None:
        """checkPreConditions (src/tree_node.cpp), in PreCond's order."""
        status = self.status(n)
        for key in PRE_CONDITIONS:
            code = n.node.attr(key)
            if code is None:
                continue
            if status in (IDLE, SKIPPED):
                if self.check(n, code, key):
                    if key != "_while":
                        return {"_failureIf": FAILURE, "_successIf": SUCCESS, "_skipIf": SKIPPED}[key]
                elif key == "_while":
                    return SKIPPED
            elif status is RUNNING and key == "_while":
                if not self.check(n, code, key):
                    self.halt_node(n)
                    return SKIPPED
        return None

    def halt_node(self, n: PNode) -> None:
        """haltNode (src/tree_node.cpp): the rule's halt, then the `_onHalted` script."""
        rule = self.program.rules[n.rule]
        (rule.halt or _halt_children)(self, n)
        code = n.node.attr("_onHalted") if self.program.version != 3 else None
        if code is not None:
            self.script(n, code, "_onHalted")

    def halt_child(self, n: PNode, i: int) -> None:
        """ControlNode::haltChild (src/control_node.cpp): halt it if RUNNING, then reset it."""
        child = n.kids[i]
        if self.status(child) is RUNNING:
            self.halt_node(child)
        self.set_status(child, IDLE)

    def reset_children(self, n: PNode, first: int = 0) -> None:
        """ControlNode::resetChildren / haltChildren(first) (src/control_node.cpp)."""
        for i in range(first, len(n.kids)):
            self.halt_child(n, i)


def _behind(path: tuple, passed: dict) -> bool:
    """Whether `path` is under a child that a sequence of Program.passing has passed."""
    return any(path[:d] in passed and path[d] < passed[path[:d]] for d in range(len(path)))


def _where(node: Node) -> str:
    """file:line:column of the element the node was read from, or '' (a tree built in code)."""
    if not node.line:
        return ""
    return f"{node.file + ':' if node.file else ''}{node.line}:{node.column}"


def _halt_children(run: _Run, n: PNode) -> None:
    """ControlNode::halt / DecoratorNode::halt: reset every child, then this node."""
    run.reset_children(n)
    run.set_status(n, IDLE)


# ---------------------------------------------------------------------------------------------
# Port values

def _is_ref(value: str | None) -> bool:
    """A blackboard reference `{key}` (TreeNode::isBlackboardPointer), or `=`."""
    if value is None:
        return False
    v = value.strip()
    return (len(v) >= 3 and v[0] == "{" and v[-1] == "}") or v in ("=", "{=}")


def _literal(n: PNode, port: str, port_type: str, default):
    """A literal port read as BT.CPP's convertFromString reads it (bt/ports.py), its default
    when absent; a value BT.CPP cannot convert is an error here as there."""
    value = n.node.attr(port)
    if value is None:
        return default
    converted = convert(port_type, value)
    if converted is None:
        raise TreeError(f"{n.node.type} {n.node.name!r}: port {port}={value!r} can not be converted to "
                        f"{TYPE_NAMES[port_type]} (BT.CPP's convertFromString)")
    return converted


def _int(n: PNode, port: str, default: int, port_type: str = "int") -> int:
    """A literal integer port: "3.5" is 3, as std::from_chars reads it."""
    return _literal(n, port, port_type, default)


def _required(n: PNode, port: str, where: str) -> None:
    """A port without a default that the node reads when ticked: absent, BT.CPP's tick throws
    "Missing parameter [port] in where"."""
    if n.node.attr(port) is None:
        raise TreeError(f"{n.node.type} {n.node.name!r}: Missing parameter [{port}] in {where} (BT.CPP)")


def _bool(n: PNode, port: str, default: bool) -> bool:
    return _literal(n, port, "bool", default)


def _status_port(n: PNode, port: str, default: Status) -> Status:
    status = _literal(n, port, "status", default.value)
    if status == "IDLE":
        raise TreeError(f"{n.node.type} {n.node.name!r}: port {port}=\"IDLE\": a node may not return IDLE")
    return Status(status)


# ---------------------------------------------------------------------------------------------
# Leaves

def _leaf(outcomes: tuple[Status, ...]) -> Callable[[_Run, PNode], Status]:
    """An Action or Condition the robot implements: the environment picks its status."""
    def tick(run: _Run, n: PNode) -> Status:
        return run.event("tick", n, outcomes)
    return tick


def _leaf_halt(run: _Run, n: PNode) -> None:
    """A RUNNING leaf halted (ActionNodeBase::halt via haltNode): an event."""
    run.event("halt", n, (None,))
    run.set_status(n, IDLE)


def _always(status: Status) -> Callable[[_Run, PNode], Status]:
    # AlwaysSuccessNode / AlwaysFailureNode (include/behaviortree_cpp/actions/always_*_node.h)
    return lambda run, n: status


def _script(run: _Run, n: PNode) -> Status:
    # ScriptNode::tick (include/behaviortree_cpp/actions/script_node.h): run `code`, SUCCESS
    run.event("script", n, (None,))
    return SUCCESS


def _script_condition(run: _Run, n: PNode) -> Status:
    # ScriptCondition::tick (include/behaviortree_cpp/actions/script_condition.h)
    return SUCCESS if run.event("check", n, (True, False)) else FAILURE


def _sleep(run: _Run, n: PNode) -> Status:
    # SleepNode::onStart/onRunning (src/actions/sleep_node.cpp): msec<=0 succeeds at once; else
    # RUNNING until the timer fires (the environment's choice of when)
    msec = n.node.attr("msec")
    if run.status(n) is not RUNNING:
        _required(n, "msec", "SleepNode")
        if not _is_ref(msec) and _int(n, "msec", 0, "unsigned") <= 0:
            return SUCCESS
        run.event("time", n, (None,))              # the timer starts
        return RUNNING
    return SUCCESS if run.event("time", n, (True, False)) else RUNNING


# ---------------------------------------------------------------------------------------------
# Controls

def _sequence_like(*, fallback: bool, asynch: bool = False, memory: bool = False, yields: bool | None = None,
                   keep_on_halt: bool | None = None) -> Rule:
    """SequenceNode::tick (src/controls/sequence_node.cpp) and FallbackNode::tick
    (src/controls/fallback_node.cpp): resume at the current child; Async* return RUNNING after
    each child that completed synchronously (the tree's wake-up signal is always set).
    SequenceWithMemory::tick (src/controls/sequence_with_memory_node.cpp) is the asynchronous
    Sequence whose failure keeps the index (halting the children from it on), and whose halt
    keeps it too (`memory`). `yields`, `keep_on_halt` (default: asynch or memory, memory) set
    the two apart for BT.CPP 3.8's SequenceStar (RULES_V3, below)."""
    go_on, stop = (FAILURE, SUCCESS) if fallback else (SUCCESS, FAILURE)
    yields = (asynch or memory) if yields is None else yields
    keep_on_halt = memory if keep_on_halt is None else keep_on_halt

    def tick(run: _Run, n: PNode) -> Status:
        count = len(n.kids)
        if run.status(n) in (IDLE, SKIPPED):                  # !isStatusActive(status())
            run.put(n, "skipped", 0)
        run.set_status(n, RUNNING)
        idx = run.get(n, "idx")
        while idx < count:
            child = n.kids[idx]
            prev = run.status(child)
            s = run.tick(child)
            if s is RUNNING:
                run.put(n, "idx", idx)
                return RUNNING
            if s is stop:
                run.put(n, "idx", idx if memory else 0)
                run.reset_children(n, idx if memory else 0)
                return s
            if s is go_on:
                idx += 1
                # Not state (docs/semantics.md, "What is state"): a finished child behind the
                # index is ticked again only after resetChildren sets it IDLE, and halting it
                # does nothing (haltChild halts a RUNNING child only); the stored index is
                # written on every way out. Both kept as BT.CPP keeps them, every position
                # of a sequence was a new state for every position it started the tick from.
                run.set_status(child, IDLE)
                run.put(n, "idx", idx)
                if yields and prev is IDLE and idx < count:
                    run.woken = True             # emitWakeUpSignal: tickOnce ticks again at once
                    return RUNNING
            elif s is SKIPPED:
                idx += 1
                run.put(n, "idx", idx)
                run.put(n, "skipped", run.get(n, "skipped") + 1)
        all_skipped = run.get(n, "skipped") == count
        run.reset_children(n)
        run.put(n, "idx", 0)
        run.put(n, "skipped", 0)
        return SKIPPED if all_skipped else go_on

    def halt(run: _Run, n: PNode) -> None:
        run.put(n, "idx", 0)
        run.put(n, "skipped", 0)
        _halt_children(run, n)

    # SequenceWithMemory::halt keeps the index: ControlNode::halt only
    return Rule(tick, _halt_children if keep_on_halt else halt)


def _reactive(*, fallback: bool) -> Rule:
    """ReactiveSequence::tick (src/controls/reactive_sequence.cpp) and ReactiveFallback::tick
    (src/controls/reactive_fallback.cpp): every tick from the first child; a RUNNING child halts
    all the others."""
    go_on, stop = (FAILURE, SUCCESS) if fallback else (SUCCESS, FAILURE)

    def tick(run: _Run, n: PNode) -> Status:
        all_skipped = True
        run.set_status(n, RUNNING)
        for i, child in enumerate(n.kids):
            s = run.tick(child)
            all_skipped &= s is SKIPPED
            if s is RUNNING:
                for j in range(len(n.kids)):
                    if j != i:
                        run.halt_child(n, j)
                return RUNNING
            if s is stop:
                run.reset_children(n)
                return s
            if s is SKIPPED:
                run.halt_child(n, i)
        run.reset_children(n)
        return SKIPPED if all_skipped else go_on

    return Rule(tick)


def _threshold(value: int, count: int) -> int:
    return max(count + value + 1, 0) if value < 0 else value


def _parallel(run: _Run, n: PNode) -> Status:
    # ParallelNode::tick (src/controls/parallel_node.cpp): success_count (default -1),
    # failure_count (default 1); completed children are not ticked again
    count = len(n.kids)
    s_raw = _int(n, "success_count", -1)
    s_req, f_req = _threshold(s_raw, count), _threshold(_int(n, "failure_count", 1), count)
    if count < s_req or count < f_req:
        raise TreeError(f"Parallel {n.node.name!r}: number of children is less than threshold")
    run.set_status(n, RUNNING)
    skipped = 0
    done = set(run.get(n, "completed", ()))
    succ, fail = run.get(n, "succ"), run.get(n, "fail")
    for i, child in enumerate(n.kids):
        if i not in done:
            s = run.tick(child)
            if s is SKIPPED:
                skipped += 1
            elif s is SUCCESS:
                done.add(i)
                succ += 1
            elif s is FAILURE:
                done.add(i)
                fail += 1
        if succ >= s_req or (s_raw < 0 and succ + skipped >= s_req):
            _parallel_clear(run, n)
            run.reset_children(n)
            return SUCCESS
        if count - fail < s_req or fail == f_req:
            _parallel_clear(run, n)
            run.reset_children(n)
            return FAILURE
    run.put(n, "completed", tuple(sorted(done)))
    run.put(n, "succ", succ)
    run.put(n, "fail", fail)
    return SKIPPED if skipped == count else RUNNING


def _parallel_clear(run: _Run, n: PNode) -> None:
    for key in ("completed", "succ", "fail"):
        run.put(n, key, 0)


def _parallel_halt(run: _Run, n: PNode) -> None:
    # ParallelNode::halt / ParallelAllNode::halt: clear the counts, then ControlNode::halt
    _parallel_clear(run, n)
    _halt_children(run, n)


def _parallel_all(run: _Run, n: PNode) -> Status:
    # ParallelAllNode::tick (src/controls/parallel_all_node.cpp): tick until every child is done,
    # FAILURE when at least max_failures (default 1) failed
    count = len(n.kids)
    f_req = _threshold(_int(n, "max_failures", 1), count)
    if count < f_req:
        raise TreeError(f"ParallelAll {n.node.name!r}: number of children is less than threshold")
    run.set_status(n, RUNNING)
    skipped = 0
    done = set(run.get(n, "completed", ()))
    fail = run.get(n, "fail")
    for i, child in enumerate(n.kids):
        if i in done:
            continue
        s = run.tick(child)
        if s in COMPLETED:
            done.add(i)
            fail += s is FAILURE
        elif s is SKIPPED:
            skipped += 1
    if skipped == count:
        run.put(n, "completed", tuple(sorted(done)))
        run.put(n, "fail", fail)
        return SKIPPED
    if skipped + len(done) >= count:
        run.reset_children(n)
        _parallel_clear(run, n)
        return FAILURE if fail >= f_req else SUCCESS
    run.put(n, "completed", tuple(sorted(done)))
    run.put(n, "fail", fail)
    return RUNNING


def _if_then_else(run: _Run, n: PNode) -> Status:
    # IfThenElseNode::tick (src/controls/if_then_else_node.cpp): the condition is ticked until it
    # completes, then the chosen branch until it completes
    count = len(n.kids)
    if count not in (2, 3):
        raise TreeError("IfThenElseNode must have either 2 or 3 children")
    run.set_status(n, RUNNING)
    idx = run.get(n, "idx")
    if idx == 0:
        c = run.tick(n.kids[0])
        if c is RUNNING:
            return RUNNING
        if c is SUCCESS:
            idx = 1
        elif c is FAILURE:
            if count == 3:
                idx = 2
            else:
                return FAILURE
    if idx > 0:
        s = run.tick(n.kids[idx])
        if s is RUNNING:
            run.put(n, "idx", idx)
            return RUNNING
        run.reset_children(n)
        run.put(n, "idx", 0)
        return s
    raise TreeError("Something unexpected happened in IfThenElseNode (its condition was SKIPPED)")


def _if_then_else_halt(run: _Run, n: PNode) -> None:
    run.put(n, "idx", 0)
    _halt_children(run, n)


def _while_do_else(run: _Run, n: PNode) -> Status:
    # WhileDoElseNode::tick (src/controls/while_do_else_node.cpp): the condition every tick; the
    # branch not taken is halted
    count = len(n.kids)
    if count not in (2, 3):
        raise TreeError("WhileDoElseNode must have either 2 or 3 children")
    run.set_status(n, RUNNING)
    c = run.tick(n.kids[0])
    if c is RUNNING:
        return RUNNING
    status = IDLE
    if c is SUCCESS:
        if count == 3:
            run.halt_child(n, 2)
        status = run.tick(n.kids[1])
    elif c is FAILURE:
        if count == 3:
            run.halt_child(n, 1)
            status = run.tick(n.kids[2])
        else:
            status = FAILURE
    if status is RUNNING:
        return RUNNING
    run.reset_children(n)
    if status is IDLE:
        raise TreeError("WhileDoElse: its condition was SKIPPED (BT.CPP returns IDLE to its parent)")
    return status


def _numeric_equal(a: str, b: str) -> bool:
    """details::CheckStringEquality (src/controls/switch_node.cpp), without scripting enums."""
    if a == b:
        return True
    for conv in (int, float):
        try:
            if abs(conv(a) - conv(b)) <= 1.2e-7:
                return True
        except ValueError:
            pass
    return False


def _switch(cases: int, equal: Callable[[str, str], bool] = _numeric_equal) -> Rule:
    """SwitchNode<N>::tick (include/behaviortree_cpp/controls/switch_node.h): the child of the
    first case equal to `variable`, else the last (default); the one running before is halted.
    A blackboard variable's value is the environment's choice (a "check" event). `equal` compares
    two texts (BT.CPP 3.8's SwitchNode compares strings: RULES_V3, below)."""
    def tick(run: _Run, n: PNode) -> Status:
        if len(n.kids) != cases + 1:
            raise TreeError(f"Wrong number of children in Switch{cases}; must be (num_cases + default)")
        variable = n.node.attr("variable")
        keys = [f"case_{i}" for i in range(1, cases + 1)]
        match = cases
        if variable is not None and not _is_ref(variable):
            for i, k in enumerate(keys):
                v = n.node.attr(k)
                if v is not None and not _is_ref(v) and equal(variable, v):
                    match = i
                    break
        elif variable is not None:
            seen: list[str] = []
            options: list[int] = []
            for i, k in enumerate(keys):
                v = n.node.attr(k)
                if v is None:
                    continue
                if not _is_ref(v) and any(equal(v, w) for w in seen):
                    continue                                # an earlier equal case always wins
                if not _is_ref(v):
                    seen.append(v)
                options.append(i)
            options.append(cases)
            match = run.event("check", n, tuple(options))
        running = run.get(n, "running", None)
        if running is not None and running != match:
            run.halt_child(n, running)
        s = run.tick(n.kids[match])
        if s is SKIPPED:
            run.put(n, "running", None)
            return SKIPPED
        if s is RUNNING:
            run.put(n, "running", match)
        else:
            run.reset_children(n)
            run.put(n, "running", None)
        return s

    def halt(run: _Run, n: PNode) -> None:
        run.put(n, "running", None)
        _halt_children(run, n)

    return Rule(tick, halt)


# Nav2 (ros-navigation/navigation2, nav2_behavior_tree/plugins/control/)

def _pipeline_sequence(run: _Run, n: PNode) -> Status:
    # PipelineSequence::tick (pipeline_sequence.cpp): every tick re-ticks the children before
    # the furthest one that ran; a RUNNING child at or past it stops the tick
    skipped = 0
    last = run.get(n, "last")
    for i, child in enumerate(n.kids):
        s = run.tick(child)
        if s is FAILURE:
            run.reset_children(n)
            run.put(n, "last", 0)
            return FAILURE
        if s is SKIPPED:
            skipped += 1
        elif s is RUNNING and i >= last:
            run.put(n, "last", i)
            return RUNNING
    run.reset_children(n)
    run.put(n, "last", 0)
    return SKIPPED if skipped == len(n.kids) else SUCCESS


def _forgetting(*keys: str) -> Callable[[_Run, PNode], None]:
    """A halt that halts the children and puts `keys` back to their first values (the index or
    count a control node or decorator keeps: ControlNode::halt / DecoratorNode::halt, then the
    node's own resets). A halt's events are its children's; the order of the resets is not seen."""
    def halt(run: _Run, n: PNode) -> None:
        _halt_children(run, n)
        for key in keys:
            run.put(n, key, 0)
    return halt


_pipeline_halt = _forgetting("last")


def _recovery(run: _Run, n: PNode) -> Status:
    # RecoveryNode::tick (recovery_node.cpp, the BT.CPP 4 version): tick the first child; on its
    # failure tick the second (the recovery) and, if that succeeds, the first again,
    # number_of_retries (default 1) times; a failed recovery fails the node. A skipped first
    # child skips the node (reset); a skipped recovery fails it without a reset: back at the
    # first child, halting the recovery, the retries counted so far kept (retry_count_)
    if len(n.kids) != 2:
        raise TreeError(f"Recovery Node {n.node.name!r} must only have 2 children.")
    retries = _int(n, "number_of_retries", 1)
    run.set_status(n, RUNNING)
    idx, count = run.get(n, "idx"), run.get(n, "retries")
    while idx < 2 and count <= retries:
        s = run.tick(n.kids[idx])
        if s not in (SUCCESS, FAILURE, RUNNING, SKIPPED):
            raise TreeError("A child node must never return IDLE")
        if s is RUNNING:
            run.put(n, "idx", idx)
            run.put(n, "retries", count)
            return RUNNING
        if s is SKIPPED:
            if idx == 0:
                _recovery_halt(run, n)
                return SKIPPED
            run.put(n, "idx", 0)
            run.put(n, "retries", count)
            run.halt_child(n, 1)
            return FAILURE
        if idx == 0:
            if s is SUCCESS:
                _recovery_halt(run, n)
                return SUCCESS
            if count < retries:
                run.halt_child(n, 0)
                idx = 1
            else:
                _recovery_halt(run, n)
                return FAILURE
        else:
            if s is SUCCESS:
                run.halt_child(n, 1)
                count += 1
                idx = 0
            else:
                _recovery_halt(run, n)
                return FAILURE
    _recovery_halt(run, n)
    return FAILURE


_recovery_halt = _forgetting("idx", "retries")


def _round_robin(run: _Run, n: PNode) -> Status:
    # RoundRobinNode::tick (round_robin_node.cpp): tick from where the last success left off;
    # SUCCESS at the first success, FAILURE when every child failed in turn
    count = len(n.kids)
    run.set_status(n, RUNNING)
    idx, failed = run.get(n, "idx"), run.get(n, "failed")
    while failed < count:
        s = run.tick(n.kids[idx])
        if s is SUCCESS:
            idx = (idx + 1) % count
            run.reset_children(n)
            run.put(n, "idx", idx)
            run.put(n, "failed", 0)
            return SUCCESS
        if s is FAILURE:
            idx = (idx + 1) % count
            failed += 1
        elif s is RUNNING:
            run.put(n, "idx", idx)
            run.put(n, "failed", failed)
            return RUNNING
        else:
            raise TreeError("Invalid status return from BT node")
    _round_robin_halt(run, n)
    return FAILURE


_round_robin_halt = _forgetting("idx", "failed")


# ---------------------------------------------------------------------------------------------
# Decorators (include/behaviortree_cpp/decorators/*.h, src/decorators/*.cpp)

def _reset_child(run: _Run, n: PNode) -> None:
    """DecoratorNode::resetChild: halt the child if RUNNING, then reset it."""
    run.halt_child(n, 0)


def _completing(on_success: Status, on_failure: Status, otherwise: Status | None = None):
    """A decorator that ticks its child and, when it completes, resets it and returns
    `on_success` or `on_failure`; RUNNING and SKIPPED pass through, or become `otherwise`."""
    def tick(run: _Run, n: PNode) -> Status:
        run.set_status(n, RUNNING)
        s = run.tick(n.kids[0])
        if s in COMPLETED:
            _reset_child(run, n)
            return on_success if s is SUCCESS else on_failure
        return s if otherwise is None else otherwise
    return tick


# InverterNode::tick (src/decorators/inverter_node.cpp): SUCCESS <-> FAILURE, RUNNING and
# SKIPPED as they are; ForceSuccessNode / ForceFailureNode::tick (force_success_node.h,
# force_failure_node.h); KeepRunningUntilFailureNode::tick (keep_running_until_failure_node.h):
# SUCCESS becomes RUNNING, FAILURE stays, SKIPPED returns status(), which tick() just set to RUNNING
_inverter = _completing(FAILURE, SUCCESS)
_keep_running_until_failure = _completing(RUNNING, FAILURE, RUNNING)


def _force(status: Status) -> Callable[[_Run, PNode], Status]:
    return _completing(status, status)


def _looping(port: str, key: str, again: Status, yields: bool = True) -> Callable[[_Run, PNode], Status]:
    """A decorator that ticks its child anew while it returns `again`, `port` times (-1: for
    ever), counting in `key`: RetryUntilSuccessful (again FAILURE) and Repeat (again SUCCESS),
    whose sources mirror each other. The other completion ends the loop with it; an `again` from
    IDLE with turns left returns RUNNING (the wake-up signal) unless not `yields` (BT.CPP 3.8 loops
    within the tick: RULES_V3, below); when the turns run out the node returns `again`."""
    done = SUCCESS if again is FAILURE else FAILURE

    def tick(run: _Run, n: PNode) -> Status:
        _required(n, port, "RepeatNode" if again is SUCCESS else "RetryNode")
        turns = _int(n, port, 0)
        count = run.get(n, key)
        loop = count < turns or turns == -1
        run.set_status(n, RUNNING)
        while loop:
            child = n.kids[0]
            prev = run.status(child)
            s = run.tick(child)
            if s is again:
                if turns != -1:
                    # -1 loops for ever: nothing reads its count (RetryNode, RepeatNode compare
                    # it with the limit only), so it is no state, and a proof stays finite
                    count += 1
                    run.put(n, key, count)
                loop = count < turns or turns == -1
                _reset_child(run, n)
                if yields and prev is IDLE and loop:
                    run.woken = True             # emitWakeUpSignal (repeat_node.cpp, retry_node.cpp)
                    return RUNNING
            elif s is done:
                run.put(n, key, 0)
                _reset_child(run, n)
                return done
            elif s is RUNNING:
                return RUNNING
            else:
                _reset_child(run, n)
                return SKIPPED
        run.put(n, key, 0)
        return again
    return tick


# RetryNode::tick (src/decorators/retry_node.cpp): re-tick a failed child up to num_attempts
# times (-1: forever); RepeatNode::tick (src/decorators/repeat_node.cpp): a successful one up to
# num_cycles times
_retry = _looping("num_attempts", "tries", FAILURE)
_repeat = _looping("num_cycles", "count", SUCCESS)


def _run_once(run: _Run, n: PNode) -> Status:
    # RunOnceNode::tick (run_once_node.h): the child until it completes, once; then SKIPPED
    # (then_skip=true, default) or the same status forever. halt() keeps the memory.
    skip = _bool(n, "then_skip", True)
    if run.get(n, "done"):
        return SKIPPED if skip else run.get(n, "returned")
    run.set_status(n, RUNNING)
    s = run.tick(n.kids[0])
    if s in COMPLETED:
        run.put(n, "done", True)
        run.put(n, "returned", s)
        _reset_child(run, n)
    return s


def _timeout(run: _Run, n: PNode) -> Status:
    # TimeoutNode::tick (src/decorators/timeout_node.cpp): the timer starts at the first tick;
    # if it fires while the child is RUNNING the child is halted and the node fails. When it
    # fires is the environment's choice, asked before each later tick while the child runs.
    _required(n, "msec", "TimeoutNode")
    msec = n.node.attr("msec")
    armed = _is_ref(msec) or _int(n, "msec", 0, "unsigned") > 0
    child = n.kids[0]
    if not run.get(n, "started"):
        run.put(n, "started", True)
        run.set_status(n, RUNNING)
    elif armed and run.status(child) is RUNNING and run.event("time", n, (True, False)):
        _reset_child(run, n)
        run.put(n, "started", False)
        return FAILURE
    s = run.tick(child)
    if s in COMPLETED:
        run.put(n, "started", False)
        _reset_child(run, n)
    return s


def _delay(run: _Run, n: PNode) -> Status:
    # DelayNode::tick (src/decorators/delay_node.cpp): the first tick starts the timer and
    # returns RUNNING; later ticks return RUNNING until it fired (the environment's choice),
    # then tick the child until it completes
    _required(n, "delay_msec", "DelayNode")
    if not _is_ref(n.node.attr("delay_msec")):
        _int(n, "delay_msec", 0, "unsigned")
    if not run.get(n, "started"):
        run.put(n, "started", True)
        run.put(n, "complete", False)
        run.set_status(n, RUNNING)
        run.event("time", n, (None,))
        return RUNNING
    if not run.get(n, "complete"):
        if not run.event("time", n, (True, False)):
            return RUNNING
        run.put(n, "complete", True)
    s = run.tick(n.kids[0])
    if s in COMPLETED:
        run.put(n, "started", False)
        run.put(n, "complete", False)
        _reset_child(run, n)
    return s


_timer_halt = _forgetting("started", "complete")    # TimeoutNode::halt / DelayNode::halt: the timer stops


def _precondition(run: _Run, n: PNode) -> Status:
    # PreconditionNode::tick (script_precondition.h): `if` is evaluated only while the child is
    # not running; false returns `else` (default FAILURE). halt() does not clear the flag.
    otherwise = _status_port(n, "else", FAILURE)
    if not run.get(n, "running"):
        if not run.check(n, n.node.attr("if") or "", "if"):
            return otherwise
        run.put(n, "running", True)
    s = run.tick(n.kids[0])
    if s in COMPLETED:
        _reset_child(run, n)
        run.put(n, "running", False)
    return s


def _subtree(run: _Run, n: PNode) -> Status:
    # SubTreeNode::tick (src/decorators/subtree_node.cpp): tick the called tree's root
    if run.status(n) is IDLE:
        run.set_status(n, RUNNING)
    s = run.tick(n.kids[0])
    if s in COMPLETED:
        _reset_child(run, n)
    return s


def _rate_controller(run: _Run, n: PNode) -> Status:
    # Nav2 RateController::tick (nav2_behavior_tree/plugins/decorator/rate_controller.cpp): the
    # child is ticked the first time (from IDLE), while it runs, and when the period elapsed (a
    # `time` event); else RUNNING; SKIPPED -> FAILURE. Nav2's tick does not reset a completed
    # child; BT.CPP 4's DecoratorNode::executeTick does, after it (_Run.tick).
    first = run.status(n) is IDLE
    run.set_status(n, RUNNING)
    child = n.kids[0]
    if first or run.status(child) is RUNNING or run.event("time", n, (True, False)):
        s = run.tick(child)
        return s if s in (RUNNING, SUCCESS) else FAILURE
    return RUNNING


# Opaque: a type whose semantics the table does not know

def _opaque(run: _Run, n: PNode) -> Status:
    """A leaf returns any status, as an Action of either registration does; a node with
    children picks, as events, children to tick and then the status it returns (it may tick
    several before returning), SKIPPED too: a custom decorator that returns its child's status
    (Nav2's GoalUpdater) passes a SKIPPED on."""
    if not n.kids:
        return _action(run, n)
    # no node of BT.CPP 3.8 returns SKIPPED (3.8's NodeStatus has none); Program.skips
    statuses = (SUCCESS, FAILURE, RUNNING, SKIPPED) if run.program.skips else (SUCCESS, FAILURE, RUNNING)
    options = tuple(range(len(n.kids))) + statuses
    while True:
        choice = run.event("choose", n, options)
        if isinstance(choice, Status):
            return choice
        run.tick(n.kids[choice])


def _opaque_halt(run: _Run, n: PNode) -> None:
    if not n.kids:
        _leaf_halt(run, n)
    else:
        _halt_children(run, n)


def _action(run: _Run, n: PNode) -> Status:
    # An Action whose registration the XML does not tell: ticked again while completed (a
    # parent that did not reset it: PipelineSequence, WhileDoElse's condition), a
    # StatefulActionNode returns its last status and any other Action runs again; which one, the
    # environment decides once per type and run (Run.registration), so a proof covers both
    prev = run.status(n)
    if prev in COMPLETED and run.registration(n) == "stateful":
        return prev
    return run.event("tick", n, ACTION_OUTCOMES)


def _stateful_action(run: _Run, n: PNode) -> Status:
    # StatefulActionNode::tick (src/action_node.cpp): onStart() from IDLE, onRunning() while
    # RUNNING, and otherwise `return prev_status;`: a completed action its parent did not reset
    # (WhileDoElse's condition child) returns its last status without running the callbacks
    prev = run.status(n)
    if prev in COMPLETED:
        return prev
    return run.event("tick", n, ACTION_OUTCOMES)


KINDS = ("re-ticked", "stateful")
"""The two registrations of an Action that behave differently: run again when ticked again
completed (SyncActionNode, SimpleActionNode, CoroActionNode, an ActionNodeBase), or returning
its last status (StatefulActionNode, ThreadedAction; Nav2's BtActionNode goes on to the result
it holds)."""

OPAQUE = Rule(_opaque, _opaque_halt)
ACTION = Rule(_action, _leaf_halt)
"""An Action of either registration (the default for Actions and unknown leaves): the first
time a run ticks a completed one of its type again, the environment says which (an event of
kind "registration"), and the run keeps that answer."""
RETICKED_ACTION = Rule(_leaf(ACTION_OUTCOMES), _leaf_halt)
"""An Action that every tick runs, RUNNING included: an ActionNodeBase whose tick() does not
look at its status, a CoroActionNode."""
SYNC_ACTION = Rule(_leaf(CONDITION_OUTCOMES), _leaf_halt)
"""An Action registered as a SyncActionNode or SimpleActionNode: every tick runs it, and it
never returns RUNNING (SyncActionNode::executeTick throws if it does)."""
STATEFUL_ACTION = Rule(_stateful_action, _leaf_halt)
"""An Action implemented as a BT.CPP StatefulActionNode (onStart/onRunning/onHalted): ticked
again completed, it returns its last status without running."""
CONDITION = Rule(_leaf(CONDITION_OUTCOMES), _leaf_halt)
_SEQ, _FALLBACK = _sequence_like(fallback=False), _sequence_like(fallback=True)

# The node table (src/bt_factory.cpp's builtin registrations; Nav2's BT_REGISTER_NODES)
# Parents that reset a child's status once it completes, before they tick it again (their rules
# above: resetChildren / resetChild on completion, and no completed child ticked again before):
# under one of these (or as a tree's root) a subtree is never ticked in a completed state.
RESETTING_PARENTS = frozenset({"Sequence", "Fallback", "SequenceWithMemory", "AsyncSequence", "AsyncFallback",
                               "Inverter", "ForceSuccess", "ForceFailure", "KeepRunningUntilFailure",
                               "RetryUntilSuccessful", "Repeat", "SubTree"})

RULES: Mapping[str, Rule] = MappingProxyType({
    "Sequence": _SEQ,
    "Fallback": _FALLBACK,
    "AsyncSequence": _sequence_like(fallback=False, asynch=True),
    "AsyncFallback": _sequence_like(fallback=True, asynch=True),
    "SequenceWithMemory": _sequence_like(fallback=False, memory=True),
    "ReactiveSequence": _reactive(fallback=False),
    "ReactiveFallback": _reactive(fallback=True),
    "Parallel": Rule(_parallel, _parallel_halt, ("success_count", "failure_count")),
    "ParallelAll": Rule(_parallel_all, _parallel_halt, ("max_failures",)),
    "IfThenElse": Rule(_if_then_else, _if_then_else_halt),
    "WhileDoElse": Rule(_while_do_else),
    **{f"Switch{k}": _switch(k) for k in range(2, 7)},
    "Inverter": Rule(_inverter),
    "ForceSuccess": Rule(_force(SUCCESS)),
    "ForceFailure": Rule(_force(FAILURE)),
    "KeepRunningUntilFailure": Rule(_keep_running_until_failure),
    "RetryUntilSuccessful": Rule(_retry, _forgetting("tries"), ("num_attempts",)),    # RetryNode::halt
    "Repeat": Rule(_repeat, _forgetting("count"), ("num_cycles",)),                  # RepeatNode::halt
    "RunOnce": Rule(_run_once, None, ("then_skip",)),
    "Timeout": Rule(_timeout, _timer_halt),
    "Delay": Rule(_delay, _timer_halt),
    "Precondition": Rule(_precondition, None, ("else",)),
    "SubTree": Rule(_subtree),
    "AlwaysSuccess": Rule(_always(SUCCESS)),
    "AlwaysFailure": Rule(_always(FAILURE)),
    "Script": Rule(_script),
    "SetBlackboard": Rule(_script),
    "ScriptCondition": Rule(_script_condition),
    "Sleep": Rule(_sleep, _leaf_halt),
    "PipelineSequence": Rule(_pipeline_sequence, _pipeline_halt),
    "RecoveryNode": Rule(_recovery, _recovery_halt, ("number_of_retries",)),
    "RoundRobin": Rule(_round_robin, _round_robin_halt),
    "RateController": Rule(_rate_controller),
})


# ---------------------------------------------------------------------------------------------
# Programs

# The table's types that BT.CPP (or Nav2) implements as a DecoratorNode
DECORATOR_TYPES = frozenset({"Inverter", "ForceSuccess", "ForceFailure", "KeepRunningUntilFailure",
                             "RetryUntilSuccessful", "Repeat", "RunOnce", "Timeout", "Delay", "Precondition",
                             "SubTree", "RateController"})


def base_table(version: int) -> Mapping[str, Rule]:
    """The node table of BT.CPP `version`: RULES (4), or RULES_V3 (the section "BT.CPP 3.8" at the end) (3.8)."""
    if version == 3:
        return RULES_V3
    return RULES


def table_for(document: Document, rules: Mapping[str, Rule] | None = None) -> dict:
    """The rules `document` runs under: its version's table extended by the user's `rules`."""
    return {**base_table(document.version), **(rules or {})}


def _decorator_types(version: int) -> frozenset:
    if version == 3:
        return DECORATOR_TYPES_V3
    return DECORATOR_TYPES


def _is_decorator(node: Node, document: Document, table: Mapping[str, Rule]) -> bool:
    """Whether BT.CPP runs `node` as a DecoratorNode: the kind its model or generic form gives,
    else the kind of the rule it runs under, else (a custom node no model declares) one child
    makes it a Decorator, as formats.btxml.infer_models declares it for BT.CPP."""
    if len(node.children) != 1:
        return False
    model = document.model(node.type)
    kind = node.form or (model.kind if model else "")
    if kind:
        return kind == "Decorator"
    rule = table.get(node.type)
    if rule is not None:
        base = base_table(document.version)
        return any(rule is base[t] for t in _decorator_types(document.version) if t in base)
    return True

def subtree_id(node: Node) -> str | None:
    """The ID of the tree a SubTree node calls, or None when `node` is no SubTree call."""
    if node.form == "SubTree":
        return node.type
    if node.type in ("SubTree", "SubTreePlus"):          # SubTreePlus: BT.CPP 3.8's (formats/btxml.py)
        return node.attr("ID")
    return None


_TRUE = ("true", "TRUE", "True", "1")                  # convertFromString<bool>'s true (formats.btxml refuses the rest)


def call_identity(node: Node, document: Document) -> tuple:
    """A SubTree call as BT.CPP creates it: ("SubTree", tree ID, effective remapping by port name, _autoremap)."""
    # recursivelyCreateSubtree (src/xml_parsing.cpp): the call's attributes that are port names,
    # `{=}` read as `{port}`; then, unless _autoremap, each port of the tree's model the call does
    # not remap gets the model's default ("remapping is not explicitly defined in the XML: use the
    # model"; one without a default is refused when the tree is read). Under _autoremap the model
    # is not read: a port the call leaves out is the parent's entry of that name.
    tree_id = subtree_id(node)
    if document.version == 3:
        return _call_identity_v3(node, tree_id)
    autoremap = node.attr("_autoremap", "false") in _TRUE
    remap = {k: "{" + k + "}" if v == "{=}" else v for k, v in node.attrs if is_port_name(k)}
    model = document.subtree_model(tree_id) if not autoremap and tree_id is not None else None
    for port in subtree_ports((model,)) if model is not None else ():
        if port.name not in remap and port.default:
            remap[port.name] = port.default
    return ("SubTree", tree_id, tuple(sorted(remap.items())), autoremap)


def _call_identity_v3(node: Node, tree_id: str | None) -> tuple:
    """A SubTree or SubTreePlus call read under BT.CPP 3.8 (recursivelyCreateTree, 3.8's
    src/xml_parsing.cpp) in call_identity's terms, so that a call of 3.8 and its BT.CPP 4
    conversion are one context where they bind the same entries:
    <SubTree ID="T" __shared_blackboard="true"/>   the parent's blackboard itself, the other
                                                   attributes unread: as 4's _autoremap="true"
    <SubTree ID="T" goal="target"/>                isolated, `goal` is the parent's `target`
                                                   (addSubtreeRemapping): 4's goal="{target}"
    <SubTreePlus ID="T" goal="{target}" n="3" __autoremap="1"/>   `{key}` a remapping, anything
                                                   else a constant, __autoremap: as 4's SubTree"""
    if node.type == "SubTree":
        if node.attr("__shared_blackboard", "false") in _TRUE:
            return ("SubTree", tree_id, (), True)
        # __shared_blackboard="false" is remapped too (it is no reserved name), a key no node reads
        remap = {k: "{" + v + "}" for k, v in node.attrs
                 if k not in ("ID", "name", "_description", "__shared_blackboard")}
        return ("SubTree", tree_id, tuple(sorted(remap.items())), False)
    autoremap = node.attr("__autoremap", "false") in _TRUE
    remap = {k: v for k, v in node.attrs if k not in ("ID", "name", "_description", "__autoremap")}
    return ("SubTree", tree_id, tuple(sorted(remap.items())), autoremap)


def _rule_key(node: Node, document: Document, rules: Mapping[str, Rule]) -> str:
    """The table key of the node's rule: its type, or a leaf kind, or opaque."""
    rule = rules.get(node.type)
    if rule is not None:
        return "<opaque>" if any(_is_ref(node.attr(p)) for p in rule.literal) else node.type
    model = document.model(node.type)
    kind = node.form or (model.kind if model else "")
    if not node.children and kind == "Condition":
        return "<condition>"
    if not node.children and kind in ("Action", ""):
        return "<action>" if kind == "Action" else "<opaque>"
    return "<opaque>"


def program(document: Document, rules: Mapping[str, Rule] | None = None, *, once: bool = False) -> Program:
    """The document's main tree with its SubTrees expanded, under RULES extended by `rules`.
    `once`: the root is never ticked again once it finished nor halted (a run that ends with
    the root's status, as the prover's), so what the sequences on its way passed is not state."""
    table = {**table_for(document, rules), "<opaque>": OPAQUE, "<action>": ACTION, "<condition>": CONDITION}

    def build(node: Node, context: tuple, path: tuple, calls: tuple) -> PNode:
        tid = subtree_id(node)
        if tid is not None:
            called = document.tree(tid)
            if called is None:
                raise SchemalogError(f"SubTree {node.name!r} calls tree {tid!r}, which the document does not define")
            if tid in calls:
                raise SchemalogError(f"SubTree {tid!r} calls itself (through {' -> '.join(calls)})")
            ident = call_identity(node, document)
            kid = build(called, context + (ident,), path + (0,), calls + (tid,))
            return PNode(node, "SubTree", (kid,), context, path, True)
        kids = tuple(build(c, context, path + (i,), calls) for i, c in enumerate(node.children))
        return PNode(node, _rule_key(node, document, table), kids, context, path,
                     _is_decorator(node, document, table))

    root = build(document.root, (), (), (document.main,))
    return Program(root, MappingProxyType(table), frozenset(_passing(root, table)) if once else frozenset(),
                   document.version, document.version != 3)


# Parents that tick a child only when they are ticked, and never tick a finished child again
# before they finish themselves (or are halted): below a node that is ticked once, so are their
# children. A Sequence or Fallback of theirs never goes back to a child it passed.
_PASSING = ("Sequence", "Fallback", "AsyncSequence", "AsyncFallback", "SequenceWithMemory")
_ONCE_THROUGH = _PASSING + ("SubTree", "Inverter", "ForceSuccess", "ForceFailure")


def _passing(root: PNode, table: Mapping[str, Rule]) -> list[tuple]:
    """The paths of the sequences that, in a run where the root is ticked once (not again after
    it finished, never halted), never tick a child they passed again: the children they passed
    and everything below are no state (docs/semantics.md, "What is state")."""
    out, stack = [], [root]
    while stack:
        n = stack.pop()
        if n.rule in _PASSING and table[n.rule] is RULES[n.rule]:
            out.append(n.path)
        if n.rule in _ONCE_THROUGH and table[n.rule] is RULES[n.rule]:
            stack.extend(n.kids)
    return out


# ---------------------------------------------------------------------------------------------
# The small step

def step(prog: Program, config: Config, *, max_node_ticks: int = 100_000) -> Await | RootTicked:
    """Run the current root tick from `config` to its next event or its end."""
    run = _Run(prog, config, max_node_ticks)
    try:
        status = run.tick(prog.root)
    except _Stop as stop:
        return Await(stop.event, stop.options, config, _continuation(run, stop))
    except TreeError as err:
        return RootTicked(None, err.message, run.node_ticks, Config(kinds=run.after().kinds), tuple(run.events),
                          isinstance(err, NodeTickLimit))
    kept = None
    if status in COMPLETED:                              # Tree::tickRoot: resetStatus on completion
        kept = run.after()
        run.set_status(prog.root, IDLE)
    return RootTicked(status, "", run.node_ticks, run.after(), tuple(run.events), kept=kept, woken=run.woken)


_UNKNOWN = object()


def _freeze_local(value: object) -> object:
    """A local variable of an interrupted rule as hashable data, or _UNKNOWN."""
    if value is None or isinstance(value, (bool, int, str, float, Status, Event)):
        return value
    if isinstance(value, PNode):
        return ("PNode", value.path)
    if isinstance(value, Rule):
        return ("Rule", id(value))                  # fixed for the program being explored
    if isinstance(value, (tuple, list)):
        items = tuple(_freeze_local(v) for v in value)
        return _UNKNOWN if _UNKNOWN in items else (type(value).__name__, items)
    if isinstance(value, (set, frozenset)):
        items = tuple(sorted((_freeze_local(v) for v in value), key=repr))
        return _UNKNOWN if _UNKNOWN in items else ("set", items)
    return _UNKNOWN


_FRAME_MODULES = frozenset({__name__, "schemalog.bt.congruence"})   # rules whose frames freeze: the
                                                                    # table's, and bt/congruence.py's node


def frozen_locals(frame) -> tuple | None:
    """A rule's frame's locals (its `self` and `run` left out), frozen and sorted, or None when
    one cannot be frozen (_freeze_local): with its code and instruction, what resumes it."""
    local = []
    for name, value in frame.f_locals.items():
        if name in ("self", "run"):
            continue
        frozen = _freeze_local(value)
        if frozen is _UNKNOWN:
            return None
        local.append((name, frozen))
    return tuple(sorted(local))


def _continuation(run: _Run, stop: _Stop) -> object:
    """The interrupted root tick as data: the memory as changed so far and, for every call on
    the stack, its code, the instruction it stopped at and its local variables (every loop
    variable here determines its iterator's position). Two interruptions with the same data
    continue alike, so the prover may merge them. None (no merging) when a frame is not this
    module's (a user's rule) or holds a value this function cannot freeze."""
    frames = []
    tb = stop.__traceback__.tb_next if stop.__traceback__ else None     # below step()
    while tb is not None:
        frame = tb.tb_frame
        if frame.f_globals.get("__name__") not in _FRAME_MODULES:
            return None
        local = frozen_locals(frame)
        if local is None:
            return None
        frames.append((frame.f_code, tb.tb_lasti, local))
        tb = tb.tb_next
    return (run.freeze(), tuple(sorted(run.kinds.items())), tuple(frames))


def advance(config: Config, outcome: object) -> Config:
    """The configuration after the environment answered the event `config` stopped at."""
    return Config(config.memory, config.pending + (outcome,), config.kinds)


def initial() -> Config:
    """The configuration before the first root tick: every node IDLE."""
    return Config()


def halt_step(prog: Program, config: Config) -> Await | RootTicked:
    """Halt the RUNNING root from `config` (its parent's haltChild, src/control_node.cpp) up to
    the next event it makes (a leaf's halt, an `_onHalted` script) or to its end: RootTicked
    with status IDLE and the memory the next root tick starts from."""
    run = _Run(prog, config, 100_000)
    try:
        run.halt_node(prog.root)
    except _Stop as stop:
        return Await(stop.event, stop.options, config)
    run.set_status(prog.root, IDLE)
    return RootTicked(IDLE, "", run.node_ticks, run.after(), tuple(run.events))


def _halt_any(run: _Run, n: PNode) -> None:
    """TreeNode::haltNode whatever the status, as Tree::haltTree calls it: a leaf's halt() does
    nothing unless it is RUNNING (StatefulActionNode::halt; an action's halt callback), and the
    `_onHalted` script runs in any case. A subtree taken whole (bt/congruence.py, a rule with its
    own visit) is halted as its rule says: what its root's halt does depends on what it holds."""
    if n.kids or run.status(n) is RUNNING or run.program.rules[n.rule].visit is not None:
        run.halt_node(n)
        return
    code = n.node.attr("_onHalted") if run.program.version != 3 else None
    if code is not None:
        run.script(n, code, "_onHalted")
    run.set_status(n, IDLE)


def _visit(run: _Run, n: PNode) -> None:
    """applyRecursiveVisitor(node, haltNode) (src/behavior_tree.cpp): every node in pre-order."""
    rule = run.program.rules[n.rule]
    if rule.visit is not None:
        rule.visit(run, n)
        return
    _halt_any(run, n)
    for kid in n.kids:
        _visit(run, kid)


def halt_tree_step(prog: Program, config: Config) -> Await | RootTicked:
    """Tree::haltTree (src/bt_factory.cpp), which an executor calls to cancel a goal or after one
    (Nav2 does after every goal): haltNode on the root whatever its status, then haltNode on
    every node in pre-order, root included (its halt resets what the node keeps: a retry count,
    a RoundRobin's index; its `_onHalted` runs again), then the root's resetStatus. Up to the
    next event, or to the end: RootTicked with status IDLE."""
    run = _Run(prog, config, 100_000)
    try:
        _halt_any(run, prog.root)
        _visit(run, prog.root)
    except _Stop as stop:
        return Await(stop.event, stop.options, config)
    run.set_status(prog.root, IDLE)
    return RootTicked(IDLE, "", run.node_ticks, run.after(), tuple(run.events))


def visit_step(prog: Program, config: Config) -> Await | RootTicked:
    """What Tree::haltTree's visitor does to a subtree that is not RUNNING (its parent halted it
    first if it was): haltNode on each of its nodes in pre-order. Up to the next event or the end."""
    run = _Run(prog, config, 100_000)
    try:
        _visit(run, prog.root)
    except _Stop as stop:
        return Await(stop.event, stop.options, config)
    return RootTicked(IDLE, "", run.node_ticks, run.after(), tuple(run.events))


# ---------------------------------------------------------------------------------------------
# BT.CPP 3.8 (a document read under version 3 runs under RULES_V3)
#
# BehaviorTree.CPP 3.8's tick semantics: the node table a document read under 3.8 runs under
# (Document.version 3; docs/behaviour_trees.md, "BT.CPP 3 files").
#
#     RULES_V3: type -> Rule        one rule per node type 3.8's BehaviorTreeFactory registers
#
# The source is BehaviorTree.CPP's tag 3.8.8 (commit 9d624dc7; its src/ and include/ are those of
# 3.8.7): src/bt_factory.cpp (BehaviorTreeFactory::BehaviorTreeFactory registers the types),
# src/controls/*.cpp, src/decorators/*.cpp, include/behaviortree_cpp_v3/{controls,decorators,
# actions}/*.h. Where 3.8 behaves as 4's rule, the rule is bt/semantics.py's own object (so a
# subtree of such nodes can be taken whole across the two versions, bt/congruence.py); the rules
# below are those that differ. What differs everywhere, in bt/semantics.py: 3.8 has no SKIPPED and
# no pre/post-condition attributes (TreeNode::executeTick, 3.8's src/tree_node.cpp, ticks and sets
# the status; _Run.tick), so no 3.8 node returns SKIPPED, an opaque one included.
#
# Same as 4 (bt/semantics.py's rule, no SKIPPED arising):
#     Sequence, Fallback        SequenceNode::tick / FallbackNode::tick (3.8, src/controls/
#                               sequence_node.cpp, fallback_node.cpp): 4's Sequence and Fallback
#                               without the SKIPPED branches (neither yields after a child)
#     ReactiveSequence,         ReactiveSequence::tick / ReactiveFallback::tick (3.8, src/controls/
#     ReactiveFallback          reactive_sequence.cpp, reactive_fallback.cpp): a RUNNING child halts
#                               every other child, as 4.8's do (4.0 to 4.x changed which: BT.CPP
#                               issue #755; the v4 rule is 4.8.2's)
#     IfThenElse                IfThenElseNode::tick (3.8, src/controls/if_then_else_node.cpp)
#     Inverter, ForceSuccess,   InverterNode::tick (src/decorators/inverter_node.cpp),
#     ForceFailure,             force_success_node.h, force_failure_node.h,
#     KeepRunningUntilFailure   keep_running_until_failure_node.h (3.8)
#     Timeout                   TimeoutNode::tick (3.8, decorators/timeout_node.h): the timer's
#                               callback halts the RUNNING child from the timer thread and the next
#                               tick returns FAILURE; the rule halts it at that next tick, before
#                               the FAILURE, as 4 does (the halt's place among the events of nodes
#                               ticked earlier in that tick is the one thing it does not follow)
#     Delay                     DelayNode::tick (3.8, src/decorators/delay_node.cpp): RUNNING until
#                               the timer fired, then the child (delay_msec="0" may fire before the
#                               first tick's check in 3.8, a race the rule leaves out: RUNNING first)
#     SubTree, SubTreePlus      SubtreeNode::tick / SubtreePlusNode::tick (3.8, src/decorators/
#                               subtree_node.cpp); their remapping: semantics._call_identity_v3
#     AlwaysSuccess, AlwaysFailure, SetBlackboard (3.8, actions/*.h; SetBlackboard a "script" event)
#     PipelineSequence, RecoveryNode, RoundRobin, RateController: Nav2's nodes; Nav2's migration to
#                               BT.CPP 4 (ros-navigation/navigation2 efd777e20) changed them only to
#                               handle SKIPPED
#
# Different from 4 (below):
#     SequenceStar              SequenceStarNode (3.8, src/controls/sequence_star_node.cpp): 4's
#                               SequenceWithMemory, but it never returns RUNNING after a child that
#                               succeeded, and halt() forgets the index (current_child_idx_ = 0)
#     Parallel                  ParallelNode::tick (3.8, src/controls/parallel_node.cpp)
#     WhileDoElse               WhileDoElseNode::tick (3.8): exactly 3 children
#     Switch2..Switch6          SwitchNode<N>::tick (3.8, controls/switch_node.h): `variable ==
#                               value` as strings (4 compares numbers as numbers)
#     Repeat, RetryUntilSuccessful  RepeatNode::tick / RetryNode::tick (3.8, src/decorators/
#                               repeat_node.cpp, retry_node.cpp): the loop runs within one tick
#                               (4 returns RUNNING between two turns after a child that completed
#                               at once, with the wake-up signal)
#     BlackboardCheckInt, ...Double, ...String, ...Bool   BlackboardPreconditionNode<T>::tick (3.8,
#                               decorators/blackboard_precondition.h)
#
# Not registered by 3.8, so not here: RetryUntilSuccesful (3.8 comments its registration out),
# ManualSelector (only where ncurses was found when 3.8 was built; opaque if a program has it),
# and 4's SequenceWithMemory, Script, Precondition, RunOnce, ... (formats/btxml.py refuses them).

def _threshold_v3(value: int, count: int) -> int:
    """ParallelNode::successThreshold / failureThreshold (3.8): a negative value counts from the
    number of children (size_t arithmetic: below -count-1 it wraps to a huge number, which the
    tick then refuses)."""
    if value >= 0:
        return value
    total = count + value + 1
    return total if total >= 0 else 2 ** 64 + total


def _parallel_v3(run: _Run, n: PNode) -> Status:
    # ParallelNode::tick (3.8, src/controls/parallel_node.cpp): success_threshold (no default: a
    # missing one throws), failure_threshold (default 1). Every tick counts again, child by child
    # in order: a child that completed before (skip_list_) is not ticked but counted by its
    # status, a child ticked now by its new one; SUCCESS as soon as the count of successes so far
    # reaches the threshold, FAILURE as soon as failures so far exceed children - success
    # threshold or reach the failure threshold. 4 keeps the counts across ticks, so a child after
    # the one that completes the count is ticked here and not in 4.
    count = len(n.kids)
    _required(n, "success_threshold", "ParallelNode")
    s_req = _threshold_v3(_int(n, "success_threshold", 1), count)
    f_req = _threshold_v3(_int(n, "failure_threshold", 1), count)
    if count < s_req:
        raise TreeError("Number of children is less than threshold. Can never succeed.")
    if count < f_req:
        raise TreeError("Number of children is less than threshold. Can never fail.")
    run.set_status(n, RUNNING)
    done = set(run.get(n, "completed", ()))
    succ = fail = 0
    for i, child in enumerate(n.kids):
        s = run.status(child) if i in done else run.tick(child)
        if s is SUCCESS:
            done.add(i)
            succ += 1
            if succ == s_req:
                run.put(n, "completed", ())
                run.reset_children(n)
                return SUCCESS
        elif s is FAILURE:
            done.add(i)
            fail += 1
            if fail > count - s_req or fail == f_req:
                run.put(n, "completed", ())
                run.reset_children(n)
                return FAILURE
        elif s is not RUNNING:
            raise TreeError("A child node must never return IDLE")
    run.put(n, "completed", tuple(sorted(done)))
    return RUNNING


def _while_do_else_v3(run: _Run, n: PNode) -> Status:
    # WhileDoElseNode::tick (3.8, src/controls/while_do_else_node.cpp): 4's with three children
    # only ("WhileDoElse must have 3 children")
    if len(n.kids) != 3:
        raise TreeError("WhileDoElse must have 3 children")
    return _while_do_else(run, n)


def _same_text(a: str, b: str) -> bool:
    """SwitchNode<N>::tick (3.8): `variable == value`, two std::strings."""
    return a == b


_PORT_TYPES = {"Int": "int", "Double": "double", "String": "text", "Bool": "bool"}


def _same_value(kind: str, a: str, b: str) -> bool:
    """BlackboardPreconditionNode<T> (3.8): both literals read as T (getInput fails, a mismatch,
    where the conversion throws) and compared with IsSame (doubles within float's epsilon)."""
    x, y = convert(_PORT_TYPES[kind], a), convert(_PORT_TYPES[kind], b)
    if x is None or y is None:
        return False
    if kind == "Double":
        return abs(x - y) <= 1.1920928955078125e-07
    return x == y


def _blackboard_check(kind: str) -> Rule:
    """BlackboardPreconditionNode<T>::tick (3.8, decorators/blackboard_precondition.h): the child
    while value_A equals value_B; otherwise the child is halted if RUNNING and the node returns
    return_on_mismatch (default FAILURE). A value from the blackboard is the environment's
    choice: whether the two are equal is a "check" event."""
    def tick(run: _Run, n: PNode) -> Status:
        run.set_status(n, RUNNING)
        a, b = n.node.attr("value_A"), n.node.attr("value_B")
        if a is None or b is None:
            same = False                           # getInput fails: a mismatch
        elif _is_ref(a) or _is_ref(b):
            same = run.check(n, f"{a} == {b}", f"BlackboardCheck{kind}")
        else:
            same = _same_value(kind, a, b)
        if same:
            return run.tick(n.kids[0])
        if run.status(n.kids[0]) is RUNNING:
            run.halt_child(n, 0)
        otherwise = n.node.attr("return_on_mismatch")
        if otherwise == "IDLE":
            raise TreeError(f"{n.node.type} {n.node.name!r}: return_on_mismatch=\"IDLE\": A child node must never "
                            f"return IDLE (its parent throws)")
        # convertFromString<NodeStatus> throws on anything else, getInput fails: FAILURE stays
        return Status(otherwise) if otherwise in ("RUNNING", "SUCCESS", "FAILURE") else FAILURE
    return Rule(tick, None, ("return_on_mismatch",))


RULES_V3: Mapping[str, Rule] = MappingProxyType({
    # the same rules as 4's (see the module's docstring)
    **{t: RULES[t] for t in ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "IfThenElse",
                             "Inverter", "ForceSuccess", "ForceFailure", "KeepRunningUntilFailure", "Timeout",
                             "Delay", "SubTree", "AlwaysSuccess", "AlwaysFailure", "SetBlackboard",
                             "PipelineSequence", "RecoveryNode", "RoundRobin", "RateController")},
    "SubTreePlus": RULES["SubTree"],
    # 3.8's own
    "SequenceStar": _sequence_like(fallback=False, memory=True, yields=False, keep_on_halt=False),
    "Parallel": Rule(_parallel_v3, _parallel_halt, ("success_threshold", "failure_threshold")),
    "WhileDoElse": Rule(_while_do_else_v3),
    **{f"Switch{k}": _switch(k, _same_text) for k in range(2, 7)},
    "Repeat": Rule(_looping("num_cycles", "count", SUCCESS, yields=False), _forgetting("count"), ("num_cycles",)),
    "RetryUntilSuccessful": Rule(_looping("num_attempts", "tries", FAILURE, yields=False), _forgetting("tries"),
                                 ("num_attempts",)),
    **{f"BlackboardCheck{k}": _blackboard_check(k) for k in _PORT_TYPES},
})

# The table's types that 3.8 implements as a DecoratorNode (its executeTick resets a completed child)
DECORATOR_TYPES_V3 = frozenset({"Inverter", "ForceSuccess", "ForceFailure", "KeepRunningUntilFailure",
                                "RetryUntilSuccessful", "Repeat", "Timeout", "Delay", "SubTree", "SubTreePlus",
                                "RateController", *(f"BlackboardCheck{k}" for k in _PORT_TYPES)})

__all__ = ["RULES_V3", "DECORATOR_TYPES_V3"]
