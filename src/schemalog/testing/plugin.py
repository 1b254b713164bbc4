"""The pytest plugin: `pytest --schemalog-tasks DIR` proves every task of every task file under DIR.

Registered as the entry point `schemalog` (pyproject.toml, `pytest11`), so an installed
schemalog adds it to every pytest run; it does nothing unless `--schemalog-tasks` (or the ini
option `schemalog_tasks`) names a folder or a file. Then each task file under it (`*.pl`, and
SEED memories `*.prolog`; hidden folders skipped) is loaded and gives one test item per task:
the tasks it declares with task/1, or, when it declares none (a SEED memory), its first root
schema, the task `schemalog query` takes (the first ground schema head with sub-tasks that no
schema of the file uses as a sub-task); a file with neither gives no item and is named in the
summary. Each item compresses its task (`--schemalog-propagate`,
default full), or takes a compressed file as it is (proved against its provenance), and proves
it: it fails with the report `schemalog verify` prints, the counterexample or the vacuity cause.

Importing this module imports only pytest and the standard library (docs/testing.md).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterator

import pytest

SUFFIXES = (".pl", ".prolog")
PROPAGATE = ("none", "pre", "full")
_SKIPPED = pytest.StashKey[list]()

# the tasks a file declares, as text; without any, its first root schema (schemalog query's
# choice): a ground schema head with sub-tasks that no schema of the file uses as a sub-task
DECLARED = "current_predicate(task/1), task(T), term_to_atom(T, A)"
ROOTS = ("current_predicate(schema/3), schema(H, L, _), L \\== [], ground(H), "
         "\\+ (schema(_, L2, _), member((S, _), L2), S = H), term_to_atom(H, A)")


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("schemalog", "schemalog: prove the compression of task files")
    group.addoption("--schemalog-tasks", action="append", default=[], metavar="PATH", dest="schemalog_tasks",
                    help="prove every task in the task files (*.pl, SEED *.prolog) under PATH, a folder or a "
                         "file: one test per task (repeatable; replaces the ini option schemalog_tasks)")
    group.addoption("--schemalog-propagate", choices=PROPAGATE, default=None, dest="schemalog_propagate",
                    help="how the tasks are compressed before the proof (default full; ini schemalog_propagate)")
    group.addoption("--schemalog-states", default=None, metavar="default|all|ATOMS", dest="schemalog_states",
                    help="initial states each proof covers, as schemalog verify --states (default: the "
                         "file's initial/1; ini schemalog_states)")
    parser.addini("schemalog_tasks", type="paths", default=[],
                  help="folders or files whose tasks are proved, as --schemalog-tasks (relative to the ini file)")
    parser.addini("schemalog_propagate", default="full", help="none, pre or full (default full)")
    parser.addini("schemalog_states", default="default", help="default, all, or atoms such as 'hand.free'")


def _settings(config: pytest.Config) -> tuple[list[Path], str, str]:
    """(paths, propagate, states): the command line's, else the ini file's."""
    given = config.getoption("schemalog_tasks")
    paths = [Path(p) for p in given] if given else [Path(p) for p in config.getini("schemalog_tasks")]
    propagate = config.getoption("schemalog_propagate") or config.getini("schemalog_propagate").strip() or "full"
    if propagate not in PROPAGATE:
        raise pytest.UsageError(f"schemalog_propagate: {propagate!r} is not one of none, pre, full")
    states = config.getoption("schemalog_states") or config.getini("schemalog_states").strip() or "default"
    return paths, propagate, states


def pytest_configure(config: pytest.Config) -> None:
    paths, _, _ = _settings(config)
    for path in paths:
        if not path.exists():
            raise pytest.UsageError(f"--schemalog-tasks: {path}: no such folder or file")
    config.stash[_SKIPPED] = []


def pytest_report_header(config: pytest.Config) -> str | None:
    paths, propagate, states = _settings(config)
    if not paths:
        return None
    here = config.invocation_params.dir
    shown = ", ".join(p.relative_to(here).as_posix() if p.is_absolute() and p.is_relative_to(here) else str(p)
                      for p in paths)
    return f"schemalog: proving the tasks under {shown} (propagate {propagate}, states {states})"


def task_files(paths: list[Path]) -> Iterator[Path]:
    """The task files under `paths`, each once, in a stable order."""
    seen: set[Path] = set()
    for path in paths:
        found = [path] if path.is_file() else sorted(
            p for p in path.rglob("*") if p.suffix in SUFFIXES and p.is_file()
            and not any(part.startswith(".") for part in p.relative_to(path).parts))
        for file in found:
            if file.resolve() not in seen:
                seen.add(file.resolve())
                yield file


@pytest.hookimpl(tryfirst=True)   # before -k and -m deselect
def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list) -> None:
    paths, _, _ = _settings(config)
    for file in task_files(paths):
        items.extend(session.genitems(TaskFile.from_parent(session, path=file.resolve())))


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    skipped = config.stash.get(_SKIPPED, [])
    for file in skipped:
        terminalreporter.write_line(f"schemalog: {file}: no task/1 and no root schema: no task to prove")


class TaskFile(pytest.File):
    """A task file: one item per task."""

    knowledge: Any = None

    def collect(self) -> Iterator[pytest.Item]:
        import schemalog

        self.knowledge = schemalog.load(str(self.path))
        names = _texts(self.knowledge, DECLARED) or _texts(self.knowledge, ROOTS)[:1]
        if not names:
            self.config.stash[_SKIPPED].append(self.nodeid)
        for name in names:
            yield TaskItem.from_parent(self, name=name)

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        from schemalog import SchemalogError

        if isinstance(excinfo.value, SchemalogError):
            return str(excinfo.value)
        return super().repr_failure(excinfo)


def _texts(knowledge: Any, goal: str) -> list[str]:
    """The answers' A, each once, in the order found."""
    return list(dict.fromkeys(str(answer["A"]) for answer in knowledge.query(goal)))


class TaskItem(pytest.Item):
    """One task of a task file, compressed and proved."""

    def runtest(self) -> None:
        from . import assert_compression_sound

        _, propagate, states = _settings(self.config)
        task = self.parent.knowledge.task(self.name)
        self.report = assert_compression_sound(task, propagate=propagate, states=states)

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        from schemalog import SchemalogError

        if isinstance(excinfo.value, (AssertionError, SchemalogError)):
            return str(excinfo.value).rstrip("\n")
        return super().repr_failure(excinfo)

    def reportinfo(self) -> tuple[Path, int | None, str]:
        # the failure's title; pytest's -v line stays the node id, which does not end with it
        return self.path, None, f"{self.name} in {self.parent.nodeid}"
