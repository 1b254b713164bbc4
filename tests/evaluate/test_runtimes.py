"""bench --runtimes: each cell runs to completion in both runtimes, original and compressed."""

from schemalog.evaluate.runtimes import measure_row, runtimes_csv, runtimes_markdown


def test_a_cell_is_measured_in_both_runtimes_and_compression_cuts_the_ticks():
    row = measure_row(4, 2, 0.7, seed=1, repeat=1)
    assert (row.nodes_before, row.nodes_after) == (15, 7)
    for runtime in ("btcpp", "py_trees"):
        original, compressed = row.times[(runtime, "original")], row.times[(runtime, "compressed")]
        assert compressed.ticks < original.ticks
        assert original.seconds > 0 and compressed.median_tick > 0
    table = runtimes_markdown([row], "schemalog bench --runtimes")
    assert "| 4x2 RD 0.7 | 15 -> 7 | 0.73 | 9 -> 3 |" in table
    assert runtimes_csv([row]).count("\n") == 5      # a header and 2 runtimes x 2 trees
