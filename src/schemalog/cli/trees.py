"""`schemalog compress F.xml|DIR ...` and `schemalog verify A B` (each a file or a folder) for
behaviour trees that are not schemalog's own exports: BT.CPP 4 semantics, the rewrites of bt/compress.py, the
prover of bt/prove.py (docs/behaviour_trees.md)."""

from __future__ import annotations

import argparse
import json
import sys

from ..errors import SchemalogError, UsageError, readable_name

def tree_route(args: argparse.Namespace) -> bool:
    """Whether the command's files are BT.CPP trees to treat as behaviour trees: every one XML
    (by its content, whatever its name: inputs.is_xml) or a folder (of BT.CPP trees: task
    knowledge is never a folder), none schemalog's own export (those are task knowledge, the
    schema route)."""
    import os

    from ..api.behaviour_trees import is_own_export
    from ..inputs import is_xml

    files = args.files
    return bool(files) and all(os.path.isdir(f) or is_xml(f) for f in files) \
        and not any(is_own_export(f, args.max_bytes) for f in files if not os.path.isdir(f))


def schema_route(args: argparse.Namespace) -> None:
    """Refuse --nodes, --semantics, --profile and --drop-names for task knowledge, which they would
    not change."""
    given = [o for o, v in (("--nodes", args.nodes), ("--semantics", args.semantics),
                            ("--profile", args.profile), ("--drop-names", getattr(args, "drop_names", False)),
                            ("--run-once", args.run_once), ("--btcpp", getattr(args, "btcpp", None))) if v]
    if given:
        raise UsageError(f"{' and '.join(given)} {'apply' if len(given) > 1 else 'applies'} to BT.CPP trees; "
                         f"{', '.join(map(readable_name, args.files)) or 'the input'} is read as task knowledge "
                         f"(a BT.CPP tree is an XML file, and not a tree schemalog exported)")


def add_nodes_option(p: argparse.ArgumentParser, max_states: bool = False, drop_names: bool = True) -> None:
    """--nodes FILE: a TreeNodesModel file (Nav2's nav2_tree_nodes.xml) for BT.CPP trees; with
    `max_states`, the prover's --max-states too (compress proves what it rewrote)."""
    if max_states:
        from .. import defaults
        from .options import positive

        p.add_argument("--max-states", type=positive, default=defaults.MAX_STATES, metavar="N",
                       help=f"BT.CPP trees: stop proving the compressed tree after N pairs of states; the "
                            f"result then says it is no proof and exits 3 (default {defaults.MAX_STATES:,})")
    p.add_argument("--semantics", action="append", default=[], metavar="FILE",
                   help="BT.CPP trees: a YAML file giving custom node types the semantics of known ones, "
                        "`MyRecovery: RecoveryNode`, `IsBatteryOk: Condition` (docs/behaviour_trees.md); "
                        "repeatable, the files read as one; other custom types are opaque")
    p.add_argument("--profile", action="append", default=[], metavar="NAME", type=profile_name,
                   help="BT.CPP trees: the node semantics schemalog ships for a framework's own node types, "
                        "read as a --semantics file given first (a type a --semantics file gives too takes "
                        "the file's rule, with a note); repeatable; one of: nav2 (Nav2's nodes, from its "
                        "source; docs/behaviour_trees.md)")
    p.add_argument("--nodes", action="append", default=[], metavar="FILE",
                   help="BT.CPP trees: a file of <TreeNodesModel> declarations (e.g. Nav2's "
                        "nav2_tree_nodes.xml); repeatable")
    p.add_argument("--btcpp", type=btcpp_versions, default=None, metavar="3|4|3:4",
                   help="BT.CPP trees: read every file under BT.CPP 3 (3.8) or 4, whatever its BTCPP_format says "
                        "(a contrary mark is a note on stderr); 3:4 (verify OLD NEW) reads the first under 3.8 and "
                        "the second under 4. By default a file's BTCPP_format, else what only one version reads "
                        "(SequenceStar, SubTreePlus: 3.8; Script, _skipIf: 4); a file with neither is proved under "
                        "both where they can differ (docs/behaviour_trees.md, \"BT.CPP 3 files\")")
    p.add_argument("--run-once", action="store_true",
                   help="BT.CPP trees: prove for trees ticked until they finish, once, and never halted "
                        "(Tree::tickWhileRunning); by default a proof also covers an executor that halts the "
                        "tree (Tree::haltTree) between any two ticks and ticks it again for a new goal, as "
                        "Nav2's navigators do")
    if not drop_names:                  # diff compresses nothing
        return
    p.add_argument("--drop-names", action="store_true",
                   help="BT.CPP trees: let the rewrites remove nodes that carry a name= attribute too; by "
                        "default they are kept, for BT.CPP's substitution rules, Groot2 and loggers find "
                        "nodes by name (docs/behaviour_trees.md)")


def btcpp_versions(text: str) -> tuple[int, ...]:
    """--btcpp 3|4|3:4: the BT.CPP version of every file, or of the first and the second (exit 2 else)."""
    parts = text.split(":")
    if len(parts) > 2 or any(p not in ("3", "4") for p in parts):
        raise argparse.ArgumentTypeError(f"{text!r}: give 3 (BT.CPP 3.8), 4, or OLD:NEW such as 3:4")
    return tuple(int(p) for p in parts)


def _versions(args: argparse.Namespace, files: int) -> tuple:
    """The version to read each of `files` files under (None: as the file tells)."""
    given = getattr(args, "btcpp", None)
    if given is None:
        return (None,) * files
    if len(given) == 2 and files != 2:
        raise UsageError(f"--btcpp {given[0]}:{given[1]} gives two files their versions (verify OLD NEW); "
                         f"{'this command reads one' if files == 1 else f'{files} files are given'}: --btcpp 3 or 4")
    return given * files if len(given) == 1 else given


def _read(args: argparse.Namespace, path, version):
    """read_tree with the command's options, its notes on stderr."""
    from ..api.behaviour_trees import read_tree

    notes: list[str] = []
    document = read_tree(path, args.nodes, args.max_bytes, args.task, version=version, notes=notes)
    for note in notes:
        print(note, file=sys.stderr)
    return document


def profile_name(text: str) -> str:
    """--profile NAME: a profile schemalog ships (an unknown name is a usage error, exit 2)."""
    from ..api.behaviour_trees import PROFILES

    if text not in PROFILES:
        raise argparse.ArgumentTypeError(f"unknown profile {text!r}; the profiles schemalog ships: "
                                         f"{', '.join(PROFILES)}")
    return text


def _profiles(args: argparse.Namespace) -> list[str]:
    return list(dict.fromkeys(args.profile))


def _with_profiles(args: argparse.Namespace) -> str:
    """How a verdict names the profiles it was proved under: '' or ' with the nav2 profile'."""
    names = _profiles(args)
    if not names:
        return ""
    return f" with the {' and '.join(names)} profile{'s' if len(names) > 1 else ''}"


def _inputs(args: argparse.Namespace, document) -> list[str]:
    return [*_given(args), *document.includes]


def _shown(files) -> str:
    """The files or folders of one program as a message names them."""
    return ", ".join(map(readable_name, files))


def _not_into_folders(output: str | None, files) -> None:
    """Refuse an -o FILE.xml inside a folder read as the program: the next reading of the folder
    would find every tree twice (a usage error, before anything is read)."""
    import os

    if not output or output == "-" or not output.endswith(".xml"):
        return
    where = os.path.realpath(os.path.dirname(os.path.abspath(output)))
    for f in files:
        if os.path.isdir(f) and os.path.realpath(f) == where:
            raise UsageError(f"-o {readable_name(output)} would be written into the folder {readable_name(f)}, "
                             f"which is read as the program: reading it again would find every tree twice; "
                             f"write it elsewhere")


def _given(args: argparse.Namespace) -> list[str]:
    """The files named on the command line: trees, --nodes, --semantics."""
    return [*args.files, *args.nodes, *args.semantics]


def _tree(args: argparse.Namespace, paths, rules, version):
    """The program in `paths` read as the command reads it (_read), with the rules read (_rules),
    as the API's TreeDocument, whose results print what the command prints (api/trees.py)."""
    from ..api.trees import document_of

    return document_of([paths] if isinstance(paths, str) else paths, _read(args, paths, version), args.nodes,
                       args.semantics, _profiles(args), args.task, rules, max_bytes=args.max_bytes, version=version)


def _rules(args: argparse.Namespace):
    from ..api.behaviour_trees import read_semantics

    if not args.semantics and not args.profile:
        return None
    notes: list[str] = []
    rules = read_semantics(args.semantics, args.max_bytes, profiles=_profiles(args), notes=notes)
    for note in notes:
        print(note, file=sys.stderr)
    return rules


def run_compress(args: argparse.Namespace) -> int:
    """Compress one BT.CPP program (a file, or several files and folders read as one), prove the
    result, print or write it."""
    from ..api.behaviour_trees import verdict_text
    from ..api.trees import INCONCLUSIVE, compress_tree, kept_words
    from .common import check_output, emit

    fmt = "json" if args.json else args.format or ("xml" if args.output and args.output.lower().endswith(".xml")
                                                    else "text" if not args.output or args.output == "-" else None)
    if fmt not in ("xml", "text", "json"):
        raise UsageError("a BT.CPP tree compresses to BT.CPP XML (-o FILE.xml), text or JSON (--json); "
                         f"not {args.format or args.output!r}")
    check_output(args.output, _given(args))
    _not_into_folders(args.output, args.files)
    rules = _rules(args)
    tree = _tree(args, args.files, rules, _versions(args, 1)[0])
    result = compress_tree(tree, max_states=args.max_states, drop_names=args.drop_names, run_once=args.run_once)
    verdict, code = result.verdict, result.exit_status
    kept = kept_words(result.kept_names)
    if verdict is not None and not verdict.equal:
        # A rewrite the prover refutes is a bug of ours: say so, write nothing.
        print(verdict_text(verdict), end="")
        raise SchemalogError(f"the compressed tree differs from {_shown(args.files)}: a rewrite of "
                             f"bt/compress.py is wrong here (nothing written); please report it with the file")
    summary = result.summary
    inputs = _inputs(args, tree.document)
    if fmt == "xml" and code == INCONCLUSIVE:
        # An unproved tree is not written where a proved one would be: a script that does not
        # read the exit status must not pick it up.
        print(f"{summary}\nnothing written to {readable_name(args.output)}: raise --max-states to prove it"
              + (f"\n{kept}" if kept else ""), file=sys.stderr)
        return code
    if fmt == "xml":
        emit(result.xml(), args.output, inputs, summary.split(": ", 1)[1])
    elif fmt == "json":
        emit(json.dumps(result.as_json(), indent=2) + "\n", args.output, inputs, "JSON")
    else:
        emit(result.text(), args.output, inputs, "text")
    if kept and fmt == "xml":
        print(kept, file=sys.stderr)     # the text and JSON outputs list them with the rewrites
    if code == INCONCLUSIVE and fmt != "text":
        print(f"NOT proved: {verdict.reason}", file=sys.stderr)
    return code


def run_verify(args: argparse.Namespace) -> int:
    """Prove a compressed BT.CPP program against its original (or compress one and prove it),
    each side a file or a folder."""
    from ..api.trees import verify_trees
    from .common import check_output, emit

    check_output(args.output, _given(args))
    _not_into_folders(args.output, args.files)
    if args.drop_names and len(args.files) != 1:
        raise UsageError("--drop-names applies when verify compresses one BT.CPP tree; with an original and a "
                         "compressed file nothing is compressed")
    rules = _rules(args)
    versions = _versions(args, len(args.files)) if len(args.files) in (1, 2) else ()
    if len(args.files) == 1:
        # Nothing rewritten is no proof (exit 3, as a limit's): nothing was checked (TreeProof)
        original = _tree(args, args.files[0], rules, versions[0])
        proof = verify_trees(original, max_states=args.max_states, drop_names=args.drop_names, run_once=args.run_once)
        includes = original.includes
    elif len(args.files) == 2:
        original = _tree(args, args.files[0], rules, versions[0])
        compressed = _tree(args, args.files[1], rules, versions[1])
        proof = verify_trees(original, compressed, max_states=args.max_states, run_once=args.run_once)
        includes = (*original.includes, *compressed.includes)
    else:
        raise UsageError("verify takes one BT.CPP tree (compressed here and proved), or an original and a compressed "
                         "tree; each a file, or a folder whose *.xml files are one program")
    inputs = [*_given(args), *includes]
    if args.json:
        emit(json.dumps(proof.as_json(), indent=2) + "\n", args.output, inputs, "JSON")
    else:
        emit(proof.text(), args.output, inputs, "text")
    return proof.exit_status
