"""`schemalog lint` for BT.CPP trees: bt/lint.py's rules over a program read as compress and
verify read it, with the entries the program provides (docs/lint.md, "BT.CPP trees").

    read_provided(paths, profiles=()) -> Provided    --provided FILE..., --profile NAME's entries
    lint_document(document, rules, provided, max_states, once) -> [Finding]   run/lint.py's Finding
    sarif(findings, files) -> dict                   SARIF 2.1.0, for GitHub code scanning
"""

from __future__ import annotations

import re
from pathlib import Path

from .. import defaults
from ..errors import SchemalogError, SourcePos

_ENTRY = re.compile(r"@?[A-Za-z_][A-Za-z0-9_]*")     # a blackboard key BT.CPP's scripts can name too
SECTIONS = ("provides", "reads", "silence")
# the rules a program may silence: what they find is true, but the program may want it so (a tree
# that loops by design, a branch kept for later, an entry written for a logger); an error never is
SILENCEABLE = ("endless-tree", "unreachable", "dead-write")


def entries_path(profile: str) -> Path:
    """The entries file of a shipped profile (bt/profiles/NAME.entries.yaml)."""
    from .behaviour_trees import profile_path

    return profile_path(profile).with_suffix(".entries.yaml")


def read_provided(paths=(), max_bytes: int = defaults.MAX_BYTES, profiles=()):
    """The entries a program provides: each file a YAML mapping with `provides:` (entries the
    program sets before the tree runs) and `reads:` (entries it reads after), each a mapping from
    an entry's name to a note (where the program does it), and `silence:`, the rules (SILENCEABLE)
    whose findings the program wants so, each with a note; a shipped profile's first."""
    from ..bt.lint import Provided
    from ..inputs import compose_yaml, read_utf8

    result = Provided()
    files = [*(entries_path(p) for p in dict.fromkeys(profiles) if entries_path(p).exists()), *map(Path, paths)]
    for path in files:
        name = str(path)
        root, fail = compose_yaml(read_utf8(name, max_bytes), name)
        if root is None or root.tag != "tag:yaml.org,2002:map":
            raise (fail("an entries file is a mapping: `provides:` and `reads:`, each `name: where`", root)
                   if root is not None else
                   SchemalogError("an empty entries file: write `provides:` and `reads:`, each `name: where`",
                                  SourcePos(name, 1, 1)))
        found: dict = {s: {} for s in SECTIONS}
        for key, value in root.value:
            if key.tag != "tag:yaml.org,2002:str" or key.value not in SECTIONS:
                raise fail(f"{key.value!r}: an entries file has `provides:`, `reads:` and `silence:` only", key)
            if value.tag == "tag:yaml.org,2002:null":
                continue
            if value.tag != "tag:yaml.org,2002:map":
                raise fail(f"{key.value}: is a mapping, `name: where` per line", value)
            for entry, note in value.value:
                if key.value == "silence":
                    if entry.tag != "tag:yaml.org,2002:str" or entry.value not in SILENCEABLE:
                        raise fail(f"{entry.value!r}: `silence:` takes the rules a program may want so: "
                                   f"{', '.join(SILENCEABLE)} (an error is never silenced)", entry)
                    found["silence"][entry.value] = f"{name}:{entry.start_mark.line + 1}"
                    continue
                if entry.tag != "tag:yaml.org,2002:str" or not _ENTRY.fullmatch(entry.value):
                    raise fail(f"{entry.value!r} is not a blackboard entry's name (letters, digits and _, "
                               f"not starting with a digit)", entry)
                found[key.value][entry.value.lstrip("@")] = str(note.value or "")
        result = result | Provided(found["provides"], found["reads"], found["silence"])
    return result


def lint_document(document, rules=None, provided=None, *, max_states: int = defaults.MAX_STATES,
                  once: bool = False, checks=None) -> list:
    """Every finding of bt/lint.py's CHECKS on the program, as run/lint.py's Findings: errors and
    warnings first in file order, then infos, then the notes saying what was covered."""
    import inspect
    from dataclasses import replace

    from ..bt.lint import CHECKS, Provided
    from ..run.lint import Finding

    options = {"max_states": max_states, "provided": provided or Provided(), "once": once}
    found = []
    for check in checks or CHECKS:
        # each check takes the options it names: bt/lint_runs.run_findings(document, rules, *, max_states)
        # joins CHECKS as it is
        takes = inspect.signature(check).parameters
        found.extend(check(document, rules, **{k: v for k, v in options.items() if k in takes}))
    given = provided or Provided()
    quiet = [f for f in found if f.code in given.silence and f.severity != "error"]
    found = [f for f in found if not (f.code in given.silence and f.severity != "error")]
    for code, where in given.silence.items():
        count = sum(f.code == code for f in quiet)
        if count:
            found.append(replace(quiet[0], pos=None, severity="note", code=code, hint="",
                                 message=f"{count} {code} finding{'s' if count != 1 else ''} silenced by {where}"))
    order = {"error": 0, "warning": 0, "info": 1, "note": 2}
    found.sort(key=lambda f: (order.get(f.severity, 1), f.pos is None, str(f.pos.file) if f.pos else "",
                              f.pos.line if f.pos else 0, f.pos.column if f.pos else 0))
    return [Finding(f.pos, f.severity, f.code, f.message, f.hint) for f in found]


_LEVELS = {"error": "error", "warning": "warning", "info": "note", "note": "note"}
RULE_TEXT = {
    "read-before-write": "An input port reads a blackboard entry before any node that may write it has ticked",
    "never-written": "A blackboard entry is read and never written nor provided",
    "type-clash": "One blackboard entry is reached by ports of different declared types",
    "dead-write": "A blackboard entry is written and never read",
    "blackboard": "What the blackboard rules covered and assumed",
    "unreachable": "A node no run of the tree ticks",
    "endless": "A root tick that may never return: the executor hangs",
    "endless-tree": "A tree that no run completes (SUCCESS or FAILURE)",
    "halt-safety": "A child left RUNNING while its parent is not",
    "not-decided": "A rule a limit left undecided",
    "load": "The input could not be read",
}


def sarif(findings, version: str = "") -> dict:
    """The findings as a SARIF 2.1.0 log (GitHub code scanning shows each result on its line);
    file paths relative, as code scanning resolves them against the repository's root."""
    import os

    codes = list(dict.fromkeys(f.code for f in findings))
    rules = [{"id": c, "shortDescription": {"text": RULE_TEXT.get(c, c)}} for c in codes]
    results = []
    for f in findings:
        text = f.message + (f" Fix: {f.hint}" if f.hint else "")
        result = {"ruleId": f.code, "ruleIndex": codes.index(f.code), "level": _LEVELS.get(f.severity, "note"),
                  "message": {"text": text}}
        if f.pos is not None and f.pos.file:
            uri = Path(os.path.relpath(f.pos.file)).as_posix() if os.path.isabs(f.pos.file) else \
                Path(f.pos.file).as_posix()
            region = {"startLine": max(1, f.pos.line or 1)}
            if f.pos.column:
                region["startColumn"] = f.pos.column
            result["locations"] = [{"physicalLocation": {"artifactLocation": {"uri": uri}, "region": region}}]
        results.append(result)
    driver = {"name": "schemalog", "rules": rules}
    if version:
        driver["version"] = version
    return {"$schema": "https://json.schemastore.org/sarif-2.1.0.json", "version": "2.1.0",
            "runs": [{"tool": {"driver": driver}, "results": results}]}
