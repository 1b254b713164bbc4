"""The `schemalog` command: check, show, compress, run, verify, generate, bench and convert.

Exit status: 0 success, 1 bad input (a message with file:line:column), 2 bad usage.
No command prints a traceback; SCHEMALOG_DEBUG=1 shows one for internal errors.
"""

from __future__ import annotations

import argparse
import gc
import io
import json
import os
import sys
import tempfile
from pathlib import Path

from .. import __version__
from ..task import conditions as cond
from ..formats.documents import (YAML_SUFFIXES, Document, check_writable, file_mode, read_document, to_pl, to_yaml,
                        write_atomically)
from ..logic.engine import DEFAULT_MAX_STEPS
from ..logic.exceptions import PrologError
from ..errors import SchemalogError, UsageError
from ..logic.kb import KnowledgeBase
from ..logic.parse import MAX_BYTES, Clause, parse_term
from ..task.compress import PROPAGATE_MODES, compress, decompress, original_of, protected_labels
from ..task.conditions import DEFAULT_SYMPY_BUDGET, MAX_SYMPY_BUDGET, Simplifier
from ..formats.render import carried_clauses, compare_dot, rich_tree, show_json, to_dot, tree_document, tree_json
from ..task.schema import check_schemas
from ..logic.terms import TRUE, Struct, Term, Var, term_to_text
from ..logic.unify import Bindings
from ..run.execute import DEFAULT_RETRIES, RECOVERIES, SELECTORS, Decision, Executive, RobotManager
from ..evaluate.generate import TOLERANCE, generate, scene_for, shortfall
from ..learn import defaults
from ..run.scene import NO_SCENE, Scene, object_name, read_scene, scene_text
from ..run.verify import (DEFAULT_MAX_STATES, Verifier, all_states, constraints, free_atoms, state_text,
                     verify_by_parts)
from ..run.world import World, initial_state, state_atoms
from ..task.tree import DEFAULT_MAX_DEPTH, DEFAULT_MAX_NODES, Behaviour, count_nodes, declared_tasks, depth, instantiate, walk


DEFAULT_JITTER = 0.05
INCONCLUSIVE = 3    # verify: no counterexample, but no proof either (state limit, sampling)

# ---------------------------------------------------------------------------
# Shared steps

def _load(args: argparse.Namespace) -> tuple[KnowledgeBase, list[Document]]:
    kb = KnowledgeBase()
    docs = []
    for path in args.files:
        doc = read_document(path, args.max_bytes)
        doc.to_kb(kb)
        docs.append(doc)
    for warning in kb.warnings:
        print(warning, file=sys.stderr)
    return kb, docs


def _task_term(text: str) -> Term:
    try:
        return parse_term(text, "--task")
    except SchemalogError as err:
        raise UsageError(f"--task {text!r} is not a term: {err.message}") from None


def _root_candidates(kb: KnowledgeBase) -> list[str]:
    """Schemas never used as a sub-task: likely tasks, for a helpful message."""
    schemas = check_schemas(kb)
    used = {term_to_text(e.behaviour) for s in schemas for e in s.entries}
    return [term_to_text(s.task) for s in schemas if s.entries and term_to_text(s.task) not in used]


def _choose_tasks(kb: KnowledgeBase, task: str | None, every: bool = False) -> list[Term]:
    if task is not None:
        term = _task_term(task)
        if not _defines(kb, term):
            known = [term_to_text(t) for t in declared_tasks(kb)] or _root_candidates(kb)
            hint = f"; tasks here: {', '.join(known[:8])}" if known else ""
            raise SchemalogError(f"unknown task {term_to_text(term)}: no schema({term_to_text(term)}, "
                                 f"Subtasks, Post) in {', '.join(kb.files)}{hint}")
        return [term]
    declared = declared_tasks(kb)
    if declared:
        return declared if every else declared[:1]
    if every:
        return []
    roots = _root_candidates(kb)
    hint = f" (candidates: {', '.join(roots[:8])})" if roots else ""
    raise UsageError(f"no task declared with task/1: name one with --task{hint}")


def _defines(kb: KnowledgeBase, task: Term) -> bool:
    """Whether some schema/3 head unifies with `task`."""
    goal = Struct("schema", (task, Var("_"), Var("_")))
    return any(Bindings().unify(c.head, goal) for c in kb.candidates("schema", 3, task) or [])


def _instantiate(kb: KnowledgeBase, task: Term, args: argparse.Namespace) -> Behaviour:
    return instantiate(kb, task, max_depth=args.max_depth, max_nodes=args.max_nodes)


def _emit(text: str, output: str | None, inputs: list[str]) -> None:
    """Print, or write atomically to `output`, which must not be any file read."""
    if output is None or output == "-":
        sys.stdout.write(text)
        return
    _emit_check(output, inputs)
    write_atomically(output, text)


def _writable(output: str) -> None:
    """Refuse, before any work is written, an output that could not be written."""
    try:
        check_writable(output)
    except SchemalogError as err:
        raise UsageError(err.message) from None


def _emit_check(output: str, inputs: list[str]) -> None:
    """Refuse an output file that is one of the files read (through links too)."""
    out = Path(output).resolve()
    if any(not i.startswith("<") and Path(i).resolve() == out for i in inputs):
        raise UsageError(f"-o {output} would overwrite an input file; choose another name")


# ---------------------------------------------------------------------------
# Commands

def cmd_check(args: argparse.Namespace) -> int:
    """Parse, read every schema, and instantiate the tasks."""
    kb, _ = _load(args)
    schemas = check_schemas(kb)
    tasks = _choose_tasks(kb, args.task, every=True)
    files = ", ".join(args.files)
    report = []
    for task in tasks:
        tree = _instantiate(kb, task, args)
        report.append(f"{term_to_text(task)} ({count_nodes(tree)} behaviours, depth {depth(tree)})")
    summary = f"ok: {files}: {len(schemas)} schemas"
    summary += f"; tasks: {', '.join(report)}" if report else "; no task/1 declared (nothing instantiated)"
    print(summary)
    return 0


_SUFFIX_FORMATS = {".json": "json", ".dot": "dot", ".gv": "dot", ".pl": "pl", ".yaml": "yaml", ".yml": "yaml"}


def _format(args: argparse.Namespace) -> str:
    """--json, else --format, else the output file's suffix, else text."""
    if args.json:
        return "json"
    if args.format:
        return args.format
    if args.output and args.output != "-":
        return _SUFFIX_FORMATS.get(Path(args.output).suffix.lower(), "text")
    return "text"


def _rendered(renderable, width: int = 120) -> str:
    from rich.console import Console

    buffer = io.StringIO()
    Console(file=buffer, width=width, no_color=True).print(renderable)
    return buffer.getvalue()


def _print_rich(renderable, output: str | None, inputs: list[str]) -> None:
    if output and output != "-":
        _emit(_rendered(renderable), output, inputs)
    else:
        from rich.console import Console

        Console(highlight=False).print(renderable)


def _output_tree(args: argparse.Namespace, task: Term, tree: Behaviour, header: str,
                 kb: KnowledgeBase | None = None) -> None:
    """Print or write one tree in the requested format (show, decompress)."""
    fmt = _format(args)
    inputs = kb.files if kb is not None else args.files
    if fmt == "json":
        _emit(json.dumps(show_json(task, tree), indent=2) + "\n", args.output, inputs)
    elif fmt == "dot":
        _emit(to_dot(tree, term_to_text(task)), args.output, inputs)
    elif fmt in ("pl", "yaml"):
        doc = tree_document(tree, carried=carried_clauses(kb) if kb is not None else [])
        _emit(to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc), args.output, inputs)
    else:
        title = f"{term_to_text(task)}: {count_nodes(tree)} behaviours, depth {depth(tree)}"
        _print_rich(rich_tree(tree, title), args.output, inputs)


def cmd_show(args: argparse.Namespace) -> int:
    """Instantiate a task and print its tree."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label  # as instantiated: --task 'add(X)' shows the schema it found
    _output_tree(args, task, tree, f"The task tree of {term_to_text(task)}, written by schemalog show.", kb)
    return 0


def cmd_compress(args: argparse.Namespace) -> int:
    """Merge sequential behaviours (Algorithm 1) and report the paper's figures."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label
    result = compress(tree, args.propagate, protected_labels(kb, tree),
                      Simplifier(sympy_budget=args.sympy_budget))
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    figures = (f"Bi = {result.nodes_before}, Bm = {result.nodes_after}, D = {result.depth_before}, "
               f"RD = (Bi - Bm) / (Bi - D) = {result.reduction_degree:.2f}")
    fmt = _format(args)
    report = _verify_compression(kb, result, args) if args.verify else None
    code = 0 if report is None else 1 if report.violated else (
        0 if report.exhaustive and report.sound and report.complete else INCONCLUSIVE)
    how = f"propagate {result.propagate}"
    if fmt == "json":
        data = {"task": term_to_text(task), "propagate": result.propagate,
                "nodes_before": result.nodes_before, "nodes_after": result.nodes_after,
                "depth_before": result.depth_before, "depth_after": result.depth_after,
                "reduction_degree": round(result.reduction_degree, 4),
                "conditions": {"simplified": result.simplifier.calls,
                               "needed_sympy": result.simplifier.sympy_calls},
                "notes": result.notes, "tree": tree_json(result.tree)}
        if report is not None:
            data["verification"] = verify_json(report, how, result.nodes_before, result.nodes_after)
        _emit(json.dumps(data, indent=2) + "\n", args.output, kb.files)
        return code
    elif fmt == "dot":
        _emit(compare_dot(result.original, result.tree, term_to_text(task), result.propagate),
              args.output, kb.files)
    elif fmt in ("pl", "yaml"):
        doc = tree_document(result.tree, carried=carried_clauses(kb))
        header = (f"Compressed by schemalog (Algorithm 1, propagate {result.propagate}) from "
                  f"{', '.join(args.files)}, task {term_to_text(task)}.\n{figures}.\n"
                  f"`schemalog decompress` restores the original tree from the origins/2 facts.")
        _emit(to_pl(doc, header=header) if fmt == "pl" else to_yaml(doc), args.output, kb.files)
    else:
        from rich.console import Console, Group
        from rich.table import Table

        before = f"Original: {result.nodes_before} behaviours, depth {result.depth_before}"
        after = (f"Compressed (propagate {result.propagate}): {result.nodes_after} behaviours, "
                 f"depth {result.depth_after}")
        to_file = bool(args.output and args.output != "-")
        if to_file or Console().width >= 140:  # side by side where there is room
            table = Table(show_header=True, header_style="bold", box=None, pad_edge=False)
            table.add_column(before)
            table.add_column(after)
            table.add_row(rich_tree(result.original), rich_tree(result.tree))
            view = Group(table, "", figures)
        else:
            view = Group(rich_tree(result.original, before), "", rich_tree(result.tree, after), "", figures)
        _print_rich(view, args.output, kb.files)
    if report is not None:
        # After the compressed task (or alone, when that went to a file): what verify would print.
        print("\n" + "\n".join(verify_lines(report, how, result.nodes_before, result.nodes_after, "default")))
    return code


def _verify_compression(kb: KnowledgeBase, result, args: argparse.Namespace):
    """`compress --verify`: prove the compressed tree against its original from the initial state."""
    world = World(result.original)
    world.reset(initial_state(kb))
    initial = [world.atoms]
    task = result.original.label
    report = verify_by_parts(result.original, result.tree, world, initial, None, task)
    return report if report is not None else Verifier(result.original, result.tree, world).verify(initial, None, task)


def cmd_decompress(args: argparse.Namespace) -> int:
    """Restore the original tree of a compressed task from its provenance."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label
    if not tree.origins:
        print(f"note: {term_to_text(task)} carries no provenance (origins/2): it is shown as it is",
              file=sys.stderr)
    original = decompress(tree)
    _output_tree(args, original.label, original,
                 f"The original tree of {term_to_text(task)}, restored by schemalog decompress.", kb)
    return 0


def cmd_convert(args: argparse.Namespace) -> int:
    """Convert knowledge between SEED, schema text and YAML."""
    doc = read_document(args.input, args.max_bytes)
    for note in doc.notes:
        print(note, file=sys.stderr)
    if args.task:
        declaration = Clause(Struct("task", (_task_term(args.task),)), TRUE, None)
        doc = Document((declaration, *doc.items), doc.file, doc.notes, doc.seed)
    loaded = doc.to_kb()
    check_schemas(loaded)  # what is written must load again: check before writing
    target = args.to or ("yaml" if args.output and args.output.endswith(YAML_SUFFIXES) else "pl")
    if target == "yaml":
        text = to_yaml(doc)
    else:
        origin = "the SEED long-term memory" if doc.seed else ""
        header = f"Converted by schemalog from {origin + ' ' if origin else ''}{doc.file}."
        text = to_pl(doc, header=header)
    _emit(text, args.output, [args.input, *loaded.files])
    return 0


def cmd_run(args: argparse.Namespace) -> int:
    """Execute a task with the attentional executive against an emulated robot."""
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    task = tree.label
    original = original_of(tree)
    kind = "compressed" if original is not tree else "original"
    if args.propagate is not None and not args.compressed:
        print("note: --propagate applies with --compressed; this run compresses nothing", file=sys.stderr)
    args.propagate = args.propagate or "full"
    if args.compressed:
        result = compress(original, args.propagate, protected_labels(kb, original),
                          Simplifier(sympy_budget=args.sympy_budget))
        for note in result.notes:
            print(f"note: {note}", file=sys.stderr)
        tree, kind = result.tree, f"compressed (propagate {args.propagate})"
    scene = _scene(args, original)
    world = World(original)
    if args.state is not None:
        initial = _atoms_option(args.state, "--state")
    else:
        initial = initial_state(kb)
        if not kb.clauses("initial", 1):
            print(f"note: {', '.join(args.files)} declares no initial state (initial/1): every atom "
                  f"starts false; give one with --state", file=sys.stderr)
    for atom in world.unknown(initial):
        print(f"warning: {'--state' if args.state is not None else 'initial/1'} names "
              f"{term_to_text(atom)}, which no condition of {term_to_text(task)} reads or sets",
              file=sys.stderr)
    world.reset(initial)
    failures = _failures(args, original, tree)
    executive = Executive(tree, world, scene, robot=RobotManager(scene, failures),
                          selector=args.selector, retries=args.retries, max_decisions=args.max_decisions,
                          recovery=args.recovery)
    if scene is NO_SCENE:
        print("note: no --scene: every behaviour gets the neutral lambda, so emphasis follows "
              "progress alone", file=sys.stderr)
    header = (f"run {term_to_text(task)}: {kind} tree of {count_nodes(tree)} behaviours; "
              f"selector {args.selector}; scene {scene.name}")
    fmt = "json" if args.json else "text"
    inputs = [*kb.files, *([args.scene] if args.scene else [])]
    if args.output and args.output != "-":
        _emit_check(args.output, inputs)   # refuse before running, not after
    if fmt == "json":
        outcome = executive.run()
        data = run_json(executive, task, kind, initial, args)
        _emit(json.dumps(data, indent=2) + "\n", args.output, inputs)
    else:
        lines = [header, f"initial state: {', '.join(term_to_text(a) for a in initial) or '(nothing true)'}"]
        out = sys.stdout if not args.output or args.output == "-" else None
        width = min(40, max(len(n.name) for n in walk(tree)))
        if out:
            print("\n".join(lines), flush=True)
            lines = []
        for decision in executive:
            text = decision_lines(decision, width)
            if out:
                print("\n".join(text))
            else:
                lines.extend(text)
        outcome = executive.outcome
        lines.extend(summary_lines(executive))
        if out:
            print("\n".join(lines))
        else:
            _emit("\n".join(lines) + "\n", args.output, inputs)
    return 0 if outcome.completed else 1


def cmd_verify(args: argparse.Namespace) -> int:
    """Prove a compressed task against its original: soundness and completion, with diagnostics."""
    kb, original, compressed, how, inputs = _verify_inputs(args)
    task = original.label
    world = World(original)
    initial = _initial_states(args, kb, world, task)
    scene = _scene(argparse.Namespace(**{**vars(args), "seed": None}), original)  # --seed samples here
    verifier = Verifier(original, compressed, world, max_states=args.max_states)
    report = None
    if args.sample:
        report = verifier.sample(initial, args.sample, args.seed or 0, scene, task)
    elif not args.no_split:
        report = verify_by_parts(original, compressed, world, initial, scene, task, args.max_states)
    if report is None:
        report = verifier.verify(initial, scene, task)
    if args.json:
        _emit(json.dumps(verify_json(report, how, count_nodes(original), count_nodes(compressed)), indent=2) + "\n",
              args.output, inputs)
    else:
        lines = verify_lines(report, how, count_nodes(original), count_nodes(compressed), args.states)
        _emit("\n".join(lines) + "\n", args.output, inputs)
    if report.violated:
        return 1
    return 0 if report.exhaustive and report.sound and report.complete else INCONCLUSIVE


def _verify_inputs(args: argparse.Namespace):
    """(kb, original, compressed, how, inputs): one task file compressed here, or an original
    file and a compressed file someone else produced."""
    if len(args.files) == 2:
        first, second = (KnowledgeBase(), KnowledgeBase())
        for kb, path in ((first, args.files[0]), (second, args.files[1])):
            read_document(path, args.max_bytes).to_kb(kb)
        task = _choose_tasks(first, args.task)[0]
        other_tasks = declared_tasks(second) or [task]
        compressed = _instantiate(second, other_tasks[0] if args.task is None else task, args)
        for kb in (first, second):
            for warning in kb.warnings:
                print(warning, file=sys.stderr)
        if any(n.origins for n in walk(compressed)):
            original = original_of(_instantiate(first, task, args))
            if (compressed.label, compressed.post) != (original.label, original.post):
                raise SchemalogError(
                    f"{args.files[1]} compresses {term_to_text(compressed.label)} (post-condition "
                    f"{cond.to_text(compressed.post)}), not {term_to_text(original.label)} of {args.files[0]} "
                    f"({cond.to_text(original.post)}): name the task with --task")
            if original_of(compressed) != original:
                print(f"note: the provenance of {args.files[1]} does not rebuild {args.files[0]}'s "
                      f"{term_to_text(task)} exactly; the world is the original file's", file=sys.stderr)
            return first, original, compressed, f"{args.files[1]}", [*first.files, *second.files]
        raise UsageError(f"{args.files[1]} carries no provenance (origins/2): give one task file to "
                         f"compress and verify, or an original and a file written by schemalog compress")
    if len(args.files) != 1:
        raise UsageError("verify takes one task file, or an original and a compressed file")
    kb, _ = _load(args)
    tree = _instantiate(kb, _choose_tasks(kb, args.task)[0], args)
    original = original_of(tree)
    if original is not tree:
        return kb, original, tree, "the compressed file", list(kb.files)
    result = compress(original, args.propagate, protected_labels(kb, original),
                      Simplifier(sympy_budget=args.sympy_budget))
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    return kb, original, result.tree, f"propagate {args.propagate}", list(kb.files)


def _initial_states(args: argparse.Namespace, kb: KnowledgeBase, world: World, task: Term) -> list:
    """--states default | all | 'atom, atom': the initial states to cover, settled."""
    if args.states == "all":
        atoms = free_atoms(kb, world.original)
        states = all_states(world, atoms, constraints(kb))
        if not states:
            raise SchemalogError("no assignment of the free atoms satisfies the constraints (constraint/1)")
        return states
    if args.states == "default":
        atoms = initial_state(kb)
    else:
        atoms = _atoms_option(args.states, "--states")
    for atom in world.unknown(atoms):
        print(f"warning: {term_to_text(atom)} is read or set by no condition of {term_to_text(task)}",
              file=sys.stderr)
    world.reset(atoms)
    return [world.atoms]


def verify_lines(report, how: str, before: int, after: int, states_option: str) -> list[str]:
    """The report as a person reads it: each property, and a counterexample where one fails."""
    n = len(report.initial_states)
    which = "default: " + state_text(report.initial_states[0]) if states_option == "default" else \
        ("all that satisfy the constraints" if states_option == "all" else state_text(report.initial_states[0]))
    lines = [f"verify {term_to_text(report.task)}: original {before} behaviours, compressed {after} ({how}); "
             f"{n} initial state{'s' if n != 1 else ''} ({which})",
             (f"sampled: visited {report.compressed_states:,} states of the compressed tree in "
              f"{report.seconds:.2f} s (NOT a proof)" if report.sampled else
              f"explored {report.compressed_states:,} states of the compressed tree and "
              f"{report.original_states:,} of the original in {report.seconds:.2f} s"
              + (f", in {report.parts} independent parts" if report.parts > 1 else "")
              + ("" if report.exhaustive else " (stopped at --max-states: NOT a proof)")), ""]
    titles = {"soundness": "soundness (no perceptual aliasing)", "completion": "completion",
              "flexibility": "flexibility (diagnostic)", "traces": "trace equivalence (diagnostic)",
              "selection": "selection under emphasis (diagnostic)"}
    for name, verdict in report.properties.items():
        status = {True: "holds", False: "FAILS", None: "unknown"}[verdict.holds]
        lines.append(f"{titles[name]}: {status}: {verdict.summary}")
        if verdict.counterexample is not None:
            lines.extend(counterexample_lines(verdict.counterexample))
        lines.append("")
    if report.violated:
        verdict = "the compressed tree is " + ("not sound" if report.properties["soundness"].holds is False
                                               else "not complete") + " (exit 1)"
    elif report.exhaustive:
        verdict = "the compressed tree is sound and complete (exit 0)"
    else:
        verdict = "no counterexample found, but this is not a proof (exit 3)"
    lines.append(f"result: {verdict}")
    return lines


def counterexample_lines(ce) -> list[str]:
    lines = [f"  counterexample, from the initial state {state_text(ce.initial)}:"]
    if not ce.path:
        lines.append("    (at the start)")
    for k, step in enumerate(ce.path, 1):
        actions = ", ".join(term_to_text(a) for a in step.actions)
        label = term_to_text(step.behaviour)
        lines.append(f"    {k:3d}  {label}" + (f"   [{actions}]" if actions != label else ""))
    if ce.action is not None:
        done = "".join(f"{term_to_text(a)}, " for a in ce.done_first)
        own = "" if ce.behaviour == ce.action and not done else f": {done}{term_to_text(ce.action)}"
        lines.append(f"    then the compressed tree takes {term_to_text(ce.behaviour)}{own}")
        lines.append(f"      ({ce.where})")
        lines.append(f"    the original would not take {term_to_text(ce.action)} there "
                     f"(state: {state_text(ce.state)}):")
    else:
        lines.append(f"    state: {state_text(ce.state)}")
    lines.extend(f"      {r}" for r in ce.reasons)
    return lines


def verify_json(report, how: str, before: int, after: int) -> dict:
    """The report as data (docs/formats.md)."""
    def ce_json(ce):
        if ce is None:
            return None
        return {"initial": sorted(term_to_text(a) for a in ce.initial),
                "run": [{"behaviour": term_to_text(s.behaviour), "actions": [term_to_text(a) for a in s.actions]}
                        for s in ce.path],
                "state": sorted(term_to_text(a) for a in ce.state),
                "behaviour": None if ce.behaviour is None else term_to_text(ce.behaviour),
                "behaviour_path": ce.where or None,
                "actions_before": [term_to_text(a) for a in ce.done_first],
                "action": None if ce.action is None else term_to_text(ce.action),
                "reasons": list(ce.reasons)}
    return {
        "task": term_to_text(report.task), "compressed": how, "behaviours": {"original": before, "compressed": after},
        "sound": report.properties["soundness"].holds, "complete": report.properties["completion"].holds,
        "exhaustive": report.exhaustive,
        "states": len(report.initial_states),
        "initial_states": [sorted(term_to_text(a) for a in s) for s in report.initial_states],
        "explored": {"compressed": report.compressed_states, "original": report.original_states,
                     "seconds": report.seconds, "parts": report.parts, "sampled": report.sampled},
        "counterexample": ce_json(report.properties["soundness"].counterexample
                                  or report.properties["completion"].counterexample),
        "properties": {name: {"holds": v.holds, "summary": v.summary, "counterexample": ce_json(v.counterexample),
                              **v.details} for name, v in report.properties.items()},
    }


def _term_option(text: str, option: str) -> Term:
    try:
        return parse_term(text, option)
    except SchemalogError as err:
        raise UsageError(f"{option} {text!r} is not a term: {err.message}") from None


def _atoms_option(text: str, option: str) -> list[Term]:
    """A state given on the command line, 'hand.free, a1.done': its atoms, or a usage error."""
    try:
        return state_atoms(_term_option(text, option), option)
    except UsageError:
        raise
    except SchemalogError as err:
        raise UsageError(err.message) from None


def _scene(args: argparse.Namespace, original: Behaviour) -> Scene:
    """The scene of --scene, jittered by --seed/--jitter, checked against the task's objects."""
    if args.scene is None:
        if args.seed is not None or args.jitter is not None:
            raise UsageError("--seed and --jitter move the objects of a scene: give --scene too")
        return NO_SCENE
    scene = read_scene(args.scene, args.max_bytes)
    for node in walk(original):
        for obj in node.objects[:1]:    # lambda reads the distance to a behaviour's first object
            if object_name(obj) not in scene.objects:
                known = ", ".join(sorted(scene.objects)) or "none"
                raise SchemalogError(f"the scene {args.scene} has no position for {object_name(obj)}, which "
                                     f"{node.name} acts on (objects in the scene: {known})", node.source)
    if args.seed is not None or args.jitter is not None:
        scene = scene.jittered(args.seed if args.seed is not None else 0,
                               args.jitter if args.jitter is not None else DEFAULT_JITTER)
    return scene


def _failures(args: argparse.Namespace, original: Behaviour, tree: Behaviour) -> dict:
    """--fail LABEL (repeatable): the robot fails these commands (--fail-times, default always)."""
    actions = {n.label for n in walk(original) if not n.children} | \
        {n.label for n in walk(tree) if not n.children}
    failures = {}
    for text in args.fail or []:
        label = _term_option(text, "--fail")
        if label not in actions:
            print(f"warning: --fail {text}: no action (leaf behaviour) of the task is labelled "
                  f"{term_to_text(label)}, so no command will fail", file=sys.stderr)
        failures[label] = args.fail_times
    return failures


def decision_lines(d: Decision, width: int) -> list[str]:
    """One decision as text: the winner, its emphasis, the runner-up, merged actions beneath."""
    runner = f"{term_to_text(d.runner_up[0])} {d.runner_up[1]:.4g}" if d.runner_up else "-"
    status = f"  FAILED: the robot did not complete {term_to_text(d.failed)}" if d.failed is not None else ""
    lines = [f"{d.index:4d}  {term_to_text(d.behaviour):<{width}}  e {d.emphasis:<9.4g} "
             f"runner-up {runner:<{width + 8}} {d.enabled:3d} enabled{status}"]
    steps = [*d.skipped, *d.executed, *([d.failed] if d.failed is not None else [])]
    if len(steps) > 1 or (steps and steps[0] != d.behaviour):  # a merged behaviour: its actions
        lines.extend(f"{'':6}- {term_to_text(a)} (skipped: accomplished)" for a in d.skipped)
        lines.extend(f"{'':6}- {term_to_text(a)}" for a in d.executed)
        if d.failed is not None:
            lines.append(f"{'':6}- {term_to_text(d.failed)} (failed)")
    if d.decompressed:
        merged, *parts = (term_to_text(x) for x in d.decompressed)
        then = f"{term_to_text(d.failed)} is retried on its own" if d.inhibited is None else \
            f"{term_to_text(d.failed)} alone is inhibited"
        lines.append(f"{'':6}decompressed {merged} into {', '.join(parts)}: {then}")
    return lines


def _micro(seconds: float) -> str:
    return f"{seconds * 1e6:.0f} us" if seconds < 0.01 else f"{seconds * 1e3:.1f} ms"


def summary_lines(ex: Executive) -> list[str]:
    """The end of a run: status, reasons, decisions and time per decision."""
    o = ex.outcome
    lines = [f"{o.status.value}: {o.reason}"]
    lines.extend(f"  {b}" for b in o.blocked)
    split = [d.decompressed[0] for d in ex.decisions if d.decompressed]
    if split:
        lines.append(f"decompressed {len(split)} merged behaviour{'s' if len(split) > 1 else ''} after failures "
                     f"({', '.join(term_to_text(x) for x in split)}): the tree went from "
                     f"{count_nodes(ex.given_tree)} to {count_nodes(ex.tree)} behaviours")
    times = sorted(d.seconds for d in ex.decisions)
    if times:
        mean = sum(times) / len(times)
        lines.append(f"{len(ex.decisions)} decisions, {len(ex.trace)} actions; time per decision "
                     f"({ex.selector_name}): mean {_micro(mean)}, median {_micro(times[len(times) // 2])}, "
                     f"max {_micro(times[-1])}")
    else:
        lines.append("no decision taken")
    return lines


def run_json(ex: Executive, task: Term, kind: str, initial: list[Term], args: argparse.Namespace) -> dict:
    """The run as data (docs/formats.md)."""
    times = [d.seconds for d in ex.decisions]
    return {
        "task": term_to_text(task), "tree": kind, "behaviours": count_nodes(ex.given_tree),
        "final_behaviours": count_nodes(ex.tree), "recovery": ex.recovery,
        "selector": ex.selector_name, "scene": ex.scene.name,
        "initial_state": [term_to_text(a) for a in initial],
        "completed": ex.outcome.completed, "status": ex.outcome.status.value,
        "reason": ex.outcome.reason, "blocked": list(ex.outcome.blocked),
        "trace": [term_to_text(a) for a in ex.trace],
        "decisions": [{
            "index": d.index, "behaviour": term_to_text(d.behaviour), "emphasis": d.emphasis,
            "runner_up": None if d.runner_up is None else {
                "behaviour": term_to_text(d.runner_up[0]), "emphasis": d.runner_up[1]},
            "enabled": d.enabled, "executed": [term_to_text(a) for a in d.executed],
            "skipped": [term_to_text(a) for a in d.skipped],
            "failed": None if d.failed is None else term_to_text(d.failed),
            "decompressed": None if not d.decompressed else {
                "behaviour": term_to_text(d.decompressed[0]),
                "into": [term_to_text(x) for x in d.decompressed[1:]]},
            "inhibited": None if d.inhibited is None else term_to_text(d.inhibited),
            "seconds": d.seconds, "hand": list(d.hand)} for d in ex.decisions],
        "decision_times": times,
        "final_state": sorted(term_to_text(a) for a in ex.world.atoms),
        "setup_seconds": ex.setup_seconds,
    }

def cmd_generate(args: argparse.Namespace) -> int:
    """Write a task in the shape of the paper's evaluation and report the RD it achieves."""
    if args.depth > DEFAULT_MAX_DEPTH:
        raise UsageError(f"--depth {args.depth}: at most {DEFAULT_MAX_DEPTH} levels (the deepest tree schemalog "
                         f"instantiates)")
    size = 0
    for level in range(args.depth):      # stop counting once over the limit: no huge integers
        size += args.children ** level
        if size > args.max_nodes:
            raise UsageError(f"depth {args.depth} with {args.children} children gives over {args.max_nodes:,} "
                             f"behaviours (--max-nodes)")
    outputs = [o for o in (args.output, args.scene) if o not in (None, "-")]
    if args.scene == "-":
        raise UsageError("--scene needs a file name (the task itself goes to standard output without -o)")
    if len(outputs) == 2 and Path(outputs[0]).resolve() == Path(outputs[1]).resolve():
        raise UsageError(f"-o and --scene name the same file, {args.output}")
    for output in outputs:              # check every destination before writing any
        _writable(output)
    cousins = not args.siblings_only
    tree = generate(args.depth, args.children, args.rd, args.seed, cousins)
    # Algorithm 1 merges the same behaviours whatever it propagates: count with the cheapest.
    result = compress(tree, "none")
    got = result.reduction_degree
    call = (f"schemalog generate --depth {args.depth} --children {args.children} --rd {args.rd:g} "
            f"--seed {args.seed}" + (" --siblings-only" if args.siblings_only else ""))
    figures = (f"Bi = {result.nodes_before:,}, D = {args.depth}; compressed: Bm = {result.nodes_after:,}, "
               f"RD = {got:.2f} (asked {args.rd:.2f})")
    fmt = args.format or ("yaml" if args.output and args.output.endswith(YAML_SUFFIXES) else "pl")
    # initial(true): the tasks start with every atom false, said so (run and verify then need no --state)
    start = Clause(Struct("initial", (TRUE,)), TRUE, None)
    doc = tree_document(tree, file=args.output or "<generated>", carried=[start])
    text = to_yaml(doc) if fmt == "yaml" else to_pl(doc, header=f"Generated by {call}.\n{figures}.")
    _emit(text, args.output, [])
    if args.scene:
        write_atomically(args.scene, scene_text(scene_for(args.children), f"Objects of the task written by {call}."))
    report = sys.stderr if args.output in (None, "-") else sys.stdout
    where = f"{args.output}: " if args.output not in (None, "-") else ""
    print(f"{where}task {term_to_text(tree.label)}, {figures}", file=report)
    why = shortfall(args.depth, args.children, args.rd, got, cousins)
    if why:
        print(f"note: RD {got:.2f} is more than {TOLERANCE} from the {args.rd:.2f} asked: {why}", file=report)
    return 0

def cmd_bench(args: argparse.Namespace) -> int:
    """Reproduce the paper's evaluation (Sec. IV) beside py_trees; write tables and figures."""
    import dataclasses

    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from ..evaluate.bench import PAPER_PLAN, QUICK_PLAN, headlines, run_bench, steps, write_results

    plan = QUICK_PLAN if args.quick else PAPER_PLAN
    changes = {k: v for k, v in (("runs", args.runs), ("seed", args.seed), ("max_states", args.max_states))
               if v is not None}
    plan = dataclasses.replace(plan, **changes)
    out = Path(args.out)
    try:                                 # make sure the results can be written before measuring
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise UsageError(f"--out {args.out} is a file, not a directory") from None
    except OSError as err:
        raise UsageError(f"--out {args.out}: cannot make the directory: {err.strerror or err}") from None
    if not os.access(out, os.W_OK):
        raise UsageError(f"--out {args.out}: the directory is not writable")
    console = Console(stderr=True)
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as progress:
        bar = progress.add_task(f"bench --{plan.name}", total=steps(plan))
        started = [False]

        def step(description: str) -> None:
            if started[0]:
                progress.advance(bar)
            started[0] = True
            progress.update(bar, description=description)

        results = run_bench(plan, step)
        progress.advance(bar)
    command = "schemalog bench " + " ".join(sys.argv[2:] if sys.argv[1:2] == ["bench"] else [f"--{plan.name}"])
    try:
        written = write_results(results, out, command)
    except OSError as err:
        raise SchemalogError(f"cannot write the results into {args.out}: {err.strerror or err}") from None
    print(f"bench --{plan.name}: {len(results.cells)} generated tasks x {plan.runs} runs, the coffee-and-tea "
          f"task, {len(results.sizes)} sizes; {results.seconds:,.0f} s")
    for line in headlines(results):
        print(f"- {line}")
    print("wrote " + ", ".join(str(p) for p in written))
    return 0


# ---------------------------------------------------------------------------
# Learning from demonstration

def cmd_learn(args: argparse.Namespace) -> int:
    """Segment a demonstration, teach it to a task structure, and write the learned knowledge."""
    from ..learn.learn import learn, lesson_lines, motions_json

    inputs = [args.demo, args.structure]
    outputs = [o for o in (args.output, args.plot, args.motions) if o and o != "-"]
    for out in outputs:
        _emit_check(out, inputs)
        _writable(out)
    if len(set(map(os.path.abspath, outputs))) < len(outputs):
        raise UsageError("-o, --plot and --motions must name different files")
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UsageError(f"--plot {args.plot}: name a .png, .svg or .pdf file")
    task = _task_term(args.task) if args.task else None
    lesson = learn(args.demo, args.structure, task, radius=args.radius, hysteresis=args.hysteresis,
                   min_motion=args.min_motion, max_bytes=args.max_bytes, bases=args.bases)
    report = lesson_lines(lesson)
    to_stdout = args.output is None or args.output == "-"
    motions_text = None
    if args.motions:
        if lesson.motions is None:
            raise UsageError("--motions needs primitives: --bases 0 turns them off")
        motions_text = json.dumps(motions_json(lesson, lesson.motions), indent=1) + "\n"
    # Everything is computed before anything is written, and the files are written side by side
    # under temporary names, then renamed together: bad input or a failed write leaves none behind.
    staged: list[tuple[str, str]] = []
    try:
        if args.plot:
            from ..evaluate.figures import demonstration_figure
            demonstration_figure(lesson, Path(_stage(args.plot, staged)))
        if motions_text is not None:
            Path(_stage(args.motions, staged)).write_text(motions_text, encoding="utf-8")
        if not to_stdout:
            Path(_stage(args.output, staged)).write_text(lesson.text, encoding="utf-8")
        for temporary, target in staged:
            os.chmod(temporary, file_mode(Path(target)))
        for temporary, target in staged:
            os.replace(temporary, target)
            report.append(f"wrote {target}")
    except OSError as err:
        temporaries = {t: target for t, target in staged}
        name = temporaries.get(err.filename, err.filename) if err.filename else (staged[-1][1] if staged else "")
        raise SchemalogError(f"cannot write {name or 'the output'}: {err.strerror or err}; nothing was written") from None
    finally:
        for temporary, _ in staged:
            if os.path.exists(temporary):
                os.unlink(temporary)
    print("\n".join(report), file=sys.stderr if to_stdout else sys.stdout)
    if to_stdout:
        sys.stdout.write(lesson.text)
    return 0


def _stage(target: str, staged: list[tuple[str, str]]) -> str:
    """A temporary file beside `target`, with its suffix, to be renamed onto it (see cmd_learn)."""
    path = Path(target)
    try:
        fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent)
    except OSError as err:
        raise OSError(err.errno, err.strerror, target) from None
    os.close(fd)
    staged.append((temporary, target))
    return temporary


def cmd_simulate_demo(args: argparse.Namespace) -> int:
    """Write a synthetic demonstration of a task in a scene (smooth motions with noise)."""
    from ..learn.demo import demonstration_csv, demonstration_json
    from ..learn.simulate import simulate

    scene = read_scene(args.scene, args.max_bytes)
    files = args.files or ([scene.knowledge] if scene.knowledge else [])
    if not files:
        raise UsageError(f"which task knowledge? {args.scene} names none (knowledge: in the scene): "
                         f"give the task file, e.g. kb/tasks/prepare_coffee_and_tea.pl")
    if args.output and args.output != "-":
        _emit_check(args.output, [*files, args.scene])
        _writable(args.output)
    kb = KnowledgeBase()
    for path in files:
        read_document(path, args.max_bytes).to_kb(kb)
    task = _choose_tasks(kb, args.task)[0]
    if args.jitter:
        scene = scene.jittered(args.seed, args.jitter)
    name = args.output if args.output and args.output != "-" else "<stdout>"
    demo = simulate(kb, task, scene, seed=args.seed, noise=args.noise, rate=args.rate, speed=args.speed,
                    radius=args.radius, file=name)
    comment = (f"A simulated demonstration of {term_to_text(task)} in {scene.name} ({args.scene}), written by "
               f"schemalog simulate-demo:\nminimum-jerk point-to-point motions at {args.speed:g} m/s, {args.rate:g} Hz, "
               f"position noise {args.noise:g} m (seed {args.seed}).")
    json_out = bool(args.output) and args.output.lower().endswith(".json")
    text = demonstration_json(demo) if json_out else demonstration_csv(demo, comment)
    commands = len(demo.gripper)
    summary = (f"simulated {term_to_text(task)} in {scene.name}: {len(demo):,} samples over {demo.times[-1]:.1f} s, "
               f"{commands} gripper commands")
    if args.output and args.output != "-":
        write_atomically(args.output, text)
        print(f"{summary}; wrote {args.output}")
    else:
        sys.stdout.write(text)
        print(summary, file=sys.stderr)
    return 0


# ---------------------------------------------------------------------------
# Argument parsing

def _workspace(args: argparse.Namespace, files: list[str]):
    """The files as a query workspace (relations.py), focused as --task/--compressed/--state ask."""
    from .relations import COMPRESSED, Options, Workspace

    options = Options(propagate=args.propagate, max_bytes=args.max_bytes, max_depth=args.max_depth,
                      max_nodes=args.max_nodes, max_steps=args.max_steps, sympy_budget=args.sympy_budget,
                      scene=NO_SCENE)
    workspace = Workspace(files, options)
    if args.scene is not None:
        if workspace.focus is None:
            raise UsageError("--scene positions the objects of a task, and these files have none")
        options = Options(**{**vars(options), "scene": _scene(args, workspace.focus.original)})
        workspace.options = options
    if args.task is not None:
        workspace.set_focus(*workspace.find_tree(_task_term(args.task)))
    if args.compressed:
        if workspace.focus is None:
            raise UsageError("--compressed needs a task: these files have none")
        workspace.set_focus(workspace.focus, COMPRESSED)
    if args.state is not None:
        workspace.set_state(_atoms_option(args.state, "--state"))
    return workspace


def cmd_query(args: argparse.Namespace) -> int:
    """Answer one query over knowledge files: every answer (or the first), as text or JSON."""
    from .toplevel import run_query

    try:
        workspace = _workspace(args, args.files)
    except SchemalogError as err:
        print(str(err), file=sys.stderr)
        return 2
    for note in workspace.notes:
        print(note, file=sys.stderr)
    return run_query(workspace, args.query, first=args.first, as_json=args.json)


def cmd_repl(args: argparse.Namespace) -> int:
    """The interactive top level (prompt_toolkit) over knowledge files."""
    from .toplevel import Repl

    workspace = _workspace(args, args.files)
    interactive = sys.stdin.isatty() and sys.stdout.isatty() and not args.plain
    return Repl(workspace).loop(interactive)


def _whole(minimum: int):
    """An argparse type: a whole number at least `minimum`."""
    def read(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}")
        return value
    return read


_positive = _whole(1)
_count = _whole(0)


def _distance(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (value >= 0 and value < float("inf")):
        raise argparse.ArgumentTypeError("must be a finite distance, at least 0")
    return value


def _bounded(low: float, high: float, kind=int):
    """An argparse type: a number of `kind` from `low` to `high`."""
    def read(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a {'whole ' if kind is int else ''}number") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be from {low:g} to {high:,g}")
        return value
    return read


def _length(text: str) -> float:
    """An argparse type: a finite positive number."""
    value = _distance(text)
    if value <= 0:
        raise argparse.ArgumentTypeError("must be more than 0")
    return value


def _fraction(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError("must be between 0 and 1")
    return value


def _budget(text: str) -> int:
    value = _positive(text)
    if value > MAX_SYMPY_BUDGET:
        raise argparse.ArgumentTypeError(f"at most {MAX_SYMPY_BUDGET} (sympy's cost doubles per variable; "
                                         f"16 ran for over 15 minutes on one condition)")
    return value


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="schemalog",
        description="Compress and check robot task structures (schema(m, l, p) knowledge).")
    parser.add_argument("--version", action="version", version=f"schemalog {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    limits = argparse.ArgumentParser(add_help=False)
    limits.add_argument("--max-bytes", type=_positive, default=MAX_BYTES,
                        help=f"refuse input files larger than this (default {MAX_BYTES:,})")
    limits.add_argument("--max-depth", type=_positive, default=DEFAULT_MAX_DEPTH,
                        help=f"deepest task tree to instantiate (default {DEFAULT_MAX_DEPTH})")
    limits.add_argument("--max-nodes", type=_positive, default=DEFAULT_MAX_NODES,
                        help=f"largest task tree to instantiate (default {DEFAULT_MAX_NODES:,})")

    p = sub.add_parser("check", parents=[limits], help="parse and validate knowledge files")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="instantiate this task (default: every task/1)")
    p.set_defaults(run=cmd_check)

    output = argparse.ArgumentParser(add_help=False)
    output.add_argument("--format", choices=["text", "json", "dot", "yaml", "pl"],
                        help="output format (default: from -o's suffix, else text)")
    output.add_argument("--json", action="store_true", help="same as --format json")
    output.add_argument("-o", "--output", help="write here (atomically) instead of standard output")

    p = sub.add_parser("show", parents=[limits, output], help="instantiate a task and print its tree")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task to instantiate (default: the first task/1)")
    p.set_defaults(run=cmd_show)

    p = sub.add_parser("compress", parents=[limits, output],
                       help="merge sequential behaviours (Definition 1, Algorithm 1)")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task to compress (default: the first task/1)")
    p.add_argument("--propagate", choices=list(PROPAGATE_MODES), default="full",
                   help="what the children of a merged behaviour inherit: its pre AND not post "
                        "(full, default), its pre (pre: the paper's rule), or nothing (none)")
    p.add_argument("--sympy-budget", type=_budget, default=DEFAULT_SYMPY_BUDGET, metavar="N",
                   help=f"simplify with sympy up to N variables (default {DEFAULT_SYMPY_BUDGET}, "
                        f"at most {MAX_SYMPY_BUDGET}: its cost doubles per variable)")
    p.add_argument("--verify", action="store_true",
                   help="then prove the compressed task against the original from the initial state "
                        "(as schemalog verify; exit 1 on a counterexample, 3 without a proof)")
    p.set_defaults(run=cmd_compress)

    p = sub.add_parser("decompress", parents=[limits, output],
                       help="restore the original tree of a compressed task file")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task (default: the first task/1)")
    p.set_defaults(run=cmd_decompress)

    p = sub.add_parser("run", parents=[limits],
                       help="execute a task with the attentional executive against an emulated robot")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--task", help="the task to run (default: the first task/1)")
    p.add_argument("--scene", metavar="FILE", help="object positions (YAML, docs/semantics.md); "
                                                   "without it every lambda is neutral")
    p.add_argument("--compressed", action="store_true", help="compress first, then run in the same world")
    p.add_argument("--propagate", choices=list(PROPAGATE_MODES),
                   help="with --compressed: what merged behaviours pass to their children (default full)")
    p.add_argument("--sympy-budget", type=_budget, default=DEFAULT_SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.add_argument("--state", metavar="ATOMS", help="the initial state, e.g. 'hand.free, spoon.taken' "
                                                    "(default: the file's initial/1 facts)")
    p.add_argument("--seed", type=int, help="move the scene's objects randomly with this seed")
    p.add_argument("--jitter", type=_distance, metavar="M",
                   help=f"how far (metres, per coordinate) --seed moves objects (default {DEFAULT_JITTER})")
    p.add_argument("--selector", choices=list(SELECTORS), default="incremental",
                   help="incremental (default): re-evaluate what an action touched; "
                        "scan: visit every behaviour at every decision, the paper's cost model")
    p.add_argument("--fail", action="append", metavar="LABEL",
                   help="make the robot fail this action's command (repeatable), e.g. 'a5(cup)'")
    p.add_argument("--fail-times", type=_positive, metavar="N",
                   help="each --fail action fails only its first N commands (default: every one)")
    p.add_argument("--retries", type=_count, default=DEFAULT_RETRIES, metavar="N",
                   help=f"retry a failed behaviour N times before inhibiting it (default {DEFAULT_RETRIES})")
    p.add_argument("--recovery", choices=list(RECOVERIES), default=RECOVERIES[0],
                   help="when the robot fails an action inside a merged behaviour: decompress (default) "
                        "splits just that behaviour into its actions, so only the failed one is retried "
                        "and inhibited; resume retries the merged behaviour from the failed action")
    p.add_argument("--max-decisions", type=_positive, metavar="N",
                   help="stop after N decisions (default: 4 per action of the original task, at least 100)")
    p.add_argument("--json", action="store_true", help="print the run as JSON (docs/formats.md)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=cmd_run)

    p = sub.add_parser("verify", parents=[limits],
                       help="prove a compressed task against its original, with counterexamples")
    p.add_argument("files", nargs="+", metavar="FILE",
                   help="a task file (compressed here), or an original and a compressed file")
    p.add_argument("--task", help="the task (default: the first task/1)")
    p.add_argument("--propagate", choices=list(PROPAGATE_MODES), default="full",
                   help="how to compress a single task file (default full; pre is the paper's rule)")
    p.add_argument("--sympy-budget", type=_budget, default=DEFAULT_SYMPY_BUDGET, metavar="N",
                   help=argparse.SUPPRESS)
    p.add_argument("--states", default="default", metavar="default|all|ATOMS",
                   help="initial states to cover: the file's (default), all assignments of the free atoms "
                        "that satisfy constraint/1, or one state such as 'hand.free, spoon.taken'")
    p.add_argument("--scene", metavar="FILE", help="scene for the selection diagnostic (winner-take-all runs)")
    p.add_argument("--max-states", type=_positive, default=DEFAULT_MAX_STATES, metavar="N",
                   help=f"stop exploring after N states per tree; the result then says it is no proof "
                        f"(default {DEFAULT_MAX_STATES:,})")
    p.add_argument("--no-split", action="store_true",
                   help="explore the whole task even where it splits into independent parts")
    p.add_argument("--sample", type=_positive, metavar="RUNS",
                   help="check RUNS random runs instead of every state: finds violations, proves nothing "
                        "(exit 3 when none is found)")
    p.add_argument("--seed", type=int, help="random seed of --sample (default 0)")
    p.add_argument("--json", action="store_true", help="print the report as JSON (docs/formats.md)")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=cmd_verify, jitter=None)

    p = sub.add_parser("generate", help="write a task in the shape of the paper's evaluation (Sec. IV-B)")
    p.add_argument("--depth", type=_positive, required=True,
                   help=f"levels of the tree (the paper: 4, 5, 6; at most {DEFAULT_MAX_DEPTH})")
    p.add_argument("--children", type=_positive, required=True,
                   help="children per behaviour (the paper: 2, 3, 4)")
    p.add_argument("--rd", type=_fraction, default=0.0, metavar="RD",
                   help="the reduction degree to aim at, 0 to 1 (default 0); the one achieved is reported")
    p.add_argument("--seed", type=int, default=0, help="which chains are drawn (default 0)")
    p.add_argument("--siblings-only", action="store_true",
                   help="release behaviours only by a sibling's done (caps RD lower, e.g. 0.55 for binary trees)")
    p.add_argument("--format", choices=["pl", "yaml"], help="output format (default: from -o's suffix, else pl)")
    p.add_argument("--scene", metavar="FILE", help="also write a scene with the objects (for schemalog run)")
    p.add_argument("--max-nodes", type=_positive, default=DEFAULT_MAX_NODES,
                   help=f"refuse shapes with more behaviours (default {DEFAULT_MAX_NODES:,})")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    p.set_defaults(run=cmd_generate)

    p = sub.add_parser("bench", help="reproduce the paper's evaluation (Sec. IV) beside py_trees: "
                                     "CSV, Markdown and figures")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--paper", action="store_true",
                       help="the whole grid: depth 4-6 x 2-4 children x RD 0, 0.3, 0.5, 0.7, 10 runs each, "
                            "the coffee-and-tea task, and sizes up to 111,111 behaviours (several minutes)")
    which.add_argument("--quick", action="store_true",
                       help="the same grid with 2 runs per tree and sizes to 5,461, in about a minute")
    p.add_argument("--out", default="bench-results", metavar="DIR",
                   help="where to write results.csv, results.md and the figures (default bench-results)")
    p.add_argument("--runs", type=_positive, metavar="N", help="runs per tree (default 10, --quick 2)")
    p.add_argument("--seed", type=int, help="seed of the generated tasks (default 1)")
    p.add_argument("--max-states", type=_positive, metavar="N",
                   help="verification stops (no proof) beyond N states (default 20,000, --quick 5,000)")
    p.set_defaults(run=cmd_bench)

    p = sub.add_parser("learn", help="learn task knowledge from a demonstration (Sec. II-C, II-D; docs/learning.md)")
    p.add_argument("demo", metavar="DEMO", help="the demonstration, CSV or JSON (docs/learning.md)")
    p.add_argument("--structure", required=True, metavar="FILE",
                   help="the partially specified task structure: schema knowledge whose sub-tasks have no actions")
    p.add_argument("--task", help="the demonstrated task (default: the structure's first task/1)")
    p.add_argument("-o", "--output", help="write the learned knowledge here (atomically); default: standard output")
    p.add_argument("--radius", type=_length, default=defaults.RADIUS, metavar="M",
                   help=f"the proximity sphere around each object (default {defaults.RADIUS} m)")
    p.add_argument("--hysteresis", type=_distance, default=defaults.HYSTERESIS, metavar="M",
                   help=f"how far beyond the radius leaving counts (default {defaults.HYSTERESIS} m)")
    p.add_argument("--min-motion", type=_distance, default=defaults.MIN_MOTION, metavar="M",
                   help=f"a stretch moving the hand less than this is a pause, not an action (default {defaults.MIN_MOTION} m)")
    p.add_argument("--max-bytes", type=_positive, default=defaults.MAX_DEMO_BYTES,
                   help=f"refuse a demonstration larger than this (default {defaults.MAX_DEMO_BYTES:,})")
    p.add_argument("--plot", metavar="FILE", help="draw the trajectory, its segments and objects, and the merged "
                   "primitives (PNG, SVG or PDF by suffix)")
    p.add_argument("--motions", metavar="FILE", help="write the motion primitives (DMPs) and their reproduction "
                   "errors as JSON")
    p.add_argument("--bases", type=_bounded(0, defaults.MAX_BASES), default=defaults.BASES, metavar="N",
                   help=f"basis functions of a primitive per segment (default {defaults.BASES}, at most "
                        f"{defaults.MAX_BASES}; 0: no primitives)")
    p.set_defaults(run=cmd_learn)

    p = sub.add_parser("simulate-demo", help="write a synthetic demonstration of a task in a scene")
    p.add_argument("files", nargs="*", metavar="FILE",
                   help="the task knowledge (default: the scene's knowledge: entry)")
    p.add_argument("--scene", required=True, metavar="FILE", help="object positions (YAML)")
    p.add_argument("--task", help="the task to demonstrate (default: the first task/1)")
    p.add_argument("-o", "--output", help="write here (atomically; .json for JSON, else CSV); default: standard output")
    p.add_argument("--seed", type=int, default=0, help="seed of the noise and of --jitter (default 0)")
    p.add_argument("--noise", type=_distance, default=defaults.NOISE, metavar="M",
                   help=f"standard deviation of the hand's position noise (default {defaults.NOISE} m)")
    p.add_argument("--jitter", type=_distance, default=0.0, metavar="M",
                   help="move each object coordinate by up to M metres (with --seed; default 0)")
    p.add_argument("--rate", type=_bounded(1, defaults.MAX_RATE, float), default=defaults.RATE, metavar="HZ",
                   help=f"samples per second (default {defaults.RATE:g}, at most {defaults.MAX_RATE:,g})")
    p.add_argument("--speed", type=_bounded(0.01, 2.0, float), default=defaults.SPEED, metavar="M/S",
                   help=f"the speed of the teacher's motions, 0.01 to 2 (default {defaults.SPEED} m/s; each motion "
                        f"also takes 0.3 s to start and stop)")
    p.add_argument("--radius", type=_length, default=defaults.RADIUS, metavar="M",
                   help=f"the proximity radius the demonstration is planned for (default {defaults.RADIUS} m)")
    p.add_argument("--max-bytes", type=_positive, default=MAX_BYTES,
                   help=f"refuse input files larger than this (default {MAX_BYTES:,})")
    p.set_defaults(run=cmd_simulate_demo)

    ask = argparse.ArgumentParser(add_help=False)
    ask.add_argument("--task", help="the task enabled/1, emphasis/2 and next_action/1 look at (default: the first)")
    ask.add_argument("--compressed", action="store_true",
                     help="look at the task's compressed tree instead of the original")
    ask.add_argument("--state", metavar="ATOMS", help="the current state, e.g. 'hand.free, a1.done' "
                     "(default: the files' initial/1)")
    ask.add_argument("--scene", metavar="FILE", help="object positions for emphasis/2 (lambda)")
    ask.add_argument("--propagate", choices=list(PROPAGATE_MODES), default="full",
                     help="how compressed/2 and merged/3 propagate conditions (default full)")
    ask.add_argument("--sympy-budget", type=_budget, default=DEFAULT_SYMPY_BUDGET, metavar="N",
                     help=argparse.SUPPRESS)
    ask.add_argument("--max-steps", type=_positive, default=DEFAULT_MAX_STEPS, metavar="N",
                     help=f"resolution steps one query may take (default {DEFAULT_MAX_STEPS:,})")
    ask.set_defaults(seed=None, jitter=None)

    p = sub.add_parser("query", parents=[limits, ask],
                       help="answer a Prolog query over knowledge files (docs/queries.md)")
    p.add_argument("files", nargs="*", metavar="FILE")
    p.add_argument("query", metavar="QUERY", help="a goal, e.g. 'sequential(X, Y)' (the final '.' is optional)")
    p.add_argument("--first", action="store_true", help="stop after the first answer")
    p.add_argument("--json", action="store_true", help="print a JSON list of bindings")
    p.set_defaults(run=cmd_query)

    p = sub.add_parser("repl", parents=[limits, ask], help="the interactive query top level")
    p.add_argument("files", nargs="*", metavar="FILE")
    p.add_argument("--plain", action="store_true",
                   help="read queries line by line without prompt_toolkit (as when piped)")
    p.set_defaults(run=cmd_repl)

    p = sub.add_parser("convert", parents=[limits],
                       help="convert knowledge: SEED or schema text or YAML -> schema text or YAML")
    p.add_argument("input", metavar="FILE")
    p.add_argument("-o", "--output", help="output file; its suffix (.pl, .yaml) picks the format")
    p.add_argument("--to", choices=["pl", "yaml"], help="output format (default: from -o, else pl)")
    p.add_argument("--task", help="declare this task (task/1) in the output")
    p.set_defaults(run=cmd_convert)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:
        # `schemalog query FILE --first QUERY`: argparse gives FILE to QUERY and leaves the
        # real query over; options may stand anywhere, as for every other command.
        if getattr(args, "command", None) == "query" and not any(e.startswith("-") for e in extra):
            args.files, args.query = [*args.files, args.query, *extra[:-1]], extra[-1]
        else:
            parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if not getattr(args, "run", None):
        parser.print_help(sys.stderr)
        return 2
    try:
        return args.run(args)
    except SchemalogError as err:
        print(str(err), file=sys.stderr)
        if err.exit_code == 2:
            print(f"(see: schemalog {args.command} --help)", file=sys.stderr)
        return err.exit_code
    except PrologError as err:
        print(f"error: uncaught Prolog exception: {err}", file=sys.stderr)
        return 1
    except RecursionError:
        print("error: the input nests too deeply to process", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as err:  # an internal error must still not dump a traceback on users
        if os.environ.get("SCHEMALOG_DEBUG"):
            raise
        print(f"internal error: {type(err).__name__}: {err} (please report it; "
              f"SCHEMALOG_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 70


def tune_gc() -> None:
    """Collect garbage less often: loading builds millions of small immutable objects and
    almost no cycles, and the default thresholds make it superlinear (x25 per 10x size
    instead of x10, benchmarks/bench_foundation.py)."""
    gc.set_threshold(50_000, 20, 100)


def run() -> None:
    """Console-script entry point."""
    tune_gc()
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20_000))
    code = main()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        pass
    raise SystemExit(code)


__all__ = ["main", "run"]
