"""The pytest plugin: `pytest --schemalog-tasks DIR` proves every task of every task file under DIR.

Registered as the entry point `schemalog` (pyproject.toml, `pytest11`), so an installed
schemalog adds it to every pytest run; it does nothing unless `--schemalog-tasks` (or the ini
option `schemalog_tasks`) names a folder or a file. Then each task file under it (`*.pl`, and
SEED memories `*.prolog`; hidden folders skipped) is loaded and gives one test item per task:
the tasks it declares with task/1 (`Knowledge.declared()`), or, when it declares none (a SEED
memory), its first root candidate (`Knowledge.tasks()[:1]`, the task `schemalog query` takes);
a file with neither gives no item and is named in the summary, as is a file that is not
schemalog knowledge (a `#!` script, or a file that does not load and holds no `schema(`), and
one that is not read at all: a FIFO (the read would wait for a writer), a device (/dev/zero's
read would never end), a socket, a link loop or a link to nothing, or a file this process may
not read, each with what it is.
Collection only loads the files: each item instantiates, compresses (`--schemalog-propagate`,
default full; a compressed file is taken as it is and proved against its provenance) and
proves its task when it runs, and fails with the report `schemalog verify` prints.

Which folders are collected: those of --schemalog-tasks (which replaces the ini's), or the
ini's when pytest is given no path arguments; a path argument inside a task folder (the node id
`tasks/two.pl::t1` pytest prints) selects what it names there instead. A folder with no task
file is a usage error, and folders that give no item at all are a collection error.

Importing this module imports only pytest and the standard library (docs/testing.md).
"""

from __future__ import annotations

import errno
import os
import stat
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator

import pytest

SUFFIXES = (".pl", ".prolog")
PROPAGATE = ("none", "pre", "full")
MAX_STATES = 50_000          # schemalog verify's defaults (defaults.MAX_STATES, --max-bdd-nodes): the
MAX_BDD_NODES = 5_000_000    # plugin passes none unless asked; these are only shown (tests check them)
MIN_TIMEOUT, MAX_TIMEOUT = 0.001, 365 * 24 * 3600
_SETTINGS = pytest.StashKey["Settings"]()
_NOTES = pytest.StashKey[list]()
_SEEN = pytest.StashKey[set]()


@dataclass
class Settings:
    paths: list[Path]            # the folders and files named (absolute)
    source: str                  # "--schemalog-tasks" or "schemalog_tasks (ini)"
    modes: dict[Path, str]       # each path: "inject" (every file), "args" (what the arguments name), "off"
    propagate: str
    states: str
    verify: dict[str, Any]       # max_states, max_bdd_nodes: those set
    timeout: float | None

    def active(self) -> list[Path]:
        return [p for p in self.paths if self.modes[p] != "off"]


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
    group.addoption("--schemalog-max-states", default=None, metavar="N", dest="schemalog_max_states",
                    help=f"stop each proof after N states per tree, as schemalog verify --max-states (default "
                         f"{MAX_STATES:,}; ini schemalog_max_states)")
    group.addoption("--schemalog-max-bdd-nodes", default=None, metavar="N", dest="schemalog_max_bdd_nodes",
                    help=f"stop each proof past N decision-diagram nodes, as schemalog verify --max-bdd-nodes "
                         f"(default {MAX_BDD_NODES:,}; ini schemalog_max_bdd_nodes)")
    group.addoption("--schemalog-timeout", default=None, metavar="SECONDS", dest="schemalog_timeout",
                    help="fail an item whose instantiation, compression and proof take longer than this "
                         "(default: none, as schemalog verify; ini schemalog_timeout)")
    parser.addini("schemalog_tasks", type="paths", default=[],
                  help="folders or files whose tasks are proved, as --schemalog-tasks (relative to the ini "
                       "file; collected when pytest is given no path arguments)")
    parser.addini("schemalog_propagate", default="full", help="none, pre or full (default full)")
    parser.addini("schemalog_states", default="default", help="default, all, or atoms such as 'hand.free'")
    parser.addini("schemalog_max_states", default="", help=f"as --schemalog-max-states (default {MAX_STATES:,})")
    parser.addini("schemalog_max_bdd_nodes", default="",
                  help=f"as --schemalog-max-bdd-nodes (default {MAX_BDD_NODES:,})")
    parser.addini("schemalog_timeout", default="", help="as --schemalog-timeout, seconds (default: none)")


def _value(config: pytest.Config, name: str) -> tuple[str, str]:
    """(text, where): the command line's value, else the ini file's ('' when neither)."""
    given = config.getoption(f"schemalog_{name}")
    if given is not None:
        return str(given).strip(), f"--schemalog-{name.replace('_', '-')}"
    return str(config.getini(f"schemalog_{name}")).strip(), f"schemalog_{name} (ini)"


def _positive(config: pytest.Config, name: str) -> int | None:
    text, where = _value(config, name)
    if not text:
        return None
    try:
        value = int(text.replace("_", "").replace(",", ""))
    except ValueError:
        value = 0
    if value < 1:
        raise pytest.UsageError(f"{where}: {text!r} is not a positive whole number")
    return value


def _timeout(config: pytest.Config) -> float | None:
    text, where = _value(config, "timeout")
    if not text or text.lower() in ("none", "off"):
        return None
    try:
        value = float(text)
    except ValueError:
        raise pytest.UsageError(f"{where}: {text!r} is not a number of seconds") from None
    if not MIN_TIMEOUT <= value <= MAX_TIMEOUT:     # NaN and inf too
        raise pytest.UsageError(f"{where}: {text}: from {MIN_TIMEOUT:g} to {MAX_TIMEOUT:,} seconds")
    return value


def _within(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def _argument_paths(config: pytest.Config) -> list[Path]:
    """The paths of the command line's test arguments (`a/b.pl::t1` gives a/b.pl); none when
    pytest was given none (it then collects testpaths or the current folder)."""
    if config.args_source != pytest.Config.ArgsSource.ARGS:
        return []
    here = config.invocation_params.dir
    found = []
    for arg in config.args:
        part = str(arg).split("::")[0]
        if part.endswith("]") and "[" in part:
            part = part[:part.index("[")]
        found.append(Path(here, part).absolute())
    return found


def _decide(config: pytest.Config) -> Settings:
    here = config.invocation_params.dir
    given = config.getoption("schemalog_tasks")
    if given:
        paths, source = [Path(here, p).absolute() for p in given], "--schemalog-tasks"
    else:
        paths, source = [Path(p).absolute() for p in config.getini("schemalog_tasks")], "schemalog_tasks (ini)"
    paths = list(dict.fromkeys(paths))
    arguments = _argument_paths(config)
    modes = {}
    for path in paths:
        if any(_within(arg, path) for arg in arguments):
            modes[path] = "args"          # `pytest tasks/two.pl::t1`: what is named there, no more
        elif given or not arguments:
            modes[path] = "inject"        # every task under it, beside the test arguments
        else:
            modes[path] = "off"           # the ini's folders, with test paths named: not collected
    propagate, where = _value(config, "propagate")
    propagate = propagate or "full"
    if propagate not in PROPAGATE:
        raise pytest.UsageError(f"{where}: {propagate!r} is not one of none, pre, full")
    states = _value(config, "states")[0] or "default"
    verify = {key: value for key, value in (("max_states", _positive(config, "max_states")),
                                            ("max_bdd_nodes", _positive(config, "max_bdd_nodes")))
              if value is not None}
    return Settings(paths, source, modes, propagate, states, verify, _timeout(config))


def settings(config: pytest.Config) -> Settings:
    if _SETTINGS not in config.stash:
        config.stash[_SETTINGS] = _decide(config)
    return config.stash[_SETTINGS]


def pytest_configure(config: pytest.Config) -> None:
    config.stash[_NOTES] = []
    config.stash[_SEEN] = set()
    config.stash[_SETTINGS] = found = _decide(config)
    for path in found.paths:
        if not os.path.lexists(path):      # a link loop or a link to nothing is skipped, saying so
            raise pytest.UsageError(f"{found.source}: {_shown(config, path)}: no such folder or file")
        if found.modes[path] == "inject" and path.is_dir():
            files = list(task_files([path]))
            if not any(why is None for _, why in files):
                skipped = "".join(f"; {_shown(config, file)}: {why}" for file, why in files)
                raise pytest.UsageError(f"{found.source}: {_shown(config, path)}: no task files (*.pl, *.prolog) "
                                        f"in this folder: no task to prove{skipped}")


def _shown(config: pytest.Config, path: Path) -> str:
    here = config.invocation_params.dir
    return path.relative_to(here).as_posix() if path.is_relative_to(here) else str(path)


def pytest_report_header(config: pytest.Config) -> str | None:
    found = settings(config)
    if not found.active():
        return None
    shown = ", ".join(_shown(config, p) for p in found.active())
    limits = [f"{key.replace('_', ' ')} {value:,}" for key, value in found.verify.items()]
    if found.timeout is not None:
        limits.append(f"timeout {found.timeout:g} s")
    return (f"schemalog: proving the tasks under {shown} (propagate {found.propagate}, states "
            f"{found.states}{''.join(', ' + limit for limit in limits)})")


def task_files(paths: list[Path]) -> Iterator[tuple[Path, str | None]]:
    """The task files under `paths`, each once, in a stable order (a file named is one), each
    with why it is skipped unread (None: it is read)."""
    seen: set[Path] = set()
    for path in paths:
        found = [path] if not path.is_dir() else sorted(
            p for p in path.rglob("*") if p.suffix in SUFFIXES and not p.is_dir()
            and not any(part.startswith(".") for part in p.relative_to(path).parts))
        for file in found:
            why = unreadable(file)
            key = file.absolute() if why else file.resolve()      # a link loop has no resolved path
            if key not in seen:
                seen.add(key)
                yield file, why


def unreadable(file: Path) -> str | None:
    """What a task file is when it is not a regular file this process can read, and so is not
    read (a FIFO would block the read, a device such as /dev/zero never end it); else None."""
    try:
        mode = file.stat().st_mode
    except OSError as err:
        if err.errno == errno.ELOOP:
            return "a link loop: skipped"
        if file.is_symlink():
            return f"a link to {os.readlink(file)}, which does not exist: skipped"
        return f"cannot be read ({err.strerror}): skipped"
    if not stat.S_ISREG(mode):
        what = ("a FIFO (reading it would wait for a writer)" if stat.S_ISFIFO(mode) else
                "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else
                "a socket" if stat.S_ISSOCK(mode) else "not a regular file")
        return f"{f'a link to {os.path.realpath(file)}, ' if file.is_symlink() else ''}{what}: skipped"
    try:
        os.close(os.open(file, os.O_RDONLY | _NONBLOCK))
    except OSError as err:
        return f"cannot be read ({err.strerror}): skipped"
    return None


_NONBLOCK = getattr(os, "O_NONBLOCK", 0)   # a file that became a FIFO since it was looked at


def read_regular(file: Path) -> bytes:
    """A task file's bytes; OSError when it is no longer a regular file (never waiting on a
    FIFO that took its place)."""
    fd = os.open(file, os.O_RDONLY | _NONBLOCK)
    with os.fdopen(fd, "rb") as opened:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "no longer a regular file")
        return opened.read()


def _is_task_file(file: Path, folder: Path) -> bool:
    if file == folder:
        return True
    return (folder in file.parents and file.suffix in SUFFIXES
            and not any(part.startswith(".") for part in file.relative_to(folder).parts))


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> pytest.Collector | None:
    """A task file pytest meets under a task folder: when it walks the folder (no arguments), or
    is given the file or a task in it (`pytest tasks/two.pl::t1`, the rerun form)."""
    if _SETTINGS not in parent.config.stash:
        return None
    path = Path(file_path).absolute()
    if any(_is_task_file(path, folder) for folder in settings(parent.config).active()):
        return TaskFile.from_parent(parent, path=file_path)
    return None


@pytest.hookimpl(tryfirst=True)   # before -k and -m deselect
def pytest_collection_modifyitems(session: pytest.Session, config: pytest.Config, items: list) -> None:
    found = settings(config)
    seen = config.stash[_SEEN]
    injected = [p for p in found.paths if found.modes[p] == "inject"]
    notes = config.stash[_NOTES]
    for file, why in task_files(injected):
        if why is not None:
            notes.append(f"{_shown(config, file.absolute())}: {why}")
        elif file.absolute() not in seen:
            items.extend(session.genitems(TaskFile.from_parent(session, path=file.absolute())))
    active = found.active()
    if active and not any(isinstance(item, TaskItem) for item in items) and not session.testsfailed:
        # a check that covers nothing is no check: say so, and do not pass
        list(session.genitems(NoTask.from_parent(session, path=active[0], name=_shown(config, active[0]))))


def pytest_terminal_summary(terminalreporter: Any, config: pytest.Config) -> None:
    for note in config.stash.get(_NOTES, []):
        terminalreporter.write_line(f"schemalog: {note}")


class NoTask(pytest.File):
    """The task folders gave no item at all: a collection error saying so."""

    def collect(self) -> Iterator[pytest.Item]:
        shown = ", ".join(_shown(self.config, p) for p in settings(self.config).active())
        notes = self.config.stash[_NOTES]
        why = "".join(f"\n  {note}" for note in notes) or " no task file there"
        self.config.stash[_NOTES] = []      # said here
        raise self.CollectError(f"schemalog: no task to prove under {shown}:{why}")


class TaskFile(pytest.File):
    """A task file: one item per task."""

    knowledge: Any = None

    def collect(self) -> Iterator[pytest.Item]:
        from schemalog import SchemalogError

        self.config.stash[_SEEN].add(self.path.absolute())
        notes = self.config.stash[_NOTES]
        try:
            data = read_regular(self.path)
        except OSError as error:
            notes.append(f"{self.nodeid}: cannot be read ({error.strerror}): skipped")
            return
        first = data.split(b"\n", 1)[0]
        if first.startswith(b"#!") and b"swipl" not in first and b"prolog" not in first:
            notes.append(f"{self.nodeid}: a script ({first.decode(errors='replace').strip()}), "
                         f"not schemalog knowledge: skipped")
            return
        import schemalog

        try:
            self.knowledge = schemalog.load(str(self.path))
        except SchemalogError as error:
            if b"schema(" in data:
                raise                       # schemalog knowledge that does not load: a collection error
            notes.append(f"{self.nodeid}: does not load and holds no schema(: not schemalog knowledge, "
                         f"skipped ({str(error).splitlines()[0]})")
            return
        names = self.knowledge.declared() or self.knowledge.tasks()[:1]
        if not names:
            notes.append(f"{self.nodeid}: no task/1 and no root schema: no task to prove")
        typed = self._typed(names)
        for name in names:
            yield TaskItem.from_parent(self, name=typed.get(name, name))

    def _typed(self, names: list[str]) -> dict[str, str]:
        """The tasks of this file that the command line names in another spelling (`file::set('table')`
        for `set(table)`, `take( cup )` for `take(cup)`): each task's name -> the name as typed, so
        that pytest, which matches node ids as text, finds the item."""
        from schemalog import SchemalogError

        here = self.path.resolve()
        typed = {}
        for argument in self.config.args:
            path, sep, rest = str(argument).partition("::")
            part = rest.split("::")[0]
            if not sep or not part or part in names or Path(self.config.invocation_params.dir, path).resolve() != here:
                continue
            for name in names:
                try:
                    same = any(True for _ in self.knowledge.query(f"({part}) == ({name})", first=True))
                except SchemalogError:          # not a term: no task of this file, as pytest will say
                    break
                if same:
                    typed[name] = part
                    break
        return typed

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        from schemalog import SchemalogError

        if isinstance(excinfo.value, SchemalogError):
            return str(excinfo.value)
        return super().repr_failure(excinfo)


class TaskItem(pytest.Item):
    """One task of a task file: instantiated, compressed and proved when it runs."""

    def runtest(self) -> None:
        from schemalog import LimitExceeded

        from . import assert_equivalent

        found = settings(self.config)
        limit = found.timeout
        deadline = None if limit is None else time.monotonic() + limit

        def left() -> float | None:
            return None if deadline is None else max(deadline - time.monotonic(), MIN_TIMEOUT)

        try:
            task = self.parent.knowledge.task(self.name, timeout=left())
            if task.compressed:       # a file schemalog compress wrote: against its provenance
                original, compressed = task.original, task
            else:
                original, compressed = task, task.compress(found.propagate, timeout=left())
            self.report = assert_equivalent(original, compressed, states=found.states, timeout=left(),
                                            **found.verify)
            return
        except LimitExceeded as error:
            if error.limit != "time":
                raise
        pytest.fail(f"{self.name}: time limit of {limit:g} s exceeded (raise it with --schemalog-timeout "
                    f"or the ini option schemalog_timeout)", pytrace=False)

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        from schemalog import SchemalogError

        if isinstance(excinfo.value, (AssertionError, SchemalogError)):
            return str(excinfo.value).rstrip("\n")
        return super().repr_failure(excinfo)

    def reportinfo(self) -> tuple[Path, int | None, str]:
        # the failure's title; pytest's -v line stays the node id, which does not end with it
        return self.path, None, f"{self.name} in {self.parent.nodeid}"
