"""`schemalog verify --each FOLDER_OR_FILES...`: prove every task of many files as one sweep."""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from ..errors import UsageError


def add_arguments(p: argparse.ArgumentParser) -> None:
    """verify's --each, and where its sweep runs."""
    from .sweep import engine_options

    p.add_argument("--each", action="store_true",
                   help="prove every task (task/1) of every file given, folders meaning their .pl files, as "
                        "one sweep on Dask (or --serial; in this process when Dask is not installed): one line "
                        "per task, a summary; exit 1 if any is refuted, vacuous or unreadable, 3 if any has no proof")
    engine_options(p)


def files_of(paths: list[str]) -> list[str]:
    """The files named, a folder standing for the .pl files under it (sorted)."""
    out: list[str] = []
    for path in paths:
        if os.path.isdir(path):
            found = sorted(str(p) for p in Path(path).rglob("*.pl") if p.is_file())
            if not found:
                raise UsageError(f"{path}: a folder with no .pl task file")
            out += found
        elif os.path.exists(path):
            out.append(path)
        else:
            raise UsageError(f"{path}: no such file or folder")
    return list(dict.fromkeys(out))


def run_each(args: argparse.Namespace) -> int:
    """Prove every task of the files; print one line per task and a summary."""
    from ..api import sweep as api
    from .sweep import progress_display

    for option, given in (("--task", args.task), ("--sample", args.sample), ("--scene", args.scene),
                          ("--seed", args.seed), ("--states", args.states != "default"), ("--drop-names", args.drop_names),
                          ("--run-once", args.run_once), ("--btcpp", getattr(args, "btcpp", None))):
        if given:
            raise UsageError(f"{option} is not for --each (each file's tasks are proved from its own initial state)")
    files = files_of(args.files)
    options = api.proof_options(propagate=args.propagate, method=args.method, max_states=args.max_states,
                                max_bdd_nodes=args.max_bdd_nodes, max_bytes=args.max_bytes, max_steps=args.max_steps,
                                max_depth=args.max_depth, max_nodes=args.max_nodes, split=not args.no_split)
    # Without Dask, in this process, and said (a scheduler named still needs Dask)
    where = api.where(args.serial, args.workers, args.scheduler, or_serial=True)
    if getattr(where, "note", None):
        print(f"note: {where.note}", file=sys.stderr)
    with where, progress_display("verify --each", len(files)) as show:
        by_file = api.prove_files(files, options, where, show)
        place = where.where
    rows = [r for f in files for r in by_file.get(f, [])]
    counts = {v: sum(r["verdict"] == v for r in rows) for v in ("proved", "refuted", "vacuous", "no proof", "error")}
    summary = (f"verify --each: {len(rows)} task{'s' if len(rows) != 1 else ''} in {len(files)} file"
               f"{'s' if len(files) != 1 else ''}: " + ", ".join(f"{n} {v}" for v, n in counts.items())
               + f" ({place})")
    if args.json:
        text = json.dumps({"tasks": rows, "summary": counts}, indent=2) + "\n"
    else:
        text = "".join(_line(r) + "\n" for r in rows) + summary + "\n"
    if args.output:
        api.write_text(args.output, text)
        print(f"wrote {args.output}: {summary}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return api.proofs_exit_status(rows)


def _line(row: dict) -> str:
    sizes = (f"; {row['original']:,} -> {row['compressed']:,} behaviours, {row['states']:,} states"
             if row.get("original") is not None else "")
    task = f": {row['task']}" if row["task"] else ""
    where = "" if row["detail"].startswith(f"{row['file']}:") else f"{row['file']}{task}: "  # file:line:col said
    return f"{row['verdict'].upper():9} {where}{row['detail']}{sizes}, {row['seconds']:.2f} s"

