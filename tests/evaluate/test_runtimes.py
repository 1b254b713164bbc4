"""bench --runtimes: each cell runs to completion in both runtimes, original and compressed, whole
runs timed, medians with their IQR, savings judged against the identical-tree noise floor."""

from schemalog.evaluate.runtimes import RuntimeRow, Timed, measure_row, noise_floor, runtimes_csv, runtimes_markdown, \
    runtimes_summary


def test_a_cell_is_measured_in_both_runtimes_and_compression_cuts_the_ticks():
    row = measure_row(4, 2, 0.7, seed=1, repeat=3)
    assert (row.nodes_before, row.nodes_after) == (15, 7)
    for runtime in ("btcpp", "py_trees"):
        original, compressed = row.times[(runtime, "original")], row.times[(runtime, "compressed")]
        assert compressed.ticks < original.ticks
        assert len(original.run_seconds) == len(compressed.run_seconds) == 3     # whole runs, each timed
        for t in (original, compressed):
            run, tick = t.run_ms, t.tick_us
            assert 0 < run.q1 <= run.median <= run.q3 and 0 < tick.q1 <= tick.median <= tick.q3
    table = runtimes_markdown([row], "schemalog bench --runtimes")
    assert "| 4x2 RD 0.7 | 15 -> 7 | 0.73 | 9 -> 3 |" in table
    assert "3 whole runs per tree" in table and "(IQR " in table and ", range " in table
    assert "No row has identical trees" in table and "within noise" not in table.split("\n", 1)[1]
    csv = runtimes_csv([row])
    assert csv.count("\n") == 5      # a header and 2 runtimes x 2 trees
    assert "ms_per_run_q1" in csv.splitlines()[0] and "warmup" not in csv


def test_a_row_with_identical_trees_measures_the_noise_floor():
    row = measure_row(4, 2, 0.0, seed=1, repeat=3)
    assert row.identical and row.nodes_before == row.nodes_after
    table = runtimes_markdown([row], "schemalog bench --runtimes")
    assert "Noise floor, the largest saving between identical trees (1 rows" in table
    body = table.splitlines()[-1]
    assert body.startswith("| 4x2 RD 0 | 15 -> 15 | 0.00 | 9 -> 9 |")
    assert body.count("(within noise \u00b1") == 2        # its own saving is the floor, in both runtimes


def _timed(ms: list[float]) -> Timed:
    return Timed(10, tuple(x / 1e3 for x in ms), 1e-4, 0.9e-4, 1.1e-4)


def _row(rd: float, after: int, original: list[float], compressed: list[float]) -> RuntimeRow:
    times = {(rt, "original"): _timed(original) for rt in ("btcpp", "py_trees")}
    times.update({(rt, "compressed"): _timed(compressed) for rt in ("btcpp", "py_trees")})
    return RuntimeRow(4, 2, rd, rd, 15, after, times)


def test_a_saving_within_the_noise_floor_is_marked_and_one_beyond_it_is_not():
    same = _row(0.0, 15, [10, 10, 10], [10.7, 10.7, 10.7])          # identical trees, +7%
    small = _row(0.3, 12, [10, 10, 10], [9.7, 9.7, 9.7])            # -3%: noise
    large = _row(0.7, 7, [10, 10, 10], [5.2, 5.2, 5.2])             # -48%: a saving
    rows = [same, small, large]
    assert round(noise_floor(rows, "btcpp"), 3) == 0.07
    table = runtimes_markdown(rows, "schemalog bench --runtimes")
    assert "BT.CPP \u00b17%, py_trees \u00b17%" in table.splitlines()[0]
    lines = table.splitlines()
    assert "| +7% (within noise \u00b17%), range +7% to +7% |" in lines[-3]
    assert "| -3% (within noise \u00b17%), range -3% to -3% |" in lines[-2]
    assert "| -48%, range -48% to -48% |" in lines[-1] and "within noise" not in lines[-1]


def test_the_terminal_gets_a_summary_that_fits_100_columns():
    """Issue 45: bench --runtimes printed the Markdown table, 600 columns a row, to the terminal;
    the table goes to runtimes.md and the terminal gets a row per tree that fits 100 columns."""
    big = RuntimeRow(6, 4, 0.7, 0.68, 1365, 411, {(rt, which): _timed([1000, 1000, 1000] if which == "original"
                                                                      else [450, 450, 450])
                                                  for rt in ("btcpp", "py_trees")
                                                  for which in ("original", "compressed")})
    rows = [_row(0.0, 15, [10, 10, 10], [10.7, 10.7, 10.7]), _row(0.7, 7, [10, 10, 10], [5.2, 5.2, 5.2]), big]
    assert max(len(line) for line in runtimes_markdown(rows, "schemalog bench --runtimes").splitlines()) > 200
    lines = runtimes_summary(rows)
    assert all(len(line) <= 100 for line in lines), max(lines, key=len)
    assert lines[1].split() == ["tree", "Bi", "->", "Bm", "RD", "ticks", "o", "->", "c", "BT.CPP", "py_trees"]
    assert lines[2].split() == ["4x2", "RD", "0", "15", "->", "15", "0.00", "10", "->", "10", "+7%~", "+7%~"]
    assert lines[3].split()[-2:] == ["-48%", "-48%"] and lines[4].split()[:6] == ["6x4", "RD", "0.7", "1,365", "->", "411"]
    assert lines[-1] == "noise floor (identical trees): BT.CPP \u00b17%, py_trees \u00b17%"
