"""Record SWI-Prolog's answers to the conformance queries into expected.json.

    python tests/conformance/record.py            # rewrite expected.json
    python tests/conformance/record.py --check    # exit 1 if expected.json is stale

Every query in queries/<program>.txt (one a line; blank lines and lines starting
with `#` are skipped) is run against programs/<program>.pl by driver.pl: one
`swipl` per program loads it once and runs each query inside snapshot/1, so that
assert/retract in one query cannot leak into another. A case's id is
`<program>-<NN>`, NN its 1-based position among the file's queries.

Each case records:
    answers : the canonical text of each answer, `[X=...,Y=...]`, at most CAP
    end     : "true" | "limit" | "timeout" | "syntax_error" | "exception:<ball>"
    output  : what the query wrote to standard output

The canonical form is the one driver.pl documents (no operators, lists as lists,
writeq atoms, variables _A, _B... in order of appearance); tests/conformance/test_conformance.py
prints schemalog's answers the same way.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
PROGRAMS = HERE / "programs"
QUERIES = HERE / "queries"
DRIVER = HERE / "driver.pl"
EXPECTED = HERE / "expected.json"

CAP = 20            # answers recorded per query; infinite generators stop here ("limit")
TIME_LIMIT = 10     # seconds of CPU per query in swipl (call_with_time_limit)
PROCESS_TIMEOUT = 60


@dataclass(frozen=True)
class Case:
    id: str
    program: str   # file name under programs/
    query: str


def load_cases() -> list[Case]:
    """Every query of every program, in file order."""
    cases = []
    for qfile in sorted(QUERIES.glob("*.txt")):
        program = qfile.stem + ".pl"
        if not (PROGRAMS / program).exists():
            raise FileNotFoundError(f"{qfile}: no program {PROGRAMS / program}")
        queries = [line.strip() for line in qfile.read_text(encoding="utf-8").splitlines()]
        queries = [q for q in queries if q and not q.startswith("#")]
        for i, query in enumerate(queries, 1):
            cases.append(Case(f"{qfile.stem}-{i:02d}", program, query))
    return cases


def swipl_path() -> str | None:
    return shutil.which("swipl")


def swipl_version(swipl: str) -> str:
    out = subprocess.run([swipl, "--version"], capture_output=True, text=True, check=True)
    return out.stdout.strip()


def run_program(program: str, cases: list[Case], swipl: str) -> list[dict]:
    """Run the cases of one program in one swipl (driver.pl runs each query inside snapshot/1)."""
    with tempfile.TemporaryDirectory(prefix="conformance-") as tmp:
        work = Path(tmp)
        (work / "queries.txt").write_text("".join(c.query + "\n" for c in cases), encoding="utf-8")
        proc = subprocess.run(
            [swipl, "-q", "-g", "cf_driver:batch", "-t", "halt", str(DRIVER), "--",
             str(PROGRAMS / program), str(work), str(CAP), str(TIME_LIMIT)],
            stdin=subprocess.DEVNULL, capture_output=True, timeout=PROCESS_TIMEOUT * len(cases),
            cwd=tmp, env={**os.environ, "LANG": "C.UTF-8", "LC_ALL": "C.UTF-8"})
        records = []
        for n, case in enumerate(cases, 1):
            res, out = work / f"{n}.res", work / f"{n}.out"
            lines = res.read_text(encoding="utf-8").splitlines() if res.exists() else []
            answers, end = [], None
            for line in lines:
                tag, _, text = line.partition("\t")
                if tag == "A":
                    answers.append(text)
                elif tag == "E":
                    end = text
            if end is None:
                raise RuntimeError(f"{case.id}: driver did not finish {case.query!r} (exit "
                                   f"{proc.returncode}):\n{proc.stderr.decode('utf-8', 'replace')[-2000:]}")
            output = out.read_text(encoding="utf-8") if out.exists() else ""
            records.append({"program": case.program, "query": case.query, "answers": answers,
                            "end": end, "output": output})
    return records


def record(swipl: str, cases: list[Case] | None = None, jobs: int | None = None) -> dict:
    """Run every case; return the expected.json document."""
    cases = load_cases() if cases is None else cases
    by_program: dict[str, list[Case]] = {}
    for case in cases:
        by_program.setdefault(case.program, []).append(case)
    jobs = jobs or (os.cpu_count() or 1)
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        results = pool.map(lambda item: run_program(item[0], item[1], swipl), by_program.items())
        records = {c.id: r for group, recs in zip(by_program.values(), results)
                   for c, r in zip(group, recs)}
    return {
        "swipl": swipl_version(swipl),
        "cap": CAP,
        "cases": {case.id: records[case.id] for case in cases},
    }


def dump(doc: dict) -> str:
    return json.dumps(doc, indent=1, ensure_ascii=False, sort_keys=False) + "\n"


def main(argv: list[str]) -> int:
    swipl = swipl_path()
    if swipl is None:
        print("record.py: swipl is not on PATH", file=sys.stderr)
        return 2
    start = time.perf_counter()
    doc = record(swipl)
    elapsed = time.perf_counter() - start
    text = dump(doc)
    n = len(doc["cases"])
    programs = len({c["program"] for c in doc["cases"].values()})
    if "--check" in argv:
        current = EXPECTED.read_text(encoding="utf-8") if EXPECTED.exists() else ""
        stale = json.loads(current or "{}").get("cases") != doc["cases"]
        print(f"{n} queries over {programs} programs recorded in {elapsed:.1f}s: "
              f"expected.json is {'STALE' if stale else 'current'}")
        return 1 if stale else 0
    EXPECTED.write_text(text, encoding="utf-8")
    print(f"{n} queries over {programs} programs recorded in {elapsed:.1f}s -> {EXPECTED}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
