"""BT.CPP trees from Python: read, compress and prove them as `schemalog compress F.xml` and
`schemalog verify A.xml [B.xml]` do (docs/api.md, "Behaviour trees").

    read_tree(paths, nodes=, semantics=, profile=, main=) -> TreeDocument     the tree as a program's
                                                             factory builds it: files, models, node semantics
    compress_tree(tree)                                   -> TreeCompression  the rewrites, proved
    verify_trees(original, compressed=None)               -> TreeProof        `schemalog verify A.xml [B.xml]`

Each result carries the fields of its command's `--json`, `.as_json()` (that JSON as data: the
command prints `json.dumps(result.as_json(), indent=2)`), `.text()` (what the command prints)
and `.exit_status`; cli/trees.py prints these. The work is api/behaviour_trees.py's (its
TreeCompression is the bare rewrites and verdict this module's TreeCompression reports on).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable

from .. import defaults
from ..errors import UsageError, readable_name
from .arguments import Count, Paths, Seconds, Size, checked
from .limits import DEFAULT, within

PROVED, REFUTED, INCONCLUSIVE = 0, 1, 3
NOTHING_PROVED = "nothing to compress, so nothing was proved (the tree is its own compression)"


@dataclass(frozen=True, eq=False)
class TreeDocument:
    """A BT.CPP program as read: the files or folders given (their <include>s read with them), the
    nodes files whose models it was read with, the semantics files and profiles its custom node types
    are proved under, the main tree chosen, the BT.CPP version asked for (None: as the files tell;
    `document.version` is the one read); `notes` what reading had to say."""

    files: tuple[str, ...]
    document: Any = field(repr=False)                 # bt/model.py's Document
    nodes: tuple[str, ...] = ()
    semantics: tuple[str, ...] = ()
    profiles: tuple[str, ...] = ()
    main: str | None = None
    notes: tuple[str, ...] = ()
    max_bytes: int = field(default=defaults.MAX_BYTES, repr=False)
    version: int | None = None                       # 3 or 4 as asked (--btcpp); None: as the files tell

    @property
    def name(self) -> str:
        """The ID of the tree that runs (main_tree_to_execute, or `main`)."""
        return self.document.main

    @property
    def includes(self) -> tuple[str, ...]:
        """The files read through <include>, in order."""
        return self.document.includes

    @property
    def rules(self) -> dict | None:
        """The node semantics its custom types follow (None: BT.CPP's own types only), read
        from `semantics` and `profiles` again after unpickling (rules hold functions)."""
        if "_rules" not in self.__dict__:
            object.__setattr__(self, "_rules", _rules(self.semantics, self.profiles, self.max_bytes, []))
        return self.__dict__["_rules"]

    def __len__(self) -> int:
        """The number of nodes in all its trees."""
        from ..bt.model import size

        return size(self.document)

    def xml(self) -> str:
        """The document as BT.CPP 4 XML with a TreeNodesModel, what `schemalog compress -o F.xml`
        writes (read back with its nodes files before it is given out)."""
        from .behaviour_trees import read_models, tree_xml

        return tree_xml(self.document, read_models(self.nodes, self.max_bytes))

    def __getstate__(self) -> dict:
        return {key: value for key, value in self.__dict__.items() if key != "_rules"}

    def __repr__(self) -> str:
        shown = ", ".join(map(readable_name, self.files)) or "a compressed tree"
        return f"<TreeDocument {shown}: main tree {self.name}, {len(self)} nodes>"


def _rules(semantics: tuple, profiles: tuple, max_bytes: int, notes: list) -> dict | None:
    from .behaviour_trees import read_semantics

    if not semantics and not profiles:
        return None
    return read_semantics(semantics, max_bytes, profiles=profiles, notes=notes)


def _profile_names(profile: str | Iterable[str], where: str) -> tuple[str, ...]:
    from .behaviour_trees import PROFILES

    names = tuple(dict.fromkeys((profile,) if isinstance(profile, str) else profile))
    for name in names:
        if name not in PROFILES:
            raise UsageError(f"{where}: unknown profile {name!r}; the profiles schemalog ships: {', '.join(PROFILES)}")
    return names


def document_of(files, document, nodes=(), semantics=(), profiles=(), main: str | None = None, rules=None,
                notes=(), max_bytes: int = defaults.MAX_BYTES, version: int | None = None) -> TreeDocument:
    """A TreeDocument of a document read already (cli/trees.py reads its arguments itself),
    with the rules read from `semantics` and `profiles`."""
    tree = TreeDocument(tuple(files), document, tuple(nodes), tuple(semantics), tuple(dict.fromkeys(profiles)),
                        main, tuple(notes), max_bytes, version)
    object.__setattr__(tree, "_rules", rules)
    return tree


@checked
def read_tree(paths: Paths, *, nodes: Paths = (), semantics: Paths = (), profile: str | Iterable[str] = (),
              main: str | None = None, version: int | None = None,
              max_bytes: Count = defaults.MAX_BYTES) -> TreeDocument:
    """Read a BT.CPP program as `schemalog verify` does: `paths` a file, or several files and
    folders read as one program; `nodes` TreeNodesModel files (Nav2's nav2_tree_nodes.xml),
    `semantics` YAML files giving custom node types a known type's rule and `profile` the shipped
    ones (`"nav2"`), read first; `main` the tree to run (BT.CPP's createTree(main)), else the main
    file's main_tree_to_execute; `version` 3 (BT.CPP 3.8) or 4 for every file, as `--btcpp`
    (default: as each file's BTCPP_format tells)."""
    from .behaviour_trees import read_tree as read_document

    profiles = _profile_names(profile, "read_tree()")
    if not paths:
        raise UsageError("read_tree(): paths is empty; pass a BT.CPP file or folder")
    if version not in (None, 3, 4):
        raise UsageError(f"read_tree(): version {version!r}: 3 (BT.CPP 3.8), 4 or None (as the files tell)")
    notes: list[str] = []
    rules = _rules(semantics, profiles, max_bytes, notes)      # its mistakes first, as the command line's
    document = read_document(paths, nodes, max_bytes, main, version=version, notes=notes)
    return document_of([str(p) for p in paths], document, [str(n) for n in nodes], [str(s) for s in semantics],
                       profiles, main, rules, notes, max_bytes, version)


def _count(n: int, word: str) -> str:
    return f"{n:,} {word}{'' if n == 1 else 's'}"


def _with_profiles(profiles: tuple[str, ...]) -> str:
    """How a verdict names the profiles it was proved under: '' or ' with the nav2 profile'."""
    if not profiles:
        return ""
    return f" with the {' and '.join(profiles)} profile{'s' if len(profiles) > 1 else ''}"


def _rewrite_json(rewrite) -> dict:
    return {"rule": rewrite.rule, "type": rewrite.type, "name": rewrite.name, "file": rewrite.file,
            "line": rewrite.line, "column": rewrite.column}


def kept_words(kept) -> str:
    """The named nodes a rewrite would have removed and compress kept, in one line ("" for none)."""
    if not kept:
        return ""
    one = len(kept) == 1
    return (f"kept {_count(len(kept), 'named node')} a rewrite would remove (--drop-names removes "
            f"{'it' if one else 'them'}): {', '.join(k.node for k in kept)}")


def _status(verdict) -> int:
    if verdict is None or verdict.equal and verdict.complete:
        return PROVED
    return INCONCLUSIVE if verdict.equal else REFUTED


def _verdict_words(verdict, under: str = "") -> str:
    if verdict.equal and verdict.complete:
        covers = f"; it {verdict.assumed}" if verdict.assumed else ""
        return (f"proved equal to the original under {verdict.under or 'BT.CPP 4'} semantics{under}: "
                f"{verdict.reason}{covers}")
    if verdict.equal:
        return f"NOT proved: {verdict.reason}"
    return f"REFUTED: {verdict.reason}"


@dataclass(frozen=True)
class TreeCompression:
    """A BT.CPP program compressed and the result proved, as `schemalog compress F.xml --json` gives
    it: its files, the nodes before and after, the rewrites made (bt/compress.py's Rewrite: rule, type, name,
    file, line, column), the named nodes kept that a rewrite would have removed, and the proof.
    Nothing rewritten is the tree itself, `proved` then True and `reason` "nothing rewritten";
    `equal` False is a rewrite the prover refutes, a bug of schemalog's."""

    files: tuple[str, ...]
    nodes_before: int
    nodes_after: int
    rewrites: tuple
    kept_names: tuple
    equal: bool
    complete: bool
    proved: bool
    states: int
    reason: str
    covers: str
    profiles: tuple[str, ...] = ()
    original: TreeDocument | None = field(default=None, repr=False, compare=False)
    compressed: TreeDocument | None = field(default=None, repr=False, compare=False)
    verdict: Any = field(default=None, repr=False, compare=False)      # bt/prove.py's Verdict; None: nothing rewritten

    @property
    def file(self) -> str:
        """The first file or folder of the program."""
        return self.files[0]

    @property
    def exit_status(self) -> int:
        """`schemalog compress`'s: 0 proved (or nothing rewritten), 1 refuted, 3 no proof (a limit)."""
        return _status(self.verdict)

    @property
    def summary(self) -> str:
        """The first line `schemalog compress` prints: the sizes and the verdict, or why nothing."""
        shown = ", ".join(map(readable_name, self.files))
        if not self.rewrites and self.kept_names:
            return (f"{shown}: nothing to compress ({_count(self.nodes_before, 'node')}): every rewrite of "
                    f"bt/compress.py that applies would remove a named node")
        if not self.rewrites:
            return (f"{shown}: nothing to compress ({_count(self.nodes_before, 'node')}): no rewrite of "
                    f"bt/compress.py applies (a composite inside one of its own type, a single-child Sequence or "
                    f"Fallback, a double Inverter or Force, each without a pre-condition that its removal would "
                    f"change), or each that does is refuted where it stands and undone")
        return (f"{shown}: {_count(self.nodes_after, 'node')} from {self.nodes_before} "
                f"({_count(len(self.rewrites), 'rewrite')}), "
                f"{_verdict_words(self.verdict, _with_profiles(self.profiles))}")

    def text(self) -> str:
        """What `schemalog compress F.xml` prints: the summary, a line per rewrite, the names kept."""
        kept = kept_words(self.kept_names)
        return self.summary + "\n" + "".join(f"  {r}\n" for r in self.rewrites) + (f"{kept}\n" if kept else "")

    def as_json(self) -> dict:
        """What `schemalog compress F.xml --json` prints."""
        return {"file": self.file, "files": list(self.files), "nodes_before": self.nodes_before,
                "nodes_after": self.nodes_after,
                "rewrites": [_rewrite_json(r) for r in self.rewrites],
                "kept_names": [_rewrite_json(k) for k in self.kept_names],
                "proved": self.proved, "complete": self.complete, "states": self.states, "reason": self.reason,
                "covers": self.covers}

    def xml(self) -> str:
        """The compressed tree as BT.CPP 4 XML, what `schemalog compress F.xml -o SMALL.xml` writes."""
        return self.compressed.xml()


@dataclass(frozen=True)
class TreeProof:
    """Two BT.CPP trees proved equal under BT.CPP 4 semantics, or refuted, or neither (a limit),
    as `schemalog verify A.xml B.xml --json` gives it; of one tree (`verify F.xml`), its
    compression proved against it, with `kept_names` and `compression`. `counterexample`: the
    runs of both trees root tick by root tick, as the command prints them (None without one).
    `proved` only when `equal` was shown for every run (`complete`): a limit, or one tree with
    nothing to compress (nothing was checked), is no proof."""

    files: tuple[str, ...]
    profiles: tuple[str, ...]
    btcpp: str                                 # the versions it was proved under: "BT.CPP 4", "BT.CPP 3.8", ...
    equal: bool
    complete: bool
    proved: bool
    states: int
    reason: str
    covers: str
    counterexample: tuple[str, ...] | None = None
    kept_names: tuple | None = None            # one tree compressed here: its named nodes kept; else None
    compression: TreeCompression | None = field(default=None, repr=False, compare=False)
    verdict: Any = field(default=None, repr=False, compare=False)      # bt/prove.py's Verdict

    @property
    def exit_status(self) -> int:
        """`schemalog verify`'s: 0 proved, 1 refuted, 3 no proof."""
        return PROVED if self.proved else INCONCLUSIVE if self.equal else REFUTED

    def text(self) -> str:
        """What `schemalog verify` prints: the verdict, and a counterexample tick by tick."""
        from .behaviour_trees import verdict_text

        kept = kept_words(self.kept_names)
        kept = f"{kept}\n" if kept else ""
        if self.verdict is None:
            return f"{readable_name(self.files[0])}: {self.reason}\n" + kept
        with_ = _with_profiles(self.profiles)
        if self.verdict.under:
            under = f" under {self.verdict.under} semantics{with_}"
        else:       # BT.CPP 4 alone, without a profile: the wording as it always was
            under = f" under BT.CPP 4 semantics{with_}" if with_ else ""
        return verdict_text(self.verdict, under) + kept

    def as_json(self) -> dict:
        """What `schemalog verify --json` prints."""
        kept = {} if self.kept_names is None else {"kept_names": [_rewrite_json(k) for k in self.kept_names]}
        if self.verdict is None:
            return {"files": list(self.files), "equal": self.equal, "complete": self.complete, "proved": self.proved,
                    "states": self.states, "reason": self.reason, "counterexample": None, **kept}
        return {"files": list(self.files), "profiles": list(self.profiles), "btcpp": self.btcpp, "equal": self.equal,
                "complete": self.complete, "proved": self.proved, "states": self.states, "reason": self.reason,
                "covers": self.covers, "counterexample": None if self.counterexample is None
                else list(self.counterexample), **kept}


def _proof(verdict, files, profiles, kept=None, compression=None) -> TreeProof:
    from .behaviour_trees import verdict_text

    if verdict is None:        # one tree, nothing rewritten: a check that covers nothing is no proof
        return TreeProof(tuple(files), tuple(profiles), "", True, True, False, 0, NOTHING_PROVED, "", None,
                         kept, compression, None)
    cex = None if verdict.counterexample is None else tuple(verdict_text(verdict).splitlines()[1:])
    return TreeProof(tuple(files), tuple(profiles), verdict.under or "BT.CPP 4", verdict.equal, verdict.complete,
                     verdict.equal and verdict.complete, verdict.states, verdict.reason, verdict.assumed, cex,
                     kept, compression, verdict)


def _tree(given, reading: dict, where: str, what: str) -> TreeDocument:
    """A TreeDocument as given, or the file(s) given read with the reading keywords."""
    if isinstance(given, TreeDocument):
        named = [key for key, value in reading.items() if value not in ((), None, defaults.MAX_BYTES)]
        if named:
            raise UsageError(f"{where}: {what} is a TreeDocument, read already; {', '.join(named)} "
                             f"{'apply' if len(named) > 1 else 'applies'} to reading a file: pass them to "
                             f"schemalog.read_tree")
        return given
    return read_tree(given, **reading)


@checked
def compress_tree(tree: TreeDocument | Paths, *, drop_names: bool = False, run_once: bool = False,
                  max_states: Count = defaults.MAX_STATES, nodes: Paths = (), semantics: Paths = (),
                  profile: str | Iterable[str] = (), main: str | None = None, version: int | None = None,
                  max_bytes: Count = defaults.MAX_BYTES,
                  timeout: Seconds | None = None, max_memory: Size | None = DEFAULT) -> TreeCompression:
    """Compress a tree (a TreeDocument, or files read with `nodes`, `semantics`, `profile`,
    `main`, `version` as read_tree reads them) with bt/compress.py's rewrites, each kept only where the
    prover does not refute it, and prove the result against it, as `schemalog compress F.xml`.
    A node with a name= attribute is never removed unless `drop_names`; `run_once`: for trees
    ticked until they finish, once, and never halted (by default also halted between any two
    ticks and ticked anew, as an executor may); `max_states` bounds the proof (past it: no proof)."""
    with within(timeout, max_memory):
        original = _tree(tree, dict(nodes=nodes, semantics=semantics, profile=profile, main=main, version=version,
                                    max_bytes=max_bytes), "compress_tree()", "tree")
        return _compressed(original, drop_names, run_once, max_states)


def _compressed(original: TreeDocument, drop_names: bool, run_once: bool, max_states: int) -> TreeCompression:
    from .behaviour_trees import compress_tree as compress

    result = compress(original.document, max_states, original.rules, drop_names=drop_names, run_once=run_once)
    verdict = result.verdict
    compressed = document_of((), result.compressed, original.nodes, original.semantics, original.profiles,
                             original.main, original.rules, (), original.max_bytes)
    return TreeCompression(
        original.files, result.nodes_before, result.nodes_after, tuple(result.rewrites), tuple(result.kept),
        verdict is None or verdict.equal, verdict is None or verdict.complete, _status(verdict) == PROVED,
        verdict.states if verdict else 0, verdict.reason if verdict else "nothing rewritten",
        verdict.assumed if verdict else "", original.profiles, original, compressed, verdict)


@checked
def verify_trees(original: TreeDocument | Paths, compressed: TreeDocument | Paths | None = None, *,
                 drop_names: bool = False, run_once: bool = False, max_states: Count = defaults.MAX_STATES,
                 nodes: Paths = (), semantics: Paths = (), profile: str | Iterable[str] = (),
                 main: str | None = None, version: int | None = None, max_bytes: Count = defaults.MAX_BYTES,
                 timeout: Seconds | None = None,
                 max_memory: Size | None = DEFAULT) -> TreeProof:
    """Prove two trees equal under BT.CPP 4 semantics, or refute them with a counterexample root tick
    by root tick, as `schemalog verify A.xml B.xml`; with `compressed` None, compress `original` and
    prove the result against it, as `schemalog verify F.xml` (`drop_names` applies there only).
    Each tree is a TreeDocument or files read with `nodes`, `semantics`, `profile`, `main`,
    `version` (as read_tree; two trees under two versions: read each with its own); two
    TreeDocuments must be read under the same semantics and profiles, which the proof uses. An
    unmarked file is proved under the version the other tells, or under both (as `schemalog
    verify`). `run_once` and `max_states` as compress_tree."""
    from .behaviour_trees import prove_trees

    reading = dict(nodes=nodes, semantics=semantics, profile=profile, main=main, version=version, max_bytes=max_bytes)
    if compressed is None:
        with within(timeout, max_memory):
            tree = _tree(original, reading, "verify_trees()", "original")
            compression = _compressed(tree, drop_names, run_once, max_states)
        return _proof(compression.verdict, tree.files, tree.profiles, compression.kept_names, compression)
    if drop_names:
        raise UsageError("verify_trees(): drop_names applies when verify_trees compresses one tree (compressed "
                         "None); given an original and a compressed tree, nothing is compressed")
    with within(timeout, max_memory):
        a = _tree(original, reading, "verify_trees()", "original")
        b = _tree(compressed, reading, "verify_trees()", "compressed")
        if (a.semantics, a.profiles) != (b.semantics, b.profiles):
            raise UsageError(f"verify_trees(): the trees were read under different node semantics (semantics "
                             f"{list(a.semantics)} and profiles {list(a.profiles)}, and {list(b.semantics)} and "
                             f"{list(b.profiles)}): a proof takes one; read both with the same")
        verdict = prove_trees(a.document, b.document, max_states, a.rules, run_once=run_once)
    return _proof(verdict, (*a.files, *b.files), a.profiles)
