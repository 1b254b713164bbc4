"""The public objects pickle, and still work unpickled (issue 46: multiprocessing and Dask send
tasks and reports between processes; a compiled condition, a clause's compiled code and a run's
generator made every one of them fail with "Can't pickle local object")."""

from __future__ import annotations

import multiprocessing
import pickle

import pytest
from conftest import COFFEE, MIX

import schemalog
from schemalog.api.knowledge import QueryError
from schemalog.logic.parse import parse_term
from schemalog.testing import NotProved, assert_equivalent


def round_trip(value):
    return pickle.loads(pickle.dumps(value))


@pytest.fixture(scope="module")
def kb():
    return schemalog.load(MIX)


def test_a_task_unpickled_still_compresses_and_proves(kb):
    task = kb.task()
    task.run()                       # the knowledge's compiled clauses and checks are caches
    copy = round_trip(task)
    assert repr(copy) == repr(task) and copy.to_prolog() == task.to_prolog()
    small = copy.compress()
    assert (len(small), schemalog.verify(copy, small).verdict) == (6, "proved")
    assert copy.verify().proved and copy.run().trace == task.run().trace


def test_a_compressed_task_keeps_its_original_and_figures(kb):
    small = round_trip(kb.task().compress())
    assert small.compressed and len(small.original) == 12
    assert small.compression.figures() == "Bi = 12, Bm = 6, D = 3, RD = (Bi - Bm) / (Bi - D) = 0.67"
    assert round_trip(small.compression) == small.compression


def test_a_report_unpickled_renders_its_counterexample():
    task = schemalog.load(COFFEE).task()
    for method in ("symbolic", "explicit"):
        report = schemalog.verify(task, task.compress("none"), method=method, states="all")
        copy = round_trip(report)
        assert (copy.verdict, copy.text(), copy.as_json()) == ("refuted", report.text(), report.as_json())
        assert copy.counterexample == report.counterexample and round_trip(report.counterexample).text()


def test_knowledge_unpickled_answers_queries_with_what_was_asserted(kb):
    list(kb.query("assertz(seen(cup))"))
    copy = round_trip(kb)
    assert copy.files == kb.files and copy.tasks() == ["use(spoon)"]
    assert list(copy.query("seen(X)")) == [{"X": "cup"}]
    assert [a["N"] for a in copy.query("merged(T, B, Parts), length(Parts, N), N > 2")] == [5]


def test_a_run_pickles_before_during_and_after(kb):
    small = kb.task().compress()
    finished = small.run()
    assert round_trip(finished).text() == finished.text()
    started = small.start()
    first = next(iter(started))
    copy = round_trip(started)
    assert repr(round_trip(small.start())).endswith("not started>")
    assert copy.status == "running" and len(copy.decisions) == 1          # as far as it had gone
    assert copy.finish().completed and copy.decisions[0].behaviour == first.behaviour
    assert copy.trace == finished.trace


def test_findings_and_errors_keep_what_they_say():
    stuck = schemalog.loads("task(t).\nschema(t, [(a, b.done)], a.done).\nschema(a, [], a.done).\n", name="stuck.pl")
    findings = stuck.lint()
    assert round_trip(findings) == findings
    errors = [schemalog.SchemalogError("bad", schemalog.SourcePos("f.pl", 2, 3), "schema(t"),
              schemalog.UsageError("wrong"), schemalog.LimitExceeded("time limit of 1 s exceeded", "time"),
              QueryError("uncaught", parse_term("error(type_error(integer, a), context(foo/1, _))"))]
    with pytest.raises(schemalog.SchemalogError) as broken:
        schemalog.loads("schema(t, [(a, true)], a.done", name="broken.pl")
    errors.append(broken.value)
    for error in errors:
        copy = round_trip(error)
        assert (type(copy), str(copy)) == (type(error), str(error))
        assert {k: v for k, v in vars(copy).items() if k != "term"} == \
            {k: v for k, v in vars(error).items() if k != "term"}
    # a term's variables are fresh ones in the copy, as in any term read again
    assert round_trip(errors[3]).term.args[0] == errors[3].term.args[0]


def test_not_proved_keeps_its_report():
    task = schemalog.load(MIX).task()
    with pytest.raises(NotProved) as failed:
        assert_equivalent(task, task.compress("none"))
    copy = round_trip(failed.value)
    assert str(copy) == str(failed.value) and copy.report.verdict == "refuted"


def _prove(task):
    return schemalog.verify(task, task.compress())


def test_a_task_goes_to_another_process_and_its_report_comes_back(kb):
    # spawn: the child imports schemalog afresh, as a Dask worker or a process pool on macOS does
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        report = pool.apply(_prove, (kb.task(),))
    assert report.proved and report.tasks[1].compressed
