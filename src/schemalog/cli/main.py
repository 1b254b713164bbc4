"""The `schemalog` command line: the top level that registers one module per command.

    schemalog COMMAND [OPTIONS] ...   COMMAND in COMMANDS; each module holds its arguments
                                      (`register`) and its handler (`run`) side by side

A command module imports only argparse and the defaults when the command line is built;
its handler imports what it needs when it runs, so `schemalog --help` and a plain query
load neither sympy, numpy, matplotlib nor py_trees.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import os
import signal
import sys

from .. import __version__
from ..errors import READABLE, SchemalogError
from ..api.limits import (TIMEOUT_EXIT, TimeLimitExceeded, apply_memory_ceiling, memory_ceiling, out_of_memory_text,
                     governed, restored_memory_limit, time_limit)
from .options import shared_parents

# In the order `schemalog --help` lists them: module names in schemalog.cli.
COMMANDS = ("check", "lint", "show", "compress", "decompress", "run", "verify", "diff", "generate", "bench", "sweep", "learn",
            "simulate_demo", "query", "repl", "convert", "export")


class Terminated(BaseException):
    """SIGTERM or SIGHUP arrived: unwinds like KeyboardInterrupt, so what cleans up after
    Ctrl-C (write_atomically's temporary file, learn's staged files) cleans up after these."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


def _terminate(signum: int, frame) -> None:
    raise Terminated(signum)


def catch_termination() -> None:
    """Turn SIGTERM and SIGHUP into Terminated, unless they are ignored (nohup)."""
    for name in ("SIGTERM", "SIGHUP"):
        number = getattr(signal, name, None)
        if number is not None and signal.getsignal(number) is signal.SIG_DFL:
            signal.signal(number, _terminate)


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command line: the top level and every command's arguments, or with `only` (a
    command's name, as typed) just that command's, which is all a run of it reads."""
    parser = argparse.ArgumentParser(
        prog="schemalog", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=EXIT_STATUS,
        description="Compress and check robot task structures (schema(m, l, p) knowledge).")
    parser.add_argument("--version", action="version", version=f"schemalog {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    parents = shared_parents()
    for name in COMMANDS if only is None else [only.replace("-", "_")]:
        importlib.import_module(f"{__package__}.{name}").register(sub, parents)
    for command in sub.choices.values():      # a wrong option is told with its command's usage
        command.set_defaults(command_parser=command)
    return parser


NO_PROOF = 3     # verify, compress --verify: no counterexample, and no proof

# What the statuses returned below (and by the commands) mean; `schemalog --help` ends with it.
EXIT_STATUS = f"""\
exit status:
  0    done: checked, compressed, proved (verify), accomplished (run), answered (query)
  1    no: a counterexample (verify), the task not accomplished (run), no answer (query);
       or bad input (a message with file:line:column), or out of memory
  2    a wrong command line (the command's usage follows); query and repl: also a bad
       query or file, or input that ends inside a query
       diff: 0 same behaviour, 1 behaviour changed, 2 bad input or usage, 3 no proof
  3    verify, compress --verify: no counterexample, but no proof (a limit, memory
       included, or --sample)
  70   an internal error (please report it; SCHEMALOG_DEBUG=1 shows the traceback)
  {TIMEOUT_EXIT:<4} --timeout ran out (as timeout(1))
  130  interrupted (Ctrl-C); 128+N for signal N (143 SIGTERM, 129 SIGHUP)
"""


def _named_command(argv: list[str]) -> str | None:
    """The command `argv` names first, when it is one of ours (`run`, `simulate-demo`)."""
    name = argv[0] if argv else None
    return name if name and name.replace("-", "_") in COMMANDS and "_" not in name else None


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    readable_streams()
    parser = build_parser(_named_command(argv))
    args, extra = parser.parse_known_args(argv)
    if extra:
        # `schemalog query FILE --first QUERY`: argparse gives FILE to QUERY and leaves the
        # real query over; options may stand anywhere, as for every other command.
        if getattr(args, "command", None) == "query" and not any(e.startswith("-") for e in extra):
            args.files, args.query = [*args.files, args.query, *extra[:-1]], extra[-1]
        else:
            command_parser = getattr(args, "command_parser", parser)
            command_parser.error(f"unrecognized arguments: {' '.join(extra)}{_misplaced(argv, args, extra)}")
    if not getattr(args, "run", None):
        parser.print_help(sys.stderr)
        return 2
    with restored_memory_limit():
        return _run_command(args, parser)


def readable_streams() -> None:
    """Write what standard output and error cannot encode as escapes (errors.READABLE), never a
    UnicodeEncodeError: a file name that is not UTF-8 reaches messages, titles and answers as
    lone surrogates, which Python's own handlers raise on (strict, in a UTF-8 locale) or write
    back as bytes no UTF-8 reader takes (surrogateescape, in the C locale)."""
    for stream in (sys.stdout, sys.stderr):
        if hasattr(stream, "reconfigure"):
            try:
                stream.reconfigure(errors=READABLE)
            except (OSError, ValueError):      # a closed or detached stream: nothing to say there
                pass


def _misplaced(argv: list[str], args: argparse.Namespace, extra: list[str]) -> str:
    """The hint for `schemalog --json show FILE`: an option of the command, given before its name."""
    command = getattr(args, "command", None)
    accepted = getattr(getattr(args, "command_parser", None), "_option_string_actions", {})
    if command not in argv:
        return ""
    before = argv[:argv.index(command)]
    early = [e for e in extra if e.split("=", 1)[0] in accepted and e in before]
    if not early:
        return ""
    return f" (options of {command} go after its name: schemalog {command} {' '.join(early)} ...)"


def _run_command(args: argparse.Namespace, parser: argparse.ArgumentParser) -> int:
    """Run the parsed command under its limits; turn whatever stops it into a message and a status."""
    from ..api.failures import PrologError

    ceiling = None
    # A proof that runs out of memory is no proof, not a counterexample: exit 3, as at --max-states
    proving = args.command in ("verify", "diff") or (args.command == "compress" and getattr(args, "verify", False))
    trouble = 2 if args.command == "diff" else 1    # diff's 1 means "they differ", as diff(1) has it
    no_proof = ": no proof (exit 3)" if proving else ""
    said = (out_of_memory_text(None) + no_proof + "\n").encode()
    try:
        ceiling = apply_memory_ceiling(memory_ceiling(getattr(args, "max_memory", None), os.environ))
        # Made now: when memory has run out, even this message may find none to be made in.
        said = (out_of_memory_text(ceiling) + no_proof + "\n").encode()
        # The timer is disarmed as the command returns, before any handler below prints.
        # governed: the API calls the command makes run under these limits, adding none of their own
        with time_limit(getattr(args, "timeout", None)), governed():
            return args.run(args)
    except SchemalogError as err:
        print(str(err), file=sys.stderr)
        if err.exit_code == 2:
            print(f"(see: schemalog {args.command} --help)", file=sys.stderr)
        return trouble if err.exit_code == 1 else err.exit_code
    except PrologError as err:
        from .toplevel import error_text     # the ISO errors in plain words, resource errors' limits

        print(error_text(err), file=sys.stderr)
        return trouble
    except RecursionError:
        print("error: the input nests too deeply to process", file=sys.stderr)
        return trouble
    except MemoryError:     # not bound: the frames holding the memory go with the traceback
        return _out_of_memory(said, NO_PROOF if proving else 1)
    except OverflowError as err:
        print(f"error: a number is too large to process ({err})", file=sys.stderr)
        return trouble
    except (TimeLimitExceeded, KeyboardInterrupt, Terminated) as stop:
        return _stopped(stop)
    except BrokenPipeError:
        return 0
    except Exception as err:  # an internal error must still not dump a traceback on users
        cause = _wrapped_stop(err)
        if isinstance(cause, MemoryError):
            return _out_of_memory(said, NO_PROOF if proving else 1)
        if cause is not None:
            return _stopped(cause)
        if os.environ.get("SCHEMALOG_DEBUG"):
            raise
        print(f"internal error: {type(err).__name__}: {err} (please report it; "
              f"SCHEMALOG_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 70


def _stopped(stop: BaseException) -> int:
    """Say why the run stopped early (the time limit, Ctrl-C, a signal); its exit status."""
    if isinstance(stop, TimeLimitExceeded):
        print(str(stop), file=sys.stderr)
        return TIMEOUT_EXIT
    if isinstance(stop, Terminated):
        print(f"terminated ({signal.Signals(stop.signum).name})", file=sys.stderr)
        return 128 + stop.signum
    print("interrupted", file=sys.stderr)
    return 130


def _wrapped_stop(err: BaseException) -> BaseException | None:
    """The time limit, a signal or MemoryError that `err` wraps: Python turns what a class
    body's __set_name__ raises into RuntimeError, so the time limit arriving while a module
    is imported would otherwise read as an internal error."""
    seen = set()
    while err is not None and id(err) not in seen:
        seen.add(id(err))
        if isinstance(err, (TimeLimitExceeded, KeyboardInterrupt, Terminated, MemoryError)):
            return err
        err = err.__cause__ or err.__context__
    return None


def tune_gc() -> None:
    """Collect garbage less often: loading builds millions of small immutable objects and
    almost no cycles, and the default thresholds make it superlinear (x25 per 10x size
    instead of x10, benchmarks/bench_foundation.py)."""
    gc.set_threshold(50_000, 20, 100)


def _leave(signum: int, frame) -> None:
    os._exit(128 + signum)      # during the final flush: stop writing, say nothing more


def _leave_on_signals() -> None:
    """From now on, Ctrl-C, SIGTERM and SIGHUP end the process at once with 128+signum: a
    traceback from a flush, or a KeyboardInterrupt while a big structure is freed, must not
    reach users, and a Ctrl-C must still stop a flush into a pipe nobody reads."""
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):
        number = getattr(signal, name, None)
        if number is not None and signal.getsignal(number) is not signal.SIG_IGN:
            signal.signal(number, _leave)


def _out_of_memory(said: bytes, status: int) -> int:
    """Say that memory ran out, with the words set aside for it, and return `status`: the handler
    may have no memory left to make a string in (a MemoryError raised here printed a traceback).
    The ceiling is lifted first, so that what follows (flushing, leaving) can allocate; main()
    restores it."""
    try:
        import resource

        _, hard = resource.getrlimit(resource.RLIMIT_DATA)
        resource.setrlimit(resource.RLIMIT_DATA, (hard, hard))
    except (ImportError, ValueError, OSError, MemoryError):
        pass
    try:
        sys.stderr.flush()
    except (OSError, ValueError, MemoryError):
        pass
    try:
        os.write(2, said)
    except OSError:
        pass
    return status


def run() -> None:
    """Console-script entry point."""
    code, started = 70, False
    while True:     # a signal may cut in until the handlers are swapped: then it is the status
        try:
            if not started:
                started = True
                tune_gc()
                sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
                catch_termination()
                code = main()
            _leave_on_signals()
            break
        except KeyboardInterrupt:
            code = 130
        except Terminated as stop:
            code = 128 + stop.signum
        except SystemExit as done:       # argparse: --help, --version, a wrong command line
            code = done.code if isinstance(done.code, int) else 0 if done.code is None else 1
            if not isinstance(done.code, (int, type(None))):
                print(done.code, file=sys.stderr)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):      # a closed pipe or stream: nothing more can be said there
            pass
    # Skip the interpreter's teardown: freeing a huge tree object by object takes seconds
    # (benchmarks/bench_exit.py) and nothing is left to write; every file is already closed.
    os._exit(code)


__all__ = ["main", "run", "build_parser", "COMMANDS"]
