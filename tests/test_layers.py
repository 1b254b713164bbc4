"""The package's layering holds: no upward import, no import circle, a light command line.

Layers, lowest first (README, Layout); a module may import from its own layer and the
ones below it, and the import graph of the package's modules has no cycle. Every import
counts, those inside functions too: a lazy import is still a dependency.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import schemalog

PACKAGE = Path(schemalog.__file__).resolve().parent
LAYERS = ["", "logic", "task", "run", "formats", "learn", "evaluate", "cli"]  # "" = errors, shipped


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _layer(module: str) -> int:
    parts = module.split(".")
    if module == "schemalog.__main__":
        return len(LAYERS)  # `python -m schemalog` sits on top of everything
    return LAYERS.index(parts[1]) if len(parts) > 2 else 0


def _imports(module: str) -> set[str]:
    """The schemalog modules that `module` imports, anywhere in its text."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                origin = ".".join(base + ([node.module] if node.module else []))
            else:
                origin = node.module or ""
            # `from ..task import conditions` names a module; `from .terms import Atom` a name in one
            names = [f"{origin}.{a.name}" if f"{origin}.{a.name}" in MODULES else origin for a in node.names]
        else:
            continue
        found.update(n for n in names if n in MODULES and n != module)
    return found


GRAPH = {module: _imports(module) for module in MODULES}


def test_the_walk_sees_the_package():
    assert len(MODULES) > 40
    assert "schemalog.logic.terms" in GRAPH["schemalog.logic.engine"] or GRAPH["schemalog.logic.engine"]
    assert "schemalog.logic.engine" in GRAPH["schemalog.logic.kb"]


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_upward_import(module):
    upward = sorted(m for m in GRAPH[module] if _layer(m) > _layer(module))
    assert not upward, f"{module} (layer {LAYERS[_layer(module)] or 'root'}) imports higher layers: {upward}"


def test_no_import_circle():
    state: dict[str, int] = {}  # 1 = on the current path, 2 = done
    for start in sorted(GRAPH):
        if state.get(start):
            continue
        path, stack = [start], [iter(sorted(GRAPH[start]))]
        state[start] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
                continue
            if state.get(nxt) == 1:
                cycle = path[path.index(nxt):] + [nxt]
                pytest.fail("import circle: " + " -> ".join(cycle))
            if not state.get(nxt):
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(GRAPH[nxt])))


def _loaded_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(' '.join(sorted(sys.modules)))"],
                         capture_output=True, text=True, timeout=60, check=True)
    return set(out.stdout.split())


def test_the_engine_loads_nothing_above_logic():
    loaded = _loaded_after("import schemalog.logic.engine")
    above = sorted(m for m in loaded if m.startswith("schemalog.") and m in MODULES and _layer(m) > 1)
    assert not above
    assert "schemalog.logic.engine" in loaded


HEAVY = ("matplotlib", "numpy", "sympy", "py_trees", "rich", "yaml", "prompt_toolkit", "dask", "distributed",
         "pyarrow")


@pytest.mark.parametrize("argv", [["--help"], ["query", "kb/tasks/mix_with_spoon.pl", "true"]])
def test_a_plain_command_loads_no_heavy_library(argv):
    root = PACKAGE.parents[1]
    code = (f"import os, sys\nos.chdir({str(root)!r})\nfrom schemalog.cli.main import main\n"
            f"import contextlib, io\nwith contextlib.redirect_stdout(io.StringIO()):\n"
            f"    try:\n        code = main({argv!r})\n    except SystemExit as e:\n        code = e.code\n"
            f"assert code == 0, code")
    loaded = _loaded_after(code)
    assert "schemalog.cli.main" in loaded
    heavy = sorted({m.split(".")[0] for m in loaded} & set(HEAVY))
    assert not heavy, f"schemalog {' '.join(argv)} loads {heavy}"


def test_no_command_line_module_over_400_lines():
    long = {p.name: n for p in (PACKAGE / "cli").glob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > 400}
    assert not long


def test_test_modules_have_unique_names():
    # pytest imports test modules by basename (no __init__.py here): two test_limits.py in
    # different folders stop the whole run at collection
    names = [p.name for p in Path(__file__).parent.rglob("test_*.py")]
    assert sorted(n for n in set(names) if names.count(n) > 1) == []
