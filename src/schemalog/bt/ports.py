"""The ports of BT.CPP's own node types, and BT.CPP's reading of a port's text, so that a tree
BT.CPP refuses to load is refused here too and a literal port means here what it means there.

    PortType     = "int" | "unsigned" | "bool" | "double" | "status" | "text" | "any"
                   | "queue:int" | "queue:bool" | "queue:double" | "queue:text"
    BUILTIN: node type -> Kind                            (the types BT.CPP 4.8.2 registers itself)
    BUILTIN_PORTS: node type -> {port name: PortType}     (their providedPorts(); absent: none)
    convert(port_type, text) -> value | None               (None: BT.CPP's conversion throws)
    refusal(node_type, attrs) -> str | None                (why BT.CPP refuses the element's attributes)

BT.CPP checks a node's attributes when it creates the tree (XMLParser::createNodeFromXML, src/
xml_parsing.cpp): an attribute whose name starts with a letter and is not reserved (`name`, `ID`,
`_autoremap`, the `_`-scripts) is a port; a port the node type's providedPorts() does not declare
is refused ("a port with name [x] is found in the XML ... but not in the providedPorts() of its
registered node type"), and a literal value (not `{key}`) of a strongly typed port (not `any`, not
an enum such as NodeStatus, which is converted only when the node reads it) must convert ("The
port with name ... can not be converted to ..."). Script, ScriptCondition and Precondition read
their script in their constructor, so without it the tree does not load. The same conversion runs
again when the node reads the port, so the value here is the one the node works with. Not checked
here: whether a script parses (BT.CPP parses `code`, `if` and the `_`-scripts when it creates the
tree; schemalog leaves scripts uninterpreted).

The conversions are src/basic_types.cpp's convertFromString: integers by std::from_chars, which
reads the longest prefix ("3.5" is 3, "7 apples" is 7, " 3" and "+3" are refused) and then
checks the type's bounds; booleans and statuses by exact spelling; doubles by std::stod (a
prefix after leading space, refused when it overflows or is an inexact subnormal); queues
`a;b;c` part by part.

>>> convert("int", "3.5"), convert("int", "+3"), convert("unsigned", "-1"), convert("bool", "True")
(3, None, None, True)
"""

from __future__ import annotations

import re
import sys
from collections.abc import Mapping
from difflib import get_close_matches
from fractions import Fraction
from types import MappingProxyType

_INT32 = (-2**31, 2**31 - 1)
_UINT32 = (0, 2**32 - 1)
_DIGITS = re.compile(r"-?[0-9]+")
# std::stod through strtod: leading white space, a sign, then a decimal or hexadecimal number,
# inf/infinity or nan(chars); the longest such prefix is read
_DOUBLE = re.compile(r"[ \t\n\v\f\r]*([+-]?(?:0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?"
                     r"|(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
                     r"|[iI][nN][fF](?:[iI][nN][iI][tT][yY])?|[nN][aA][nN](?:\([0-9A-Za-z_]*\))?))")
STATUSES = ("IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED")


def _integer(text: str, bounds: tuple[int, int]) -> int | None:
    """convertFromString<int64_t> (from_chars: the longest prefix) then ConvertWithBoundCheck."""
    m = _DIGITS.match(text)
    if m is None:
        return None
    value = int(m.group())
    return value if bounds[0] <= value <= bounds[1] else None


def _exactly(number: str) -> Fraction:
    """The rational number a decimal or hexadecimal floating literal writes."""
    sign = -1 if number.startswith("-") else 1
    digits = number.lstrip("+-").lower()
    if not digits.startswith("0x"):
        return sign * Fraction(digits)
    mantissa, _, exponent = digits[2:].partition("p")
    whole, _, fraction = mantissa.partition(".")
    return sign * Fraction(int(whole + fraction or "0", 16), 16 ** len(fraction)) * Fraction(2) ** int(exponent or 0)


def _double(text: str) -> float | None:
    """std::stod: the longest number after leading white space; refused when strtod sets ERANGE,
    on overflow and on an inexact result below the smallest normal double (glibc)."""
    m = _DOUBLE.match(text)
    if m is None:
        return None
    number = m.group(1)
    digits = number.lstrip("+-").lower()
    if digits.startswith(("inf", "nan")):
        return float(digits[:3]) if number[0] != "-" else -float(digits[:3])
    try:
        value = float.fromhex(number) if digits.startswith("0x") else float(number)
    except OverflowError:                       # float.fromhex("0x1p1024")
        return None
    if value in (float("inf"), float("-inf")):
        return None
    if abs(value) < sys.float_info.min and Fraction(value) != _exactly(number):
        return None
    return value


def _bool(text: str) -> bool | None:
    """convertFromString<bool>: 0/1 and true/false in three spellings."""
    return {"0": False, "1": True, "true": True, "TRUE": True, "True": True,
            "false": False, "FALSE": False, "False": False}.get(text)


def convert(port_type: str, text: str):
    """Read `text` as BT.CPP reads a port of `port_type`; None when BT.CPP's conversion throws."""
    if port_type in ("text", "any"):
        return text
    if port_type == "int":
        return _integer(text, _INT32)
    if port_type == "unsigned":
        return _integer(text, _UINT32)
    if port_type == "bool":
        return _bool(text)
    if port_type == "double":
        return _double(text)
    if port_type == "status":
        return text if text in STATUSES else None
    if port_type.startswith("queue:"):
        # splitString(text, ';'): no part after a final ';', an empty part between two
        parts = text.split(";")
        if parts and parts[-1] == "":
            parts.pop()
        values = tuple(convert(port_type[6:], p) for p in parts)
        return None if None in values else values
    raise ValueError(f"unknown port type {port_type!r}")


# The node types BehaviorTreeFactory registers in BT.CPP 4.8.2 (src/bt_factory.cpp), by kind.
BUILTIN: Mapping[str, str] = MappingProxyType({
    **dict.fromkeys(("Sequence", "SequenceWithMemory", "ReactiveSequence", "Fallback", "ReactiveFallback",
                     "Parallel", "ParallelAll", "IfThenElse", "WhileDoElse", "Switch2", "Switch3", "Switch4",
                     "Switch5", "Switch6", "AsyncSequence", "AsyncFallback"), "Control"),
    **dict.fromkeys(("Inverter", "RetryUntilSuccessful", "KeepRunningUntilFailure",
                     "Repeat", "Timeout", "Delay", "RunOnce", "ForceSuccess", "ForceFailure", "Precondition",
                     "LoopInt", "LoopBool", "LoopDouble", "LoopString", "SkipUnlessUpdated",
                     "WaitValueUpdate"), "Decorator"),
    **dict.fromkeys(("AlwaysSuccess", "AlwaysFailure", "Script", "SetBlackboard", "UnsetBlackboard",
                     "Sleep"), "Action"),
    **dict.fromkeys(("ScriptCondition", "WasEntryUpdated"), "Condition"),
    "SubTree": "SubTree",
})


def _loop(element: str) -> dict[str, str]:
    # LoopNode<T>::providedPorts (decorators/loop_node.h)
    return {"queue": f"queue:{element}", "if_empty": "status", "value": element}


# BT.CPP 4.8.2's node types (BehaviorTreeFactory's constructor, src/bt_factory.cpp) and the ports
# each declares in providedPorts(); a type absent from the table declares none.
BUILTIN_PORTS: Mapping[str, Mapping[str, str]] = MappingProxyType({
    "Parallel": {"success_count": "int", "failure_count": "int"},        # controls/parallel_node.h
    "ParallelAll": {"max_failures": "int"},                               # controls/parallel_all_node.h
    # SwitchNode<N>::providedPorts (controls/switch_node.h): variable, case_1 .. case_N
    **{f"Switch{n}": {"variable": "text", **{f"case_{i}": "text" for i in range(1, n + 1)}}
       for n in range(2, 7)},
    "Delay": {"delay_msec": "unsigned"},                                  # decorators/delay_node.h
    "Timeout": {"msec": "unsigned"},                                      # decorators/timeout_node.h
    "Repeat": {"num_cycles": "int"},                                      # decorators/repeat_node.h
    "RetryUntilSuccessful": {"num_attempts": "int"},                      # decorators/retry_node.h
    "RunOnce": {"then_skip": "bool"},                                     # decorators/run_once_node.h
    "Precondition": {"if": "text", "else": "status"},                     # decorators/script_precondition.h
    "LoopInt": _loop("int"), "LoopBool": _loop("bool"), "LoopDouble": _loop("double"),
    "LoopString": _loop("text"),
    "SkipUnlessUpdated": {"entry": "any"}, "WaitValueUpdate": {"entry": "any"},   # updated_decorator.h
    "WasEntryUpdated": {"entry": "any"},                                  # actions/updated_action.h
    "Script": {"code": "text"},                                           # actions/script_node.h
    "ScriptCondition": {"code": "any"},                                   # actions/script_condition.h
    "SetBlackboard": {"value": "any", "output_key": "any"},               # actions/set_blackboard_node.h
    "UnsetBlackboard": {"key": "text"},                                   # actions/unset_blackboard_node.h
    "Sleep": {"msec": "unsigned"},                                        # actions/sleep_node.h
})
TYPE_NAMES = {"int": "int", "unsigned": "unsigned int", "bool": "bool", "double": "double",
               "status": "BT::NodeStatus", "text": "std::string"}
_EXAMPLES = {"int": "e.g. 3, or -1 where it means for ever", "unsigned": "milliseconds, e.g. 500",
             "bool": "true or false", "double": "e.g. 0.5", "queue:int": "e.g. 1;2;3", "queue:bool": "e.g. true;false",
             "queue:double": "e.g. 0.5;1.5", "queue:text": "e.g. a;b"}
RESERVED = frozenset({"name", "ID", "_autoremap", "_failureIf", "_successIf", "_skipIf", "_while",
                      "_onSuccess", "_onFailure", "_onHalted", "_post"})


# The node types BehaviorTreeFactory's constructor registers in BT.CPP 3.8 (3.8.8, src/bt_factory.cpp;
# ManualSelector only where ncurses was found, so not here: a program without it refuses the tag),
# and the ports each declares (providedPorts() in include/behaviortree_cpp_v3/...). RetryUntilSuccesful
# is not among them: 3.8 comments its registration out ("typo but back compatibility").
BUILTIN_V3: Mapping[str, str] = MappingProxyType({
    **dict.fromkeys(("Fallback", "Sequence", "SequenceStar", "Parallel", "ReactiveSequence", "ReactiveFallback",
                     "IfThenElse", "WhileDoElse", "Switch2", "Switch3", "Switch4", "Switch5", "Switch6"), "Control"),
    **dict.fromkeys(("Inverter", "RetryUntilSuccessful", "KeepRunningUntilFailure", "Repeat", "Timeout", "Delay",
                     "ForceSuccess", "ForceFailure", "BlackboardCheckInt", "BlackboardCheckDouble",
                     "BlackboardCheckString", "BlackboardCheckBool"), "Decorator"),
    **dict.fromkeys(("AlwaysSuccess", "AlwaysFailure", "SetBlackboard"), "Action"),
    "SubTree": "SubTree", "SubTreePlus": "SubTree",
})
BUILTIN_PORTS_V3: Mapping[str, Mapping[str, str]] = MappingProxyType({
    "Parallel": {"success_threshold": "int", "failure_threshold": "int"},   # controls/parallel_node.h
    **{f"Switch{n}": {"variable": "text", **{f"case_{i}": "text" for i in range(1, n + 1)}}
       for n in range(2, 7)},                                               # controls/switch_node.h
    "Delay": {"delay_msec": "unsigned"}, "Timeout": {"msec": "unsigned"},
    "Repeat": {"num_cycles": "int"}, "RetryUntilSuccessful": {"num_attempts": "int"},
    **{f"BlackboardCheck{t}": {"value_A": "any", "value_B": "any", "return_on_mismatch": "status"}
       for t in ("Int", "Double", "String", "Bool")},                      # decorators/blackboard_precondition.h
    "SetBlackboard": {"value": "any", "output_key": "any"},               # actions/set_blackboard_node.h
})
RESERVED_V3 = frozenset({"ID", "name", "_description"})                 # IsReservedPortname (basic_types.h)


def refusal_v3(node_type: str, attrs) -> str | None:
    """Why BT.CPP 3.8 refuses one of its own node types with these attributes, or None: every
    attribute but ID, name and _description must be a port the type declares
    (XMLParser::Pimpl::createNodeFromXML, src/xml_parsing.cpp, "Possible typo?"). 3.8 converts a
    literal only when the node reads it, so a value is not checked here."""
    if node_type not in BUILTIN_V3 or node_type in ("SubTree", "SubTreePlus"):
        return None
    ports = BUILTIN_PORTS_V3.get(node_type, {})
    for key, _ in attrs:
        if key not in RESERVED_V3 and key not in ports:
            near = get_close_matches(key, list(ports), n=1, cutoff=0.6)
            return (f"Possible typo? In the XML, you tried to remap port \"{key}\" in node [{node_type}], but the "
                    f"manifest of this node does not contain a port with this name (BT.CPP 3.8; {node_type} "
                    f"declares {', '.join(ports) if ports else 'no port'}){f'; did you mean {near[0]}?' if near else ''}")
    return None

def is_port_name(key: str) -> bool:
    """IsAllowedPortName: a port's name starts with an ASCII letter and is not reserved."""
    return key[:1].isascii() and key[:1].isalpha() and key not in RESERVED


def is_blackboard(value: str) -> bool:
    """A `{key}` value: a blackboard entry, converted when the node reads it, not at load."""
    return len(value) >= 3 and value[0] == "{" and value[-1] == "}"


# The ports whose absence a node's constructor throws on (an empty `entry` too): ScriptNode's and
# ScriptCondition's loadExecutor, PreconditionNode's constructor, EntryUpdatedDecorator's and
# EntryUpdatedAction's (src/decorators/updated_decorator.cpp, src/actions/updated_action.cpp),
# LoopNode's.
REQUIRED = MappingProxyType({
    "Script": ("code", False, "Missing port [code] in Script"),
    "ScriptCondition": ("code", False, "Missing port [code] in ScriptCondition"),
    "Precondition": ("if", False, "Missing parameter [if] in Precondition"),
    **{t: ("entry", True, f"Missing port 'entry' in {t}")
       for t in ("SkipUnlessUpdated", "WaitValueUpdate", "WasEntryUpdated")},
    # LoopNode's constructor: getRawPortValue("queue") (src/tree_node.cpp) throws without it
    **{t: ("queue", False, "[queue] not found") for t in ("LoopInt", "LoopBool", "LoopDouble", "LoopString")},
})


def refusal(node_type: str, attrs) -> str | None:
    """Why BT.CPP 4.8.2 refuses one of its own node types with these (key, value) attributes, or
    None (None too for a type it does not register: the robot's code declares those ports)."""
    if node_type not in BUILTIN:
        return None
    for key, value in attrs:
        why = attribute_error(node_type, key, value)
        if why is not None:
            return why
    if node_type in REQUIRED:
        port, empty_is_missing, message = REQUIRED[node_type]
        if all(k != port or (empty_is_missing and not v) for k, v in attrs):
            return f"{message} (BT.CPP)"
    return None


def attribute_error(node_type: str, key: str, value: str) -> str | None:
    """Why BT.CPP 4.8.2 refuses attribute key="value" on one of its own node types, or None."""
    if node_type == "SubTree" or not is_port_name(key):
        return None
    ports = BUILTIN_PORTS.get(node_type, {})
    if key not in ports:
        near = get_close_matches(key, [*ports, *sorted(RESERVED)], n=1, cutoff=0.6)
        return (f"a port with name [{key}] is found in the XML (<{node_type}>) but not in the providedPorts() "
                f"of its registered node type (BT.CPP; {node_type} declares "
                f"{', '.join(ports) if ports else 'no port'}){f'; did you mean {near[0]}?' if near else ''}")
    port_type = ports[key]
    # an enum (NodeStatus) has no converter (GetAnyFromStringFunctor): read only when ticked
    if port_type == "status" or is_blackboard(value) or convert(port_type, value) is not None:
        return None
    wanted = f"a queue of {TYPE_NAMES[port_type[6:]]}" if port_type.startswith("queue:") else TYPE_NAMES[port_type]
    return (f"The port with name \"{key}\" and value \"{value}\" can not be converted to {wanted} (BT.CPP; "
            f"{_EXAMPLES[port_type]})")
