"""bt/ports.py: BT.CPP 4.8.2's own node ports and its reading of port text (convertFromString).

What BT.CPP itself does with the same nodes is checked in tests/bt/test_btcpp_harness.py
(test_btcpp_and_schemalog_refuse_the_same_attributes_of_btcpp_nodes)."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from schemalog.bt.ports import convert, is_blackboard, is_port_name, refusal


@pytest.mark.parametrize("text,value", [
    ("3", 3), ("-0", 0), ("3.5", 3), ("7 apples", 7), ("00012", 12), ("-2147483648", -2**31),
    (" 3", None), ("+3", None), ("", None), ("x", None), ("-", None), ("2147483648", None),
    ("99999999999999999999", None)])
def test_an_int_is_the_longest_prefix_std_from_chars_reads_within_bounds(text, value):
    assert convert("int", text) == value


def test_unsigned_ports_refuse_negatives_and_keep_32_bits():
    assert (convert("unsigned", "-1"), convert("unsigned", "4294967295"), convert("unsigned", "4294967296")) == \
        (None, 2**32 - 1, None)


@given(st.from_regex(r"-?[0-9]{1,9}", fullmatch=True), st.text(max_size=5).filter(lambda t: not t[:1].isdigit()))
def test_digits_and_any_tail_read_as_the_digits(digits, tail):
    assert convert("int", digits + tail) == int(digits)


@given(st.text(min_size=1, max_size=4).map(lambda t: " " + t))
def test_leading_space_never_reads_as_an_int(text):
    assert convert("int", text) is None


@pytest.mark.parametrize("text,value", [
    ("0", False), ("1", True), ("true", True), ("TRUE", True), ("True", True), ("False", False),
    ("tRue", None), ("yes", None), (" true", None), ("", None)])
def test_booleans_in_the_spellings_bt_cpp_knows(text, value):
    assert convert("bool", text) == value


@pytest.mark.parametrize("text,value", [
    (" 1.5e3x", 1500.0), (".5", 0.5), ("0x10", 16.0), ("0x1p4", 16.0), ("-inf", float("-inf")),
    ("1e999", None), ("1e-400", None), ("2e-310", None), ("abc", None), ("", None),
    ("0x1p1024", None), ("0x1p-1074", 2**-1074), ("0x1.8p-1074", None)])      # an exact subnormal loads
def test_doubles_as_std_stod_reads_them(text, value):
    assert convert("double", text) == value


def test_statuses_are_spelled_exactly_and_queues_read_part_by_part():
    assert convert("status", "SUCCESS") == "SUCCESS" and convert("status", "success") is None
    assert convert("queue:int", "1;2;") == (1, 2) and convert("queue:int", "1;;2") is None
    assert convert("queue:text", "a;;b") == ("a", "", "b") and convert("queue:int", "") == ()


def test_port_names_and_blackboard_entries_as_bt_cpp_tells_them():
    assert is_port_name("msec") and is_port_name("Name")
    assert not any(is_port_name(k) for k in ("name", "ID", "_skipIf", "_description", "1a", ""))
    assert is_blackboard("{n}") and is_blackboard("{=}") and not is_blackboard("{}") and not is_blackboard(" {n}")


@pytest.mark.parametrize("node_type,attrs,words", [
    ("Sequence", (("foo", "1"),), "port with name [foo]"),
    ("Switch2", (("case_3", "a"),), "port with name [case_3]"),
    ("Sleep", (("msec", "-1"),), "can not be converted to unsigned int"),
    ("Repeat", (("num_cycles", "{}"),), "can not be converted to int"),
    ("LoopInt", (("queue", "1;;2"),), "a queue of int"),
    ("Script", (), "Missing port [code]"),
    ("WaitValueUpdate", (("entry", ""),), "Missing port 'entry'"),
    ("LoopBool", (("if_empty", "SUCCESS"),), "[queue] not found")])
def test_what_bt_cpp_refuses_when_it_creates_the_node(node_type, attrs, words):
    assert words in refusal(node_type, attrs)


@pytest.mark.parametrize("node_type,attrs", [
    ("Sequence", (("name", "x"), ("_description", "y"), ("_skipIf", "a > 1"))),
    ("Repeat", (("num_cycles", "3.5"),)), ("Repeat", (("num_cycles", "{n}"),)),
    ("Precondition", (("if", "x"), ("else", "success"))),      # an enum: read only when ticked
    ("Script", (("code", ""),)), ("SetBlackboard", ()), ("LoopDouble", (("queue", " nan;0x1p3"),)),
    ("MyCustomNode", (("anything", "goes"),)), ("SubTree", (("ID", "S"), ("x", "{y}")))])
def test_what_bt_cpp_loads(node_type, attrs):
    assert refusal(node_type, attrs) is None


def test_the_module_examples_hold():
    import doctest

    from schemalog.bt import ports
    result = doctest.testmod(ports)
    assert result.attempted >= 1 and result.failed == 0
