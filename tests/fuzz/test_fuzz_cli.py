"""The command line keeps its promises on hostile input (README "What you can do", docs/formats.md
Outputs): no traceback, no internal error (exit 70), a documented exit status, inputs untouched,
no partial output or temporary file beside an -o target.

Every subcommand is driven with hypothesis-generated inputs (tests/fuzz/mutations.py) in-process,
with lowered limits and a SIGALRM guard per case (tests/fuzz/harness.py); the REPL, special files
and signals run as subprocesses. The fast profile (the default) is derandomized, so CI sees the
same cases every run; SCHEMALOG_FUZZ=long gives each test many more random examples, and
benchmarks/fuzz.py runs the same generators for N minutes and reports every distinct failure.
"""

from __future__ import annotations

import dataclasses

import os
import signal
import threading
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import mutations as m
from harness import (COFFEE, EXIT_STATUSES, KITCHEN, MIX, MIX_SCENE, ROOT, SEED, SIGNAL_STATUSES, STRUCTURE, Case,
                     assert_kept, invoke, kind_of, spawn, violations)

pytestmark = pytest.mark.fuzz

LONG = os.environ.get("SCHEMALOG_FUZZ") == "long"
GUARD = 10.0   # seconds one in-process case may take before it counts as a hang


def profile(examples: int):
    """The fast profile: `examples` derandomized cases, not shrunk (a hanging case would make each
    shrinking step cost the whole guard); the long one: 50 times as many, random, shrunk."""
    checks = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much,
              HealthCheck.large_base_example]
    if LONG:
        return settings(max_examples=examples * 50, deadline=None, database=None, suppress_health_check=checks)
    return settings(max_examples=examples, deadline=None, database=None, derandomize=True,
                    suppress_health_check=checks, print_blob=False,
                    phases=[Phase.explicit, Phase.reuse, Phase.generate])


def shipped(path: Path) -> tuple[str, bytes]:
    return path.name, path.read_bytes()


# What each command is asked over one knowledge file `k.pl`, its limits lowered so a case is quick.
KNOWLEDGE_COMMANDS = {
    "check": ["check", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--max-depth", "64"],
    "show": ["show", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--max-depth", "64"],
    "show-pl": ["show", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--format", "pl", "-o", "out.pl"],
    "compress": ["compress", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--max-depth", "64", "--json", "-o", "out.json"],
    "compress-pl": ["compress", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "-o", "out.pl"],
    "decompress": ["decompress", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--format", "yaml", "-o", "out.yaml"],
    "run": ["run", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--max-decisions", "300", "--json", "-o", "out.json"],
    "run-compressed": ["run", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--compressed", "--max-decisions", "300",
                       "--scene", "mix_with_spoon.yaml"],
    "verify": ["verify", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--max-states", "300", "--json", "-o", "out.json"],
    "query": ["query", "k.pl", "--max-nodes", "3000", "--max-steps", "20000", "sequential(X, Y)"],
    "query-schema": ["query", "k.pl", "--max-steps", "20000", "schema(T, S, P), node(N)"],
    "convert": ["convert", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "-o", "out.yaml"],
    "export-btcpp": ["export", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "--compressed", "-o", "out.xml"],
    "export-py_trees": ["export", "k.pl", "--max-nodes", "3000", "--max-steps", "200000", "-o", "out.py"],
    "simulate-demo": ["simulate-demo", "k.pl", "--max-steps", "200000", "--scene", "mix_with_spoon.yaml", "--rate", "5",
                      "-o", "d.csv"],
}


def output_of(argv: list[str]) -> str | None:
    return argv[argv.index("-o") + 1] if "-o" in argv else None


def probe_knowledge(command, text, old):
    argv = KNOWLEDGE_COMMANDS[command]
    case = Case(tuple(argv), files=(("k.pl", text[1]), shipped(MIX_SCENE)), output=output_of(argv),
                old_output=b"OLD\n" if old else None)
    return case, invoke(case, GUARD)


KNOWLEDGE = dict(command=st.sampled_from(sorted(KNOWLEDGE_COMMANDS)), text=m.knowledge(long=LONG), old=st.booleans())


@profile(70)
@given(**KNOWLEDGE)
def test_mutated_knowledge(command, text, old):
    assert_kept(*probe_knowledge(command, text, old))


LIMITS = ("--max-nodes", "3000", "--max-steps", "200000", "--max-depth", "64")


@profile(40)
@given(text=m.knowledge(long=LONG))
def test_lint_never_crashes_or_hangs_where_check_accepts(text):
    """Lint on mutated knowledge: a finding or a clean report, never a traceback or a hang, and on
    what check accepts nothing but 0 (clean) or 1 (errors found)."""
    files = (("k.pl", text[1]),)
    checked = invoke(Case(("check", "k.pl", *LIMITS), files=files), GUARD)
    for argv in (("lint", "k.pl", *LIMITS), ("lint", "k.pl", "--json", "--strict", *LIMITS)):
        case = Case(argv, files=files)
        outcome = invoke(case, GUARD)
        assert_kept(case, outcome)
        if checked.status == 0:
            assert outcome.status in (0, 1), case.reproducer()


def test_lint_over_every_file_the_suite_loads():
    """The shipped knowledge and every conformance program: lint reports, never crashes."""
    programs = sorted((Path(__file__).parents[1] / "conformance" / "programs").glob("*.pl"))
    assert len(programs) > 30
    for path in [MIX, COFFEE, STRUCTURE, SEED, *programs]:
        case = Case(("lint", path.name, *LIMITS), files=((path.name, path.read_bytes()),))
        outcome = invoke(case, 30)
        assert_kept(case, outcome)
        assert outcome.status in (0, 1), (path, outcome.stderr)


SCENE_COMMANDS = {
    "run": ["run", "mix_with_spoon.pl", "--scene", "s.yaml", "--max-decisions", "300"],
    "run-coffee": ["run", "prepare_coffee_and_tea.pl", "--task", "preparecoffee", "--scene", "s.yaml",
                   "--seed", "3", "--json", "-o", "out.json"],
    "verify": ["verify", "mix_with_spoon.pl", "--scene", "s.yaml", "--max-states", "300"],
    "simulate-demo": ["simulate-demo", "mix_with_spoon.pl", "--scene", "s.yaml", "--rate", "5", "-o", "d.csv"],
    "simulate-kitchen": ["simulate-demo", "prepare_coffee_and_tea.pl", "--scene", "s.yaml", "--task",
                         "preparetea", "--rate", "2", "-o", "d.json"],
    "query": ["query", "mix_with_spoon.pl", "--scene", "s.yaml", "--max-steps", "20000", "emphasis(B, E)"],
}


def probe_scenes(command, scene, old):
    argv = SCENE_COMMANDS[command]
    case = Case(tuple(argv), files=(("s.yaml", scene), shipped(MIX), shipped(COFFEE)), output=output_of(argv),
                old_output=b"OLD\n" if old else None)
    return case, invoke(case, GUARD)


SCENES = dict(command=st.sampled_from(sorted(SCENE_COMMANDS)), scene=m.scenes(long=LONG), old=st.booleans())


@profile(35)
@given(**SCENES)
def test_mutated_scenes(command, scene, old):
    assert_kept(*probe_scenes(command, scene, old))


_DEMO: list[bytes] = []


def demonstration() -> bytes:
    """A small simulated demonstration of preparecoffee (4 samples a second), made once."""
    if not _DEMO:
        case = Case(("simulate-demo", "prepare_coffee_and_tea.pl", "--scene", "kitchen.yaml", "--task",
                     "preparecoffee", "--rate", "4", "-o", "demo.csv"), files=(shipped(COFFEE), shipped(KITCHEN)),
                    output="demo.csv")
        outcome = invoke(case, 60)
        assert outcome.status == 0 and outcome.output_after, outcome.stderr
        _DEMO.append(outcome.output_after)
    return _DEMO[0]


def test_the_demonstration_teaches():
    """The seed of the demonstration cases is itself a good demonstration."""
    case = Case(("learn", "demo.csv", "--structure", "coffee_structure.pl", "--task", "preparecoffee",
                 "--bases", "1", "-o", "out.pl"), files=(("demo.csv", demonstration()), shipped(STRUCTURE)),
                output="out.pl")
    outcome = invoke(case, 30)
    assert_kept(case, outcome)
    assert outcome.status == 0 and outcome.output_after and b"schema(" in outcome.output_after


def probe_demonstrations(demo, old, plot):
    argv = ["learn", "demo.csv", "--structure", "coffee_structure.pl", "--task", "preparecoffee", "--bases", "1",
            "-o", "out.pl"] + (["--motions", "motions.json"] if plot else [])
    case = Case(tuple(argv), files=(("demo.csv", demo), shipped(STRUCTURE)), output="out.pl",
                old_output=b"OLD\n" if old else None)
    return case, invoke(case, 30)


DEMONSTRATIONS = dict(demo=st.deferred(lambda: m.demonstrations(demonstration())), old=st.booleans(),
                      plot=st.booleans())


@profile(12)
@given(**DEMONSTRATIONS)
def test_mutated_demonstrations(demo, old, plot):
    assert_kept(*probe_demonstrations(demo, old, plot))


def probe_queries(query, flags):
    case = Case(("query", "mix_with_spoon.pl", "--max-steps", "20000", *flags, query), files=(shipped(MIX),))
    return case, invoke(case, GUARD)


QUERIES = dict(query=m.queries(), flags=st.sampled_from([[], ["--json"], ["--first"], ["--json", "--first"]]))


@profile(120)
@given(**QUERIES)
def test_queries(query, flags):
    assert_kept(*probe_queries(query, flags))


READER = dict(query=m.reader_queries(), flags=st.sampled_from([[], ["--json"]]))


@profile(40)
@given(**READER)
def test_reader_escapes(query, flags):
    assert_kept(*probe_queries(query, flags))


def options_of(command: str) -> list[tuple[str, object]]:
    """(option string, argparse action) for every option `command` takes, from its parser."""
    from schemalog.cli.main import build_parser
    parser = build_parser(command)
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    found = []
    for action in sub.choices[command]._actions:
        if action.option_strings and action.dest != "help":
            found.append((max(action.option_strings, key=len), action))
    return found


# A valid command line per command, and the limits kept low after the odd options (the last
# value of an option wins) so that a case stays small; the long profile fuzzes those too.
COMMAND_LINES = {
    "check": (["check", "mix_with_spoon.pl"], []),
    "show": (["show", "mix_with_spoon.pl"], []),
    "compress": (["compress", "mix_with_spoon.pl", "-o", "out.pl"], []),
    "decompress": (["decompress", "mix_with_spoon.pl", "-o", "out.yaml"], []),
    "run": (["run", "mix_with_spoon.pl", "--scene", "mix_with_spoon.yaml", "-o", "out.json"], ["--max-decisions", "300"]),
    "verify": (["verify", "mix_with_spoon.pl", "-o", "out.json"], ["--max-states", "2000"]),
    "generate": (["generate", "--depth", "2", "--children", "2", "-o", "out.pl"], ["--max-nodes", "2000"]),
    "learn": (["learn", "demo.csv", "--structure", "coffee_structure.pl", "--task", "preparecoffee", "-o", "out.pl"],
              ["--bases", "1"]),
    "simulate-demo": (["simulate-demo", "mix_with_spoon.pl", "--scene", "mix_with_spoon.yaml", "-o", "d.csv"],
                      ["--rate", "5"]),
    "query": (["query", "mix_with_spoon.pl", "sequential(X, Y)"], ["--max-steps", "20000"]),
    "convert": (["convert", "coffee_and_tea_seed.prolog", "--task", "prepareboth", "-o", "out.pl"], []),
}
PATHS = ["sub", "sub/", "missing.pl", "empty.pl", "mix_with_spoon.pl", "mix_with_spoon.yaml", "nowhere/out.pl",
         "/dev/null", "out.pl", "out.json", ".", "sub/x.yaml"]
SLOW_OPTIONS = {"--max-nodes", "--max-depth", "--max-states", "--max-steps", "--max-decisions", "--depth",
                "--children", "--rate", "--sample", "--bases", "--paper", "--quick", "--runs", "--speed",
                "--sympy-budget"}


@st.composite
def command_lines(draw):
    """(command, argv): a valid command line with one to three options given odd values."""
    command = draw(st.sampled_from(sorted(COMMAND_LINES)))
    base, limits = COMMAND_LINES[command]
    argv = list(base)
    options = [(o, a) for o, a in options_of(command) if LONG or o not in SLOW_OPTIONS or limits == []]
    for _ in range(draw(st.integers(1, 3))):
        option, action = draw(st.sampled_from(options))
        if action.nargs == 0:
            argv.append(option)
            continue
        values = list(action.choices or []) + m.ODD_VALUES + PATHS
        argv += [option, draw(st.sampled_from(values))]
    if draw(st.integers(0, 5)) == 0:   # a positional argument dropped, doubled or odd
        i = draw(st.integers(1, len(argv) - 1))
        argv.insert(i, draw(st.sampled_from(PATHS + m.ODD_VALUES)))
    return command, argv + ([] if LONG else limits)


def probe_command_lines(line, old):
    command, argv = line
    files = (shipped(MIX), shipped(MIX_SCENE), shipped(SEED), shipped(STRUCTURE), ("empty.pl", b""),
             ("sub/x.yaml", b"objects: {}\n"))
    if command == "learn":
        files += (("demo.csv", demonstration()),)
    case = Case(tuple(argv), files=files, output=output_of(argv) if output_of(argv) in ("out.pl", "out.json",
                "out.yaml", "d.csv") else None, old_output=b"OLD\n" if old else None)
    outcome = invoke(case, 30 if command == "learn" else GUARD)
    if command == "generate" and "--scene" in argv[:-1]:
        # generate's --scene names the scene it writes, an output like -o: replacing it is asked for
        written = argv[max(k for k, a in enumerate(argv[:-1]) if a == "--scene") + 1]
        outcome = dataclasses.replace(outcome, inputs_changed=tuple(
            name for name in outcome.inputs_changed if name != written))
    return case, outcome


COMMAND_LINES_DRAWN = dict(line=command_lines(), old=st.booleans())


@profile(90)
@given(**COMMAND_LINES_DRAWN)
def test_odd_command_lines(line, old):
    assert_kept(*probe_command_lines(line, old))


@pytest.mark.parametrize("argv", [
    ["bench"], ["bench", "--paper", "--quick"], ["bench", "--quick", "--runs", "0"], ["bench", "--quick", "--runs", "-1"],
    ["bench", "--quick", "--runs", "nan"], ["bench", "--quick", "--seed", "x"], ["bench", "--quick", "--max-states", "0"],
    ["bench", "--quick", "--out", "mix_with_spoon.pl"], ["bench", "--quick", "--out", "/dev/null"],
    ["bench", "--quick", "--out", "mix_with_spoon.pl/sub"], ["bench", "--quick", "--out", ""],
    ["bench", "--quick", "--runs", "99999999999999999999999", "--max-states", "-5"],
])
def test_bench_command_lines(argv):
    """bench refuses what it cannot do before it starts its minute of work."""
    case = Case(tuple(argv), files=(shipped(MIX),))
    outcome = invoke(case, GUARD)
    assert_kept(case, outcome)
    assert outcome.status != 0


# --- subprocesses: the REPL on standard input, special files, signals ---------------------------

REPL_LINES = [":tree", ":compress", ":run", ":verify", ":help", ":nonsense", ":tree extra args", ":run --bad",
              ":compress --propagate x", "sequential(X, Y).", "X = f(X).", "halt(foo).", "atom_length(X, Y).",
              "between(1, inf, X).", ";", "", "\x04", "'unterminated", "a :- b.", ":verify 1 2 3",
              "0'\\z.", "format(\"~*c\", [99999999, 0'x]).", "X is 2**100000, Y = 1.", "repeat, fail.", "\x1b[2J"]


def probe_repl(lines):
    stdin = ("\n".join(lines) + "\n").encode()
    case = Case(("repl", "--plain", "--max-steps", "20000", "mix_with_spoon.pl"), files=(shipped(MIX),), stdin=stdin)
    return case, spawn(case, 60)


REPL = dict(lines=st.lists(st.one_of(st.sampled_from(REPL_LINES), m.queries().map(lambda q: q + ".")), min_size=1,
                           max_size=6))


@profile(6)
@given(**REPL)
def test_repl_on_standard_input(lines):
    assert_kept(*probe_repl(lines))


DEVICES = {"null": 3, "zero": 5, "full": 7}


def _device(directory: Path, name: str, kind: str) -> bool:
    """Make a character device like /dev/`kind` in `directory`; without CAP_MKNOD (not root),
    a link to the system's own instead. Whether it is a link."""
    import stat
    try:
        os.mknod(directory / name, 0o666 | stat.S_IFCHR, os.makedev(1, DEVICES[kind]))
        return False
    except PermissionError:
        os.symlink(f"/dev/{kind}", directory / name)
        return True


def _fifo_writer(path: Path, data: bytes):
    def write():
        try:
            with open(path, "wb") as fifo:
                fifo.write(data)
        except OSError:
            pass
    thread = threading.Thread(target=write, daemon=True)
    thread.start()
    return thread


def _fifo_reader(path: Path, got: list):
    def read():
        try:
            with open(path, "rb") as fifo:
                got.append(fifo.read())
        except OSError:
            pass
    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    return thread


# (argv, the special file's name, what it is: fifo-in, fifo-out, null, full, zero)
SPECIAL = [
    (["check", "in.pl"], "in.pl", "fifo-in"),
    (["run", "mix_with_spoon.pl", "--scene", "in.yaml"], "in.yaml", "fifo-in"),
    (["learn", "in.csv", "--structure", "coffee_structure.pl", "--task", "preparecoffee", "--bases", "1"], "in.csv",
     "fifo-in"),
    (["show", "mix_with_spoon.pl", "--format", "pl", "-o", "out.pl"], "out.pl", "fifo-out"),
    (["compress", "mix_with_spoon.pl", "--json", "-o", "out.json"], "out.json", "fifo-out"),
    (["check", "null.pl"], "null.pl", "null"),
    (["run", "mix_with_spoon.pl", "--scene", "null.yaml"], "null.yaml", "null"),
    (["learn", "null.csv", "--structure", "coffee_structure.pl"], "null.csv", "null"),
    (["check", "zero.pl", "--max-bytes", "1000"], "zero.pl", "zero"),
    (["learn", "zero.csv", "--structure", "coffee_structure.pl", "--max-bytes", "1000"], "zero.csv", "zero"),
    (["query", "zero.pl", "--max-bytes", "1000", "true"], "zero.pl", "zero"),
    (["show", "mix_with_spoon.pl", "-o", "null"], "null", "null"),
    (["generate", "--depth", "2", "--children", "2", "-o", "null.pl", "--scene", "null.yaml"], "null.pl", "null"),
    (["verify", "mix_with_spoon.pl", "--json", "-o", "null.json"], "null.json", "null"),
    (["show", "mix_with_spoon.pl", "--format", "pl", "-o", "full.pl"], "full.pl", "full"),
    (["compress", "mix_with_spoon.pl", "-o", "full"], "full", "full"),
    (["simulate-demo", "mix_with_spoon.pl", "--scene", "mix_with_spoon.yaml", "--rate", "5", "-o", "full.csv"],
     "full.csv", "full"),
    (["convert", "mix_with_spoon.pl", "-o", "full.yaml"], "full.yaml", "full"),
    (["show", "mix_with_spoon.pl", "--format", "pl", "-o", "link.pl"], "link.pl", "link"),
    (["compress", "mix_with_spoon.pl", "-o", "link.pl"], "link.pl", "link-to-input"),
]


@pytest.mark.parametrize("argv, name, kind", SPECIAL, ids=[f"{a[0]}-{k}-{n}" for a, n, k in SPECIAL])
def test_special_files(argv, name, kind):
    """FIFOs, character devices and links as inputs and as -o targets: read within --max-bytes,
    written in place (a link followed) and never replaced by a regular file; /dev/full's ENOSPC
    is an error; a link to an input is refused as -o."""
    case = Case(tuple(argv), files=(shipped(MIX), shipped(MIX_SCENE), shipped(STRUCTURE)))
    got: list[bytes] = []
    linked = []

    def prepare(directory: Path) -> None:
        path = directory / name
        if kind.startswith("fifo"):
            os.mkfifo(path)
        elif kind == "link":
            (directory / "real.pl").write_bytes(b"OLD\n")
            os.symlink("real.pl", path)
        elif kind == "link-to-input":
            os.symlink("mix_with_spoon.pl", path)
        else:
            linked.append(_device(directory, name, kind))

    def during(process, directory):
        path = directory / name
        if kind == "fifo-in":
            source = {".pl": MIX, ".yaml": MIX_SCENE}.get(path.suffix)
            _fifo_writer(path, source.read_bytes() if source else demonstration())
        elif kind == "fifo-out":
            _fifo_reader(path, got)

    import tempfile
    with tempfile.TemporaryDirectory(prefix="schemalog-fuzz-") as tmp:
        outcome = spawn(case, 60, directory=Path(tmp), prepare=prepare, during=during)
        after = kind_of(Path(tmp) / name)
        real = (Path(tmp) / "real.pl").read_bytes() if kind == "link" else None
    assert_kept(case, outcome)
    expected = {"fifo-in": "fifo", "fifo-out": "fifo", "link": "link", "link-to-input": "link"}.get(
        kind, "link" if linked and linked[0] else "chardev")
    assert after == expected, f"{name} became a {after}"
    if kind == "link":   # followed: the file it names gets the whole tree
        assert outcome.status == 0 and b"schema(" in real, real[:200]
    if kind == "link-to-input":   # an input reached through a link is still an input
        assert outcome.status == 2 and "overwrite an input" in outcome.stderr, outcome.stderr
    if kind == "full":
        assert outcome.status == 1 and "space" in outcome.stderr, outcome.stderr
    if kind == "fifo-out":
        assert outcome.status == 0, outcome.stderr
        time.sleep(0.2)
        assert got and got[0], "nothing was written into the FIFO"
    if kind == "zero":
        # query exits 2 on a file it cannot read (docs/queries.md), the other commands 1
        assert outcome.status in (1, 2) and "--max-bytes" in outcome.stderr, outcome.stderr


def _handlers_installed(pid: int, signums) -> bool:
    """Whether the process catches every one of `signums` yet (/proc/PID/status SigCgt)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return True
    caught = int(next(line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), 16)
    return all(caught & (1 << (s - 1)) for s in signums)


SIGNAL_COMMANDS = [
    (["compress", "prepare_coffee_and_tea.pl", "-o", "out.pl"], "out.pl"),
    (["verify", "prepare_coffee_and_tea.pl", "--states", "all", "--json", "-o", "out.json"], "out.json"),
    (["simulate-demo", "prepare_coffee_and_tea.pl", "--scene", "kitchen.yaml", "--task", "preparecoffee", "-o",
      "out.csv"], "out.csv"),
    (["show", "prepare_coffee_and_tea.pl", "--format", "yaml", "-o", "out.yaml"], "out.yaml"),
]
_REFERENCE: dict[tuple[str, ...], bytes] = {}


def reference(argv: list[str], output: str) -> bytes:
    """What the command writes when nothing stops it."""
    key = tuple(argv)
    if key not in _REFERENCE:
        case = Case(key, files=(shipped(COFFEE), shipped(KITCHEN)), output=output)
        outcome = spawn(case, 120)
        assert outcome.status == 0, outcome.stderr
        _REFERENCE[key] = outcome.output_after
    return _REFERENCE[key]


def probe_signals(command: int, signum: int, delay: float, wait: bool = True):
    """Run a command that writes -o and send it `signum` `delay` seconds after its handlers are
    in place (or, without `wait`, after it starts)."""
    argv, output = SIGNAL_COMMANDS[command]
    case = Case(tuple(argv), files=(shipped(COFFEE), shipped(KITCHEN)), output=output, old_output=b"OLD\n")

    def during(process, directory):
        deadline = time.monotonic() + 30
        while wait and not _handlers_installed(process.pid, SIGNAL_STATUSES) and time.monotonic() < deadline:
            time.sleep(0.002)
        time.sleep(delay)
        if process.poll() is None:
            process.send_signal(signum)
        return {"delay": delay}

    return case, spawn(case, 120, during=during)


def check_signalled(case, outcome, signum, **_) -> list[str]:
    """The promises of a run stopped by `signum`: its status, no temporary file, the target old or whole."""
    # Killed by the signal itself (it came before Python's handlers were in place) is what the
    # shell reports as 128 + signum too, and nothing was written yet: the same promise kept.
    found = violations(case, outcome, statuses={0, SIGNAL_STATUSES[signum], -signum})
    if interpreter_start(outcome):
        # Sent without waiting, it struck CPython's own start-up (site, a .pth, importlib), before
        # any schemalog code exists to handle it: Python's traceback and status 1 are its own.
        found = [f for f in found if not f.startswith(("traceback on stderr", "undocumented exit status 1"))]
    if outcome.output_after != b"OLD\n" and untimed(outcome.output_after) != untimed(
            reference(list(case.argv), case.output)):
        found.append(f"-o target is neither its old content nor the whole new one after "
                     f"{signal_name(signum)} at {outcome.extra.get('delay')} s ({len(outcome.output_after or b'')} bytes)")
    return found


def interpreter_start(outcome) -> bool:
    """Whether the run died in the interpreter's start-up: a traceback with no schemalog frame."""
    err = outcome.stderr or ""
    return "Traceback" in err and "<frozen" in err and "schemalog" not in err


def untimed(data: bytes | None):
    """A document without what changes from run to run: verify's JSON `seconds`."""
    if data is None or not data.lstrip().startswith(b"{"):
        return data
    import json

    def strip(value):
        if isinstance(value, dict):
            return {k: strip(v) for k, v in value.items() if k != "seconds"}
        if isinstance(value, list):
            return [strip(v) for v in value]
        return value
    try:
        return strip(json.loads(data))
    except ValueError:
        return data


def signal_name(signum) -> str:
    return signal.Signals(signum).name


SIGNALS = dict(command=st.integers(0, len(SIGNAL_COMMANDS) - 1), signum=st.sampled_from(sorted(SIGNAL_STATUSES)),
               delay=st.floats(0, 2.0 if LONG else 0.8), wait=st.booleans() if LONG else st.just(True))


@profile(6)
@given(**SIGNALS)
def test_signals_during_output(command, signum, delay, wait):
    """SIGINT, SIGTERM, SIGHUP at a random moment: exit 130/143/129 or 0, nothing partial left."""
    case, outcome = probe_signals(command, signum, delay, wait)
    found = check_signalled(case, outcome, signum)
    assert not found, "\n".join([*found, f"stderr: {outcome.stderr[-800:]}", case.reproducer(),
                                 f"(and send {signal_name(signum)} {delay:.3f} s after it starts)"])


# Issue 32: hostile names in exported files, and BT.CPP documents that include others.

# Text that has broken generated files: quotes that end a docstring, comment markers, markup,
# escapes, control characters, BT.CPP's own names; file names add undecodable bytes.
HOSTILE_PIECES = ['"""', "'''", "\\", "\n", "\0", "-->", "--", "---", "<!--", "]]>", "&", "{x}", "\x01", "\x7f",
                  "\u2028", "\u200b", "Ω", 'if __import__("os").system("touch PWNED") else', "SubTree", "Action",
                  "acted", "q__", "__", " ", "'", '"', "%", "(", ")", "."]
HOSTILE_NAME = st.lists(st.one_of(st.sampled_from(HOSTILE_PIECES), st.text(max_size=6)), min_size=1, max_size=5) \
    .map("".join).filter(lambda s: s.strip() != "")
FILE_NAME = st.tuples(HOSTILE_NAME, st.sampled_from(["", "\udcff", "\udce9"])).map(
    lambda p: (p[0] + p[1]).replace("/", "|").replace("\0", "0")[:120] + ".pl").filter(
    lambda n: n not in (".pl", "..pl") and not n.startswith("-"))
EXPORT_COMMANDS = {
    "btcpp": ["--to", "btcpp", "-o", "out.xml"],
    "btcpp-compressed": ["--to", "btcpp", "--compressed", "-o", "out.xml"],
    "py_trees": ["--to", "py_trees", "-o", "out.py"],
    "py_trees-compressed": ["--to", "py_trees", "--compressed", "-o", "out.py"],
}


def hostile_knowledge(task: str, actions: list[str], obj: str, agent: str) -> bytes:
    """A task of `actions` in sequence, the last acting on `obj`, the first done by `agent`."""
    from schemalog.logic.terms import Atom, Struct, term_to_text as q

    labels = [Atom(a) for a in actions[:-1]] + [Struct(actions[-1], (Atom(obj),))]
    entries, previous = [], Atom("true")
    for label in labels:
        entries.append(f"({q(label)}, {q(previous)})")
        previous = Struct(".", (label, Atom("done")))
    lines = [f"task({q(Atom(task))}).", f"object({q(Atom(obj))}).", f"agent({q(labels[0])}, {q(Atom(agent))}).",
             f"schema({q(Atom(task))}, [{', '.join(entries)}], {q(Struct('.', (Atom(task), Atom('done'))))})."]
    lines += [f"schema({q(label)}, [], {q(Struct('.', (label, Atom('done'))))})." for label in labels]
    return ("\n".join(lines) + "\n").encode()


def module_runs_nothing_else(source: bytes) -> list[str]:
    """Import an exported module in a subprocess inside an empty folder: it must import, and
    create nothing (a name that ran code would)."""
    import subprocess
    import sys
    import tempfile
    with tempfile.TemporaryDirectory(prefix="schemalog-fuzz-module-") as tmp:
        Path(tmp, "tree.py").write_bytes(source)
        done = subprocess.run([sys.executable, "-c", "import runpy; runpy.run_path('tree.py', run_name='fuzz')"],
                              cwd=tmp, capture_output=True, text=True, timeout=60)
        found = [] if done.returncode == 0 else [f"exported module does not import: {_last(done.stderr)}"]
        made = sorted(set(os.listdir(tmp)) - {"tree.py", "__pycache__"})
        return found + ([f"importing the exported module created {', '.join(made)}"] if made else [])


def _last(text: str) -> str:
    lines = [line for line in text.splitlines() if line.strip()]
    return lines[-1][:300] if lines else ""


def probe_exports(command, names, file_name, old):
    task, first, last, obj, agent = names
    argv = ["export", file_name, *EXPORT_COMMANDS[command]]
    case = Case(tuple(argv), files=((file_name, hostile_knowledge(task, [first, last], obj, agent)),),
                output=output_of(argv), old_output=b"OLD\n" if old else None)
    return case, invoke(case, GUARD)


def export_kept(case, outcome, **_) -> list[str]:
    """The promises, and an export the runtime takes: the XML imports back (harness.complete),
    the module imports and runs no code."""
    found = violations(case, outcome)
    if outcome.status == 0 and case.output.endswith(".py") and outcome.output_after is not None:
        found += module_runs_nothing_else(outcome.output_after)
    return found


EXPORTS = dict(command=st.sampled_from(sorted(EXPORT_COMMANDS)),
               names=st.lists(HOSTILE_NAME, min_size=5, max_size=5, unique=True), file_name=FILE_NAME,
               old=st.booleans())


@profile(12)
@given(**EXPORTS)
def test_exports_of_hostile_names(command, names, file_name, old):
    case, outcome = probe_exports(command, names, file_name, old)
    found = export_kept(case, outcome)
    assert not found, "\n".join([*found, f"exit status: {outcome.status}", f"stderr: {outcome.stderr[-800:]}",
                                 case.reproducer()])


INCLUDED = ('<root BTCPP_format="4">{include}\n  <BehaviorTree ID="{id}"><Sequence><OpenDoor/>{inner}</Sequence>'
            '</BehaviorTree>\n</root>\n')


@st.composite
def include_graphs(draw):
    """A main document including others (in sub-folders, through `..`, in a cycle, one missing),
    and an -o naming one of them, the main document, or a new file."""
    count = draw(st.integers(1, 4))
    folders = draw(st.lists(st.sampled_from(["", "sub/", "sub/deeper/", "other/"]), min_size=count, max_size=count))
    names = [f"{folder}inc{i}.xml" for i, folder in enumerate(folders)]
    files = {}
    for i, name in enumerate(names):
        target = draw(st.sampled_from([None, *range(count)]))
        include = "" if target is None else f'<include path="{"../" * name.count("/")}{names[target]}"/>'
        inner = f'<SubTree ID="T{target}"/>' if target is not None and target != i and draw(st.booleans()) else ""
        files[name] = INCLUDED.format(include=include, id=f"T{i}", inner=inner).encode()
    included = draw(st.lists(st.sampled_from(names), min_size=1, max_size=count, unique=True))
    main = "".join(f'<include path="{n}"/>' for n in included)
    if draw(st.booleans()):
        main += '<include path="missing.xml"/>'
    files["main.xml"] = (f'<root BTCPP_format="4" main_tree_to_execute="Main">{main}<BehaviorTree ID="Main">'
                         f'<Sequence><SubTree ID="T0"/></Sequence></BehaviorTree></root>\n').encode()
    around = [f"{n.split('/')[0]}/../{n}" for n in names if "/" in n]     # sub/../sub/inc1.xml
    output = draw(st.sampled_from([*names, *around, "main.xml", "./" + names[0], "new.pl"]))
    to = draw(st.sampled_from([(), ("--to", "yaml"), ("--to", "pl")]))
    return tuple(files.items()), output, to


def probe_includes(graph, old):
    files, output, to = graph
    argv = ["convert", "main.xml", "-o", output, *to]
    existing = dict(files).get(os.path.normpath(output))
    case = Case(tuple(argv), files=files, output=output,
                old_output=existing if existing is not None else (b"OLD\n" if old else None))
    return case, invoke(case, GUARD)


def includes_kept(case, outcome, **_) -> list[str]:
    """The promises, and no file the document includes (nor the document) written over."""
    import re
    found = violations(case, outcome)
    files = dict(case.files)
    read, todo = {}, ["main.xml"]
    while todo:                      # the files convert reads: main.xml and what it includes, transitively
        name = todo.pop()
        if name in files and name not in read:
            read[name] = files[name]
            todo += [os.path.normpath(os.path.join(os.path.dirname(name), p))
                     for p in re.findall(rb'<include path="([^"]+)"', files[name]) for p in [p.decode()]]
    target = os.path.normpath(case.output)
    if target in read and outcome.output_after != read[target]:
        found.append(f"convert wrote over {target}, a file it read (exit {outcome.status})")
    return found


INCLUDES = dict(graph=include_graphs(), old=st.booleans())


@profile(25)
@given(**INCLUDES)
def test_includes_are_never_written_over(graph, old):
    case, outcome = probe_includes(graph, old)
    found = includes_kept(case, outcome)
    assert not found, "\n".join([*found, f"exit status: {outcome.status}", f"stderr: {outcome.stderr[-800:]}",
                                 case.reproducer()])


def kept(case, outcome, **_) -> list[str]:
    return violations(case, outcome)


# --- hostile file names: inputs, outputs and scenes named with them ---------------------------

# Every command given a file name (NAME) it reads or writes; {suffix} is the name's ending.
NAMED_COMMANDS = {
    "check": (["check", "NAME"], "input", ".pl"),
    "lint": (["lint", "NAME", "--json"], "input", ".pl"),
    "show": (["show", "NAME", "--format", "yaml", "-o", "out.yaml"], "input", ".pl"),
    "compress": (["compress", "NAME", "-o", "out.pl"], "input", ".pl"),
    "decompress": (["decompress", "NAME"], "input", ".pl"),
    "run": (["run", "NAME", "--max-decisions", "300"], "input", ".pl"),
    "verify": (["verify", "NAME", "--max-states", "300", "--json", "-o", "out.json"], "input", ".pl"),
    "query": (["query", "NAME", "--max-steps", "20000", "sequential(X, Y)"], "input", ".pl"),
    "convert": (["convert", "NAME", "-o", "out.pl"], "input", ".pl"),
    "convert-seed": (["convert", "NAME", "--to", "seed", "-o", "out.prolog"], "input", ".pl"),
    "export-btcpp": (["export", "NAME", "--to", "btcpp", "-o", "out.xml"], "input", ".pl"),
    "export-py": (["export", "NAME", "--to", "py_trees", "-o", "out.py"], "input", ".pl"),
    "simulate-demo": (["simulate-demo", "NAME", "--scene", "mix_with_spoon.yaml", "--rate", "5", "-o", "d.csv"],
                      "input", ".pl"),
    "run-scene": (["run", "mix_with_spoon.pl", "--scene", "NAME", "--max-decisions", "300"], "scene", ".yaml"),
    "compress-out": (["compress", "mix_with_spoon.pl", "-o", "NAME"], "output", ".pl"),
    "show-out": (["show", "mix_with_spoon.pl", "--json", "-o", "NAME"], "output", ".json"),
    "generate-out": (["generate", "--depth", "2", "--children", "2", "-o", "NAME"], "output", ".pl"),
    "export-out": (["export", "mix_with_spoon.pl", "--to", "py_trees", "-o", "NAME"], "output", ".py"),
}


@st.composite
def named_cases(draw):
    """(command, the hostile name, whether the named input exists)."""
    command = draw(st.sampled_from(sorted(NAMED_COMMANDS)))
    _, role, suffix = NAMED_COMMANDS[command]
    return command, draw(m.file_names(suffix, long=LONG)), draw(st.booleans()) if role != "output" else False


def _creatable(name: str) -> bool:
    """Whether a file can have this name (NAME_MAX counts bytes)."""
    return all(len(os.fsencode(part)) <= 255 for part in name.split("/"))


def probe_file_names(case_):
    command, name, exists = case_
    argv, role, _ = NAMED_COMMANDS[command]
    files = [shipped(MIX), shipped(MIX_SCENE)]
    if exists and _creatable(name):
        files.append((name, (MIX if role == "input" else MIX_SCENE).read_bytes()))
    argv = [name if a == "NAME" else a for a in argv]
    output = name if role == "output" and _creatable(name) else output_of(argv) if role != "output" else None
    case = Case(tuple(argv), files=tuple(files), output=output)
    return case, invoke(case, GUARD)


def check_file_names(case, outcome, **_) -> list[str]:
    """The promises, and for a name: what is written is UTF-8 and loads (a module, an XML
    document) whatever the name it came from, and no control character of it reaches a terminal."""
    found = violations(case, outcome)
    for stream, text in (("stdout", outcome.stdout), ("stderr", outcome.stderr)):
        if "\x1b" in text:
            found.append(f"an escape character of the name reached {stream}")
    data = outcome.output_after
    if data is not None and outcome.status == 0:
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as err:
            return found + [f"-o target is not UTF-8: {err}"]
        if case.output.endswith(".py"):
            import ast
            try:
                ast.parse(text)
            except SyntaxError as err:
                found.append(f"the exported module does not parse: {err.msg}")
        elif case.output.endswith(".xml"):
            import xml.etree.ElementTree as ElementTree
            try:
                ElementTree.fromstring(data)
            except ElementTree.ParseError as err:
                found.append(f"the exported XML does not parse: {err}")
    return found


FILE_NAMES = dict(case_=named_cases())


@profile(30)
@given(**FILE_NAMES)
def test_hostile_file_names(case_):
    """Names past NAME_MAX, not UTF-8, with a leading dash, newlines, quotes, `\"\"\"`, `--`, control
    characters, as inputs, scenes and -o targets: a message or the work done, never a crash."""
    case, outcome = probe_file_names(case_)
    found = check_file_names(case, outcome)
    assert not found, "\n".join([*found, f"exit status: {outcome.status}", f"stderr: {outcome.stderr[-1500:]}",
                                 "reproduce with:", case.reproducer()])


# --- behaviour trees: mutated BT.CPP documents, models and semantics; sweep grids -------------

NAV2_NODES = ROOT / "tests" / "bt" / "corpus" / "nav2" / "nav2_tree_nodes.xml"
BT_LIMITS = ("--max-states", "2000", "--max-bytes", "2000000")
BT_COMMANDS = {
    "compress": ["compress", "t.xml", *BT_LIMITS],
    "compress-xml": ["compress", "t.xml", *BT_LIMITS, "-o", "out.xml"],
    "compress-json": ["compress", "t.xml", *BT_LIMITS, "--json", "-o", "out.json"],
    "verify": ["verify", "t.xml", "u.xml", *BT_LIMITS],
    "verify-json": ["verify", "t.xml", "u.xml", *BT_LIMITS, "--json"],
    "verify-self": ["verify", "t.xml", *BT_LIMITS],
    "convert": ["convert", "t.xml", "-o", "out.pl"],
    "lint": ["lint", "t.xml", "--json"],
}
SECRET = ("secret.txt", f"HOME=/root\0TOKEN={m.SECRET_MARKER}\n".encode())


def probe_bt_trees(command, tree, other, nodes):
    """A mutated BT.CPP document (and a second one for verify), with Nav2's models or without;
    secret.txt lies beside them, and a mutation may include it."""
    argv = [*BT_COMMANDS[command], *(["--nodes", "nodes.xml"] if nodes and command.startswith(("compress", "verify"))
                                     else [])]
    files = (("t.xml", tree[1]), ("u.xml", other[1]), ("nodes.xml", NAV2_NODES.read_bytes()), SECRET)
    case = Case(tuple(argv), files=files, output=output_of(argv))
    return case, invoke(case, GUARD)


def secret_kept(case, outcome, **_) -> list[str]:
    """The promises, and nothing of secret.txt, which only an <include> can reach, on the screen
    or in what was written."""
    found = violations(case, outcome)
    shown = outcome.stdout + outcome.stderr + (outcome.output_after or b"").decode("utf-8", "replace")
    if m.SECRET_MARKER in shown:
        found.append("leak: the content of a file the command line does not name was shown")
    return found


BT_TREES = dict(command=st.sampled_from(sorted(BT_COMMANDS)), tree=m.bt_trees(), other=m.bt_trees(),
                nodes=st.booleans())


@profile(40)
@given(**BT_TREES)
def test_mutated_behaviour_trees(command, tree, other, nodes):
    found = secret_kept(*probe_bt_trees(command, tree, other, nodes))
    assert not found, "\n".join(found)


def probe_bt_models(nodes, semantics, command):
    """A BT.CPP tree read with a mutated --nodes file and a mutated --semantics file."""
    tree = ROOT / "tests" / "bt" / "corpus" / "nav2" / "navigate_to_pose_w_replanning_and_recovery.xml"
    argv = [*BT_COMMANDS[command], "--nodes", "nodes.xml", "--semantics", "semantics.yaml"]
    files = (("t.xml", tree.read_bytes()), ("u.xml", tree.read_bytes()), ("nodes.xml", nodes),
             ("semantics.yaml", semantics), SECRET)
    case = Case(tuple(argv), files=files, output=output_of(argv))
    return case, invoke(case, GUARD)


BT_MODELS = dict(nodes=m.bt_nodes(), semantics=m.semantics_files(),
                 command=st.sampled_from(["compress", "verify", "verify-json", "compress-xml"]))


@profile(25)
@given(**BT_MODELS)
def test_mutated_models_and_semantics(nodes, semantics, command):
    found = secret_kept(*probe_bt_models(nodes, semantics, command))
    assert not found, "\n".join(found)


def probe_grids(grid):
    """A mutated grid swept in this process into --out o, bounded by --timeout (exit 124)."""
    argv = ["sweep", "g.yaml", "--serial", "--out", "o", "--timeout", "6"]
    case = Case(tuple(argv), files=(("g.yaml", grid[1]),))
    return case, invoke(case, GUARD + 4)


def grid_kept(case, outcome, **_) -> list[str]:
    """The promises (--timeout's 124 among the statuses), and no file written outside o/."""
    return violations(case, outcome, EXIT_STATUSES | {124})


GRIDS = dict(grid=m.grids())


@profile(15)
@given(**GRIDS)
def test_mutated_grids(grid):
    found = grid_kept(*probe_grids(grid))
    assert not found, "\n".join(found)


# name -> (the strategies of its arguments, the probe, the check): what benchmarks/fuzz.py runs.
PROBES = {
    "knowledge": (KNOWLEDGE, probe_knowledge, kept),
    "scenes": (SCENES, probe_scenes, kept),
    "demonstrations": (DEMONSTRATIONS, probe_demonstrations, kept),
    "queries": (QUERIES, probe_queries, kept),
    "reader": (READER, probe_queries, kept),
    "command-lines": (COMMAND_LINES_DRAWN, probe_command_lines, kept),
    "repl": (REPL, probe_repl, kept),
    "signals": (SIGNALS, probe_signals, check_signalled),
    "exports": (EXPORTS, probe_exports, export_kept),
    "includes": (INCLUDES, probe_includes, includes_kept),
    "file-names": (FILE_NAMES, probe_file_names, check_file_names),
    "bt-trees": (BT_TREES, probe_bt_trees, secret_kept),
    "bt-models": (BT_MODELS, probe_bt_models, secret_kept),
    "grids": (GRIDS, probe_grids, grid_kept),
}
