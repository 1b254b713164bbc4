"""The paper's evaluation as a command: what `schemalog bench` measures and writes.

Timings are never asserted (they belong to benchmarks/): these tests check that a run
completes, that every generated task has the requested reduction degree, that compressed
runs complete and are proved, and that the tables and figures are written and readable.
"""

import csv
import io
import os
import subprocess
import sys

import py_trees
import pytest

from schemalog.task import conditions as cond
from schemalog.evaluate.bench import (BenchPlan, Cell, Results, Spread, headlines, judge, py_trees_tree, run_bench,
                                      to_csv, to_markdown)
from schemalog.task.compress import compress
from schemalog.evaluate.generate import TOLERANCE, generate
from schemalog.task.tree import count_nodes, walk

PNG = b"\x89PNG\r\n\x1a\n"


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd)


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench") / "results"
    done = run("bench", "--quick", "--out", out)
    return done, out


def test_bench_quick_writes_the_tables_and_the_figures(quick):
    done, out = quick
    assert done.returncode == 0, done.stderr
    for name in ("figure4", "selectors", "figure3"):
        assert (out / f"{name}.png").read_bytes().startswith(PNG)
        assert "<svg" in (out / f"{name}.svg").read_text()[:2000]
    assert "digraph" in (out / "figure3.dot").read_text()
    assert not [p for p in out.iterdir() if p.name.startswith(".")]      # no temporary files left
    mask = os.umask(0)
    os.umask(mask)
    assert {p.stat().st_mode & 0o777 for p in out.iterdir()} == {0o666 & ~mask}   # not mkstemp's 0600
    markdown = (out / "results.md").read_text()
    assert "## Headlines" in markdown and "| D | b | Bi |" in markdown and "0.23 -> 0.03 s" in markdown
    assert "- reduction degree: every cell within" in done.stdout
    # Progress on stderr, which is not a terminal here: one line per step, not a redrawn bar.
    steps = [line for line in done.stderr.splitlines() if line.startswith("bench --quick [")]
    assert steps[0].startswith("bench --quick [1/40, ") and steps[-1].startswith("bench --quick [40/40, ")
    assert len(steps) == 40 and "\r" not in done.stderr
    verdict = next(line for line in done.stdout.splitlines() if line.startswith("- scan, 1,365 behaviours"))
    assert "range" in verdict and any(v in verdict for v in (": met)", ": MISSED)", ": too noisy to judge)"))


def test_bench_quick_every_generated_task_has_its_rd_and_is_proved(quick):
    _, out = quick
    rows = list(csv.DictReader((out / "results.csv").open()))
    generated = [r for r in rows if r["task"] == "generated"]
    cells = {(r["depth"], r["children"], r["rd_asked"]) for r in generated}
    assert len(cells) == 36                              # the paper's 9 shapes x 4 RDs
    for r in generated:
        assert abs(float(r["rd_achieved"]) - float(r["rd_asked"])) <= TOLERANCE, r
        assert r["verify_result"] in ("proved", "limit"), r                 # never a counterexample
        if int(r["behaviours"]) <= 121:
            assert r["verify_result"] == "proved", r
        assert {"scan", "incremental", "py_trees"} >= {r["selector"]}
    selectors = {(r["depth"], r["children"], r["rd_asked"], r["tree"], r["selector"]) for r in generated}
    assert len(selectors) == len(cells) * 2 * 3          # original and compressed, three executives


def test_bench_quick_reproduces_the_coffee_and_tea_row(quick):
    _, out = quick
    rows = [r for r in csv.DictReader((out / "results.csv").open()) if r["task"] == "coffee and tea"]
    assert {(r["behaviours"], r["behaviours_compressed"]) for r in rows} == {("63", "33")}
    decisions = {(r["tree"], r["selector"]): r["decisions_per_run"] for r in rows}
    assert decisions["original", "scan"] == decisions["original", "incremental"] == "36"
    assert decisions["compressed", "scan"] == decisions["compressed", "incremental"] == "16"
    assert rows[0]["verify_result"] == "proved"


def test_bench_refuses_a_file_as_out_and_needs_a_plan(tmp_path):
    target = tmp_path / "file"
    target.write_text("keep me")
    refused = run("bench", "--quick", "--out", target)
    assert refused.returncode == 2 and "is a file" in refused.stderr and "Traceback" not in refused.stderr
    assert target.read_text() == "keep me"
    nested = run("bench", "--quick", "--out", target / "sub")      # found before measuring, not after
    assert nested.returncode == 2 and "cannot make the directory" in nested.stderr
    assert "error: error" not in nested.stderr
    assert run("bench").returncode == 2
    assert run("bench", "--quick", "--paper").returncode == 2


def test_a_small_plan_measures_every_run_and_every_decision():
    plan = BenchPlan(shapes=((3, 2), (4, 2)), reductions=(0.0, 0.7), runs=2, ticks=2, max_states=1_000)
    results = run_bench(plan)
    assert [(c.depth, c.rd_asked) for c in results.cells] == [(3, 0.0), (3, 0.7), (4, 0.0), (4, 0.7)]
    for cell in results.cells + [results.coffee]:
        for tree in ("original", "compressed"):
            scan, inc = cell.timing(tree, "scan"), cell.timing(tree, "incremental")
            assert len(scan.per_run) == len(inc.per_run) == 2
            assert scan.decisions == inc.decisions                       # both selectors decide alike
            assert len(scan.per_decision) == sum(scan.decisions)
            assert len(cell.timing(tree, "py_trees").per_decision) == 2 * 2
    four = results.cells[3]
    assert (four.behaviours, four.merged) == (15, 7)
    assert four.timing("compressed", "scan").decisions == [2, 2]        # two merged chains, one decision each
    table = to_markdown(results, "test")
    assert table.count("\n| 3 | 2 |") == 2 and "| 5 | coffee | 63 |" in table
    rows = list(csv.DictReader(io.StringIO(to_csv(results))))
    assert len(rows) == 5 * 2 * 3
    first = headlines(results)[0]          # two RD 0 cells tie on their distance from the request
    assert first.startswith("reduction degree: 1 cell(s) beyond 0.05: depth 3, 2 children, RD 0.7")
    assert "allows RD at most 0.50" in first                             # ... and the cell says why


def test_the_py_trees_peer_has_the_same_shape_and_reads_the_same_state():
    tree = compress(generate(4, 2, 0.5, seed=1)).tree
    state: set = set()
    peer = py_trees_tree(tree, state)
    assert sum(1 for _ in peer.iterate()) == count_nodes(tree)
    peer.tick_once()
    Status = py_trees.common.Status
    assert all(b.status == Status.RUNNING for b in peer.iterate())      # one tick visits every behaviour
    leaves = {b.name: b.enabled for b in peer.iterate() if not b.children}
    for leaf in (n for n in walk(tree) if not n.children):              # ... and checks its releaser
        assert leaves[leaf.name] == cond.holds(leaf.pre, set())
    assert any(leaves.values()) and not all(leaves.values())
    state.update(lit.atom for n in walk(tree) for lit in cond.literals(n.post))
    peer.tick_once()
    assert peer.status == Status.SUCCESS


def test_bench_refuses_an_empty_out_before_measuring(tmp_path):
    refused = run("bench", "--quick", "--out", "", cwd=tmp_path)
    assert refused.returncode == 2 and "--out needs a directory name" in refused.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_spread_is_the_median_and_quartiles_of_the_runs():
    assert Spread.of([5.0, 1.0, 3.0, 2.0, 4.0]) == Spread(3.0, 2.0, 4.0)
    assert Spread.of([0.002], 1e3) == Spread(2.0, 2.0, 2.0)
    one_slow = Spread.of([1.0, 1.0, 1.1, 1.0, 9.0])        # a preempted run does not move the median
    assert one_slow.median == 1.0 and one_slow.q3 == 1.1
    assert Spread.of([]).text() == "n/a" and Spread(3.0, 2.0, 4.0).text(1) == "3.0 (IQR 2.0-4.0)"


def test_a_target_is_met_missed_or_too_noisy_to_judge_from_the_range():
    assert judge(0.88, 0.92, 0.87) == "met"
    assert judge(0.80, 0.86, 0.87) == "MISSED"
    assert judge(0.85, 0.90, 0.87) == "too noisy to judge"       # the spread straddles the target
    assert judge(float("nan"), 0.9, 0.87) == "not measured"


def test_the_headline_says_too_noisy_rather_than_missed_when_runs_disagree():
    def cell(original, compressed):
        c = Cell("depth 6, 4 children, RD 0.7", 6, 4, 1365, 0.7, 0.7, 100, 0.0)
        for tree, times in (("original", original), ("compressed", compressed)):
            t = c.timing(tree, "scan")
            t.per_run, t.decisions = list(times), [100] * len(times)
        return c

    plan = BenchPlan(shapes=((6, 4),), reductions=(0.7,), runs=5)
    steady = cell([1.0, 1.0, 1.0, 1.0, 1.0], [0.10, 0.10, 0.10, 0.10, 0.10])
    noisy = cell([0.7, 0.8, 1.0, 1.2, 1.3], [0.09, 0.10, 0.10, 0.12, 0.13])
    slow = cell([1.0, 1.0, 1.0, 1.0, 1.0], [0.20, 0.20, 0.20, 0.20, 0.20])
    said = {name: next(line for line in headlines(Results(plan, [c])) if line.startswith("scan, 1,365"))
            for name, c in (("steady", steady), ("noisy", noisy), ("slow", slow))}
    assert "-90%" in said["steady"] and "target at least 87%: met" in said["steady"]
    assert "-90%" in said["noisy"] and "target at least 87%: too noisy to judge" in said["noisy"]
    assert "target at least 87%: MISSED" in said["slow"]


def test_figure_4_fits_a_screen(tmp_path):
    """Issue 45: figure4.png was 1,997 px wide at its 150 dpi."""
    from matplotlib.image import imread

    from schemalog.evaluate.figures import figure4

    written = figure4(_grid_results(), tmp_path)
    png = next(p for p in written if p.suffix == ".png")
    height, width = imread(str(png)).shape[:2]
    assert width <= 1920, (width, height)


def _grid_results():
    """The paper's nine shapes at four RDs, timed as if each run cost its behaviours left."""
    plan = BenchPlan(shapes=(), runs=3)
    results = Results(plan)
    for depth in (4, 5, 6):
        for children in (2, 3, 4):
            behaviours = sum(children ** level for level in range(depth))
            for rd in (0.0, 0.3, 0.5, 0.7):
                cell = Cell(f"d{depth}c{children}", depth, children, behaviours, rd, rd, 0, 0.0)
                ms = behaviours * (1 - rd) * 0.01          # the largest trees on top, at every RD
                tree = "compressed" if rd else "original"
                for selector in ("scan", "incremental"):
                    cell.timing(tree, selector).per_run.extend([ms / 1e3] * 3)
                    cell.timing(tree, selector).decisions.extend([10] * 3)
                results.cells.append(cell)
    return results


def test_figure_4s_legends_cover_no_point():
    from schemalog.evaluate.figures import figure4_figure, plt

    fig = figure4_figure(_grid_results())
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            legend = ax.get_legend().get_window_extent(renderer)
            assert not legend.overlaps(ax.get_window_extent(renderer))     # outside the plot: no point hidden
            for line in ax.get_lines():
                for x, y in ax.transData.transform(line.get_xydata()):
                    assert not legend.contains(x, y)
    finally:
        plt.close(fig)
