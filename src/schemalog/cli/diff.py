"""`schemalog diff A B`: what changed in behaviour between two versions of a BT.CPP program
(docs/behaviour_trees.md, "Reviewing a change: schemalog diff")."""

from __future__ import annotations

import argparse
import sys

from .options import Parents

FORMATS = ("text", "json", "markdown", "dot", "png", "svg", "pdf")


def register(sub, parents: Parents) -> None:
    """Add `schemalog diff` and its arguments to the command line."""
    p = sub.add_parser("diff", parents=[parents.limits, parents.resources],
                       help="what changed in behaviour between two versions of a BT.CPP tree or a task, place by place",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       description=(
                           "Prove two versions of a BT.CPP program equal under BT.CPP's semantics, or show where\n"
                           "their runs part: the first divergence, every place that changes behaviour with its\n"
                           "shortest run, the direction that holds, and the structural changes that make no\n"
                           "difference. Two versions of a task (task knowledge, .pl) are compared on the\n"
                           "verifier's runs, both ways.\n\n"
                           "examples:\n"
                           "  schemalog diff old.xml new.xml --nodes nav2_tree_nodes.xml\n"
                           "  schemalog diff --rev HEAD behavior_trees/navigate.xml --format markdown -o diff.md\n"
                           "  schemalog diff old_trees/ new_trees/ --task MainTree -o diff.svg\n\n"
                           "exit status: 0 same behaviour, 1 behaviour changed, 2 bad input or usage,\n"
                           "3 no proof either way (a limit)"))
    p.add_argument("files", nargs="+", metavar="PATH",
                   help="A and B, the old and the new version: BT.CPP XML files, folders of them (each one "
                        "program), or task knowledge files; with --rev, each PATH against its version at REV")
    p.add_argument("--rev", metavar="REV",
                   help="compare each PATH (a BT.CPP file or folder) with its own version at git revision REV (HEAD, "
                        "origin/main, a tag, a hash): a pre-commit hook's and a pull request's check; the exit "
                        "status is the worst of them, trouble (2) before no proof (3) before a change (1)")
    p.add_argument("--task", help="the BehaviorTree ID to run on both sides (default: each side's "
                                  "main_tree_to_execute)")
    from .. import defaults
    from .options import positive

    p.add_argument("--max-states", type=positive, default=defaults.MAX_STATES, metavar="N",
                   help=f"stop after N pairs of states in all (the whole pair, then each place); what is left "
                        f"undecided then says so, and with no verdict on the whole the exit status is 3 "
                        f"(default {defaults.MAX_STATES:,})")
    p.add_argument("--json", action="store_true", help="print the report as JSON (docs/formats.md)")
    p.add_argument("--format", choices=FORMATS,
                   help="text (default), json, markdown (a pull-request comment), dot, or a picture (png, svg, "
                        "pdf: both trees side by side, the places marked, the path to the first divergence in "
                        "bold); default: from -o's suffix")
    p.add_argument("-o", "--output", help="write here (atomically) instead of standard output")
    from .trees import add_nodes_option
    add_nodes_option(p, drop_names=False)
    p.set_defaults(run=run)


def _format(args: argparse.Namespace) -> str:
    from ..errors import UsageError
    from ..formats.graphviz import dot_program, image_format, refuse_unknown_picture

    if args.json:
        if args.format not in (None, "json"):
            raise UsageError(f"--json and --format {args.format} ask for two outputs; give one")
        return "json"
    if args.format:
        if args.format in ("png", "svg", "pdf"):
            if not args.output or args.output == "-":
                raise UsageError(f"a {args.format.upper()} picture is written to a file: give -o diff.{args.format}")
            dot_program()
        return args.format
    if args.output and args.output != "-":
        refuse_unknown_picture(args.output)
        picture = image_format(args.output)
        if picture is not None:
            dot_program()                  # before any work: say Graphviz is missing now
            return picture
        suffix = args.output.lower().rsplit(".", 1)[-1]
        return {"md": "markdown", "json": "json", "dot": "dot"}.get(suffix, "text")
    return "text"


def run(args: argparse.Namespace) -> int:
    """Compare two versions of a BT.CPP program and report what changed in behaviour."""
    import json

    from ..api.behaviour_trees import is_own_export
    from ..api.tree_diff import diff_trees
    from ..errors import UsageError, readable_name
    from ..inputs import is_xml
    from .common import check_output, emit
    from .trees import _given, _read, _rules, _versions, _with_profiles

    if args.rev is not None:                 # schemalog diff --rev REV PATH...: each PATH against git's REV
        from .diff_rev import run_rev
        return run_rev(args, _format(args))
    if len(args.files) != 2:
        raise UsageError("diff takes two versions: A (the old) and B (the new)")
    fmt = _format(args)
    import os

    # a folder is a BT.CPP program (task knowledge is never a folder), as compress and verify read it
    xml = [os.path.isdir(f) or is_xml(f) and not is_own_export(f, args.max_bytes) for f in args.files]
    if not all(xml):
        if any(xml):
            tree, task = (args.files[0], args.files[1]) if xml[0] else (args.files[1], args.files[0])
            raise UsageError(f"{readable_name(tree)} is a BT.CPP tree and {readable_name(task)} task knowledge: "
                             f"diff compares two versions of one kind (two BT.CPP trees, or two task files)")
        from .diff_tasks import run_tasks
        return run_tasks(args, fmt)
    check_output(args.output, _given(args))
    rules = _rules(args)
    versions = _versions(args, 2)
    a, b = _read(args, args.files[0], versions[0]), _read(args, args.files[1], versions[1])
    report = diff_trees(a, b, args.max_states, rules, run_once=args.run_once, a_name=readable_name(args.files[0]),
                        b_name=readable_name(args.files[1]), under=_with_profiles(args))
    inputs = [*_given(args), *a.includes, *b.includes]
    if fmt == "json":
        emit(json.dumps(report.as_json(), indent=2) + "\n", args.output, inputs, "JSON")
    elif fmt == "markdown":
        emit(report.markdown(), args.output, inputs, "Markdown")
    elif fmt == "dot":
        emit(report.dot(a, b), args.output, inputs, "DOT")
    elif fmt in ("png", "svg", "pdf"):
        from ..formats.graphviz import write_image

        check_output(args.output, inputs)
        write_image(args.output, report.dot(a, b), fmt)
        # as every command that writes a file says so, with the verdict a reader would look for
        article = "an" if fmt == "svg" else "a"
        print(f"wrote {readable_name(args.output)}: {article} {fmt.upper()} picture; {report.headline()}",
              file=sys.stderr)
    else:
        emit(report.text(), args.output, inputs, "text")
    return report.exit_status
