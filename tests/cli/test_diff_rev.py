"""`schemalog diff --rev REV PATH...` in a real git repository: each BT.CPP file against its own
version at REV, as a pre-commit hook and a pull request's job run it (docs/behaviour_trees.md,
"In CI: pre-commit and GitHub Actions")."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT

NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
NAVIGATE = NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml"
GIT_ENV = {"GIT_AUTHOR_NAME": "t", "GIT_AUTHOR_EMAIL": "t@example.org", "GIT_COMMITTER_NAME": "t",
           "GIT_COMMITTER_EMAIL": "t@example.org", "GIT_CONFIG_NOSYSTEM": "1"}

MAIN = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <include path="common/recovery.xml"/>
  <BehaviorTree ID="Main">
    <Fallback>
      <Sequence><IsReady/><SubTree ID="Recover"/></Sequence>
      <AlwaysFailure/>
    </Fallback>
  </BehaviorTree>
  <TreeNodesModel><Condition ID="IsReady"/><Action ID="Clear"/></TreeNodesModel>
</root>
"""
RECOVERY = """<root BTCPP_format="4">
  <BehaviorTree ID="Recover">
    <RetryUntilSuccessful num_attempts="3"><Clear/></RetryUntilSuccessful>
  </BehaviorTree>
</root>
"""


def git(repo, *args):
    done = subprocess.run(["git", *args], cwd=repo, capture_output=True, text=True, timeout=60,
                          env={**os.environ, **GIT_ENV})
    assert done.returncode == 0, done.stderr
    return done.stdout


def diff(repo, *args, env=None):
    return subprocess.run([sys.executable, "-m", "schemalog", "diff", *map(str, args)], capture_output=True, text=True,
                          cwd=repo, timeout=300, env={**os.environ, **(env or {})})


@pytest.fixture
def repo(tmp_path):
    """A git repository with a committed tree that includes a file of a subfolder."""
    r = tmp_path / "robot"
    (r / "trees" / "common").mkdir(parents=True)
    (r / "trees" / "main.xml").write_text(MAIN, encoding="utf-8")
    (r / "trees" / "common" / "recovery.xml").write_text(RECOVERY, encoding="utf-8")
    (r / "package.xml").write_text("<package format=\"3\"><name>robot</name></package>\n", encoding="utf-8")
    git(r, "init", "-q")
    git(r, "add", ".")
    git(r, "commit", "-qm", "trees")
    return r


def test_an_edit_of_an_included_file_is_found_against_the_revisions_include(repo):
    # main.xml is unchanged: only its <include>d file is; REV's side must read REV's include
    recovery = repo / "trees" / "common" / "recovery.xml"
    recovery.write_text(RECOVERY.replace('num_attempts="3"', 'num_attempts="2"'), encoding="utf-8")
    r = diff(repo, "--rev", "HEAD", "trees/main.xml")
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout.startswith("HEAD:trees/main.xml -> trees/main.xml: behaviour changed")
    assert "HEAD:trees/common/recovery.xml:3:5" in r.stdout            # REV's file, named as git names it
    assert "schemalog-rev-" not in r.stdout + r.stderr                   # never the temporary folder
    git(repo, "stash", "-q")
    same = diff(repo, "--rev", "HEAD", "trees/main.xml")
    assert same.returncode == 0 and "same behaviour" in same.stdout, same.stdout + same.stderr


def test_several_paths_new_files_and_other_xml_and_the_worst_status(repo):
    (repo / "trees" / "new.xml").write_text(RECOVERY, encoding="utf-8")
    (repo / "package.xml").write_text("<package format=\"3\"><name>robot2</name></package>\n", encoding="utf-8")
    main = repo / "trees" / "main.xml"
    # attributes reordered and a single-child Sequence wrapper: a pure refactoring
    main.write_text(MAIN.replace("<Fallback>", "<Sequence><Fallback>").replace("</Fallback>", "</Fallback></Sequence>")
                    .replace('BTCPP_format="4" main_tree_to_execute="Main"', 'main_tree_to_execute="Main" BTCPP_format="4"'),
                    encoding="utf-8")
    r = diff(repo, "--rev", "HEAD", "trees/main.xml", "trees/new.xml", "package.xml")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "HEAD:trees/main.xml -> trees/main.xml: same behaviour" in r.stdout
    assert "trees/new.xml: new file since HEAD: nothing to compare" in r.stdout
    assert "package.xml: not a BT.CPP tree (its root element is <package>" in r.stdout
    (repo / "trees" / "common" / "recovery.xml").write_text(RECOVERY.replace("<Clear/>", "<Sequence><Clear/><Clear/></Sequence>"),
                                                           encoding="utf-8")
    changed = diff(repo, "--rev", "HEAD", "trees/main.xml", "trees/new.xml", "--json")
    assert changed.returncode == 1, changed.stderr
    report = json.loads(changed.stdout)
    assert report["rev"] == "HEAD" and report["exit"] == 1
    assert [(f["path"], f["status"]) for f in report["files"]] == [("trees/main.xml", "changed"),
                                                                    ("trees/new.xml", "new")]
    # trouble beats a change (diff(1)'s 2): a file that cannot be read leaves the whole undecided
    (repo / "trees" / "broken.xml").write_text("<root BTCPP_format=\"4\"><BehaviorTree ID=\"X\">", encoding="utf-8")
    git(repo, "add", "trees/broken.xml")
    git(repo, "commit", "-qm", "broken")
    both = diff(repo, "--rev", "HEAD", "trees/main.xml", "trees/broken.xml")
    assert both.returncode == 2, both.stdout + both.stderr
    # the report says it too (a PR comment must not read as complete): a summary, then each PATH
    assert both.stdout.startswith("schemalog diff against HEAD: 2 paths: 1 changed, 1 could not be compared\n")
    assert "behaviour changed" in both.stdout and "HEAD:trees/broken.xml:1:45: error: malformed XML" in both.stdout
    assert "HEAD:trees/broken.xml:1:" in both.stderr and "Traceback" not in both.stderr


def test_outside_a_repository_or_at_an_unknown_revision_it_says_so(repo, tmp_path):
    loose = tmp_path / "loose.xml"
    loose.write_text(RECOVERY, encoding="utf-8")
    r = diff(tmp_path, "--rev", "HEAD", loose, env={"GIT_CEILING_DIRECTORIES": str(tmp_path)})
    assert r.returncode == 2 and "loose.xml: not in a git repository" in r.stderr, r.stderr
    r = diff(repo, "--rev", "v9.9", "trees/main.xml")
    assert r.returncode == 2 and "--rev v9.9: no such commit in the repository" in r.stderr, r.stderr
    r = diff(repo, "--rev=--output=x", "trees/main.xml")
    assert r.returncode == 2 and "a revision does not start with" in r.stderr, r.stderr
    assert not (repo / "x").exists()


def test_a_nav2_tree_against_the_previous_commit_as_markdown(tmp_path):
    r = tmp_path / "nav"
    r.mkdir()
    (r / "navigate.xml").write_bytes(NAVIGATE.read_bytes())
    (r / "nav2_tree_nodes.xml").write_bytes(NODES.read_bytes())
    git(r, "init", "-q")
    git(r, "add", ".")
    git(r, "commit", "-qm", "one")
    (r / "navigate.xml").write_text(NAVIGATE.read_text(encoding="utf-8").replace('number_of_retries="6"',
                                                                                 'number_of_retries="5"'))
    git(r, "commit", "-qam", "two")
    out = diff(r, "--rev", "HEAD~1", "navigate.xml", "nav2_tree_nodes.xml", "--nodes", "nav2_tree_nodes.xml",
               "--format", "markdown", "-o", "diff.md")
    assert out.returncode == 1, out.stderr
    text = (r / "diff.md").read_text(encoding="utf-8")
    assert text.startswith("## schemalog diff against HEAD~1: 2 paths: 1 changed, 1 skipped\n\n"
                           "### schemalog diff: behaviour changed")
    assert "`HEAD~1:navigate.xml` → `navigate.xml`" in text
    assert "nav2\\_tree\\_nodes.xml: no &lt;BehaviorTree&gt; nor &lt;include&gt; in it" in text


def test_ctrl_c_while_git_runs_removes_the_temporary_folder(repo, tmp_path):
    # A git that stalls in cat-file (a slow disk, a network file system): the old files' folder
    # exists by then, and Ctrl-C must remove it
    fake = tmp_path / "bin"
    fake.mkdir()
    real = subprocess.run(["sh", "-c", "command -v git"], capture_output=True, text=True).stdout.strip()
    (fake / "git").write_text(f'#!/bin/sh\ncase "$1" in cat-file) touch "{tmp_path}/stalled"; sleep 60;; esac\n'
                              f'exec "{real}" "$@"\n')
    (fake / "git").chmod(0o755)
    temp = tmp_path / "tmp"
    temp.mkdir()
    env = {**os.environ, "PATH": f"{fake}{os.pathsep}{os.environ['PATH']}", "TMPDIR": str(temp)}
    p = subprocess.Popen([sys.executable, "-m", "schemalog", "diff", "--rev", "HEAD", "trees/main.xml"], cwd=repo,
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 60
    while not (tmp_path / "stalled").exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert [f.name for f in temp.iterdir()][0].startswith("schemalog-rev-")
    os.killpg(p.pid, signal.SIGINT)            # as a terminal's Ctrl-C: the whole foreground group
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130 and "interrupted" in err and "Traceback" not in err, err
    assert list(temp.iterdir()) == []


def test_a_folder_is_compared_with_the_folder_at_the_revision(repo):
    # `schemalog diff --rev HEAD trees/common`: the folder's *.xml files as one program, REV's from REV
    common = repo / "trees" / "common"
    (common / "main.xml").write_text('<root BTCPP_format="4" main_tree_to_execute="Top"><BehaviorTree ID="Top">'
                                     '<SubTree ID="Recover"/></BehaviorTree></root>\n', encoding="utf-8")
    git(repo, "add", ".")
    git(repo, "commit", "-qm", "a folder")
    same = diff(repo, "--rev", "HEAD", "trees/common")
    assert same.returncode == 0 and same.stdout.startswith("HEAD:trees/common -> trees/common: same behaviour"), \
        same.stdout + same.stderr
    (common / "recovery.xml").write_text(RECOVERY.replace('num_attempts="3"', 'num_attempts="4"'), encoding="utf-8")
    changed = diff(repo, "--rev", "HEAD", "trees/common")
    assert changed.returncode == 1, changed.stdout + changed.stderr
    assert "RetryUntilSuccessful at HEAD:trees/common/recovery.xml:3:5 / trees/common/recovery.xml:3:5" in changed.stdout
    assert "4 times instead of 3" in changed.stdout


def test_a_typo_is_an_error_a_deleted_file_a_change_and_an_error_reaches_the_comment(repo):
    """A path that exists neither now nor at REV must not pass a CI job as a new file; a file
    deleted since REV is a change; with -o, the error is written into the report the job posts."""
    typo = diff(repo, "--rev", "HEAD", "trees/mian.xml")
    assert typo.returncode == 2 and "trees/mian.xml: no such file, now nor at HEAD" in typo.stderr
    (repo / "trees" / "common" / "recovery.xml").unlink()
    gone = diff(repo, "--rev", "HEAD", "trees/common/recovery.xml", "--json")
    assert gone.returncode == 1, gone.stderr
    assert json.loads(gone.stdout)["files"][0]["status"] == "deleted"
    (repo / "trees" / "main.xml").write_text("<root BTCPP_format=\"4\"><BehaviorTree ID=\"X\">", encoding="utf-8")
    broken = diff(repo, "--rev", "HEAD", "trees/main.xml", "--format", "markdown", "-o", "diff.md")
    assert broken.returncode == 2
    comment = (repo / "diff.md").read_text(encoding="utf-8")
    assert "trees/main.xml:1:" in comment and "malformed XML" in comment and comment.endswith("\n")
