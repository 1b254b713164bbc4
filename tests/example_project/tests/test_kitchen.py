"""The example project's own tests: what a user of schemalog writes (docs/testing.md).

Every task under tasks/ is also proved by the schemalog pytest plugin (pyproject.toml,
schemalog_tasks), one test item per task, with no code here.
"""

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

import schemalog
from schemalog.testing import assert_compression_sound, assert_equivalent
from schemalog.testing.strategies import task_files, tasks

import kitchen_tasks

HERE = Path(__file__).resolve().parents[1]
SERVE = HERE / "tasks" / "serve_water.pl"
BROKEN = HERE / "broken" / "serve_water_compressed.pl"


def test_serve_water_compresses_soundly():
    report = assert_compression_sound(schemalog.load(str(SERVE)).task())
    assert report.proved and report.verdict == "proved"


def test_what_our_code_compresses_is_the_original_task():
    original = schemalog.load(str(SERVE)).task()
    assert_equivalent(original, kitchen_tasks.compressed(SERVE))


def test_the_hand_edited_compressed_file_is_refuted():
    broken = schemalog.load(str(BROKEN)).task()
    with pytest.raises(AssertionError, match="counterexample") as failure:
        assert_compression_sound(broken)
    assert "a3_a4_a5(bottle)" in str(failure.value)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(tasks(levels=(2, 4), max_behaviours=20))
def test_every_generated_task_compresses_soundly(task):
    assert_compression_sound(task)


@settings(max_examples=10, deadline=None)
@given(task_files(max_behaviours=12))
def test_every_generated_file_loads_with_one_task(text):
    assert schemalog.loads(text).tasks() == ["t0"]
