"""Parse and instantiate generated task files from 1k to 100k behaviours.

    python benchmarks/bench_foundation.py [--sizes 1000 10000 100000] [--repeat 3]
                                          [--options-size 10000]

For each size it writes a task file in the schema language (a balanced tree, four
children per behaviour, learned-action style releasers), then measures, in one run:

- read:   schemalog's reader (its fast path, fastread.py) -> tokens/s, MB/s
- lark:   lark's own parse of the same text into a parse tree, no terms (the baseline)
- inst:   instantiation of the root task (loadTaskFromLTM) -> behaviours/s

and prints a Markdown table with the growth of each time per 10x size (1.0 per 10x
would be constant time; 10x is linear). Then, on the file of --options-size behaviours,
the ways of reading the issue named, side by side, as MB/s and as a ratio to the lark
reader (LALR with the transformer inline, the reader before the fast path): a tree then
transformed, lark's `basic` lexer, and the time to build the parser with and without lark's
cache of the analysed grammar.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

from lark import Lark

from schemalog.cli.main import tune_gc
from schemalog.formats.documents import read_document
from schemalog.logic.fastread import parse_text
from schemalog.logic.parse import _LineIndex, _ToTerms, grammar_text, parse_text_by_lark, read_source
from schemalog.logic.terms import Atom
from schemalog.task.tree import count_nodes, instantiate

BRANCHING = 4
OBJECTS = ("cup", "spoon", "water", "coffee", "tea")


def task_text(size: int) -> str:
    """A balanced task with about `size` behaviours, one schema per behaviour."""
    lines = ["task(t0).", *(f"object({o})." for o in OBJECTS), "agent(gripper(_), gripper)."]
    made, frontier, next_id = 1, ["t0"], 1
    children: dict[str, list[str]] = {}
    while made < size:
        parent = frontier.pop(0)
        kids = []
        for _ in range(BRANCHING):
            if made >= size:
                break
            kids.append(f"b{next_id}")
            next_id += 1
            made += 1
        children[parent] = kids
        frontier.extend(kids)
    def label(name: str) -> str:
        return name if name == "t0" else f"{name}({OBJECTS[int(name[1:]) % len(OBJECTS)]})"
    for parent, kids in children.items():
        entries = [f"({label(k)}, {'true' if i == 0 else kids[i - 1] + '.done'})" for i, k in enumerate(kids)]
        lines.append(f"schema({label(parent)}, [{', '.join(entries)}], {parent}.done).")
    for leaf in frontier:
        lines.append(f"schema({label(leaf)}, [], {leaf}.done).")
    return "\n".join(lines) + "\n"


def best_of(repeat: int, fn) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def lark_reader(inline: bool = True, **options):
    """A reader of clauses built on lark as parse.py builds its own, with `options` changed;
    inline=False builds lark's parse tree first and transforms it after."""
    terms = _ToTerms("<bench>")
    end = {"END": lambda token: (terms.starts.append(token.end_pos), token)[1]}
    lark = Lark(grammar_text(), parser="lalr", maybe_placeholders=False, lexer_callbacks=end,
                transformer=terms if inline else None, **options)

    def read(text: str):
        terms.varmap, terms.text, terms.line_at = {}, text, _LineIndex(text)
        terms.starts.clear()
        terms.starts.append(0)
        parsed = lark.parse(text)
        return parsed if inline else terms.transform(parsed)
    return read


def reader_options(path: Path, repeat: int) -> list[tuple[str, float, str]]:
    """(option, seconds, note) for each way of reading the file at `path`."""
    text = read_source(path)
    expected = len(parse_text_by_lark(text, str(path)))
    rows = []
    for name, read in [("lark LALR, transformer inline (the reader before)", lambda t: parse_text_by_lark(t, "b")),
                       ("lark LALR, parse tree then transformer", lark_reader(inline=False)),
                       ("lark LALR, `basic` lexer, transformer inline", lark_reader(lexer="basic")),
                       ("fast path (fastread.py), lark for any other clause", lambda t: parse_text(t, "b"))]:
        try:
            seconds, items = best_of(repeat, lambda: read(text))
            note = "same clauses" if len(items) == expected else f"{len(items)} clauses, not {expected}"
        except Exception as err:  # an option that cannot read the file says why, in the table
            seconds, note = float("nan"), f"fails: {type(err).__name__}"
        rows.append((name, seconds, note))
    with tempfile.TemporaryDirectory() as tmp:
        cached = str(Path(tmp) / "grammar.cache")
        Lark(grammar_text(), parser="lalr", cache=cached)  # writes the cache
        for name, cache in [("building the parser, no cache", False), ("building the parser, lark's cache", cached)]:
            seconds, _ = best_of(repeat, lambda: Lark(grammar_text(), parser="lalr", cache=cache))
            rows.append((name, seconds, "once per process"))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--options-size", type=int, default=10000)
    args = parser.parse_args(argv)
    tune_gc()  # measure what the schemalog command does

    baseline = Lark(grammar_text(), parser="lalr")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for size in args.sizes:
            path = Path(tmp) / f"task_{size}.pl"
            path.write_text(task_text(size))
            text = read_source(path)
            tokens = sum(1 for _ in baseline.lex(text))
            t_lark, _ = best_of(args.repeat, lambda: baseline.parse(text))
            t_read, doc = best_of(args.repeat, lambda: read_document(path))
            kb = doc.to_kb()
            t_inst, tree = best_of(args.repeat, lambda: instantiate(kb, Atom("t0")))
            nodes = count_nodes(tree)
            rows.append((size, nodes, len(text), tokens, t_lark, t_read, t_inst))
            print(f"  {nodes:>7} behaviours: read {t_read:.2f}s, lark tree {t_lark:.2f}s, "
                  f"instantiate {t_inst:.2f}s", file=sys.stderr)

    print("| behaviours | file MB | tokens | read s | tokens/s | MB/s | lark tree s | read/lark "
          "| instantiate s | behaviours/s |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for size, nodes, nbytes, tokens, t_lark, t_read, t_inst in rows:
        print(f"| {nodes:,} | {nbytes / 1e6:.2f} | {tokens:,} | {t_read:.3f} | {tokens / t_read:,.0f} "
              f"| {nbytes / 1e6 / t_read:.2f} | {t_lark:.3f} | {t_read / t_lark:.2f} | {t_inst:.3f} "
              f"| {nodes / t_inst:,.0f} |")
    if len(rows) > 1:
        print()
        print("Growth of time per 10x behaviours (10x = linear):")
        for (s0, *_, r0, i0), (s1, *_, r1, i1) in zip(rows, rows[1:]):
            span = s1 / s0
            print(f"- {s0:,} -> {s1:,}: read x{r1 / r0:.1f}, instantiate x{i1 / i0:.1f} "
                  f"(size x{span:.0f})")
        reads = [r[5] / r[1] for r in rows]
        insts = [r[6] / r[1] for r in rows]
        print(f"- time per behaviour, smallest to largest: read {statistics.mean(reads[:1]) * 1e6:.1f} -> "
              f"{reads[-1] * 1e6:.1f} us, instantiate {insts[0] * 1e6:.1f} -> {insts[-1] * 1e6:.1f} us")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "options.pl"
        path.write_text(task_text(args.options_size))
        mb = path.stat().st_size / 1e6
        rows_o = reader_options(path, args.repeat)
    print()
    print(f"Ways of reading {args.options_size:,} behaviours ({mb:.2f} MB):")
    print()
    print("| reader | s | MB/s | speed vs the reader before | |")
    print("|---|---:|---:|---:|---|")
    before = rows_o[0][1]
    for name, seconds, note in rows_o:
        speed = f"x{before / seconds:.2f}" if "building" not in name else ""
        rate = f"{mb / seconds:.2f}" if "building" not in name else ""
        print(f"| {name} | {seconds:.3f} | {rate} | {speed} | {note} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
