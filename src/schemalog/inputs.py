"""Reading input files within a byte limit, whatever they are: regular files, FIFOs, devices.

    read_limited(path, max_bytes, label) -> bytes   at most max_bytes bytes, or an error naming the file
    missing(path) -> bool                           whether nothing has that name (a name the system
                                                    refuses, too long, is not missing: reading says why)
    is_xml(path) -> bool                            whether a file is XML (a BT.CPP tree): by its content
    folder_files(folder, suffix) -> names           a folder's regular files named *suffix, sorted, not opened
    check_yaml_nesting(text, file)                  refuse flow collections nested past MAX_YAML_NESTING

Every reader of a user's file (knowledge files and consulted ones, scenes, demonstrations)
reads through it, so `--max-bytes` bounds what is read, not only what `stat` reports, and
one rule holds for every input: a FIFO or a terminal is read like a file, and when standard
error is a terminal a note says so before the read waits for a writer (or for typing), so
a run never waits without a word; `--timeout` bounds the wait.
"""

from __future__ import annotations

import errno
import os
import stat
import sys
from pathlib import Path

from .errors import SchemalogError, SourcePos, shown_name

# PyYAML's scanner keeps a possible simple key per open flow collection and revisits them
# all at each token: 5,000 unclosed `{` cost ~20 s to refuse, and composing recurses per
# level. Scenes and task files nest three or four levels; a hundred is far past any.
MAX_YAML_NESTING = 100


def size_text(n: int) -> str:
    """A size as users read it: MiB from one MiB up, else bytes."""
    return f"{n / 2**20:.1f} MiB" if n >= 2**20 else f"{n:,} bytes"


def read_limited(path: str | Path, max_bytes: int, label: str | None = None) -> bytes:
    """The bytes of a file, at most `max_bytes` of them, or an error naming the file (`label`).

    The limit holds for the bytes actually read, not only for the size the file system
    reports: a FIFO, a device (/dev/zero) or a file that grows while it is read is read
    up to the limit and refused past it, never read into memory without end."""
    p = Path(path)
    label = label or shown_name(os.fspath(path))
    try:
        if stat.S_ISFIFO(os.stat(p).st_mode):      # opening it waits for a writer
            _note(f"reading {label}: waiting for input (a FIFO)")
    except OSError:
        pass                                       # open says what is wrong
    try:
        with open(p, "rb") as handle:
            info = os.fstat(handle.fileno())
            if os.isatty(handle.fileno()):
                _note(f"reading {label}: waiting for input (a terminal: end it with Ctrl-D)")
            if stat.S_ISDIR(info.st_mode):
                raise IsADirectoryError(errno.EISDIR, "is a directory")
            if stat.S_ISREG(info.st_mode) and info.st_size > max_bytes:
                raise SchemalogError(f"{label}: file is {size_text(info.st_size)}, over the "
                                     f"{size_text(max_bytes)} limit (raise it with --max-bytes)")
            data = _read_at_most(handle, max_bytes + 1)
    except FileNotFoundError:
        raise SchemalogError(f"{label}: no such file") from None
    except IsADirectoryError:
        raise SchemalogError(f"{label}: is a directory, not a file to read") from None
    except OSError as err:
        raise SchemalogError(f"{label}: cannot read: {err.strerror or err}") from None
    if len(data) > max_bytes:
        raise SchemalogError(f"{label}: over the {size_text(max_bytes)} limit (reading stopped there; "
                             f"raise it with --max-bytes)")
    return data


def not_regular(path: str | Path) -> str | None:
    """What a path names when it is there and is no regular file ("a FIFO", "a directory", ...),
    else None. A file read on the program's own account (an <include>, a folder's trees) must
    be a regular file: opening a FIFO waits for a writer without end, a device never ends."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return None                                # reading it says what is wrong
    for test, what in ((stat.S_ISREG, None), (stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return what
    return "not a regular file"


def folder_files(folder: str | Path, suffix: str = ".xml") -> tuple[str, ...]:
    """The files directly in `folder` whose name ends in `suffix` (as written: `.xml`, not `.XML`,
    and not a file named `.xml` alone, as std::filesystem's extension() reads names, which Nav2
    and BehaviorTree.ROS2 match), as paths, sorted by name. Subfolders are not entered. A symlink
    to a regular file is one (colcon --symlink-install installs every file so); one named so that
    is no regular file (a FIFO, a device, a socket, a directory or a link to one) is refused with
    its name and never opened: opening a FIFO waits for a writer without end."""
    label = shown_name(os.fspath(folder))
    try:
        names = sorted(os.listdir(folder))
    except FileNotFoundError:
        raise SchemalogError(f"{label}: no such folder") from None
    except OSError as err:
        raise SchemalogError(f"{label}: cannot read the folder: {err.strerror or err}") from None
    out = []
    for name in names:
        if not name.endswith(suffix) or name == suffix:
            continue
        path = os.path.join(os.fspath(folder), name)
        what = not_regular(path)
        if what is not None:
            raise SchemalogError(f"{shown_name(path)}: {what} named *{suffix} in the folder {label}, not a file: "
                                 f"schemalog reads a folder's regular *{suffix} files (and links to them) and "
                                 f"does not open it")
        out.append(path)
    return tuple(out)


def read_utf8(path: str | Path, max_bytes: int) -> str:
    """The text of a file (a BOM dropped), at most `max_bytes` of it; bytes that are not UTF-8
    are an error at the line and column where they stand."""
    data = read_limited(path, max_bytes)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = data[:err.start].count(b"\n") + 1
        column = err.start - (data.rfind(b"\n", 0, err.start) + 1) + 1
        raise SchemalogError("not UTF-8 text", SourcePos(str(path), line, column)) from None


def is_xml(path: str | Path) -> bool:
    """Whether a file is XML, a BehaviorTree.CPP document, whatever its name: its first character
    after blank space (and a UTF-8 byte order mark) is `<`, which begins an XML declaration, a
    comment or an element, and no Prolog, SEED or YAML task; or its name ends in .xml. Every
    command that takes a BT.CPP tree tells it so (docs/behaviour_trees.md).

    Only a regular file is looked into: a FIFO, a terminal or a device is read once, by the
    reader this chooses, so it is told by its name alone. A file that cannot be read is XML
    only by its name; its reader says why it cannot be read."""
    named = os.fspath(path).lower().endswith(".xml")
    try:
        if named or not stat.S_ISREG(os.stat(path).st_mode):
            return named
        with open(path, "rb") as handle:
            start = b""
            while chunk := handle.read(4096):
                start = chunk.lstrip(_BLANK)
                if start:
                    break
    except (OSError, ValueError):
        return named
    return start.startswith(b"<")


_BLANK = b" \t\r\n\xef\xbb\xbf"      # blank space, and the bytes of a UTF-8 byte order mark


def missing(path: str | Path) -> bool:
    """Whether no file has this name. A name the system refuses for another reason (longer than
    NAME_MAX, a directory that cannot be searched) is not missing: reading it says why, where
    Path.exists() would raise that OSError from wherever it was asked."""
    try:
        os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        return True
    except (OSError, ValueError):
        return False
    return False


def _read_at_most(handle, n: int, chunk: int = 1 << 20) -> bytes:
    """Up to `n` bytes, read a chunk at a time: one read(n) allocates n bytes at once, and
    fails outright for an n past the C size type (`--max-bytes 99999999999999999999`)."""
    parts, total = [], 0
    while total < n:
        part = handle.read(min(chunk, n - total))
        if not part:
            break
        parts.append(part)
        total += len(part)
    return b"".join(parts)


def check_yaml_nesting(text: str, file: str, limit: int = MAX_YAML_NESTING) -> None:
    """Refuse YAML whose flow collections (`{...}`, `[...]`) nest deeper than `limit`, in one
    pass before PyYAML sees it. Quoted scalars and comments are skipped; a bracket in a plain
    scalar counts, which can only refuse sooner."""
    depth = 0
    line, start = 1, 0
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "\n":
            line, start = line + 1, i + 1
        elif c in "{[":
            depth += 1
            if depth > limit:
                raise SchemalogError(f"YAML nests deeper than {limit} levels of brackets here",
                                     SourcePos(file, line, i - start + 1),
                                     text[start:text.find("\n", start) if "\n" in text[start:] else n][:200])
        elif c in "}]":
            depth = max(0, depth - 1)
        elif c == "#" and (i == 0 or text[i - 1] in " \t\n"):
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        elif c in "'\"" and (i == 0 or text[i - 1] in " \t\n,[{:"):
            end = text.find(c, i + 1)                 # to the closing quote ('' and \" close early:
            if end < 0:                               # harmless, the rest is still scanned)
                return
            skipped = text.count("\n", i, end)
            if skipped:
                line, start = line + skipped, text.rfind("\n", i, end) + 1
            i = end + 1
            continue
        i += 1


def _note(text: str) -> None:
    """Tell a user at a terminal what the process waits for (a script's stderr stays clean:
    `schemalog check <(cat f)` reads a FIFO too)."""
    try:
        if sys.stderr is not None and sys.stderr.isatty():
            print(text, file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass


def compose_yaml(text: str, file: str):
    """YAML composed into nodes (not constructed: every value keeps its place), with `fail`:
    (message, node) -> a SchemalogError at the node's file:line:column. A syntax error is one too."""
    import yaml  # loaded only when YAML is read

    lines = text.split("\n")

    def fail(message: str, node) -> SchemalogError:
        mark = node.start_mark
        line = lines[mark.line] if mark.line < len(lines) else None
        return SchemalogError(message, SourcePos(file, mark.line + 1, mark.column + 1), line)

    check_yaml_nesting(text, file)
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        pos = SourcePos(file, mark.line + 1, mark.column + 1) if mark else SourcePos(file, 1, 1)
        line = lines[mark.line] if mark and mark.line < len(lines) else None
        raise SchemalogError(f"YAML syntax error: {getattr(err, 'problem', None) or err}", pos, line) from None
    return root, fail
