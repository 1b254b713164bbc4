"""Check your own tasks in your own tests: assertions, hypothesis strategies, a pytest plugin.

    import schemalog
    from schemalog.testing import assert_compression_sound

    def test_my_task_compresses_soundly():
        assert_compression_sound(schemalog.load("tasks/pour.pl").task())

`assert_compression_sound` and `assert_equivalent` prove with `schemalog.verify` and, unless the
result is a proof, raise an AssertionError (NotProved) whose message is the report `schemalog
verify` prints: the counterexample, or why the task itself cannot complete, or the limit hit.
`assert_bt_equal` and `assert_bt_compresses` do the same for BT.CPP trees with
`schemalog.verify_trees` (TreesNotProved: the counterexample root tick by root tick). The strategies are in
`schemalog.testing.strategies` (they need hypothesis), the pytest plugin (`pytest
--schemalog-tasks DIR`) in `schemalog.testing.plugin`. docs/testing.md has an example suite.

This module uses only the public API (`import schemalog`) and imports nothing heavy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # annotations only: `import schemalog.testing` stays light
    from schemalog import Report, Task, TreeDocument, TreeProof

__all__ = ["NotProved", "TreesNotProved", "assert_bt_compresses", "assert_bt_equal", "assert_compression_sound",
           "assert_equivalent"]


class NotProved(AssertionError):
    """A verification that is no proof: its message is the report's text, `.report` the report."""

    def __init__(self, report: "Report") -> None:
        super().__init__(report.text())
        self.report = report

    def __reduce__(self):
        """Rebuild from the attributes (pytest-xdist, multiprocessing): unpickled by calling the
        class with `args`, it would be given the report's text where it takes the report."""
        import copyreg

        return copyreg.__newobj__, (type(self), *self.args), self.__dict__


def assert_compression_sound(task: "Task", *, propagate: str = "full", states: str = "default",
                             **verify_options: Any) -> "Report":
    """Compress `task` (with `propagate`) and prove the result sound and complete against it.

    A task that is already compressed (loaded from a file `schemalog compress` wrote, with its
    provenance) is proved against its own original instead, and `propagate` is not used.
    `states` and `verify_options` (method, max_states, max_bdd_nodes, split, scene) are those of
    `schemalog.verify`. Returns the report of a proof; raises NotProved (an AssertionError), with
    the report's text as its message and the report as `.report`, when the result is refuted (a
    counterexample), vacuous (the task itself cannot complete) or inconclusive (a limit stopped
    the search).
    """
    __tracebackhide__ = True  # pytest: the failure is the report, not this frame
    if task.compressed:
        original, compressed = task.original, task
    else:
        original, compressed = task, task.compress(propagate=propagate)
    return _proved(original, compressed, states=states, **verify_options)


def assert_equivalent(original: "Task", compressed: "Task", **verify_options: Any) -> "Report":
    """Prove `compressed` sound and complete against `original` (`schemalog.verify`'s options).

    Returns the report of a proof; raises NotProved (an AssertionError) with the report's text otherwise
    (refuted, vacuous or inconclusive), as assert_compression_sound does.
    """
    __tracebackhide__ = True
    return _proved(original, compressed, **verify_options)


def _proved(original: "Task", compressed: "Task", **verify_options: Any) -> "Report":
    __tracebackhide__ = True
    import schemalog

    report = schemalog.verify(original, compressed, **verify_options)
    if not report.proved:
        raise NotProved(report)
    return report


class TreesNotProved(NotProved):
    """Two BT.CPP trees not proved equal: the message is what `schemalog verify A.xml B.xml` prints
    (the counterexample root tick by root tick, or the limit that made it no proof), `.report`
    the TreeProof."""


def assert_bt_equal(original: "TreeDocument | str", compressed: "TreeDocument | str", **options: Any) -> "TreeProof":
    """Prove two BT.CPP trees equal under BT.CPP 4 semantics, as `schemalog verify A.xml B.xml`.

    Each is a file name (or several, one tree) or a TreeDocument from `schemalog.read_tree`;
    `options` are `schemalog.verify_trees`'s (nodes, semantics, profile, main, run_once,
    max_states, timeout). Returns the TreeProof of a proof; raises TreesNotProved (an
    AssertionError) with what `schemalog verify` prints when the trees are refuted or a limit cut
    the proof short.
    """
    __tracebackhide__ = True
    import schemalog

    return _trees_proved(schemalog.verify_trees(original, compressed, **options))


def assert_bt_compresses(tree: "TreeDocument | str", **options: Any) -> "TreeProof":
    """Compress a BT.CPP tree and prove the result equal to it, as `schemalog verify F.xml`.

    Passes exactly when that command exits 0: a tree with nothing to compress fails too (nothing
    was proved), as a refuted rewrite or a limit does, with the command's words. `options` as
    assert_bt_equal's, and `drop_names`. Returns the TreeProof; its `.compression` has the
    rewrites and the compressed tree (`.compression.xml()`).
    """
    __tracebackhide__ = True
    import schemalog

    return _trees_proved(schemalog.verify_trees(tree, **options))


def _trees_proved(proof: "TreeProof") -> "TreeProof":
    __tracebackhide__ = True
    if not proof.proved:
        raise TreesNotProved(proof)
    return proof
