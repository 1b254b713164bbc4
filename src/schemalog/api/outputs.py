"""Where the API's results are written: outputs checked before any work, written atomically,
several together, never over a file that was read (docs/formats.md, Outputs).

    check_output(name, inputs)   refuse an output that is an input or names no file
    write_atomically(name, text) through a temporary file and a rename (a FIFO: written into)
    write_together([(name, bytes)])  several files, all or none
    Staging                      files made by others (a plot) under temporary names, renamed together

The command line's writers are these (cli/common.py: emit; cli/output.py: pictures; learn).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Iterable

from ..errors import CannotWrite, SchemalogError, UsageError
from ..formats.documents import file_mode, output_target, write_atomically, write_in_place, write_together
from .arguments import refuse_overwriting

__all__ = ["check_output", "write_atomically", "write_together", "writes_in_place", "Staging"]


def check_output(output: str | None, inputs: Iterable[str], option: str = "-o") -> None:
    """Refuse, before any work is written, an output that is one of the `inputs` (the files
    read) or that names no file (a directory, `name/`, no such directory), a usage error, or
    that the system would refuse (a name too long, a directory not writable), CannotWrite.
    Standard output (None, `-`) is always fine."""
    if output is None or output == "-":
        return
    refuse_overwriting(output, inputs, option)
    try:
        output_target(output)
    except CannotWrite:
        raise
    except SchemalogError as err:
        raise UsageError(err.message) from None


def writes_in_place(output: str) -> bool:
    """Whether `output` is written into (a FIFO, a device) rather than replaced."""
    return output_target(output).in_place


class Staging:
    """Files written under temporary names beside their targets, then renamed onto them
    together: bad input or a failed write leaves none behind (learn's -o, --plot, --motions)."""

    def __init__(self) -> None:
        self.staged: list[tuple[str, str]] = []     # (temporary, target)

    def stage(self, target: str) -> str:
        """A temporary file beside `target`, with its suffix, to be renamed onto it; for a
        FIFO or a device, one in the temporary directory, to be copied into it."""
        path = output_target(target)
        try:
            fd, temporary = tempfile.mkstemp(prefix=f".{path.path.name}.", suffix=Path(target).suffix,
                                             dir=None if path.in_place else path.path.parent)
        except OSError as err:
            raise OSError(err.errno, err.strerror, target) from None
        os.close(fd)
        self.staged.append((temporary, target))
        return temporary

    def commit(self) -> None:
        """Write the special ones (FIFO, device) in place, then rename the staged files onto
        their targets (through links), together: a device that refuses (/dev/full) is found
        before any file is replaced, since it cannot be checked beforehand."""
        targets = [(temporary, output_target(target)) for temporary, target in self.staged]
        for temporary, target in targets:
            if target.in_place:
                write_in_place(target.path, Path(temporary).read_bytes())
        for temporary, target in targets:
            if not target.in_place:
                os.chmod(temporary, file_mode(target.path))
        for temporary, target in targets:
            if not target.in_place:
                os.replace(temporary, target.path)

    def failed(self, err: OSError) -> SchemalogError:
        """The message for a write that failed: the target's name, not the temporary one's."""
        temporaries = dict(self.staged)
        name = temporaries.get(err.filename, err.filename) if err.filename else \
            (self.staged[-1][1] if self.staged else "")
        return SchemalogError(f"cannot write {name or 'the output'}: {err.strerror or err}; nothing was written")

    def clean(self) -> None:
        """Remove what is left of the temporary files (after a failure, or an interrupt)."""
        for temporary, _ in self.staged:
            if os.path.exists(temporary):
                os.unlink(temporary)
