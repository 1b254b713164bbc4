"""The start-up cache: used only where it is safe, rebuilt when stale or torn, and never
changing an answer, whatever the process's hash seed."""

import os
import subprocess
import sys
from pathlib import Path

from schemalog import cache
from schemalog.logic.kb import KnowledgeBase, _prelude
from schemalog.logic.fastread import parse_text
from schemalog.logic.terms import TRUE, Struct, Var, iter_vars
from schemalog.logic.unify import variant

from conftest import ROOT


def test_remembered_builds_once_then_loads(tmp_path, monkeypatch):
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(tmp_path / "c"))
    calls = []

    def build():
        calls.append(1)
        return {"answer": 42}

    assert cache.remembered("t", ["source"], build) == {"answer": 42}
    assert cache.remembered("t", ["source"], build) == {"answer": 42}
    assert len(calls) == 1
    assert cache.remembered("t", ["changed source"], build) == {"answer": 42}
    assert len(calls) == 2                                  # another source: another entry
    assert oct((tmp_path / "c").stat().st_mode & 0o777) == "0o700"


def test_a_torn_entry_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(tmp_path))
    cache.remembered("t", ["s"], lambda: [1, 2, 3])
    (entry,) = tmp_path.glob("t-*.pickle")
    entry.write_bytes(entry.read_bytes()[:5])
    assert cache.remembered("t", ["s"], lambda: [4]) == [4]
    assert cache.remembered("t", ["s"], lambda: [5]) == [4]   # and written again, whole


def test_an_entry_is_named_by_its_sources_and_replaces_other_versions(tmp_path, monkeypatch):
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(tmp_path))
    one = cache.cache_file("grammar-start", ["grammar v1", "lark 1.3"], ".cache")
    Path(one).write_text("tables")
    assert cache.cache_file("grammar-start", ["grammar v1", "lark 1.3"], ".cache") == one
    two = cache.cache_file("grammar-start", ["grammar v2", "lark 1.3"], ".cache")
    assert two != one and not Path(one).exists()           # another grammar: another name
    assert cache.cache_file("grammar-start", ["grammar v1", "lark 1.4"], ".cache") != one


def test_a_missing_home_is_not_made(tmp_path, monkeypatch):
    monkeypatch.delenv("SCHEMALOG_CACHE_DIR", raising=False)
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "no" / "such" / "home"))
    assert cache.cache_dir() is None
    assert not (tmp_path / "no").exists()
    monkeypatch.setenv("HOME", str(tmp_path))              # a HOME that exists: ~/.cache/schemalog
    assert cache.cache_dir() == tmp_path / ".cache" / "schemalog"


def test_no_cache_where_others_could_write_or_when_turned_off(tmp_path, monkeypatch):
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(shared))
    assert cache.cache_dir() is None
    calls = []
    cache.remembered("t", ["s"], lambda: calls.append(1))
    cache.remembered("t", ["s"], lambda: calls.append(1))
    assert calls == [1, 1] and not list(shared.iterdir())
    (shared / "mine").mkdir(mode=0o700)        # private, but others may rename it away
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(shared / "mine"))
    assert cache.cache_dir() is None
    shared.chmod(0o1777)                        # sticky, as /tmp: only its owner may
    assert cache.cache_dir() == shared / "mine"
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", "off")
    assert cache.cache_dir() is None
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(tmp_path / "a-file"))
    (tmp_path / "a-file").write_text("not a directory")
    assert cache.cache_dir() is None


def test_the_cached_prelude_is_the_parsed_prelude_with_fresh_variables(tmp_path, monkeypatch):
    text = (ROOT / "src/schemalog/logic/prelude.pl").read_text(encoding="utf-8")
    parsed = [c for c in parse_text(text, "<prelude>") if hasattr(c, "head")]
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", str(tmp_path))
    _prelude.cache_clear()
    first = _prelude()                      # parsed and written
    _prelude.cache_clear()
    loaded = _prelude()                     # read back
    _prelude.cache_clear()
    assert list(tmp_path.glob("prelude-*.pickle"))
    for clauses in (first, loaded):
        assert len(clauses) == len(parsed) > 50
        for mine, theirs in zip(clauses, parsed):
            assert mine.pos == theirs.pos
            assert (mine.body is TRUE) == (theirs.body is TRUE)     # the engine skips `true` bodies
            assert variant(Struct(":-", (mine.head, mine.body)), Struct(":-", (theirs.head, theirs.body)))
    fresh = Var("X")
    ids = [v.id for c in loaded for t in (c.head, c.body) for v in iter_vars(t)]
    assert ids and fresh.id not in ids and max(ids) < fresh.id   # numbered in this process


def _query(cache_dir, seed, goal):
    env = {**os.environ, "SCHEMALOG_CACHE_DIR": str(cache_dir), "PYTHONHASHSEED": str(seed)}
    return subprocess.run([sys.executable, "-m", "schemalog", "query", goal], capture_output=True,
                          text=True, cwd=ROOT, env=env, timeout=120)


def test_answers_do_not_depend_on_a_warm_cache_or_the_hash_seed(tmp_path):
    goal = "msort([c, f(b), a], L), sort(0, @>=, [1, 3, 2], D), last([x, y], Z)"
    runs = [_query(tmp_path, seed, goal) for seed in (1, 2, 3)]     # cold, then warm twice
    assert {r.stdout for r in runs} == {"L = [a, c, f(b)], D = [3, 2, 1], Z = y\n"}
    assert all(r.returncode == 0 and r.stderr == "" for r in runs)
    names = sorted(p.name.split("-")[0] for p in tmp_path.iterdir())
    assert names == ["grammar", "grammar", "prelude"]


def test_reading_errors_are_the_same_with_a_warm_grammar_cache(tmp_path):
    broken, deep = tmp_path / "broken.pl", tmp_path / "deep.pl"
    broken.write_text("ok(1).\nbroken(( .\n")
    deep.write_text("ok(1).\ndeep(" + "f(" * 3000 + "x" + ")" * 3001 + ".\n")   # the bracket guard
    env = {**os.environ, "SCHEMALOG_CACHE_DIR": str(tmp_path / "cache")}
    for path in (broken, deep):
        runs = [subprocess.run([sys.executable, "-m", "schemalog", "check", str(path)], capture_output=True,
                               text=True, env=env, timeout=120) for _ in range(2)]
        assert runs[0].returncode == runs[1].returncode == 1
        assert runs[0].stderr == runs[1].stderr
        assert f"{path}:2:" in runs[0].stderr


def test_a_knowledge_base_still_loads_without_any_cache(monkeypatch):
    monkeypatch.setenv("SCHEMALOG_CACHE_DIR", "off")
    _prelude.cache_clear()
    try:
        assert ("append", 3) in KnowledgeBase().predicates
    finally:
        _prelude.cache_clear()


def test_a_term_read_back_in_another_process_hashes_as_built_there(tmp_path):
    code = ("import pickle, sys\nfrom schemalog.logic.terms import Atom, Struct\n"
            "term = Struct('f', (Atom('a'), Struct('g', (Atom('b'),))))\n"
            "if sys.argv[1] == 'write':\n"
            "    hash(term)  # the hash is cached in the term: it must not travel\n"
            "    open(sys.argv[2], 'wb').write(pickle.dumps(term))\n"
            "else:\n"
            "    back = pickle.loads(open(sys.argv[2], 'rb').read())\n"
            "    print(back in {term}, back == term)\n")
    target = str(tmp_path / "term.pickle")
    for seed, mode in ((1, "write"), (2, "read")):
        out = subprocess.run([sys.executable, "-c", code, mode, target], capture_output=True, text=True,
                             env={**os.environ, "PYTHONHASHSEED": str(seed)}, timeout=60, check=True)
    assert out.stdout == "True True\n"


def test_a_warm_cache_takes_the_same_steps(tmp_path):
    # the fewest steps that answer (resolution, and the cells of the answers printed): a library
    # fact read back must still skip its `true` body, or the third answer is cut off
    goal = "append(X, Y, [1, 2])"
    cold = subprocess.run([sys.executable, "-m", "schemalog", "query", goal, "--max-steps", "12"], cwd=ROOT,
                          env={**os.environ, "SCHEMALOG_CACHE_DIR": "off"}, capture_output=True, text=True)
    warm = [_query_steps(tmp_path, goal, 12) for _ in range(2)]
    assert cold.returncode == 0 and cold.stdout.count("X = ") == 3
    assert [(r.returncode, r.stdout) for r in warm] == [(0, cold.stdout)] * 2


def _query_steps(cache_dir, goal, steps):
    env = {**os.environ, "SCHEMALOG_CACHE_DIR": str(cache_dir)}
    return subprocess.run([sys.executable, "-m", "schemalog", "query", goal, "--max-steps", str(steps)],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
