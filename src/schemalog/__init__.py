"""schemalog: symbolic task compression for structured robot tasks, as a Prolog-style engine.

The public API (docs/api.md); anything not named here is private:

    >>> import schemalog
    >>> kb = schemalog.load("kb/tasks/mix_with_spoon.pl")       # doctest: +SKIP
    >>> task = kb.task(); small = task.compress()                 # doctest: +SKIP
    >>> schemalog.verify(task, small).proved                      # doctest: +SKIP
    True

The names load lazily, so `import schemalog` reads no engine, sympy or numpy until used.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

__version__ = "0.1.0"

# name -> the module of the API layer that defines it
_EXPORTS = {
    "load": "schemalog.api.knowledge", "loads": "schemalog.api.knowledge", "Knowledge": "schemalog.api.knowledge",
    "Task": "schemalog.api.task", "Compression": "schemalog.api.task",
    "verify": "schemalog.api.report", "Report": "schemalog.api.report", "Counterexample": "schemalog.api.report",
    "Run": "schemalog.api.execution", "Finding": "schemalog.run.lint", "LimitExceeded": "schemalog.api.limits",
    "QueryError": "schemalog.api.knowledge",
    "SchemalogError": "schemalog.errors", "UsageError": "schemalog.errors", "SourcePos": "schemalog.errors",
    # BT.CPP trees (docs/api.md, "Behaviour trees")
    "read_tree": "schemalog.api.trees", "compress_tree": "schemalog.api.trees", "verify_trees": "schemalog.api.trees",
    "TreeDocument": "schemalog.api.trees", "TreeCompression": "schemalog.api.trees", "TreeProof": "schemalog.api.trees",
    # here: the public diff (`schemalog diff`: api/tree_diff.py's diff_trees, DiffReport; docs/api.md)
}

__all__ = sorted([*_EXPORTS, "__version__"])

if TYPE_CHECKING:  # what type checkers and editors see; at run time __getattr__ imports on first use
    from .api.execution import Run
    from .api.knowledge import Knowledge, QueryError, load, loads
    from .api.limits import LimitExceeded
    from .api.report import Counterexample, Report, verify
    from .api.task import Compression, Task
    from .api.trees import TreeCompression, TreeDocument, TreeProof, compress_tree, read_tree, verify_trees
    from .errors import SchemalogError, SourcePos, UsageError
    from .run.lint import Finding


def __getattr__(name: str):
    """Import a public name's module when the name is first used (PEP 562)."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'schemalog' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return __all__
