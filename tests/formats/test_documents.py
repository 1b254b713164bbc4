"""Knowledge files: pl <-> YAML round trips exactly; YAML errors have positions; writes are atomic;
several files load as one program, each sub-task's schema from one file."""

import os
import stat
import threading

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from schemalog.formats.documents import (document_from_text, document_from_yaml, load_kb, read_document, to_pl,
                                 to_yaml, write_atomically)
from schemalog.logic.parse import parse_term
from schemalog.task.tree import count_nodes, instantiate
from schemalog.errors import SchemalogError

from conftest import COFFEE, MIX, SEED_COFFEE, read_fifo_in_thread


@pytest.mark.parametrize("path", [MIX, COFFEE, SEED_COFFEE])
def test_pl_yaml_pl_round_trips_exactly(path):
    doc = read_document(path)
    pl = to_pl(doc)
    assert to_pl(document_from_yaml(to_yaml(doc), "t.yaml")) == pl
    assert to_pl(document_from_text(pl)) == pl  # canonical text is a fixed point


names = st.sampled_from(["take", "mix", "pour", "a1", "a2", "gripper"])
objects_ = st.sampled_from(["spoon", "cup", "water", "O", "_"])
literal = st.builds(lambda o, p, neg: f"{'not ' if neg else ''}{o}.{p}",
                    st.sampled_from(["hand", "spoon", "O"]), st.sampled_from(["free", "taken", "done"]),
                    st.booleans())
releaser = st.one_of(st.just("true"), literal,
                     st.lists(literal, min_size=2, max_size=3).map(" and ".join),
                     st.lists(literal, min_size=2, max_size=3).map(" or ".join))
entry = st.builds(lambda n, o, r, w: f"({n}({o}), {r}{'' if w is None else f', {w}'})",
                  names, objects_, releaser, st.one_of(st.none(), st.integers(0, 5), st.just(1.5)))
schema_clause = st.builds(
    lambda n, o, es, post: f"schema({n}({o}), [{', '.join(es)}], {post}).",
    names, objects_, st.lists(entry, max_size=4), literal.filter(lambda s: True))
declaration = st.sampled_from(["task(use(spoon)).", "object(cup).", "initial(hand.free).",
                               "agent(gripper(_), gripper).", "behaviour(a9(_)).",
                               "helper(X) :- member(X, [a, b]), X \\== c.", ":- dynamic seen/1."])


@settings(max_examples=150, deadline=None)
@given(st.lists(st.one_of(schema_clause, declaration), min_size=1, max_size=8))
def test_generated_knowledge_round_trips_through_yaml(clauses):
    text = "\n".join(clauses) + "\n"
    doc = document_from_text(text, "gen.pl")
    pl = to_pl(doc)
    assert to_pl(document_from_yaml(to_yaml(doc), "gen.yaml")) == pl
    assert to_pl(document_from_text(pl, "again.pl")) == pl


def test_yaml_syntax_error_has_line_and_column():
    with pytest.raises(SchemalogError) as err:
        document_from_yaml("schemalog: 1\nitems:\n  - schema: [unclosed\n", "bad.yaml")
    assert err.value.pos.file == "bad.yaml" and err.value.pos.line >= 3


@pytest.mark.parametrize("text, message", [
    ("- just a list\n", "mapping with an `items` list"),
    ("items:\n  - 42\n", r"items\[0\]: expected a mapping"),
    ("items:\n  - {schema: a}\n", r"items\[0\]: missing `post`"),
    ("items:\n  - {schema: a, post: a.done, subtasks: [{behaviour: b, importance: x}]}\n",
     "importance` must be a number"),
    ("items:\n  - {schema: 'a(', post: a.done}\n", r"items\[0\]: .*syntax error|end of file"),
    ("items:\n  - {colour: red}\n", "unknown key `colour`"),
    ("items:\n  - {post: a.done}\n", "a record needs one of"),
])
def test_bad_yaml_records_are_named(text, message):
    with pytest.raises(SchemalogError, match=message):
        document_from_yaml(text, "bad.yaml")


# A set-the-table task as a person writes it: place the plate, then the fork on it.
TABLE_YAML = """schemalog: 1
items:
- task: lay(dinner)
- initial: hand.free
- schema: lay(dinner)
  subtasks:
  - behaviour: place(plate)
    releaser: hand.free
  - behaviour: place(fork)
    releaser: plate.placed
  post: dinner.laid
- schema: place(plate)
  subtasks: []
  post: plate.placed
- schema: place(fork)
  subtasks: []
  post: fork.placed
"""


@pytest.mark.parametrize("edit, where, message", [
    # a misspelt key was dropped: the releaser became `true` and the fork went first
    (("releaser: plate.placed", "releasr: plate.placed"), (10, 5),
     r"items\[2\]\.subtasks\[1\]: unknown key `releasr`; did you mean `releaser`\?"),
    # the US spelling was reported as a missing `behaviour` at the schema's line
    (("- behaviour: place(fork)", "- behavior: place(fork)"), (9, 5),
     r"items\[2\]\.subtasks\[1\]: unknown key `behavior`; did you mean `behaviour`\?"),
    # a post-condition indented into the last sub-task was dropped from the schema
    (("  post: dinner.laid", "    post: dinner.laid"), (11, 5),
     r"unknown key `post`; `post` is the schema's key: indent it as `subtasks:` is"),
    (("  post: fork.placed", "  post: fork.placed\n  colour: red"), (18, 3),
     r"items\[4\]: unknown key `colour` \(a schema record's keys: schema, subtasks, post, if\)"),
    (("  post: plate.placed", "  post: plate.placed\n  importance: 2"), (15, 3),
     r"`importance` is a sub-task's key"),
    (("- task: lay(dinner)", "- task: lay(dinner)\n  object: plate"), (4, 3),
     r"`object` beside `task`: a record makes one clause"),
    (("- initial: hand.free", "- intial: hand.free"), (4, 3), r"unknown key `intial`; did you mean `initial`\?"),
    (("- schema: place(plate)", "- behaviour: place(plate)\n  schema: place(plate)"), (12, 3),
     r"`behaviour` is a sub-task's key: write it in an entry of `subtasks`"),
    (("items:", "item:"), (2, 1), r"unknown key `item`; did you mean `items`\?"),
    (("    releaser: hand.free", "    releaser: hand.free\n    releaser: true"), (9, 5),
     r"`releaser` is given twice \(first at line 8\)"),
    (("schemalog: 1", "schemalog: 2"), (1, 12), r"`schemalog` is the format's version, 1"),
])
def test_every_yaml_key_is_known_and_an_unknown_one_is_named_where_it_is(edit, where, message):
    text = TABLE_YAML.replace(*edit)
    assert text != TABLE_YAML
    with pytest.raises(SchemalogError, match=message) as err:
        document_from_yaml(text, "table.yaml")
    assert (err.value.line, err.value.column) == where
    assert err.value.source_line == text.splitlines()[where[0] - 1]


def test_optional_yaml_keys_have_their_documented_meaning():
    """What docs/formats.md says a missing optional key means."""
    text = TABLE_YAML.replace("    releaser: hand.free\n", "").replace("schemalog: 1\n", "")
    doc = document_from_yaml(text, "table.yaml")
    assert "(place(plate), true)" in to_pl(doc).replace("\n", "").replace("  ", "")


def test_a_merged_yaml_key_may_be_overridden():
    text = TABLE_YAML.replace("  - behaviour: place(plate)\n    releaser: hand.free\n",
                              "  - &first {behaviour: place(plate), releaser: hand.free}\n"
                              "  - {<<: *first, behaviour: place(knife)}\n")
    pl = to_pl(document_from_yaml(text, "table.yaml"))
    assert "(place(knife), hand.free)" in pl


def test_a_missing_sub_task_behaviour_is_named_at_the_sub_task():
    text = TABLE_YAML.replace("  - behaviour: place(fork)\n    releaser", "  - releaser")
    with pytest.raises(SchemalogError, match=r"items\[2\]\.subtasks\[1\]: missing `behaviour`") as err:
        document_from_yaml(text, "table.yaml")
    assert (err.value.line, err.value.column) == (9, 5)


def test_yaml_tags_are_refused_by_safe_load():
    with pytest.raises(SchemalogError, match="YAML"):
        document_from_yaml("items: !!python/object/apply:os.system ['true']\n", "evil.yaml")


def test_atomic_write_leaves_no_partial_file(tmp_path, monkeypatch):
    target = tmp_path / "out.pl"
    write_atomically(target, "a.\n")
    assert target.read_text() == "a.\n"
    with pytest.raises(SchemalogError, match="no such directory"):
        write_atomically(tmp_path / "missing" / "x.pl", "a.\n")

    def failing_replace(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", failing_replace)
    with pytest.raises(SchemalogError, match="cannot write .*disk full"):  # a message, not a traceback
        write_atomically(target, "b.\n")
    assert target.read_text() == "a.\n"  # the old content survives
    assert [p.name for p in tmp_path.iterdir()] == ["out.pl"]  # and no temporary is left


def test_written_files_follow_the_umask_or_keep_the_mode_they_replace(tmp_path):
    import os
    from schemalog.formats.documents import write_atomically

    mask = os.umask(0o022)
    try:
        fresh = tmp_path / "fresh.pl"
        write_atomically(fresh, "task(a).\n")
        assert fresh.stat().st_mode & 0o777 == 0o644          # not mkstemp's private 0600
        kept = tmp_path / "kept.pl"
        kept.write_text("old")
        kept.chmod(0o640)
        write_atomically(kept, "task(b).\n")
        assert kept.stat().st_mode & 0o777 == 0o640 and kept.read_text() == "task(b).\n"
    finally:
        os.umask(mask)


# --- special files: written into, never replaced (docs/formats.md, Outputs) ------------------

def _null_device(path):
    os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 3))   # the null device, inside tmp_path
    return path


def test_a_fifo_is_written_into_not_replaced(tmp_path):
    fifo = tmp_path / "out.pl"
    os.mkfifo(fifo)
    reader, got = read_fifo_in_thread(fifo)
    write_atomically(fifo, "task(a).\n")
    reader.join(10)
    assert got == [b"task(a).\n"]
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode) and os.listdir(tmp_path) == ["out.pl"]


def test_a_character_device_is_written_into_not_replaced(tmp_path):
    null = _null_device(tmp_path / "null")
    write_atomically(null, "task(a).\n")
    info = os.lstat(null)
    assert stat.S_ISCHR(info.st_mode) and info.st_rdev == os.makedev(1, 3)
    assert os.listdir(tmp_path) == ["null"]


def test_a_symlink_is_followed_never_replaced(tmp_path):
    real = tmp_path / "real.pl"
    real.write_text("old.\n")
    link = tmp_path / "link.pl"
    link.symlink_to("real.pl")
    write_atomically(link, "new.\n")
    assert link.is_symlink() and real.read_text() == "new.\n"
    dangling = tmp_path / "dangling.pl"
    dangling.symlink_to("made.pl")                 # a link to nothing yet: the file it names is made
    write_atomically(dangling, "made.\n")
    assert dangling.is_symlink() and (tmp_path / "made.pl").read_text() == "made.\n"
    to_device = tmp_path / "to_null"
    to_device.symlink_to(_null_device(tmp_path / "null"))
    write_atomically(to_device, "gone.\n")          # in place through the link
    assert to_device.is_symlink() and stat.S_ISCHR(os.lstat(tmp_path / "null").st_mode)
    assert sorted(os.listdir(tmp_path)) == ["dangling.pl", "link.pl", "made.pl", "null", "real.pl", "to_null"]


@pytest.mark.parametrize("name", ["newdir/", "missing/x.pl", "adir", "adir/"])
def test_a_directory_or_a_missing_one_is_refused_and_nothing_made(tmp_path, name):
    (tmp_path / "adir").mkdir()
    with pytest.raises(SchemalogError, match="directory"):
        write_atomically(f"{tmp_path}/{name}", "a.\n")
    assert os.listdir(tmp_path) == ["adir"] and os.listdir(tmp_path / "adir") == []


# --- inputs that never end: --max-bytes bounds the bytes read ---------------------------------

def test_a_device_that_never_ends_is_read_up_to_the_limit(tmp_path):
    from schemalog.learn.demo import read_demonstration
    from schemalog.run.scene import read_scene

    zero = tmp_path / "zero.pl"
    os.mknod(zero, stat.S_IFCHR | 0o666, os.makedev(1, 5))   # the zero device, inside tmp_path
    for reader in (read_document, read_scene, read_demonstration):
        with pytest.raises(SchemalogError, match=r"zero\.pl.*over the 1,000 bytes limit"):
            reader(zero, max_bytes=1000)
    (tmp_path / "inc.pl").write_text(":- consult('zero.pl').\n")
    from schemalog.logic.kb import KnowledgeBase
    kb = KnowledgeBase()
    kb.max_bytes = 1000
    with pytest.raises(SchemalogError, match=r"zero\.pl.*over the 1,000 bytes limit"):
        read_document(tmp_path / "inc.pl").to_kb(kb)


def test_a_fifo_input_is_read_within_the_limit(tmp_path):
    fifo = tmp_path / "in.pl"
    os.mkfifo(fifo)

    def feed(text):
        try:
            with open(fifo, "w") as handle:
                handle.write(text)
        except BrokenPipeError:      # the reader stopped at the limit
            pass

    writer = threading.Thread(target=feed, args=("task(a).\n",), daemon=True)
    writer.start()
    assert len(read_document(fifo).items) == 1
    writer.join(10)
    writer = threading.Thread(target=lambda: feed("a." * 1000), daemon=True)
    writer.start()
    with pytest.raises(SchemalogError, match="over the 100 bytes limit"):
        read_document(fifo, max_bytes=100)


# ---------------------------------------------------------------------------
# Several files, one program (docs/syntax.md, Several files)

PRIMITIVES = """% a library of primitive behaviours, shared by task files
agent(gripper(_), gripper).
schema(gripper(close), [], not hand.free).
schema(gripper(open), [], hand.free).
schema(a1(O), [], a1.done) :- object(O).
"""
TASK = """task(grab(spoon)).
object(spoon).
initial(hand.free).
schema(grab(O), [(a1(O), true), (gripper(close), a1.done)], O.taken).
"""


def _write(tmp_path, name: str, text: str):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_a_task_file_and_a_library_of_primitives_are_one_program(tmp_path):
    kb = load_kb([_write(tmp_path, "prims.pl", PRIMITIVES), _write(tmp_path, "task.pl", TASK)])
    tree = instantiate(kb, parse_term("grab(spoon)"))
    assert count_nodes(tree) == 3 and tree.children[1].agent == "gripper"


def test_a_schema_for_the_same_sub_task_in_two_files_names_both_places(tmp_path):
    structure = _write(tmp_path, "structure.pl", "object(water).\n\nschema(subtask(take, O), [], O.taken).\n")
    learned = _write(tmp_path, "learned.pl", "object(water).\nschema(a1(water), [], a1.done).\n"
                     "schema(subtask(take, water), [(a1(water), true)], water.taken).\n")
    with pytest.raises(SchemalogError) as err:
        load_kb([structure, learned])
    assert str(err.value.pos) == f"{learned}:3:1"
    message = err.value.message
    assert f"{structure}:3:1" in message and "subtask(take, water)" in message and "subtask(take, O)" in message
    assert "multifile(subtask/2)" in message


@pytest.mark.parametrize("declaration", [":- multifile(subtask/2).", ":- multifile schema/3."])
def test_multifile_says_two_files_mean_to_define_one_sub_task(tmp_path, declaration):
    structure = _write(tmp_path, "structure.pl", "schema(subtask(take, O), [], O.taken).\n")
    learned = _write(tmp_path, "learned.pl", f"{declaration}\nschema(subtask(take, water), [], w.taken).\n")
    kb = load_kb([structure, learned])
    assert len(kb.clauses("schema", 3)) == 2


def test_schemas_of_one_name_for_other_arguments_are_no_clash(tmp_path):
    one = _write(tmp_path, "one.pl", "schema(a1(spoon), [], a1.done).\nobject(cup).\ninitial(hand.free).\n")
    two = _write(tmp_path, "two.pl", "schema(a1(water), [], a1.done).\nobject(cup).\ninitial(cup.clean).\n")
    kb = load_kb([one, two])
    assert len(kb.clauses("schema", 3)) == 2
    assert len(kb.clauses("initial", 1)) == 2          # declarations add up


def test_a_task_declared_in_two_files_is_an_error(tmp_path):
    one = _write(tmp_path, "one.pl", TASK)
    two = _write(tmp_path, "two.pl", "task(grab(spoon)).\n")
    with pytest.raises(SchemalogError, match=r"task\(grab\(spoon\)\) here and task\(grab\(spoon\)\) at .*one.pl:1:1"):
        load_kb([one, two])


def test_a_yaml_file_is_named_by_its_line_and_column(tmp_path):
    one = _write(tmp_path, "one.pl", TASK)
    two = _write(tmp_path, "two.yaml", "schemalog: 1\nitems:\n  - task: other\n  - schema: grab(X)\n"
                 "    subtasks: []\n    post: X.taken\n")
    with pytest.raises(SchemalogError) as err:
        load_kb([one, two])
    assert str(err.value.pos) == f"{two}:4:5" and f"{one}:4:1" in err.value.message
