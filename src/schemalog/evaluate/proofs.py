"""Batch proofs (`schemalog verify --each`): every task of many files, one sweep task per file.

    prove_file(path, options) -> list[dict]     # one row per task: its verdict, never raises

A verdict is `proved` only when the proof is exhaustive, sound and complete and the task
itself can complete (not vacuous); `refuted` on a counterexample; `vacuous` when no run of the
original completes; `no proof` at a limit (--max-states, --max-bdd-nodes); `error` when the
file cannot be read or its task instantiated (the message names file:line:column).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from .. import defaults
from ..errors import SchemalogError

VERDICTS = ("proved", "refuted", "vacuous", "no proof", "error")


@dataclass(frozen=True)
class ProofOptions:
    propagate: str = "full"
    method: str = "auto"
    max_states: int = defaults.MAX_STATES
    max_bdd_nodes: int = 5_000_000
    max_bytes: int = defaults.MAX_BYTES
    max_steps: int = defaults.MAX_STEPS
    max_depth: int = defaults.MAX_DEPTH
    max_nodes: int = defaults.MAX_NODES
    split: bool = True


def prove_file(path: str, options: ProofOptions) -> list[dict]:
    """Load `path`, and compress and prove each task it declares (task/1): one row per task."""
    from ..formats.documents import load_kb
    from ..logic.exceptions import PrologError
    from ..logic.terms import term_to_text
    from ..task.tree import declared_tasks

    started = time.perf_counter()
    try:
        kb = load_kb([path], options.max_bytes, options.max_steps)
        tasks = declared_tasks(kb)
    except (SchemalogError, PrologError, RecursionError, MemoryError, OSError) as err:
        return [_row(path, "", "error", _message(err), started)]
    if not tasks:
        return [_row(path, "", "error", "no task declared with task/1", started)]
    rows = []
    for task in tasks:
        begun = time.perf_counter()
        try:
            rows.append(_prove_task(kb, task, path, options) | {"seconds": time.perf_counter() - begun})
        except (SchemalogError, PrologError, RecursionError, MemoryError, ValueError) as err:
            rows.append(_row(path, term_to_text(task), "error", _message(err), begun))
    return rows


def _message(err: BaseException) -> str:
    if isinstance(err, RecursionError):
        return "the input nests too deeply to process"
    if isinstance(err, MemoryError):
        return "out of memory"
    if isinstance(err, OSError):
        return f"cannot read it: {err.strerror or err}"
    return str(err).removeprefix("error: ").split("\n")[0]      # one line: the place, not the caret


def _row(path: str, task: str, verdict: str, detail: str, started: float, **more) -> dict:
    return {"file": path, "task": task, "verdict": verdict, "detail": detail,
            "seconds": time.perf_counter() - started, "original": None, "compressed": None, "states": None, **more}


def _prove_task(kb, task, path: str, options: ProofOptions) -> dict:
    from ..logic.terms import term_to_text
    from ..run.vacuity import vacuity_of
    from ..run.verify import prove
    from ..run.world import World, initial_state
    from ..task.compress import compress, original_of, protected_labels
    from ..task.tree import Instantiator, count_nodes

    tree = Instantiator(kb, max_depth=options.max_depth, max_nodes=options.max_nodes).instantiate(task)
    original = original_of(tree)
    if original is not tree:
        compressed, how = tree, "the compressed file"
    else:
        compressed, how = compress(original, options.propagate, protected_labels(kb, original)).tree, \
            f"propagate {options.propagate}"
    world = World(original)
    world.reset(initial_state(kb))
    report = prove(original, compressed, world, [world.atoms], None, task, options.method, options.max_states,
                   options.max_bdd_nodes, split=options.split)
    vacuity = vacuity_of(original, World(original), report.initial_states, options.max_states,
                         report.original_completes)
    if report.violated:
        failing = "soundness" if report.properties["soundness"].holds is False else "completion"
        verdict, detail = "refuted", f"{failing} fails: {report.properties[failing].summary}"
    elif vacuity.vacuous:
        verdict = "vacuous"
        detail = "the task itself cannot complete" + (f": {vacuity.cause.text()}" if vacuity.cause else "")
    elif vacuity.undecided:
        verdict, detail = "no proof", "whether the task itself can complete was not decided within the state limit"
    elif report.exhaustive and report.sound and report.complete:
        verdict, detail = "proved", "sound and complete"
    else:
        verdict = "no proof"
        detail = f"stopped at the limit of {report.limit}" if report.limit else "not exhaustive"
    return {"file": path, "task": term_to_text(task), "verdict": verdict, "detail": detail, "how": how,
            "original": count_nodes(original), "compressed": count_nodes(compressed),
            "states": report.compressed_states + report.original_states}


def exit_status(rows: list[dict]) -> int:
    """1 if any task is refuted, vacuous or could not be read; 3 (verify's inconclusive) if any
    has no proof; 0 when every task is proved."""
    verdicts = {r["verdict"] for r in rows}
    if verdicts & {"refuted", "vacuous", "error"}:
        return 1
    return 3 if "no proof" in verdicts else 0


__all__ = ["ProofOptions", "prove_file", "exit_status", "VERDICTS"]
