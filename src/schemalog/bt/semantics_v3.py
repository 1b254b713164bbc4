"""BehaviorTree.CPP 3.8's tick semantics: the node table a document read under 3.8 runs under
(Document.version 3; docs/behaviour_trees.md, "BT.CPP 3 files").

    RULES_V3: type -> Rule        one rule per node type 3.8's BehaviorTreeFactory registers

The source is BehaviorTree.CPP's tag 3.8.8 (commit 9d624dc7; its src/ and include/ are those of
3.8.7): src/bt_factory.cpp (BehaviorTreeFactory::BehaviorTreeFactory registers the types),
src/controls/*.cpp, src/decorators/*.cpp, include/behaviortree_cpp_v3/{controls,decorators,
actions}/*.h. Where 3.8 behaves as 4's rule, the rule is bt/semantics.py's own object (so a
subtree of such nodes can be taken whole across the two versions, bt/congruence.py); the rules
below are those that differ. What differs everywhere, in bt/semantics.py: 3.8 has no SKIPPED and
no pre/post-condition attributes (TreeNode::executeTick, 3.8's src/tree_node.cpp, ticks and sets
the status; _Run.tick), so no 3.8 node returns SKIPPED, an opaque one included.

Same as 4 (bt/semantics.py's rule, no SKIPPED arising):
    Sequence, Fallback        SequenceNode::tick / FallbackNode::tick (3.8, src/controls/
                              sequence_node.cpp, fallback_node.cpp): 4's Sequence and Fallback
                              without the SKIPPED branches (neither yields after a child)
    ReactiveSequence,         ReactiveSequence::tick / ReactiveFallback::tick (3.8, src/controls/
    ReactiveFallback          reactive_sequence.cpp, reactive_fallback.cpp): a RUNNING child halts
                              every other child, as 4.8's do (4.0 to 4.x changed which: BT.CPP
                              issue #755; the v4 rule is 4.8.2's)
    IfThenElse                IfThenElseNode::tick (3.8, src/controls/if_then_else_node.cpp)
    Inverter, ForceSuccess,   InverterNode::tick (src/decorators/inverter_node.cpp),
    ForceFailure,             force_success_node.h, force_failure_node.h,
    KeepRunningUntilFailure   keep_running_until_failure_node.h (3.8)
    Timeout                   TimeoutNode::tick (3.8, decorators/timeout_node.h): the timer's
                              callback halts the RUNNING child from the timer thread and the next
                              tick returns FAILURE; the rule halts it at that next tick, before
                              the FAILURE, as 4 does (the halt's place among the events of nodes
                              ticked earlier in that tick is the one thing it does not follow)
    Delay                     DelayNode::tick (3.8, src/decorators/delay_node.cpp): RUNNING until
                              the timer fired, then the child (delay_msec="0" may fire before the
                              first tick's check in 3.8, a race the rule leaves out: RUNNING first)
    SubTree, SubTreePlus      SubtreeNode::tick / SubtreePlusNode::tick (3.8, src/decorators/
                              subtree_node.cpp); their remapping: semantics._call_identity_v3
    AlwaysSuccess, AlwaysFailure, SetBlackboard (3.8, actions/*.h; SetBlackboard a "script" event)
    PipelineSequence, RecoveryNode, RoundRobin, RateController: Nav2's nodes; Nav2's migration to
                              BT.CPP 4 (ros-navigation/navigation2 efd777e20) changed them only to
                              handle SKIPPED

Different from 4 (below):
    SequenceStar              SequenceStarNode (3.8, src/controls/sequence_star_node.cpp): 4's
                              SequenceWithMemory, but it never returns RUNNING after a child that
                              succeeded, and halt() forgets the index (current_child_idx_ = 0)
    Parallel                  ParallelNode::tick (3.8, src/controls/parallel_node.cpp)
    WhileDoElse               WhileDoElseNode::tick (3.8): exactly 3 children
    Switch2..Switch6          SwitchNode<N>::tick (3.8, controls/switch_node.h): `variable ==
                              value` as strings (4 compares numbers as numbers)
    Repeat, RetryUntilSuccessful  RepeatNode::tick / RetryNode::tick (3.8, src/decorators/
                              repeat_node.cpp, retry_node.cpp): the loop runs within one tick
                              (4 returns RUNNING between two turns after a child that completed
                              at once, with the wake-up signal)
    BlackboardCheckInt, ...Double, ...String, ...Bool   BlackboardPreconditionNode<T>::tick (3.8,
                              decorators/blackboard_precondition.h)

Not registered by 3.8, so not here: RetryUntilSuccesful (3.8 comments its registration out),
ManualSelector (only where ncurses was found when 3.8 was built; opaque if a program has it),
and 4's SequenceWithMemory, Script, Precondition, RunOnce, ... (formats/btxml.py refuses them).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from schemalog.bt.ports import convert
from schemalog.bt.semantics import (FAILURE, RULES, RUNNING, SUCCESS, PNode, Rule, Status, TreeError, _forgetting,
                                    _int, _is_ref, _looping, _parallel_halt, _required, _Run, _sequence_like, _switch,
                                    _while_do_else)


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
