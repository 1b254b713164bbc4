"""The `schemalog-diff` pre-commit hook (.pre-commit-hooks.yaml) run by pre-commit itself in a
temporary git repository (docs/behaviour_trees.md, "In CI: pre-commit and GitHub Actions").

What is exercised, and how:
- test_the_published_hook_fails_a_behaviour_change: the hook as users get it. `pre-commit
  try-repo <this repository> schemalog-diff` reads this repository's .pre-commit-hooks.yaml,
  builds the hook's `language: python` environment as for any user (a fresh virtualenv, `pip
  install` of this repository and its dependencies: 22 to 43 s measured on the project's
  machine with pip's cache warm, longer on a first download) and runs the entry on a
  behavioural edit.
  try-repo builds in a temporary store every time, so this runs once, on the edit that must fail.
- test_a_commit_passes_a_refactoring_fails_a_change_and_skip_acknowledges_it: the rest through
  real `git commit`s with the hook installed (`pre-commit install`), from a local config whose
  hook is the published one (id, name, entry, files, types read from .pre-commit-hooks.yaml)
  with `language: system`, so it runs the schemalog installed with these tests rather than
  building that environment again; `args:` passes --nodes as a user's config does. It covers
  pre-commit's file selection, the exit status failing the commit, the diff in its output, and
  SKIP=schemalog-diff as the acknowledgement; it does not cover the environment's build, which
  the first test does.
pre-commit comes from the test extras (pyproject.toml), so these run wherever the tests do.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import yaml

from conftest import ROOT

NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NAVIGATE = NAV2 / "navigate_to_pose_w_replanning_and_recovery.xml"
TREE = """<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <RetryUntilSuccessful num_attempts="3">
      <Sequence><IsReady/><Clear/></Sequence>
    </RetryUntilSuccessful>
  </BehaviorTree>
  <TreeNodesModel><Condition ID="IsReady"/><Action ID="Clear"/></TreeNodesModel>
</root>
"""


def environment(tmp_path: Path) -> dict:
    """A git and pre-commit of their own: no user's or system's git config (a core.hooksPath
    there stops `pre-commit install`), no user's pre-commit cache; this Python's scripts first."""
    return {**os.environ, "GIT_AUTHOR_NAME": "t", "GIT_AUTHOR_EMAIL": "t@example.org", "GIT_COMMITTER_NAME": "t",
            "GIT_COMMITTER_EMAIL": "t@example.org", "GIT_CONFIG_NOSYSTEM": "1", "GIT_CONFIG_GLOBAL": os.devnull,
            "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home"),
            "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}


def sh(repo: Path, env: dict, *args: str, check: bool = True, **extra) -> subprocess.CompletedProcess:
    done = subprocess.run(list(args), cwd=repo, capture_output=True, text=True, timeout=900, env={**env, **extra})
    assert not check or done.returncode == 0, done.stdout + done.stderr
    return done


def pre_commit(repo: Path, env: dict, *args: str, **extra) -> subprocess.CompletedProcess:
    return sh(repo, env, sys.executable, "-m", "pre_commit", *args, check=False, **extra)


def new_repository(tmp_path: Path, files: dict[str, str]) -> tuple[Path, dict]:
    repo = tmp_path / "robot"
    repo.mkdir()
    env = environment(tmp_path)
    for name, text in files.items():
        (repo / name).write_text(text, encoding="utf-8")
    sh(repo, env, "git", "init", "-q")
    sh(repo, env, "git", "add", ".")
    sh(repo, env, "git", "commit", "-qm", "trees")
    return repo, env


def published_hook(hook_id: str = "schemalog-diff") -> dict:
    hooks = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text(encoding="utf-8"))
    assert [h["id"] for h in hooks] == ["schemalog-diff", "schemalog-lint"]
    (hook,) = (h for h in hooks if h["id"] == hook_id)
    return hook


def test_the_published_hook_fails_a_behaviour_change(tmp_path):
    assert (ROOT / ".git").exists(), f"try-repo needs {ROOT} as a git repository (a clone, not an sdist)"
    repo, env = new_repository(tmp_path, {"tree.xml": TREE})
    (repo / "tree.xml").write_text(TREE.replace('num_attempts="3"', 'num_attempts="2"'), encoding="utf-8")
    r = pre_commit(repo, env, "try-repo", str(ROOT), "schemalog-diff", "--files", "tree.xml")
    out = r.stdout + r.stderr
    assert r.returncode == 1, out
    assert "schemalog diff (BT.CPP behaviour against HEAD)" in out and "Failed" in out
    assert "HEAD:tree.xml -> tree.xml: behaviour changed" in out
    assert "RetryUntilSuccessful at HEAD:tree.xml:3:5 / tree.xml:3:5" in out and "B tries Sequence 2 times instead of 3" in out


def test_a_commit_passes_a_refactoring_fails_a_change_and_skip_acknowledges_it(tmp_path):
    assert shutil.which("schemalog", path=environment(tmp_path)["PATH"]), "the schemalog command is not installed"
    hook = {**published_hook(), "language": "system", "args": ["--nodes", "nav2_tree_nodes.xml"]}
    config = yaml.safe_dump({"repos": [{"repo": "local", "hooks": [hook]}]}, sort_keys=False)
    original = NAVIGATE.read_text(encoding="utf-8")
    repo, env = new_repository(tmp_path, {"navigate.xml": original, ".pre-commit-config.yaml": config,
                                          "nav2_tree_nodes.xml": (NAV2 / "nav2_tree_nodes.xml").read_text("utf-8")})
    installed = pre_commit(repo, env, "install")
    assert installed.returncode == 0, installed.stdout + installed.stderr

    # a pure refactoring: a node's attributes reordered, the tree wrapped in a single-child Sequence
    refactored = (original.replace('<RecoveryNode number_of_retries="6" name="NavigateRecovery">',
                                   '<RecoveryNode name="NavigateRecovery" number_of_retries="6">')
                  .replace('<BehaviorTree ID="MainTree">', '<BehaviorTree ID="MainTree">\n<Sequence>')
                  .replace("</BehaviorTree>", "</Sequence>\n</BehaviorTree>"))
    assert refactored.count("<Sequence>") == original.count("<Sequence>") + 1 and '<RecoveryNode name="Nav' in refactored
    (repo / "navigate.xml").write_text(refactored, encoding="utf-8")
    head = sh(repo, env, "git", "rev-parse", "HEAD").stdout
    ok = sh(repo, env, "git", "commit", "-qam", "refactor", check=False)
    said = ok.stdout + ok.stderr                      # a git hook's output goes to git's standard error
    assert ok.returncode == 0, said
    assert "schemalog diff (BT.CPP behaviour against HEAD)" in said and "Passed" in said
    assert sh(repo, env, "git", "rev-parse", "HEAD").stdout != head

    # a behaviour change fails the commit, with the diff in pre-commit's output
    (repo / "navigate.xml").write_text(refactored.replace('number_of_retries="6"', 'number_of_retries="5"'),
                                       encoding="utf-8")
    head = sh(repo, env, "git", "rev-parse", "HEAD").stdout
    failed = sh(repo, env, "git", "commit", "-qam", "fewer retries", check=False)
    said = failed.stdout + failed.stderr
    assert failed.returncode == 1, said
    assert "Failed" in said and "HEAD:navigate.xml -> navigate.xml: behaviour changed" in said
    assert 'B retries PipelineSequence "NavigateWithReplanning" 5 times instead of 6' in said
    assert sh(repo, env, "git", "rev-parse", "HEAD").stdout == head

    # pre-commit's own SKIP acknowledges it
    skipped = sh(repo, env, "git", "commit", "-qam", "fewer retries", check=False, SKIP="schemalog-diff")
    said = skipped.stdout + skipped.stderr
    assert skipped.returncode == 0, said
    assert "schemalog diff (BT.CPP behaviour against HEAD)" in said and "Skipped" in said
    assert sh(repo, env, "git", "rev-parse", "HEAD").stdout != head


def test_the_lint_hook_fails_a_read_nothing_writes_and_passes_the_tree_as_nav2_ships_it(tmp_path):
    """The published schemalog-lint hook (with `language: system`, as above): Nav2's tree with
    the nav2 profile commits; with one port reading a mistyped entry, the commit fails with the
    finding at its line and the entry it meant; a package.xml among the changed files is skipped."""
    hook = {**published_hook("schemalog-lint"), "language": "system",
            "args": ["--nodes", "nav2_tree_nodes.xml", "--profile", "nav2"]}
    config = yaml.safe_dump({"repos": [{"repo": "local", "hooks": [hook]}]}, sort_keys=False)
    original = NAVIGATE.read_text(encoding="utf-8")
    repo, env = new_repository(tmp_path, {".pre-commit-config.yaml": config,
                                          "nav2_tree_nodes.xml": (NAV2 / "nav2_tree_nodes.xml").read_text("utf-8")})
    assert pre_commit(repo, env, "install").returncode == 0
    (repo / "navigate.xml").write_text(original, encoding="utf-8")
    (repo / "package.xml").write_text("<package format=\"3\"><name>robot</name></package>\n", encoding="utf-8")
    sh(repo, env, "git", "add", ".")
    ok = sh(repo, env, "git", "commit", "-qm", "trees", check=False)
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert "package.xml: not a BT.CPP tree" in ok.stdout + ok.stderr or "Passed" in ok.stdout + ok.stderr
    typo = original.replace('<FollowPath path="{path}"', '<FollowPath path="{paht}"', 1)
    assert typo != original
    (repo / "navigate.xml").write_text(typo, encoding="utf-8")
    failed = sh(repo, env, "git", "commit", "-qam", "typo", check=False)
    said = failed.stdout + failed.stderr
    line = next(i for i, t in enumerate(typo.splitlines(), 1) if "{paht}" in t)
    assert failed.returncode == 1, said
    assert f"navigate.xml:{line}:" in said and "{paht}" in said and "did you mean {path}" in said


# -- docs/behaviour_trees.md's configurations, read out of the page -------------------------------

def doc_blocks(language: str) -> list[str]:
    """The fenced blocks of `language` in docs/behaviour_trees.md's section "In CI"."""
    import re

    page = (ROOT / "docs" / "behaviour_trees.md").read_text(encoding="utf-8")
    section = page[page.index("## In CI: pre-commit and GitHub Actions"):]
    return re.findall(rf"^```{language}\n(.*?)^```$", section, flags=re.S | re.M)


def test_the_documented_pre_commit_config_names_the_published_hook():
    (config, _workflow) = doc_blocks("yaml")
    (repo,) = yaml.safe_load(config)["repos"]
    (hook,) = repo["hooks"]
    assert hook["id"] == published_hook()["id"] == "schemalog-diff"
    assert hook["args"][0] == "--nodes"
    import re

    pattern = re.compile(hook["files"])          # pre-commit's files: a Python regular expression
    assert pattern.search("behavior_trees/navigate.xml") and not pattern.search("package.xml")


def workflow_steps() -> dict:
    (_config, workflow) = doc_blocks("yaml")
    flow = yaml.safe_load(workflow)
    # YAML 1.1 reads the key `on` as True: GitHub reads it as `on`
    on = flow.get("on", flow.get(True))
    assert {"labeled", "unlabeled", "synchronize"} <= set(on["pull_request"]["types"])
    assert flow["permissions"]["pull-requests"] == "write"
    steps = flow["jobs"]["schemalog-diff"]["steps"]
    assert steps[0]["uses"].startswith("actions/checkout@") and steps[0]["with"]["fetch-depth"] == 0
    for step in steps:
        assert "${{" not in step.get("run", ""), f"an expression inside run: ({step.get('name')}): pass it by env:"
    return {s.get("id") or s.get("name") or s["uses"]: s for s in steps}


def run_step(step: dict, repo: Path, env: dict, expressions: dict) -> subprocess.CompletedProcess:
    """Run a step's script as GitHub's runner does (shell: bash), its env's expressions evaluated."""
    import re

    assert step["shell"] == "bash"
    values = {}
    for key, value in step.get("env", {}).items():
        for expression in re.findall(r"\$\{\{.*?\}\}", value):
            assert expression in expressions, f"an expression this test does not evaluate: {expression}"
            value = value.replace(expression, expressions[expression])
        values[key] = value
    script = repo.parent / "step.sh"
    script.write_text(step["run"], encoding="utf-8")
    return sh(repo, env, "bash", "--noprofile", "--norc", "-eo", "pipefail", str(script), check=False, **values)


def test_the_documented_workflow_fails_a_change_unless_labelled(tmp_path):
    steps = workflow_steps()
    diff_step, policy = steps["diff"], steps["A behaviour change needs the behaviour-change label"]
    assert steps["Post the report"]["with"]["path"] == "diff.md"
    original = NAVIGATE.read_text(encoding="utf-8")
    repo = tmp_path / "robot"
    (repo / "behavior_trees").mkdir(parents=True)
    env = environment(tmp_path)
    (repo / "behavior_trees" / "navigate.xml").write_text(original, encoding="utf-8")
    (repo / "behavior_trees" / "nav2_tree_nodes.xml").write_text((NAV2 / "nav2_tree_nodes.xml").read_text("utf-8"))
    (repo / "package.xml").write_text("<package format=\"3\"><name>robot</name></package>\n", encoding="utf-8")
    sh(repo, env, "git", "init", "-q", "-b", "main")
    sh(repo, env, "git", "add", ".")
    sh(repo, env, "git", "commit", "-qm", "base")
    sh(repo, env, "git", "update-ref", "refs/remotes/origin/main", "HEAD")   # what fetch-depth: 0 brings

    def pull_request(text: str, label: bool) -> tuple[str, subprocess.CompletedProcess, Path]:
        sh(repo, env, "git", "checkout", "-q", "--detach", "origin/main")
        (repo / "behavior_trees" / "navigate.xml").write_text(text, encoding="utf-8")
        (repo / "package.xml").write_text("<package format=\"3\"><name>robot2</name></package>\n", encoding="utf-8")
        sh(repo, env, "git", "commit", "-qam", "the pull request")     # as the merge actions/checkout makes
        (repo / "diff.md").unlink(missing_ok=True)
        outputs = tmp_path / "github_output"
        outputs.write_text("")
        compared = run_step(diff_step, repo, env, {"${{ github.base_ref }}": "main"})
        assert compared.returncode == 0, compared.stdout + compared.stderr
        status = dict(line.split("=", 1) for line in outputs.read_text().split())["status"]
        return status, run_step(policy, repo, env, {
            "${{ steps.diff.outputs.status }}": status,
            "${{ contains(github.event.pull_request.labels.*.name, 'behaviour-change') }}": str(label).lower()}), \
            repo / "diff.md"

    env["GITHUB_OUTPUT"] = str(tmp_path / "github_output")
    changed = original.replace('number_of_retries="6"', 'number_of_retries="5"')
    status, verdict, report = pull_request(changed, label=False)
    assert status == "1" and verdict.returncode == 1, verdict.stdout + verdict.stderr
    assert "::error::behaviour changed" in verdict.stdout
    text = report.read_text(encoding="utf-8")
    assert text.startswith("## schemalog diff against origin/main: 2 paths: 1 changed, 1 skipped\n\n"
                           "### schemalog diff: behaviour changed")
    assert "`origin/main:behavior\\_trees/navigate.xml` → `behavior\\_trees/navigate.xml`" in text
    assert "package.xml: not a BT.CPP tree" in text

    status, verdict, _ = pull_request(changed, label=True)
    assert status == "1" and verdict.returncode == 0 and "acknowledged" in verdict.stdout, verdict.stdout

    refactored = original.replace('<RecoveryNode number_of_retries="6" name="NavigateRecovery">',
                                  '<RecoveryNode name="NavigateRecovery" number_of_retries="6">')
    assert refactored != original
    status, verdict, report = pull_request(refactored, label=False)
    assert status == "0" and verdict.returncode == 0 and "same behaviour" in verdict.stdout, verdict.stdout
    assert report.read_text(encoding="utf-8").startswith("## schemalog diff against origin/main: 2 paths: 1 same, "
                                                         "1 skipped\n\n### schemalog diff: same behaviour")
