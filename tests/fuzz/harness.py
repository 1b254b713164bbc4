"""Running one fuzz case through the command line and checking the promises it must keep.

A case is a `Case`: an argv whose file names are relative to a fresh directory, the files
to write there first (name -> bytes), the bytes fed to standard input, and the -o target
(a name in that directory, or None) with the content it holds before the run (None: absent).
`invoke` runs it in-process (schemalog.cli.main.main, standard streams captured, a
SIGALRM guard against hangs); `spawn` runs it as `python -m schemalog` for what needs a
real process (FIFOs, devices, signals). Both give an `Outcome`, and `violations` lists
the promises an outcome broke, as one-line strings, empty when it kept them all.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src"
KB = ROOT / "kb"
MIX = KB / "tasks" / "mix_with_spoon.pl"
COFFEE = KB / "tasks" / "prepare_coffee_and_tea.pl"
STRUCTURE = KB / "tasks" / "coffee_structure.pl"
SEED = ROOT / "examples" / "coffee_and_tea_seed.prolog"
KITCHEN = KB / "scenes" / "kitchen.yaml"
MIX_SCENE = KB / "scenes" / "mix_with_spoon.yaml"
SHIPPED = (MIX, COFFEE, STRUCTURE, SEED, KITCHEN, MIX_SCENE)

# README "What you can do": 0 success, 1 bad input (or run not completing, verify's
# counterexample), 2 a wrong command line, 3 verify found nothing but proved nothing;
# 130, 143, 129 after SIGINT, SIGTERM, SIGHUP.
EXIT_STATUSES = frozenset({0, 1, 2, 3})
SIGNAL_STATUSES = {signal.SIGINT: 130, signal.SIGTERM: 143, signal.SIGHUP: 129}


@dataclass(frozen=True)
class Case:
    """One command line over files made for it."""

    argv: tuple[str, ...]
    files: tuple[tuple[str, bytes], ...] = ()
    stdin: bytes = b""
    output: str | None = None          # the -o target's name in the case directory
    old_output: bytes | None = None    # what it holds before the run (None: it does not exist)

    def reproducer(self, limit: int = 4000) -> str:
        """Shell lines that make the files and run the command, for a failure message."""
        lines = ["cd \"$(mktemp -d)\""]
        made = dict(self.files)
        if self.output is not None and self.old_output is not None:
            made.setdefault(self.output, self.old_output)
        shipped = {p.read_bytes(): p for p in SHIPPED}
        for name, data in made.items():
            if data in shipped:
                lines.append(f"cp {shlex.quote(str(shipped[data]))} {shell_word(name)}")
                continue
            text = repr(data)
            if len(text) > limit:
                text = text[:limit] + "...(truncated)"
            lines.append(f"python3 -c 'import sys; open(sys.argv[1], \"wb\").write(eval(sys.argv[2]))' "
                         f"{shell_word(name)} {shlex.quote(text)}")
        command = "schemalog " + " ".join(shell_word(a) for a in self.argv)
        if self.stdin:
            command = f"printf %s {shlex.quote(self.stdin.decode('utf-8', 'replace'))} | {command}"
        lines.append(command)
        return "\n".join(lines)


def shell_word(word: str) -> str:
    """`word` as a shell reads it back: quoted, or as $'...' with \\xNN escapes when it holds bytes
    that are not UTF-8 (os.fsdecode's surrogates) or control characters, so that a reproducer
    prints and pastes whole."""
    if word.isprintable():
        return shlex.quote(word)
    return "$'" + "".join(chr(b) if 32 <= b < 127 and chr(b) not in "'\\" else f"\\x{b:02x}"
                          for b in os.fsencode(word)) + "'"


@dataclass(frozen=True)
class Outcome:
    """What a run did: its exit status (None: it hung or died), streams, and the files after."""

    status: int | None
    stdout: str
    stderr: str
    hung: bool = False
    died: str = ""                                  # a signal that killed a subprocess, a crash
    inputs_changed: tuple[str, ...] = ()
    leftovers: tuple[str, ...] = ()                 # *.tmp and hidden (staged) files in the case directory
    outside: tuple[str, ...] = ()                   # files made or changed that the command line did not name
    output_after: bytes | None = None
    output_kind: str = ""                           # 'file', 'missing', 'fifo', 'chardev', 'dir', ...
    extra: dict = field(default_factory=dict)


class Hang(BaseException):
    """The per-case guard went off; a BaseException so `except Exception` in the code under
    test does not swallow it."""


class _Stream(io.TextIOBase):
    """A text stream that writes to (or reads from) whatever case buffer is current."""

    def __init__(self) -> None:
        self.target: io.StringIO = io.StringIO()

    encoding = "utf-8"
    errors = "strict"

    def write(self, text: str) -> int:
        return self.target.write(text)

    def read(self, size: int = -1) -> str:
        return self.target.read(size)

    def readline(self, size: int = -1) -> str:
        return self.target.readline(size)

    def isatty(self) -> bool:
        return False

    def readable(self) -> bool:
        return True

    def writable(self) -> bool:
        return True

    def flush(self) -> None:
        pass


STDOUT, STDERR, STDIN = _Stream(), _Stream(), _Stream()


def _bind_stream_defaults() -> None:
    """Import the modules whose functions take sys.stdout as a default argument while it is
    our stream: the default is fixed when the module is first imported."""
    saved = sys.stdout, sys.stderr, sys.stdin
    sys.stdout, sys.stderr, sys.stdin = STDOUT, STDERR, STDIN
    try:
        import schemalog.cli.toplevel  # noqa: F401
        import schemalog.cli.session  # noqa: F401
    finally:
        sys.stdout, sys.stderr, sys.stdin = saved


_bind_stream_defaults()


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def kind_of(path: Path) -> str:
    """What `path` is: missing, file, dir, fifo, chardev, link, other."""
    import stat
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return "missing"
    for name, test in (("link", stat.S_ISLNK), ("file", stat.S_ISREG), ("dir", stat.S_ISDIR),
                       ("fifo", stat.S_ISFIFO), ("chardev", stat.S_ISCHR)):
        if test(mode):
            return name
    return "other"


def _hashes(directory: Path, names) -> dict[str, str]:
    return {n: sha(directory / n) for n in names if kind_of(directory / n) == "file"}


def _shipped_hashes() -> dict[str, str]:
    return {str(p): sha(p) for p in SHIPPED}


SHIPPED_HASHES = _shipped_hashes()


_ARMED = [False]


def _alarm(signum, frame):
    # The timer repeats (setitimer's interval): a Hang raised where Python ignores exceptions
    # (a garbage-collector callback, a __del__) is raised again a moment later. Once the case
    # is over (_ARMED cleared first thing), a late tick does nothing.
    if _ARMED[0]:
        raise Hang()


MEMORY = 2 << 30   # bytes of address space one in-process case may add (a runaway case once took 24 GB)


@contextlib.contextmanager
def memory_cap(extra: int = MEMORY):
    """Lower the soft address-space limit to what the process has now plus `extra`, so that a
    case that allocates without bound gets MemoryError instead of the machine's OOM killer."""
    import resource
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    try:
        size = int(next(line.split()[1] for line in Path("/proc/self/status").read_text().splitlines()
                        if line.startswith("VmSize:"))) * 1024
    except (OSError, StopIteration):
        yield
        return
    cap = size + extra if hard == resource.RLIM_INFINITY else min(hard, size + extra)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def invoke(case: Case, seconds: float = 10.0) -> Outcome:
    """Run `case` in-process in a fresh directory; the guard stops it after `seconds`."""
    from schemalog.cli.main import main

    with tempfile.TemporaryDirectory(prefix="schemalog-fuzz-") as tmp:
        directory = Path(tmp)
        _make_files(directory, case)
        before = _hashes(directory, inputs_of(case))
        files_before = snapshot(directory)
        STDOUT.target, STDERR.target = io.StringIO(), io.StringIO()
        STDIN.target = io.StringIO(case.stdin.decode("utf-8", "replace"))
        saved = sys.stdout, sys.stderr, sys.stdin
        limit = sys.getrecursionlimit()
        cwd = os.getcwd()
        previous = signal.signal(signal.SIGALRM, _alarm)
        hung, status, died = False, None, ""
        try:
            os.chdir(directory)
            sys.stdout, sys.stderr, sys.stdin = STDOUT, STDERR, STDIN
            sys.setrecursionlimit(max(limit, 20_000))   # what the console script (cli.main.run) sets
            _ARMED[0] = True
            signal.setitimer(signal.ITIMER_REAL, seconds, 0.5)
            try:
                with memory_cap():
                    status = main(list(case.argv))
            except SystemExit as exit_:
                status = exit_.code if isinstance(exit_.code, int) else (0 if exit_.code is None else 1)
        except Hang:
            hung = True
        except BaseException as err:  # anything main lets out is what a user would see as a traceback
            import traceback
            died = "Traceback (most recent call last): " + "".join(
                traceback.format_exception_only(type(err), err)).strip()
        finally:
            _ARMED[0] = False
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
            sys.stdout, sys.stderr, sys.stdin = saved
            sys.setrecursionlimit(limit)
            os.chdir(cwd)
        return _outcome(directory, case, before, status, STDOUT.target.getvalue(),
                        STDERR.target.getvalue() + died, hung=hung, died=died, files_before=files_before)


def spawn(case: Case, seconds: float = 30.0, directory: Path | None = None, prepare=None,
          during=None) -> Outcome:
    """Run `case` as `python -m schemalog` in a fresh directory (or `directory`, already made);
    `prepare(directory)` runs before it starts, `during(process, directory)` while it runs."""
    with contextlib.ExitStack() as stack:
        if directory is None:
            directory = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="schemalog-fuzz-")))
        _make_files(directory, case)
        if prepare is not None:
            prepare(directory)
        before = _hashes(directory, inputs_of(case))
        files_before = snapshot(directory)
        env = {**os.environ, "PYTHONPATH": f"{SRC}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
        env.pop("SCHEMALOG_DEBUG", None)
        process = subprocess.Popen([sys.executable, "-m", "schemalog", *case.argv], cwd=directory, env=env,
                                   stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                   preexec_fn=_child_memory_cap)
        extra = {}
        if during is not None:
            extra = during(process, directory) or {}
        hung = False
        try:
            out, err = process.communicate(case.stdin, timeout=seconds)
        except subprocess.TimeoutExpired:
            process.kill()
            out, err = process.communicate()
            hung = True
        status = process.returncode
        died = f"killed by {signal.Signals(-status).name}" if status is not None and status < 0 else ""
        return _outcome(directory, case, before, None if hung else status, out.decode("utf-8", "replace"),
                        err.decode("utf-8", "replace"), hung=hung, died=died, extra=extra, files_before=files_before)


OUTPUT_OPTIONS = {"-o", "--output", "--plot", "--motions", "--out"}


def inputs_of(case: Case) -> list[str]:
    """The case's files the command line names other than as an output (generate's --scene is one)."""
    argv = list(case.argv)
    outputs = {argv[i + 1] for i, a in enumerate(argv[:-1])
               if a in OUTPUT_OPTIONS or (a == "--scene" and argv[0] == "generate")}
    named = set(argv) - outputs
    named |= {a.split("=", 1)[1] for a in argv if a.startswith("--") and "=" in a}
    for i, a in enumerate(argv[1:], 1):   # a name given both as an input and as an output counts
        if a in outputs and argv[i - 1] not in OUTPUT_OPTIONS:
            named.add(a)
    return [n for n, _ in case.files if n in named]


def _child_memory_cap() -> None:
    import resource
    resource.setrlimit(resource.RLIMIT_AS, (3 * MEMORY, resource.RLIM_INFINITY))


def _make_files(directory: Path, case: Case) -> None:
    for name, data in case.files:
        path = directory / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    if case.output is not None and case.old_output is not None and kind_of(directory / case.output) == "missing":
        (directory / case.output).write_bytes(case.old_output)


def _outcome(directory, case, before, status, stdout, stderr, hung=False, died="", extra=None,
             files_before=None) -> Outcome:
    after = _hashes(directory, before)
    changed = tuple(n for n in before if after.get(n) != before[n])
    made = {name for name, _ in case.files}     # a case's own file may be named `.x.pl`
    leftovers = tuple(sorted(str(p.relative_to(directory)) for p in directory.rglob("*")
                             if (p.name.endswith(".tmp") or p.name.startswith("."))
                             and str(p.relative_to(directory)) not in made))
    output_after, output_kind = None, ""
    if case.output is not None:
        target = directory / case.output
        output_kind = kind_of(target)
        if output_kind == "file":
            output_after = target.read_bytes()
    return Outcome(status, stdout, stderr, hung=hung, died=died, inputs_changed=changed, leftovers=leftovers,
                   output_after=output_after, output_kind=output_kind, extra=extra or {},
                   outside=_outside(directory, case, files_before or {}))


def snapshot(directory: Path) -> dict[str, str]:
    """Every regular file under `directory` (links not followed) and its hash."""
    return {os.path.normpath(str(p.relative_to(directory))): sha(p) for p in directory.rglob("*")
            if kind_of(p) == "file"}


def _outside(directory: Path, case: Case, files_before: dict[str, str]) -> tuple[str, ...]:
    """Regular files in the case directory, made or changed by the run, that no output option
    names: the -o file (and a picture's pages, NAME-1.png ...), or anything inside an --out folder."""
    argv = list(case.argv)
    named = [os.path.normpath(argv[i + 1]) for i, a in enumerate(argv[:-1])
             if a in OUTPUT_OPTIONS or (a == "--scene" and argv[0] == "generate")]   # generate writes its scene
    real = os.path.realpath(directory)
    for n in list(named):          # an -o link is followed: the file it names is named too
        target = os.path.realpath(directory / n)
        if target.startswith(real + os.sep):
            named.append(os.path.relpath(target, real))
    found = []
    for name, digest in snapshot(directory).items():
        if files_before.get(name) == digest:
            continue
        pages = [re.fullmatch(re.escape(os.path.splitext(n)[0]) + r"-\d+" + re.escape(os.path.splitext(n)[1]), name)
                 for n in named]
        if name in named or any(name.startswith(n + os.sep) for n in named) or any(pages):
            continue
        if Path(name).name.endswith(".tmp") or Path(name).name.startswith("."):
            continue                                   # counted as a leftover
        found.append(name)
    return tuple(sorted(found))


def output_format(name: str, argv) -> str:
    """The format a command line asks for its -o: --json, --format, --to, else the name's suffix."""
    argv = list(argv)
    if "--json" in argv:
        return "json"
    for option in ("--format", "--to"):
        if option in argv[:-1]:
            return argv[len(argv) - 1 - argv[::-1].index(option) + 1]
    return Path(name).suffix.lstrip(".")


def complete(data: bytes, name: str, argv=()) -> bool:
    """Whether `data` is a whole document of the kind the command line promises (JSON, YAML, .pl,
    BT.CPP XML that imports back, a Python module that compiles)."""
    text = data.decode("utf-8", "replace")
    kind = output_format(name, argv)
    if argv and argv[0] in ("run", "verify") and "--json" not in argv:
        return True   # a report in text: run and verify take JSON from --json only, not from -o's suffix
    bt_route = bool(argv) and argv[0] == "compress" and str(argv[1]).lower().endswith(".xml")
    if argv and argv[0] != "export" and kind in ("xml", "py") and not bt_route:
        kind = "pl"   # only export (and compress of a BT.CPP tree) writes XML; convert writes schema text
    if kind == "json":
        try:
            json.loads(text)
        except ValueError:
            return False
        return True
    if kind in ("yaml", "yml"):
        import yaml
        try:
            yaml.safe_load(text)
        except yaml.YAMLError:
            return False
        return True
    if kind in ("xml", "btcpp"):
        from schemalog.errors import SchemalogError
        from schemalog.formats.btcpp import import_btcpp
        from schemalog.formats.btxml import read_bt
        try:
            if bt_route:
                read_bt(data.decode("utf-8"), name)       # a BT.CPP tree compressed: BT.CPP's reading of it
            else:
                import_btcpp(data.decode("utf-8"), name)  # an export must import back (convert reads it)
        except (SchemalogError, UnicodeDecodeError):
            return False
        return True
    if kind in ("py", "py_trees"):
        import ast
        try:
            compile(ast.parse(data), name, "exec")
        except (SyntaxError, ValueError, RecursionError, MemoryError):
            return False
        return True
    if kind == "pl":
        from schemalog.logic.kb import KnowledgeBase
        from schemalog.errors import SchemalogError
        try:
            KnowledgeBase().consult_text(text, name)
        except (SchemalogError, RecursionError):
            return False
        except Exception:
            return False
        return True
    return True


def violations(case: Case, outcome: Outcome, statuses=EXIT_STATUSES) -> list[str]:
    """The promises `outcome` broke, one line each."""
    found = []
    if outcome.hung:
        found.append("hang: no exit within the per-case guard")
    if outcome.died and outcome.status not in statuses:
        found.append(f"crash: {outcome.died.splitlines()[0][:300]}")
    for stream, text in (("stdout", outcome.stdout), ("stderr", outcome.stderr)):
        if "Traceback" in text and not outcome.hung:   # a hung case's guard may print one itself
            found.append(f"traceback on {stream}: {last_line(text, 'Traceback')}")
    if "internal error" in outcome.stderr or outcome.status == 70:
        found.append(f"internal error (exit {outcome.status}): {last_line(outcome.stderr, 'internal error')}")
    elif outcome.status is not None and outcome.status not in statuses and not outcome.died:
        found.append(f"undocumented exit status {outcome.status}: {first_line(outcome.stderr)}")
    if outcome.inputs_changed:
        found.append(f"input files changed: {', '.join(outcome.inputs_changed)}")
    changed_shipped = [p for p, h in SHIPPED_HASHES.items() if sha(Path(p)) != h]
    if changed_shipped:
        found.append(f"shipped files changed: {', '.join(changed_shipped)}")
    if outcome.leftovers:
        found.append(f"temporary files left: {', '.join(outcome.leftovers)}")
    if outcome.outside and not outcome.hung:
        found.append(f"written outside what the command line named: {', '.join(outcome.outside)}")
    if case.output is not None and not outcome.hung:
        found += _output_violations(case, outcome)
    return found


def _output_violations(case: Case, outcome: Outcome) -> list[str]:
    """An -o target is its old content, or absent as before, or a whole new document."""
    kind, after = outcome.output_kind, outcome.output_after
    if case.old_output is None and kind == "missing":
        return []
    if kind != "file":
        return [] if kind in ("fifo", "chardev", "dir") else [f"-o target became a {kind}"]
    if after == case.old_output:
        return []
    if outcome.status == 2:
        return [f"-o target written although the command line was refused (exit 2): {first_line(outcome.stderr)}"]
    if outcome.status not in (0, 1, 3) and outcome.status is not None:
        return [f"-o target changed by a run that exited {outcome.status}"]
    if not complete(after, case.output, case.argv):
        return [f"-o target {case.output} holds a partial or malformed document ({len(after)} bytes)"]
    return []


def first_line(text: str) -> str:
    return next((line for line in text.splitlines() if line.strip()), "")[:300]


def last_line(text: str, marker: str) -> str:
    """The line a traceback ends with (its exception), or the line holding `marker`."""
    lines = [line for line in text.splitlines() if line.strip()]
    if marker == "Traceback":
        start = max(i for i, line in enumerate(lines) if "Traceback" in line)
        tail = [line for line in lines[start:] if not line.startswith((" ", "Traceback"))]
        return (tail[0] if tail else lines[-1])[:300]
    return next((line for line in lines if marker in line), "")[:300]


def signature(problem: str) -> str:
    """A failure's kind without its particulars (numbers, names, quoted text), to deduplicate."""
    text = re.sub(r"'[^']*'|\"[^\"]*\"", "Q", problem)
    text = re.sub(r"\b[\w./-]+\.(pl|yaml|csv|json|prolog|tmp)\b", "FILE", text)
    text = re.sub(r"0x[0-9a-f]+|\d+(\.\d+)?(e[+-]?\d+)?", "N", text)
    return text[:160]


def assert_kept(case: Case, outcome: Outcome, statuses=EXIT_STATUSES) -> None:
    """Fail with the broken promises, the output and a reproducer."""
    found = violations(case, outcome, statuses)
    if found:
        raise AssertionError("\n".join([*found, f"exit status: {outcome.status}",
                                        f"stderr: {outcome.stderr[-1500:]}", f"stdout: {outcome.stdout[-500:]}",
                                        "reproduce with:", case.reproducer()]))
