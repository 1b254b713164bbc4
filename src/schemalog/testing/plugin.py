"""The pytest plugin: `pytest --schemalog-tasks DIR` proves every task of every task file under DIR;
`pytest --schemalog-trees DIR` proves every BT.CPP tree under DIR equal to its recorded version.

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

BT.CPP trees (--schemalog-trees, the ini option schemalog_trees, collected as the task folders
are): a tree `X.xml` with a recorded version beside it, `X.compressed.xml` (what `schemalog
compress X.xml -o X.compressed.xml` wrote) or `X.approved.xml` (a version someone approved), gives
one item per recorded version, `X.xml::X.compressed.xml`, that proves the two equal under BT.CPP 4
semantics as `schemalog verify X.xml X.compressed.xml` does, read with the nodes files, semantics
files and profiles of --schemalog-nodes, --schemalog-semantics and --schemalog-profile (or their
ini options). A failure is what that command prints: the counterexample root tick by root tick,
or the limit that made it no proof, or the file:line:column of a file that does not read.

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
RECORDED = ("compressed", "approved")     # X.xml's recorded versions: X.compressed.xml, X.approved.xml
PROPAGATE = ("none", "pre", "full")
MAX_STATES = 50_000          # schemalog verify's defaults (defaults.MAX_STATES, --max-bdd-nodes): the
MAX_BDD_NODES = 5_000_000    # plugin passes none unless asked; these are only shown (tests check them)
MIN_TIMEOUT, MAX_TIMEOUT = 0.001, 365 * 24 * 3600
_SETTINGS = pytest.StashKey["Settings"]()
_NOTES = pytest.StashKey[list]()
_SEEN = pytest.StashKey[set]()
_TREES = pytest.StashKey["TreeSettings"]()


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


@dataclass
class TreeSettings:
    paths: list[Path]            # the folders and files named (absolute)
    source: str                  # "--schemalog-trees" or "schemalog_trees (ini)"
    modes: dict[Path, str]       # as Settings.modes
    reading: dict[str, Any]      # read_tree's nodes, semantics, profile (those set)
    proving: dict[str, Any]      # verify_trees's run_once, max_states (those set)
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
    group.addoption("--schemalog-trees", action="append", default=[], metavar="PATH", dest="schemalog_trees",
                    help="prove every BT.CPP tree X.xml under PATH, a folder or a file, equal to its recorded "
                         "version beside it, X.compressed.xml or X.approved.xml: one test per pair (repeatable; "
                         "replaces the ini option schemalog_trees)")
    group.addoption("--schemalog-nodes", action="append", default=None, metavar="FILE", dest="schemalog_nodes",
                    help="trees: a <TreeNodesModel> file (Nav2's nav2_tree_nodes.xml), as schemalog verify --nodes "
                         "(repeatable; ini schemalog_nodes)")
    group.addoption("--schemalog-semantics", action="append", default=None, metavar="FILE",
                    dest="schemalog_semantics",
                    help="trees: a YAML file of custom node types' semantics, as schemalog verify --semantics "
                         "(repeatable; ini schemalog_semantics)")
    group.addoption("--schemalog-profile", action="append", default=None, metavar="NAME", dest="schemalog_profile",
                    help="trees: node semantics schemalog ships, as schemalog verify --profile: nav2 "
                         "(repeatable; ini schemalog_profile)")
    group.addoption("--schemalog-run-once", action="store_true", default=None, dest="schemalog_run_once",
                    help="trees: prove for trees ticked until they finish, once, never halted, as schemalog verify "
                         "--run-once (ini schemalog_run_once)")
    parser.addini("schemalog_tasks", type="paths", default=[],
                  help="folders or files whose tasks are proved, as --schemalog-tasks (relative to the ini "
                       "file; collected when pytest is given no path arguments)")
    parser.addini("schemalog_propagate", default="full", help="none, pre or full (default full)")
    parser.addini("schemalog_states", default="default", help="default, all, or atoms such as 'hand.free'")
    parser.addini("schemalog_max_states", default="", help=f"as --schemalog-max-states (default {MAX_STATES:,})")
    parser.addini("schemalog_max_bdd_nodes", default="",
                  help=f"as --schemalog-max-bdd-nodes (default {MAX_BDD_NODES:,})")
    parser.addini("schemalog_timeout", default="", help="as --schemalog-timeout, seconds (default: none)")
    parser.addini("schemalog_trees", type="paths", default=[],
                  help="folders or files whose BT.CPP trees are proved equal to their recorded versions, as "
                       "--schemalog-trees (relative to the ini file; collected when pytest is given no path arguments)")
    parser.addini("schemalog_nodes", type="paths", default=[], help="as --schemalog-nodes (relative to the ini file)")
    parser.addini("schemalog_semantics", type="paths", default=[],
                  help="as --schemalog-semantics (relative to the ini file)")
    parser.addini("schemalog_profile", type="args", default=[], help="as --schemalog-profile: nav2")
    parser.addini("schemalog_run_once", type="bool", default=False, help="as --schemalog-run-once")


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
    modes = _modes(config, paths, bool(given))
    propagate, where = _value(config, "propagate")
    propagate = propagate or "full"
    if propagate not in PROPAGATE:
        raise pytest.UsageError(f"{where}: {propagate!r} is not one of none, pre, full")
    states = _value(config, "states")[0] or "default"
    verify = {key: value for key, value in (("max_states", _positive(config, "max_states")),
                                            ("max_bdd_nodes", _positive(config, "max_bdd_nodes")))
              if value is not None}
    return Settings(paths, source, modes, propagate, states, verify, _timeout(config))


def _modes(config: pytest.Config, paths: list[Path], given: bool) -> dict[Path, str]:
    """How each folder named is collected: "args", "inject" or "off"."""
    arguments = _argument_paths(config)
    modes = {}
    for path in paths:
        if any(_within(arg, path) for arg in arguments):
            modes[path] = "args"          # `pytest tasks/two.pl::t1`: what is named there, no more
        elif given or not arguments:
            modes[path] = "inject"        # every task under it, beside the test arguments
        else:
            modes[path] = "off"           # the ini's folders, with test paths named: not collected
    return modes


def _named_files(config: pytest.Config, name: str) -> tuple[list[Path], str]:
    """The files of a repeatable option, else of its ini option (relative to the ini file)."""
    given = config.getoption(f"schemalog_{name}")
    if given:
        here = config.invocation_params.dir
        return [Path(here, p).absolute() for p in given], f"--schemalog-{name}"
    return [Path(p).absolute() for p in config.getini(f"schemalog_{name}")], f"schemalog_{name} (ini)"


def _decide_trees(config: pytest.Config) -> TreeSettings:
    here = config.invocation_params.dir
    given = config.getoption("schemalog_trees")
    if given:
        paths, source = [Path(here, p).absolute() for p in given], "--schemalog-trees"
    else:
        paths, source = [Path(p).absolute() for p in config.getini("schemalog_trees")], "schemalog_trees (ini)"
    paths = list(dict.fromkeys(paths))
    reading: dict[str, Any] = {}
    for name in ("nodes", "semantics"):
        files, where = _named_files(config, name)
        for file in files:
            if paths and not file.is_file():
                raise pytest.UsageError(f"{where}: {_shown(config, file)}: no such file")
        if files:
            reading[name] = [str(f) for f in files]
    profiles = config.getoption("schemalog_profile") or config.getini("schemalog_profile")
    if profiles:
        from schemalog.api.behaviour_trees import PROFILES      # light: no engine, no yaml

        where = "--schemalog-profile" if config.getoption("schemalog_profile") else "schemalog_profile (ini)"
        for name in profiles:
            if name not in PROFILES:
                raise pytest.UsageError(f"{where}: unknown profile {name!r}; the profiles schemalog ships: "
                                        f"{', '.join(PROFILES)}")
        reading["profile"] = list(dict.fromkeys(profiles))
    run_once = config.getoption("schemalog_run_once")
    proving: dict[str, Any] = {"run_once": True} if (config.getini("schemalog_run_once") if run_once is None
                                                       else run_once) else {}
    max_states = _positive(config, "max_states")
    if max_states is not None:
        proving["max_states"] = max_states
    return TreeSettings(paths, source, _modes(config, paths, bool(given)), reading, proving, _timeout(config))


def tree_settings(config: pytest.Config) -> TreeSettings:
    if _TREES not in config.stash:
        config.stash[_TREES] = _decide_trees(config)
    return config.stash[_TREES]


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
    config.stash[_TREES] = trees = _decide_trees(config)
    for path in trees.paths:
        if not os.path.lexists(path):
            raise pytest.UsageError(f"{trees.source}: {_shown(config, path)}: no such folder or file")
        if trees.modes[path] == "inject" and path.is_dir() and not any(True for _ in tree_pairs([path])):
            raise pytest.UsageError(f"{trees.source}: {_shown(config, path)}: no tree with a recorded version "
                                    f"in this folder (X.xml beside X.compressed.xml or X.approved.xml): no tree "
                                    f"to prove")


def _given(config: pytest.Config, path: Path) -> str:
    """A file's name as a user would give it on the command line (relative to the folder pytest
    runs in) while that folder is the current one; else its absolute name."""
    shown = _shown(config, path.absolute())
    return shown if Path(shown).absolute() == path.absolute() else str(path.absolute())


def _shown(config: pytest.Config, path: Path) -> str:
    here = config.invocation_params.dir
    return path.relative_to(here).as_posix() if path.is_relative_to(here) else str(path)


def pytest_report_header(config: pytest.Config) -> list[str] | None:
    lines = []
    found = settings(config)
    if found.active():
        shown = ", ".join(_shown(config, p) for p in found.active())
        limits = [f"{key.replace('_', ' ')} {value:,}" for key, value in found.verify.items()]
        if found.timeout is not None:
            limits.append(f"timeout {found.timeout:g} s")
        lines.append(f"schemalog: proving the tasks under {shown} (propagate {found.propagate}, states "
                     f"{found.states}{''.join(', ' + limit for limit in limits)})")
    trees = tree_settings(config)
    if trees.active():
        shown = ", ".join(_shown(config, p) for p in trees.active())
        how = [f"{key} {', '.join(_shown(config, Path(v)) if key != 'profile' else v for v in values)}"
               for key, values in trees.reading.items()]
        how += ["run once" if key == "run_once" else f"max states {value:,}" for key, value in trees.proving.items()]
        if trees.timeout is not None:
            how.append(f"timeout {trees.timeout:g} s")
        lines.append(f"schemalog: proving the trees under {shown} equal to their recorded versions "
                     f"(X.compressed.xml, X.approved.xml){''.join('; ' + h for h in how)}")
    return lines or None


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


def recorded_of(tree: Path) -> list[Path]:
    """The recorded versions beside a tree X.xml: X.compressed.xml, X.approved.xml (those there)."""
    if tree.suffix != ".xml" or _original_of(tree) is not None:
        return []
    return [v for v in (tree.with_name(f"{tree.stem}.{tag}.xml") for tag in RECORDED) if os.path.lexists(v)]


def _original_of(file: Path) -> Path | None:
    """X.xml for a recorded version X.compressed.xml or X.approved.xml; None for another file."""
    for tag in RECORDED:
        if file.name.endswith(f".{tag}.xml") and len(file.name) > len(tag) + 5:
            return file.with_name(file.name[:-len(f".{tag}.xml")] + ".xml")
    return None


def tree_pairs(paths: list[Path]) -> Iterator[tuple[Path, Path | None, str | None]]:
    """(tree, recorded version, why it is skipped or None) under `paths`, each once, in a stable
    order: every X.xml with a recorded version beside it; a recorded version whose tree is not
    there, or a file that is no regular file (a FIFO, a device: never opened), with the reason."""
    seen: set[tuple[Path, Path | None]] = set()
    for path in paths:
        if path.is_dir():
            found = sorted(p for p in path.rglob("*.xml") if not p.is_dir()
                           and not any(part.startswith(".") for part in p.relative_to(path).parts))
        else:
            found = [path]
        for file in found:
            original = _original_of(file)
            if original is not None and not os.path.lexists(original):
                pairs = [(file, None, f"a recorded version with no {original.name} beside it: skipped")]
            elif original is not None:
                if path.is_dir():
                    continue            # its tree gives it
                pairs = [(original, file, None)]
            else:
                pairs = [(file, v, None) for v in recorded_of(file)]
            for tree, recorded, why in pairs:
                if why is None:
                    # a FIFO or a device is named with what it is, never opened for reading
                    for file in (tree, recorded):
                        why = unreadable(file)
                        if why is not None:
                            tree, recorded = file, None
                            break
                if (tree.absolute(), recorded) not in seen:
                    seen.add((tree.absolute(), recorded))
                    yield tree, recorded, why


def _is_tree(file: Path, folder: Path) -> bool:
    """A tree with a recorded version, under `folder` (or `folder` itself)."""
    if not (file == folder or folder in file.parents
            and not any(part.startswith(".") for part in file.relative_to(folder).parts)):
        return False
    return bool(recorded_of(file))


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
    if any(_is_tree(path, folder) for folder in tree_settings(parent.config).active()):
        return TreeFile.from_parent(parent, path=file_path)
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
    trees = tree_settings(config)
    injected = [p for p in trees.paths if trees.modes[p] == "inject"]
    wanted: dict[Path, list[Path]] = {}
    for tree, recorded, why in tree_pairs(injected):
        if why is not None:
            note = f"{_shown(config, tree.absolute())}: {why}"
            if note not in notes:            # a TreeFile pytest collected may have said it
                notes.append(note)
        elif tree.absolute() not in seen:
            wanted.setdefault(tree.absolute(), []).append(recorded)
    for tree, versions in wanted.items():
        named = None if set(versions) == set(recorded_of(tree)) else versions      # a recorded version named alone
        items.extend(session.genitems(TreeFile.from_parent(session, path=tree, only=named)))
    active = trees.active()
    if active and not any(isinstance(item, TreeItem) for item in items) and not session.testsfailed:
        list(session.genitems(NoTree.from_parent(session, path=active[0], name=_shown(config, active[0]))))


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


class _ProofItem(pytest.Item):
    """A test item that proves something: its failure is the proof's words (a counterexample, a
    limit, file:line:col), not a traceback; past its time limit it says which option raises it."""

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException], style: Any = None) -> Any:
        from schemalog import SchemalogError

        if isinstance(excinfo.value, (AssertionError, SchemalogError)):
            return str(excinfo.value).rstrip("\n")
        return super().repr_failure(excinfo)

    def out_of_time(self, limit: float) -> None:
        pytest.fail(f"{self.name}: time limit of {limit:g} s exceeded (raise it with --schemalog-timeout "
                    f"or the ini option schemalog_timeout)", pytrace=False)


class TaskItem(_ProofItem):
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
        self.out_of_time(limit)

    def reportinfo(self) -> tuple[Path, int | None, str]:
        # the failure's title; pytest's -v line stays the node id, which does not end with it
        return self.path, None, f"{self.name} in {self.parent.nodeid}"


class NoTree(pytest.File):
    """The tree folders gave no item at all: a collection error saying so."""

    def collect(self) -> Iterator[pytest.Item]:
        shown = ", ".join(_shown(self.config, p) for p in tree_settings(self.config).active())
        notes = self.config.stash[_NOTES]
        why = "".join(f"\n  {note}" for note in notes) or " no X.xml beside an X.compressed.xml or X.approved.xml"
        self.config.stash[_NOTES] = []      # said here
        raise self.CollectError(f"schemalog: no tree to prove under {shown}:{why}")


class TreeFile(pytest.File):
    """A BT.CPP tree X.xml: one item per recorded version beside it (X.compressed.xml, X.approved.xml)."""

    def __init__(self, *, only: list[Path] | None = None, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.only = only

    def collect(self) -> Iterator[pytest.Item]:
        self.config.stash[_SEEN].add(self.path.absolute())
        notes = self.config.stash[_NOTES]
        why = unreadable(self.path)
        if why is not None:
            notes.append(f"{self.nodeid}: {why}")
            return
        for recorded in self.only or recorded_of(self.path):
            why = unreadable(recorded)
            if why is not None:
                notes.append(f"{_shown(self.config, recorded.absolute())}: {why}")
                continue
            yield TreeItem.from_parent(self, name=recorded.name, recorded=recorded)


class TreeItem(_ProofItem):
    """A tree and one recorded version of it, proved equal when it runs (read then: a file that
    does not read fails this item alone, with its file:line:column)."""

    def __init__(self, *, recorded: Path, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.recorded = recorded

    def runtest(self) -> None:
        from schemalog import LimitExceeded

        from . import assert_bt_equal

        found = tree_settings(self.config)
        for file in (self.path, self.recorded):      # still a regular file: a FIFO put there since is not read
            why = unreadable(file)
            if why is not None:
                pytest.fail(f"{_shown(self.config, file.absolute())}: {why.removesuffix(': skipped')}", pytrace=False)
        shown = lambda file: _given(self.config, Path(file))      # noqa: E731
        reading = {key: values if key == "profile" else [shown(v) for v in values]
                   for key, values in found.reading.items()}
        try:
            self.proof = assert_bt_equal(shown(self.path), shown(self.recorded), timeout=found.timeout,
                                         **reading, **found.proving)
            return
        except LimitExceeded as error:
            if error.limit != "time":
                raise
        self.out_of_time(found.timeout)

    def reportinfo(self) -> tuple[Path, int | None, str]:
        return self.path, None, f"{self.name} against {self.parent.nodeid}"
