"""`schemalog compress DIR|FILE ...` and `schemalog verify A B` with each side a file or a folder:
a robot's folder of BT.CPP trees read as one program, end to end, and every bad folder one
message with nothing written and nothing changed."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

CORPUS = ROOT / "tests" / "bt" / "corpus"
COMBAT = CORPUS / "combat" / "behavior_trees"
T14 = [CORPUS / "btcpp" / "tutorials" / "t14_subtree_model_1.xml", CORPUS / "btcpp" / "tutorials" / "t14_subtree_model_2.xml"]


def run(*args, cwd=ROOT, timeout=300):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=timeout)


def digest(folder) -> dict[str, str]:
    """Every file under `folder` and its content's hash: what a run must leave as it was."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and not p.is_symlink()}


def one_error(r, code: int = 1) -> str:
    """The run's one message: its exit status `code`, no traceback, one line on stderr (a usage
    error's followed by its `(see: schemalog CMD --help)`), nothing on stdout."""
    assert r.returncode == code, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    if code == 2 and lines and lines[-1].startswith("(see: schemalog "):
        lines = lines[:-1]
    assert "Traceback" not in r.stderr and not r.stdout and len(lines) == 1, r.stderr
    return r.stderr


def test_a_robots_folder_compresses_to_one_document_btcpp_loads_as_the_program(tmp_path):
    before = digest(COMBAT)
    out = tmp_path / "small.xml"
    r = run("compress", COMBAT, "--task", "rmuc_2026", "-o", out)
    assert r.returncode == 0, r.stderr
    assert "589 nodes from 596 (7 rewrites), proved equal to the original" in r.stderr
    written = out.read_text()
    assert written.count("<BehaviorTree ID=") == 65 and 'main_tree_to_execute="rmuc_2026"' in written
    # the one document is the program: proved against the folder, and read back alone
    v = run("verify", COMBAT, out, "--task", "rmuc_2026")
    assert v.returncode == 0 and v.stdout.startswith("proved equal"), v.stdout + v.stderr
    again = run("verify", out, out)                 # its own main_tree_to_execute, no --task
    assert again.returncode == 0 and again.stdout.startswith("proved equal"), again.stdout + again.stderr
    assert digest(COMBAT) == before


def test_a_folder_with_an_edit_in_a_sibling_file_is_refuted(tmp_path):
    edited = tmp_path / "edited"
    shutil.copytree(COMBAT, edited)
    recovery = edited / "rmuc_2026_recovery.xml"
    text = recovery.read_text()
    assert text.count("<Fallback") >= 1
    recovery.write_text(text.replace("<Fallback", "<Sequence", 1).replace("</Fallback>", "</Sequence>", 1))
    r = run("verify", COMBAT, edited, "--task", "rmuc_2026")
    assert r.returncode == 1 and r.stdout.startswith("refuted after"), r.stdout + r.stderr
    # the counterexample runs through SubTrees into the edited file
    assert f"{edited / 'rmuc_2026_recovery.xml'}:" in r.stdout and "<- the trees part here" in r.stdout
    same = run("verify", COMBAT, edited / "..", "--task", "rmuc_2026")        # a folder of folders: no *.xml
    assert "no *.xml file in this folder" in one_error(same)


def test_btcpps_partner_files_compress_as_one_program(tmp_path):
    r = run("compress", *T14, "--task", "MainTree", "--json")
    assert r.returncode == 0, r.stderr
    import json
    said = json.loads(r.stdout)
    assert said["files"] == [str(p) for p in T14] and said["nodes_before"] == 7
    # one of the two alone: its SubTree names a tree of the other file
    alone = run("compress", T14[1], "--task", "MainTree")
    assert "t14_subtree_model_2.xml:7:7: error: <SubTree ID=\"MySub\"> names no BehaviorTree" in alone.stderr
    assert alone.returncode == 1


def bad_folder(tmp_path, case: str):
    """A folder of trees with one thing wrong, and what the message says."""
    trees = tmp_path / "trees"
    trees.mkdir()
    main = '<root BTCPP_format="4" main_tree_to_execute="Main">\n  <BehaviorTree ID="Main"><SubTree ID="Sub"/></BehaviorTree>\n</root>\n'
    sub = '<root BTCPP_format="4">\n  <BehaviorTree ID="Sub"><AlwaysSuccess/></BehaviorTree>\n</root>\n'
    if case == "empty folder":
        return trees, "trees: no *.xml file in this folder"
    if case == "no tree":
        (trees / "models.xml").write_text('<root BTCPP_format="4"><TreeNodesModel/></root>\n')
        return trees, "models.xml:1:1: error: the document defines no <BehaviorTree>"
    (trees / "main.xml").write_text(main)
    (trees / "sub.xml").write_text(sub)
    if case == "a tree in two files":
        (trees / "sub2.xml").write_text(sub)
        return trees, "sub2.xml:2:3: error: BehaviorTree Sub is defined twice (first at "
    if case == "a FIFO":
        os.mkfifo(trees / "waiting.xml")
        return trees, "waiting.xml: a FIFO named *.xml in the folder"
    if case == "a link to a folder":
        os.symlink(tmp_path, trees / "all.xml")
        return trees, "all.xml: a directory named *.xml in the folder"
    if case == "no main tree":
        (trees / "main.xml").write_text(main.replace(' main_tree_to_execute="Main"', ""))
        return trees, "no file read names main_tree_to_execute, and the 2 files"
    if case == "not a tree":
        (trees / "package.xml").write_text('<package format="3"/>\n')
        return trees, "package.xml:1:1: error: a BT.CPP document starts with <root"
    raise AssertionError(case)


CASES = ["empty folder", "no tree", "a tree in two files", "a FIFO", "a link to a folder", "no main tree", "not a tree"]


@pytest.mark.parametrize("command", ["compress", "verify"])
@pytest.mark.parametrize("case", CASES)
def test_a_bad_folder_is_one_message_and_nothing_is_written(tmp_path, case, command):
    trees, said = bad_folder(tmp_path, case)
    before = digest(trees)
    out = tmp_path / "out.xml"
    r = run(command, trees, *([COMBAT] if command == "verify" else []), "-o", out, timeout=60)
    assert said in one_error(r)
    assert not out.exists() and digest(trees) == before


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a folder whatever its mode")
def test_a_folder_that_cannot_be_read_is_one_message(tmp_path):
    trees, _ = bad_folder(tmp_path, "empty folder")
    trees.chmod(0)
    try:
        assert "trees: cannot read the folder: Permission denied" in one_error(run("compress", trees))
    finally:
        trees.chmod(0o755)


def test_an_output_into_the_folder_read_is_a_usage_error(tmp_path):
    trees = tmp_path / "trees"
    shutil.copytree(COMBAT, trees)
    before = digest(trees)
    r = run("compress", trees, "--task", "rmuc_2026", "-o", trees / "small.xml")
    assert "would be written into the folder" in one_error(r, 2)
    # onto one of its files: refused as any input is
    r = run("compress", trees, "--task", "rmuc_2026", "-o", trees / "test.xml")
    assert r.returncode == 2 and digest(trees) == before


def test_verify_takes_one_program_a_side(tmp_path):
    r = run("verify", COMBAT, COMBAT, COMBAT, "--task", "rmuc_2026")
    assert "each a file, or a folder whose *.xml files are one program" in one_error(r, 2)


def test_the_folder_commands_of_the_readme_and_the_docs_do_what_they_say(tmp_path):
    """README's folder line and docs/behaviour_trees.md's "A folder of trees" block, run as written."""
    import re

    readme = [line for line in (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
              if "corpus/combat/behavior_trees" in line]
    docs = (ROOT / "docs" / "behaviour_trees.md").read_text(encoding="utf-8")
    block = docs.split("## A folder of trees", 1)[1].split("```sh\n", 1)[1].split("```", 1)[0]
    assert len(readme) == 1 and "589 nodes from 596" in readme[0] and "589 nodes from 596 (7 rewrites)" in block
    for script in (readme[0].split("   #", 1)[0], block):
        script = script.replace("small.xml", str(tmp_path / "small.xml"))
        script = re.sub(r"\bschemalog\b", f"{sys.executable} -m schemalog", script)
        r = subprocess.run(["bash", "-ec", script], capture_output=True, text=True, cwd=ROOT, timeout=600)
        assert r.returncode == 0, r.stderr
        assert "589 nodes from 596 (7 rewrites), proved equal to the original" in r.stderr
    assert r.stdout.startswith("proved equal")                       # the block's verify
    assert "t14_subtree_model_2.xml: nothing to compress (7 nodes)" in r.stdout    # the t14 pair, as one
