"""`schemalog diff --rev REV PATH...`: each BT.CPP file (or folder) compared with its own version at
git revision REV, the check a pre-commit hook or a pull request's job runs on the trees a change
touches (docs/behaviour_trees.md, "In CI: pre-commit and GitHub Actions").

    run_rev(args, fmt) -> exit status      every PATH against REV; the worst status of them all

REV's side is read from a temporary folder that holds the repository's *.xml files (and every
file under a folder PATH) as they were at REV, laid out as in the repository, so an <include
path="../common/recovery.xml"/> reads REV's file and a folder reads REV's folder. It is written
from `git ls-tree` and `git cat-file` (not `git archive`, which applies export-ignore and
export-subst), and removed on every way out, Ctrl-C and SIGTERM too. Messages and reports name
REV's files as git does, `HEAD:behavior_trees/navigate.xml`, never the temporary folder.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from dataclasses import dataclass, replace
from pathlib import PurePosixPath

from ..errors import SchemalogError, UsageError, readable_name

GIT_TIMEOUT = 120          # seconds for one git command: a repository on a stalled network drive stops
SAME, CHANGED, TROUBLE, UNDECIDED = 0, 1, 2, 3
# The exit status of several PATHs is the worst of theirs, in this order: trouble (a file could not
# be compared, so nothing can be said of the whole, as diff(1) -r has it), then no proof (a limit:
# a change may hide there), then a proved change (the one status a CI label or SKIP acknowledges),
# then the same behaviour. A label that acknowledges a change so never passes an undecided file.
RANK = (TROUBLE, UNDECIDED, CHANGED, SAME)


def worst(statuses) -> int:
    """The exit status of several comparisons (RANK); SAME for none."""
    return min(statuses, key=RANK.index, default=SAME)


@dataclass(frozen=True)
class Outcome:
    """One PATH compared: its report (None for a new file, a skipped one, or trouble), a note."""

    path: str
    status: int
    report: object = None          # api.tree_diff.TreeDiff
    note: str = ""
    documents: tuple = ()          # (A, B) for a picture
    what: str = ""                 # "new" (not at REV), "skipped" (no BT.CPP tree), else ""


def _git(args: list[str], cwd: str, stdin: bytes | None = None) -> subprocess.CompletedProcess:
    """Run git (never a shell) in `cwd`, bounded by GIT_TIMEOUT; a missing git or a timeout is trouble."""
    try:
        return subprocess.run(["git", *args], cwd=cwd, input=stdin, capture_output=True, timeout=GIT_TIMEOUT,
                              check=False)
    except FileNotFoundError:
        raise SchemalogError("--rev reads the old version from git, and git is not installed (or not on PATH)",
                             exit_code=2) from None
    except subprocess.TimeoutExpired:
        raise SchemalogError(f"git {args[0]} in {readable_name(cwd)} took more than {GIT_TIMEOUT} s: stopped",
                             exit_code=2) from None


def _said(done: subprocess.CompletedProcess) -> str:
    return os.fsdecode(done.stderr).strip().splitlines()[-1] if done.stderr.strip() else f"exit {done.returncode}"


def repository(path: str) -> str:
    """The top folder of the git work tree that holds `path` (a file or a folder)."""
    where = path if os.path.isdir(path) else os.path.dirname(path) or "."
    if not os.path.isdir(where):
        raise SchemalogError(f"{readable_name(path)}: no such file", exit_code=2)
    done = _git(["rev-parse", "--show-toplevel"], where)
    if done.returncode != 0:
        raise SchemalogError(f"{readable_name(path)}: not in a git repository (--rev compares a file with its "
                             f"version in git: {_said(done)})", exit_code=2)
    return os.fsdecode(done.stdout).rstrip("\n")


def commit_of(rev: str, top: str) -> str:
    """The commit `rev` names in the repository at `top` (a branch, a tag, HEAD~1, origin/main, a hash)."""
    done = _git(["rev-parse", "--verify", "--quiet", "--end-of-options", f"{rev}^{{commit}}"], top)
    if done.returncode != 0:
        raise SchemalogError(f"--rev {rev}: no such commit in the repository {readable_name(top)} (a shallow "
                             f"clone may lack it: fetch it, e.g. git fetch origin {rev.split('/')[-1]})",
                             exit_code=2)
    return os.fsdecode(done.stdout).strip()


@dataclass(frozen=True)
class Entry:
    mode: str
    kind: str
    sha: str
    size: int
    path: str                       # as in the repository, with /


def tree_entries(commit: str, top: str) -> tuple[Entry, ...]:
    """Every file of `commit` (git ls-tree -r), with its size."""
    done = _git(["ls-tree", "-r", "-z", "-l", "--full-tree", commit], top)
    if done.returncode != 0:
        raise SchemalogError(f"git ls-tree {commit}: {_said(done)}", exit_code=2)
    out = []
    for record in done.stdout.split(b"\0"):
        if not record:
            continue
        head, name = record.split(b"\t", 1)
        mode, kind, sha, size = head.decode().split()
        out.append(Entry(mode, kind, sha, 0 if size == "-" else int(size), os.fsdecode(name)))
    return tuple(out)


def _wanted(entry: Entry, paths: tuple[str, ...]) -> bool:
    # <include path="x.xml"/> may reach any *.xml of the repository; a folder PATH reads its own files
    return entry.kind == "blob" and (entry.path.endswith(".xml") or any(
        entry.path == p or entry.path.startswith(p + "/") for p in paths))


def materialise(commit: str, top: str, paths: tuple[str, ...], into: str, max_bytes: int) -> None:
    """Write into `into` the files of `commit` that the PATHs (repository-relative) may read at it."""
    entries = [e for e in tree_entries(commit, top) if _wanted(e, paths)]
    total = sum(e.size for e in entries)
    if total > 8 * max_bytes:
        raise SchemalogError(f"the repository's *.xml files at {commit[:12]} add up to {total:,} bytes, more than "
                             f"8 x --max-bytes ({8 * max_bytes:,}): raise --max-bytes to compare against them",
                             exit_code=2)
    if not entries:
        return
    done = _git(["cat-file", "--batch"], top, "".join(f"{e.sha}\n" for e in entries).encode())
    if done.returncode != 0:
        raise SchemalogError(f"git cat-file: {_said(done)}", exit_code=2)
    data, at = done.stdout, 0
    for e in entries:
        header_end = data.index(b"\n", at)
        size = int(data[at:header_end].split()[2])
        body = data[header_end + 1:header_end + 1 + size]
        at = header_end + 1 + size + 1
        target = os.path.join(into, *PurePosixPath(e.path).parts)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        if e.mode == "120000":
            # a symlink in the repository: kept when it points inside it (the file it names is
            # then written too, if it is one the PATHs may read), else left out
            link = os.fsdecode(body)
            if not os.path.isabs(link) and not os.path.normpath(
                    os.path.join(os.path.dirname(e.path), link)).startswith(".."):
                os.symlink(link, target)
            continue
        with open(target, "wb") as out:
            out.write(body)


def _inside(path: str, top: str) -> str | None:
    """`path` relative to the repository's top, with /; None when it is outside."""
    rel = os.path.relpath(os.path.realpath(path), os.path.realpath(top))
    return None if rel == ".." or rel.startswith(".." + os.sep) else PurePosixPath(*rel.split(os.sep)).as_posix()


def relabel(document, folder: str, rev: str):
    """The document read from `folder` (REV's files), each node's file named REV:path as git names it."""
    prefix = os.path.join(folder, "")

    def name(file: str) -> str:
        return f"{rev}:{PurePosixPath(*file[len(prefix):].split(os.sep))}" if file.startswith(prefix) else file

    def node(n):
        return replace(n, file=name(n.file), children=tuple(node(c) for c in n.children))

    return replace(document, trees=tuple((key, node(root)) for key, root in document.trees),
                   includes=tuple(name(f) for f in document.includes))


def _relabelled_error(err: SchemalogError, folder: str, rev: str) -> SchemalogError:
    prefix = os.path.join(folder, "")
    pos = err.pos
    if pos is not None and pos.file.startswith(prefix):
        pos = replace(pos, file=f"{rev}:{PurePosixPath(*pos.file[len(prefix):].split(os.sep))}")
    message = err.message.replace(prefix, f"{rev}:").replace(folder, f"{rev}:.")
    return SchemalogError(message, pos, err.source_line, err.exit_code)


def _root_element(path: str, max_bytes: int):
    """The root element of an XML file (defusedxml), or None when it is not well-formed XML."""
    from defusedxml import ElementTree

    try:
        with open(path, "rb") as f:
            return ElementTree.fromstring(f.read(max_bytes + 1))
    except Exception:          # not XML, too big, unreadable: reading it as a tree says what is wrong
        return None


def not_a_tree(paths: tuple[str, ...], max_bytes: int) -> str | None:
    """Why the XML files `paths` (a PATH now and at REV) are no BT.CPP trees, or None when one may be.
    pre-commit's `files: \\.xml$` hands the hook every XML file a commit touches: package.xml,
    URDF, launch files (none has BT.CPP's <root>), and Nav2's nav2_tree_nodes.xml (a <root> with a
    <TreeNodesModel> and no <BehaviorTree>, nor an <include> of one)."""
    roots = [_root_element(p, max_bytes) for p in paths if os.path.isfile(p)]
    if not roots or any(r is None for r in roots):
        return None
    if all(r.tag != "root" for r in roots):
        tags = sorted({r.tag for r in roots})
        return f"not a BT.CPP tree (its root element is <{'>, <'.join(tags)}>; BT.CPP's is <root>): skipped"
    if all(r.tag == "root" and r.find("BehaviorTree") is None and r.find("include") is None for r in roots):
        return "no <BehaviorTree> nor <include> in it (a nodes file, as nav2_tree_nodes.xml): skipped"
    return None


def _compare(path: str, rel: str, old_root: str, rev: str, args, rules, under) -> Outcome:
    """One PATH against its version under `old_root` (REV's files)."""
    from ..api.behaviour_trees import read_tree
    from ..api.tree_diff import diff_trees

    old = os.path.join(old_root, *PurePosixPath(rel).parts)
    if not os.path.lexists(path):
        if not os.path.lexists(old):           # a typo must not pass a CI job as "new"
            raise SchemalogError(f"{readable_name(path)}: no such file, now nor at {rev}")
        return Outcome(path, CHANGED, note=f"{readable_name(path)}: deleted since {rev}: the program lost its trees",
                       what="deleted")
    if not os.path.lexists(old):
        return Outcome(path, SAME, note=f"{readable_name(path)}: new file since {rev}: nothing to compare", what="new")
    if not os.path.isdir(path):
        skip = not_a_tree((old, path), args.max_bytes)
        if skip:
            return Outcome(path, SAME, note=f"{readable_name(path)}: {skip}", what="skipped")
    try:
        a = relabel(read_tree(old, args.nodes, args.max_bytes, args.task), old_root, rev)
    except SchemalogError as err:
        raise _relabelled_error(err, old_root, rev) from None
    b = read_tree(path, args.nodes, args.max_bytes, args.task)
    report = diff_trees(a, b, args.max_states, rules, run_once=args.run_once, a_name=f"{rev}:{rel}",
                        b_name=readable_name(path), under=under)
    return Outcome(path, report.exit_status, report, documents=(a, b))


def compare_all(args, rules, under, say) -> list[Outcome]:
    """Every PATH against REV, one temporary folder per repository, removed on every way out;
    `say(text)` reports a PATH that could not be compared, as it happens."""
    groups: dict[str, list[str]] = {}
    outcomes: dict[int, Outcome] = {}
    for k, path in enumerate(args.files):
        try:
            groups.setdefault(repository(path), []).append(k)
        except SchemalogError as err:
            say(str(err))
            outcomes[k] = Outcome(path, TROUBLE, note=str(err))
    for top, indices in groups.items():
        commit = commit_of(args.rev, top)          # an unknown REV stops the whole run: exit 2
        rels = {}
        for k in indices:
            rel = _inside(args.files[k], top)
            if rel is None:
                said = f"error: {readable_name(args.files[k])}: outside the repository {readable_name(top)}"
                say(said)
                outcomes[k] = Outcome(args.files[k], TROUBLE, note=said)
            else:
                rels[k] = rel
        with tempfile.TemporaryDirectory(prefix="schemalog-rev-") as old_root:
            materialise(commit, top, tuple(rels.values()), old_root, args.max_bytes)
            for k, rel in rels.items():
                try:
                    outcomes[k] = _compare(args.files[k], rel, old_root, args.rev, args, rules, under)
                except SchemalogError as err:
                    say(str(err))
                    outcomes[k] = Outcome(args.files[k], TROUBLE, note=str(err))
    return [outcomes[k] for k in range(len(args.files))]


def _json(outcomes: list[Outcome], rev: str) -> dict:
    status = {SAME: "same", CHANGED: "changed", TROUBLE: "error", UNDECIDED: "undecided"}
    return {"rev": rev, "exit": worst(o.status for o in outcomes), "files": [
        {"path": o.path, "status": o.what or status[o.status],
         "note": o.note or None, "report": o.report.as_json() if o.report is not None else None}
        for o in outcomes]}


def run_rev(args: argparse.Namespace, fmt: str) -> int:
    """`schemalog diff --rev REV PATH...`: each PATH against its version at REV; the worst status."""
    import json

    from .common import check_output, emit
    from .trees import _given, _rules, _with_profiles

    if args.rev.startswith("-"):
        raise UsageError(f"--rev {args.rev}: a revision does not start with '-'")
    if fmt in ("dot", "png", "svg", "pdf") and len(args.files) != 1:
        raise UsageError(f"a {fmt} picture shows one comparison: give one PATH with --rev, or --format markdown")
    check_output(args.output, _given(args))
    outcomes = compare_all(args, _rules(args), _with_profiles(args), lambda text: print(text, file=sys.stderr))
    shown = [o for o in outcomes if o.report is not None or o.note]
    inputs = [*_given(args), *(f for o in outcomes for f in (o.documents[1].includes if o.documents else ()))]
    if fmt == "json":
        emit(json.dumps(_json(outcomes, args.rev), indent=2) + "\n", args.output, inputs, "JSON")
    elif fmt == "markdown":
        parts = [o.report.markdown() if o.report is not None else f"{_md_note(o.note)}\n" for o in shown]
        if len(outcomes) > 1 or not parts:
            parts.insert(0, f"## {_md_note(_summary(outcomes, args.rev))}\n")
        emit("\n".join(p if p.endswith("\n") else p + "\n" for p in parts), args.output, inputs, "Markdown")
    elif fmt in ("dot", "png", "svg", "pdf"):
        (o,) = outcomes
        if o.report is None:
            if o.note:
                print(o.note, file=sys.stderr)
        elif fmt == "dot":
            emit(o.report.dot(*o.documents), args.output, inputs, "DOT")
        else:
            from ..formats.graphviz import write_image

            write_image(args.output, o.report.dot(*o.documents), fmt)
            article = "an" if fmt == "svg" else "a"
            print(f"wrote {readable_name(args.output)}: {article} {fmt.upper()} picture; {o.report.headline()}",
                  file=sys.stderr)
    else:
        parts = [o.report.text() if o.report is not None else f"{o.note}\n" for o in shown]
        if len(outcomes) > 1 or not parts:
            parts.insert(0, _summary(outcomes, args.rev) + "\n")
        emit("\n".join(parts), args.output, inputs, "text")
    return worst(o.status for o in outcomes)


def _summary(outcomes: list, rev: str) -> str:
    """One line over several PATHs: how many changed, are the same, failed, against REV."""
    names = {CHANGED: "changed", SAME: "same", TROUBLE: "could not be compared", UNDECIDED: "not decided"}
    kinds = [o.what or names[o.status] for o in outcomes]
    counts = [f"{kinds.count(k)} {k}" for k in dict.fromkeys(
        ["changed", "deleted", "same", "new", "skipped", "not decided", "could not be compared"]) if k in kinds]
    return f"schemalog diff against {rev}: {len(outcomes)} path{'s' if len(outcomes) != 1 else ''}: {', '.join(counts)}"


def _md_note(note: str) -> str:
    from ..api.tree_diff import _md

    return _md(note)
