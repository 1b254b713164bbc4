"""A public call given what it cannot take raises a UsageError saying what to pass, never
Python's TypeError, AttributeError or ValueError from inside (issue 46, section 4)."""

from __future__ import annotations

import inspect
import pathlib

import numpy
import pytest
from conftest import MIX

import schemalog


@pytest.fixture(scope="module")
def kb():
    return schemalog.load(MIX)


@pytest.fixture(scope="module")
def task(kb):
    return kb.task()


# (call, what the message says): the list first
WRONG = [
    (lambda kb, t: schemalog.verify("table.pl", "table.pl"),
     "verify(): original is a str ('table.pl'); pass a Task (load the file first: schemalog.load('table.pl').task())"),
    (lambda kb, t: schemalog.verify(t, kb),
     "verify(): compressed is a Knowledge; pass a Task (a Knowledge's task is knowledge.task())"),
    (lambda kb, t: schemalog.verify(t, t, max_states="lots"), "verify(): max_states is a str ('lots'); pass an int of 1 or more"),
    (lambda kb, t: schemalog.loads(b"task(t)."), "loads(): text is bytes (b'task(t).'); pass a str (decode it first"),
    (lambda kb, t: schemalog.load(42), "load(): paths[0] is an int (42); pass a file name (a str or a pathlib.Path)"),
    (lambda kb, t: kb.task(123), "Knowledge.task(): name is an int (123); pass a str or None"),
    (lambda kb, t: kb.query(42), "Knowledge.query(): goal is an int (42); pass a str"),
    (lambda kb, t: t.run(scene=42), "Task.run(): scene is an int (42); pass a file name (a str or a pathlib.Path) or None"),
    (lambda kb, t: t.save(42), "Task.save(): path is an int (42); pass a file name"),
    (lambda kb, t: schemalog.load("a\x00b"), r"load(): paths[0] 'a\x00b' holds a NUL character, which no file name can"),
    (lambda kb, t: schemalog.loads("task(t).", name=123), "loads(): name is an int (123); pass a str"),
    # and their kin
    (lambda kb, t: schemalog.verify(pathlib.Path(MIX), t), "original is a PosixPath; pass a Task (load the file first"),
    (lambda kb, t: schemalog.verify(t, t, max_states=True), "max_states is a bool (True); pass an int of 1 or more"),
    (lambda kb, t: schemalog.verify(t, t, max_bdd_nodes=0), "max_bdd_nodes is 0; pass an int of 1 or more"),
    (lambda kb, t: schemalog.verify(t, t, scene=pathlib.Path("a\x00b.yaml")), "scene 'a\\x00b.yaml' holds a NUL"),
    (lambda kb, t: schemalog.load(b"kb/tasks/mix_with_spoon.pl"), "paths[0] is bytes"),
    (lambda kb, t: schemalog.loads("task(t).", name="a\x00b"), "name 'a\\x00b' holds a NUL character"),
    (lambda kb, t: kb.lint(task=3), "Knowledge.lint(): task is an int (3); pass a str or None"),
    (lambda kb, t: kb.check(lint="no"), "Knowledge.check(): lint is a str ('no'); pass True or False"),
    (lambda kb, t: kb.query("true", output=[]), "Knowledge.query(): output is a list; pass a function or None"),
    (lambda kb, t: t.compress(timeout=True), "Task.compress(): timeout is a bool (True); pass a number of seconds or None"),
    (lambda kb, t: t.compress(max_memory=1.5), "max_memory is a float (1.5); pass a size (bytes as an int, or a str"),
    (lambda kb, t: t.compress(propagat="pre"), ("Task.compress(): got an unexpected keyword argument 'propagat' "
                                                "(it takes propagate, sympy_budget, timeout, max_memory)")),
    (lambda kb, t: t.verify(kb), "Task.verify(): compressed is a Knowledge; pass a Task or None"),
    (lambda kb, t: t.run(fail="a1(spoon)"), "Task.run(): fail is a str ('a1(spoon)'); pass a list of str"),
    (lambda kb, t: t.run(state=["hand.free", 1]), "Task.run(): state holds an int (1); each of its items must be a str"),
    (lambda kb, t: t.start(retries=-1), "Task.start(): retries is -1; pass an int of 0 or more"),
    (lambda kb, t: t.run(max_decisions=2.0), "Task.run(): max_decisions is a float (2.0); pass an int of 1 or more or None"),
    (lambda kb, t: t.to_btcpp(retries="2"), "Task.to_btcpp(): retries is a str ('2'); pass an int of 0 or more"),
    (lambda kb, t: t.to_btcpp(node_types=7), "node_types is an int (7); pass a dict, a file name"),
    (lambda kb, t: t.text(1), "Task.text(): fmt is an int (1); pass a str"),
    (lambda kb, t: t.tree_text(width=0), "Task.tree_text(): width is 0; pass an int of 1 or more"),
]


@pytest.mark.parametrize("call, says", WRONG, ids=[says[:50] for _, says in WRONG])
def test_what_a_call_cannot_take_is_a_usage_error_saying_what_to_pass(kb, task, call, says):
    with pytest.raises(schemalog.UsageError) as err:
        call(kb, task)
    assert says in err.value.message
    assert isinstance(err.value, schemalog.SchemalogError) and err.value.exit_code == 2


def test_a_query_is_refused_when_called_not_when_its_answers_are_read(kb):
    with pytest.raises(schemalog.UsageError, match="goal is an int"):
        kb.query(42)                 # a generator's body runs at its first next(); the check does not wait


def test_an_iterator_of_atoms_is_read_once_and_passed_whole(task):
    given = task.run(fail=(label for label in ["a1(spoon)"]), fail_times=1)
    listed = task.run(fail=["a1(spoon)"], fail_times=1)
    assert given.trace == listed.trace and given.trace.count("a1(spoon)") == 1
    assert given.decisions[0].failed is not None
    assert task.run(state=iter(["hand.free"])).completed


def test_numpy_numbers_are_numbers(task):
    # a sweep's parameters often come out of numpy arrays
    assert schemalog.verify(task, task.compress(), max_states=numpy.int64(1000), timeout=numpy.float32(600)).proved
    assert task.to_btcpp(retries=numpy.int32(1)) == task.to_btcpp(retries=1)


PUBLIC_CLASSES = ("Knowledge", "Task", "Report", "Run", "Counterexample", "Compression", "TreeDocument",
                  "TreeCompression", "TreeProof")
# Task.instantiated builds a Task from the knowledge's insides (Knowledge.task() is the public
# way); Finding is the lint layer's, below the API, and its text(severity) takes a word only.
NOT_CHECKED = {"Task.instantiated"}


def _public_calls():
    for name in ("load", "loads", "verify", "read_tree", "compress_tree", "verify_trees"):
        yield name, getattr(schemalog, name)
    for cls_name in PUBLIC_CLASSES:
        for name, member in vars(getattr(schemalog, cls_name)).items():
            if name.startswith("_") or not callable(member) or f"{cls_name}.{name}" in NOT_CHECKED:
                continue
            yield f"{cls_name}.{name}", member


def test_every_public_call_that_takes_arguments_checks_them():
    unchecked = []
    for name, function in _public_calls():
        parameters = [p for p in inspect.signature(function).parameters if p != "self"]
        if parameters and not hasattr(function, "__wrapped__"):
            unchecked.append(name)
    assert not unchecked, f"public calls whose arguments are not @checked (api/arguments.py): {unchecked}"
