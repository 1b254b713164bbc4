"""A declared evaluation grid (`schemalog sweep GRID.yaml`): what to generate and what to measure.

    read_grid(path) -> Grid            # checked: every error names file:line:column
    named_grid("paper") -> Grid        # a grid shipped in evaluate/grids/ (paper, quick, runtimes)
    grid.cells() -> list[CellSpec]     # one Dask task each (evaluate/sweep.py)

A grid names shapes (depth x children), reduction degrees, seeds and propagation modes; their
product is the generated cells. `coffee: true` adds the paper's coffee-and-tea task, `sizes`
the selectors on large original trees (bench --paper's last table). `measures` says what each
generated cell does besides generating and compressing: `prove` (verify --method auto),
`time` (the selectors of `selectors`, `runs` object configurations per tree) and `runtimes`
(BT.CPP and py_trees, bench --runtimes). `limits` bound every cell.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

from .. import defaults
from ..errors import SchemalogError, SourcePos, UsageError, shown_number
from ..inputs import compose_yaml, read_limited
from ..logic.terms import int_of_digits
from .generate import node_count

Shape = tuple[int, int]
MEASURES = ("compress", "prove", "time", "runtimes")
SELECTORS = ("scan", "incremental", "py_trees")
GRIDS = Path(__file__).resolve().parent / "grids"
MAX_GRID_NODES = 2_000_000          # generate's own --max-nodes default
MAX_CELLS = 1_000_000


@dataclass(frozen=True)
class CellSpec:
    """One cell of a grid: its parameters are its key in the results file."""

    kind: str                       # "generated", "coffee" or "size"
    depth: int = 0
    children: int = 0
    rd: float | None = None
    seed: int = 1
    propagate: str = "full"

    @property
    def key(self) -> str:
        if self.kind == "coffee":
            return f"coffee/seed{self.seed}/{self.propagate}"
        if self.kind == "size":
            return f"size/{self.depth}x{self.children}/seed{self.seed}"
        return f"generated/{self.depth}x{self.children}/rd{self.rd:g}/seed{self.seed}/{self.propagate}"

    @property
    def behaviours(self) -> int:
        return 63 if self.kind == "coffee" else node_count(self.depth, self.children)

    @property
    def title(self) -> str:
        if self.kind == "coffee":
            return "coffee and tea"
        if self.kind == "size":
            return f"selectors at {self.behaviours:,} behaviours"
        return (f"depth {self.depth}, {self.children} children ({self.behaviours:,} behaviours), RD {self.rd:g}"
                f", seed {self.seed}, propagate {self.propagate}")


@dataclass(frozen=True)
class Grid:
    """What a sweep generates and measures (the YAML's keys, with these defaults)."""

    name: str = "grid"
    shapes: tuple[Shape, ...] = ()
    reductions: tuple[float, ...] = (0.0, 0.3, 0.5, 0.7)
    seeds: tuple[int, ...] = (1,)
    propagate: tuple[str, ...] = ("full",)
    measures: tuple[str, ...] = ("compress", "prove")
    selectors: tuple[str, ...] = SELECTORS
    runs: int = 10
    ticks: int = 5
    min_seconds: float = 0.0
    coffee: bool = False
    sizes: tuple[Shape, ...] = ()
    max_states: int = 20_000
    verify_seconds: float | None = None
    max_bdd_nodes: int = 5_000_000
    cell_seconds: float | None = None
    file: str = field(default="", compare=False)

    def cells(self) -> list[CellSpec]:
        """Every cell, in the order the reports list them."""
        out = [CellSpec("generated", d, b, rd, seed, mode) for d, b in self.shapes for rd in self.reductions
               for seed in self.seeds for mode in self.propagate]
        if self.coffee:
            # its configurations are the kitchen's, jittered by run: a seed changes nothing there
            out += [CellSpec("coffee", seed=self.seeds[0], propagate=mode) for mode in self.propagate]
        out += [CellSpec("size", d, b, 0.5, seed) for d, b in self.sizes for seed in self.seeds]
        return out

    def settings(self) -> str:
        """What every cell's result depends on besides its key: stored beside each row, so a
        results file is never resumed by a grid that measures differently."""
        keep = {k: v for k, v in asdict(self).items()
                if k not in ("name", "file", "shapes", "reductions", "seeds", "propagate", "coffee", "sizes")}
        return json.dumps(keep, sort_keys=True)

    @property
    def timed(self) -> bool:
        return "time" in self.measures


def named_grid(name: str) -> Grid:
    """A grid shipped with schemalog (evaluate/grids/NAME.yaml)."""
    path = GRIDS / f"{name}.yaml"
    if not path.is_file():
        raise UsageError(f"no grid named {name!r} (shipped: {', '.join(shipped_grids())}); or give a grid file")
    return grid_from_yaml(path.read_text(encoding="utf-8"), str(path))


def shipped_grids() -> list[str]:
    return sorted(p.stem for p in GRIDS.glob("*.yaml"))


def read_grid(path: str, max_bytes: int = defaults.MAX_BYTES) -> Grid:
    """A grid file, or the name of a shipped grid (paper, quick, runtimes)."""
    # a bare word names a shipped grid unless a file has that name (a folder `paper` does not
    # shadow it); ./paper names the file
    if "/" not in path and not path.endswith((".yaml", ".yml")) and not Path(path).is_file():
        return named_grid(path)
    data = read_limited(path, max_bytes, f"grid {path}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SchemalogError(f"grid {path} is not UTF-8 text (byte {err.start})") from None
    return grid_from_yaml(text, path)


_KEYS = ("name", "shapes", "reductions", "seeds", "propagate", "measures", "selectors", "runs", "ticks",
         "min_seconds", "coffee", "sizes", "limits")
_LIMITS = ("max_states", "verify_seconds", "max_bdd_nodes", "cell_seconds")


def grid_from_yaml(text: str, file: str = "<grid>") -> Grid:
    """Read a grid from YAML (composed, not constructed: every value keeps its place)."""
    import yaml  # loaded only when YAML is read

    lines = text.split("\n")
    root, compose_fail = compose_yaml(text, file)

    def fail(message: str, node) -> SchemalogError:
        return compose_fail(f"grid: {message}", node)

    if not isinstance(root, yaml.MappingNode):
        raise SchemalogError("a grid is a mapping: shapes, reductions, seeds, propagate, measures, ... "
                             "(docs/evaluation.md)", SourcePos(file, 1, 1))

    def scalar(node, what: str) -> str:
        if not isinstance(node, yaml.ScalarNode) or node.tag == "tag:yaml.org,2002:null":
            raise fail(f"{what} must be a single value", node)
        return str(node.value).strip()

    def number(node, what: str, kind=float, low: float | None = None, high: float | None = None):
        raw = scalar(node, what).replace("_", "").lower()
        shown = shown_number(str(node.value))
        # ASCII only: int() and float() read any Unicode digit (`٣` is 3), and int() refuses
        # past 4,300 digits with a ValueError of its own
        value = _decimal(raw) if kind is int else None
        if kind is float and raw.isascii():
            try:
                value = float(raw)
            except ValueError:
                pass
        if value is None:
            raise fail(f"{what} must be {'a whole number' if kind is int else 'a number'}, not {shown}", node)
        if kind is float and not math.isfinite(value):
            raise fail(f"{what} must be finite", node)
        if (low is not None and value < low) or (high is not None and value > high):
            bounds = f"at least {_shown(low)}" if high is None else f"between {_shown(low)} and {_shown(high)}"
            raise fail(f"{what} must be {bounds}, not {shown}", node)
        return value

    def optional(node, what: str, **kw):
        if isinstance(node, yaml.ScalarNode) and (node.tag == "tag:yaml.org,2002:null" or
                                                  str(node.value).strip().lower() in ("none", "off")):
            return None
        return number(node, what, **kw)

    def sequence(node, what: str) -> list:
        if isinstance(node, yaml.ScalarNode) and node.tag != "tag:yaml.org,2002:null":
            return [node]                     # a single value stands for a list of one
        if not isinstance(node, yaml.SequenceNode) or not node.value:
            raise fail(f"{what} must be a non-empty list, like [1, 2]", node)
        return node.value

    def shape(node, what: str) -> Shape:
        if isinstance(node, yaml.SequenceNode) and len(node.value) == 2:
            depth, children = (number(n, f"{what}'s depth and children", int, 1) for n in node.value)
            texts = [str(n.value).strip() for n in node.value]
        else:
            texts = [r.strip() for r in scalar(node, what).lower().split("x")]
            raw = [_decimal(r) for r in texts]
            if len(raw) != 2 or None in raw or min(raw) < 0:
                raise fail(f"{what} is depth x children, like 4x2 or [4, 2], not {shown_number(str(node.value))}",
                           node)
            depth, children = raw
        if depth < 1 or children < 1:
            raise fail(f"{what}: depth and children must be at least 1", node)
        if depth > 64 or (children > 1 and (depth - 1) * math.log(children) > math.log(MAX_GRID_NODES) + 1) \
                or node_count(depth, children) > MAX_GRID_NODES:
            raise fail(f"{what} {'x'.join(map(shown_number, texts))} is over {MAX_GRID_NODES:,} behaviours", node)
        return depth, children

    def distinct(items: list, nodes: list, what: str) -> tuple:
        seen = {}
        for item, node in zip(items, nodes):
            if item in seen:
                raise fail(f"{item!r} appears twice in {what}", node)
            seen[item] = node
        return tuple(items)

    def words(node, what: str, allowed: tuple[str, ...]) -> tuple[str, ...]:
        nodes = sequence(node, what)
        out = []
        for n in nodes:
            word = scalar(n, f"an entry of {what}")
            if word not in allowed:
                raise fail(f"unknown {what[:-1] if what.endswith('s') else what} {word!r} "
                           f"(known: {', '.join(allowed)})", n)
            out.append(word)
        return distinct(out, nodes, what)

    def entries(node, known: tuple[str, ...], what: str):
        """(name, value node) of a mapping whose keys are all known, none twice."""
        seen: set[str] = set()
        for key_node, value in node.value:
            key = key_node.value if isinstance(key_node, yaml.ScalarNode) else None
            if key not in known:
                raise fail(f"unknown {what} {key!r} (known: {', '.join(known)})", key_node)
            if key in seen:
                raise fail(f"{key!r} appears twice", key_node)
            seen.add(key)
            yield key, value

    values: dict = {}
    for key, value in entries(root, _KEYS, "key"):
        if key == "name":
            name = scalar(value, "name")
            if not name or not all(c.isalnum() or c in "-_." for c in name):
                raise fail("the name is a word (letters, digits, - _ .)", value)
            values["name"] = name
        elif key in ("shapes", "sizes"):
            nodes = sequence(value, key)
            values[key] = distinct([shape(n, f"a shape of {key}") for n in nodes], nodes, key)
        elif key == "reductions":
            nodes = sequence(value, key)
            values[key] = distinct([number(n, "a reduction degree", float, 0.0, 1.0) for n in nodes], nodes, key)
        elif key == "seeds":
            nodes = sequence(value, key)
            values[key] = distinct([number(n, "a seed", int, 0, 2 ** 32 - 1) for n in nodes], nodes, key)
        elif key == "propagate":
            values[key] = words(value, "propagate", defaults.PROPAGATE_MODES)
        elif key == "measures":
            values[key] = words(value, "measures", MEASURES)
        elif key == "selectors":
            values[key] = words(value, "selectors", SELECTORS)
        elif key == "runs":
            values[key] = number(value, "runs", int, 1, 1000)
        elif key == "ticks":
            values[key] = number(value, "ticks", int, 0, 1000)
        elif key == "min_seconds":
            values[key] = number(value, "min_seconds", float, 0.0, 3600.0)
        elif key == "coffee":
            flag = scalar(value, "coffee").lower()
            if flag not in ("true", "false", "yes", "no"):
                raise fail("coffee is true or false", value)
            values[key] = flag in ("true", "yes")
        elif key == "limits":
            if not isinstance(value, yaml.MappingNode):
                raise fail(f"limits maps each limit to its value ({', '.join(_LIMITS)})", value)
            for name, limit in entries(value, _LIMITS, "limit"):
                if name in ("max_states", "max_bdd_nodes"):
                    values[name] = number(limit, name, int, 1, 10 ** 12)
                else:
                    values[name] = optional(limit, f"{name} (CPU seconds, or none)", low=0.001, high=10 ** 7)
    if not values.get("shapes") and not values.get("coffee") and not values.get("sizes"):
        raise SchemalogError("grid: no cells: name `shapes` (and reductions, seeds), `coffee: true` or `sizes`",
                             SourcePos(file, 1, 1), lines[0] if lines else None)
    measures = values.get("measures", Grid.measures)
    if "compress" not in measures:
        measures = ("compress", *measures)    # every other measure compresses first
    grid = Grid(**{**values, "measures": measures}, file=file)
    if len(grid.cells()) > MAX_CELLS:
        raise SchemalogError(f"grid: {len(grid.cells()):,} cells, over {MAX_CELLS:,}", SourcePos(file, 1, 1))
    return grid


def _decimal(text: str) -> int | None:
    """The integer an ASCII decimal (an optional sign, then digits) writes, else None; any
    length (int() stops at 4,300 digits: a longer one is read by parts)."""
    digits = text[1:] if text[:1] in "+-" else text
    if not digits or not (digits.isascii() and digits.isdigit()):
        return None
    value = int_of_digits(digits)
    return -value if text[:1] == "-" else value


def _shown(value: float) -> str:
    """A bound as a message writes it: a whole number whole (4294967295, not 4.29497e+09)."""
    return str(int(value)) if float(value).is_integer() and abs(value) < 1e18 else f"{value:g}"


def override(grid: Grid, **changes) -> Grid:
    """The grid with the given settings changed (None: unchanged): bench's --runs, --seed, ..."""
    return replace(grid, **{k: v for k, v in changes.items() if v is not None})


__all__ = ["Grid", "CellSpec", "read_grid", "named_grid", "grid_from_yaml", "shipped_grids", "override",
           "MEASURES", "SELECTORS"]
