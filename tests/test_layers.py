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
LAYERS = ["", "logic", "task", "bt", "run", "formats", "learn", "evaluate", "api", "testing", "cli"]  # "" = errors, shipped


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _layer(module: str) -> int:
    parts = module.split(".")
    if module == "schemalog.__main__":
        return len(LAYERS)  # `python -m schemalog` sits on top of everything
    if module == "schemalog":
        return LAYERS.index("api")  # the package's own names are the API's, imported when first used
    if len(parts) == 2 and parts[1] in LAYERS:
        return LAYERS.index(parts[1])  # a layer's own __init__ (schemalog.testing imports schemalog)
    return LAYERS.index(parts[1]) if len(parts) > 2 else 0


def _type_only(tree: ast.AST) -> set[int]:
    """The ids of the import nodes inside `if TYPE_CHECKING:` blocks: names for annotations,
    never imported when the program runs."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            found.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    return found


def _imports(module: str, runtime: bool = False) -> set[str]:
    """The schemalog modules that `module` imports, anywhere in its text (runtime: leaving out
    the imports only a type checker makes)."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _type_only(tree) if runtime else set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
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
# The circle test's graph: a type checker resolves annotations in any order (Task's methods
# return a Run and a Report, whose modules name Task in their annotations).
RUNTIME = {module: _imports(module, runtime=True) for module in MODULES}


def test_the_walk_sees_the_package():
    assert len(MODULES) > 40
    assert "schemalog.logic.terms" in GRAPH["schemalog.logic.engine"] or GRAPH["schemalog.logic.engine"]
    assert "schemalog.logic.engine" in GRAPH["schemalog.logic.kb"]


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_upward_import(module):
    upward = sorted(m for m in GRAPH[module] if _layer(m) > _layer(module))
    assert not upward, f"{module} (layer {LAYERS[_layer(module)] or 'root'}) imports higher layers: {upward}"


def test_no_import_circle():
    GRAPH = RUNTIME
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


# The command line only parses arguments, calls the API and prints (issue 34): a cli module
# imports from schemalog only the API layer (schemalog, schemalog.api.*), other cli modules,
# what needs no layer (errors, defaults, inputs) and these presentation modules.
PRESENTATION = {
    "schemalog.formats.render": "rich trees, DOT and the pictures' panels: how a tree is laid out",
    "schemalog.formats.graphviz": "Graphviz's dot program: a picture rendered from DOT text",
}
BELOW_THE_API = {"schemalog.errors", "schemalog.defaults", "schemalog.inputs"}
PENDING: set[str] = set()        # none left: bench, sweep and verify --each call api/sweep.py (issue 36)


def _allowed_from_the_command_line(module: str) -> bool:
    return (module == "schemalog" or module.startswith(("schemalog.api.", "schemalog.cli."))
            or module == "schemalog.api" or module in BELOW_THE_API or module in PRESENTATION)


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith("schemalog.cli.") and m not in PENDING))
def test_the_command_line_reaches_only_the_api(module):
    below = sorted(m for m in GRAPH[module] if not _allowed_from_the_command_line(m))
    assert not below, (f"{module} imports below the API: {below}; move what it needs into schemalog/api/ "
                       f"(presentation: add the module to PRESENTATION with its reason)")


def test_the_rule_sees_the_command_line():
    assert "schemalog.cli.main" in MODULES and "schemalog.api.task" in GRAPH["schemalog.cli.compress"] or \
        "schemalog" in GRAPH["schemalog.cli.compress"]
    assert not _allowed_from_the_command_line("schemalog.logic.engine")
    assert all(m in MODULES for m in PRESENTATION)


def test_no_command_line_module_over_400_lines():
    long = {p.name: n for p in (PACKAGE / "cli").glob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > 400}
    assert not long


def test_test_modules_have_unique_names():
    # pytest imports test modules by basename (no __init__.py here): two test_limits.py in
    # different folders stop the whole run at collection
    names = [p.name for p in Path(__file__).parent.rglob("test_*.py")]
    assert sorted(n for n in set(names) if names.count(n) > 1) == []


EXAMPLE = Path(__file__).parent / "example_project"


def test_the_example_project_uses_only_the_public_api():
    """A user's project (tests/example_project) imports schemalog and schemalog.testing (its
    strategies too), nothing else of the package: what is not exported there is private."""
    allowed = {"schemalog", "schemalog.testing", "schemalog.testing.strategies"}
    files = sorted(EXAMPLE.rglob("*.py"))
    assert len(files) >= 2
    found = {}
    for path in files:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module or ""]
                names += [f"{node.module}.{a.name}" for a in node.names
                          if f"{node.module}.{a.name}" in MODULES]       # `from schemalog import api`
            else:
                continue
            for name in names:
                if name.split(".")[0] == "schemalog" and name not in allowed:
                    found.setdefault(str(path.relative_to(EXAMPLE)), []).append(name)
    assert not found, f"the example project imports private modules: {found}"
