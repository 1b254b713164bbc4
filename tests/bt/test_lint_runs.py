"""The run rules of `schemalog lint` (bt/lint_runs.py; docs/lint.md, "Run rules"): each finds its
minimal tree at the right file:line:column and stays silent where it must; a limit makes a
"not decided" warning, never a claim; the fixtures (real trees with one fault put in, under
tests/bt/lint_fixtures/runs_*) are found, and real BT.CPP shows the same faults (behaviortreepy's
Tree.tick_once hanging, bounded by a timeout; the harness never ticking the unreachable node);
the corpus gives no error, and its warnings are the ones docs/lint.md lists."""

from __future__ import annotations

import json
import random
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import schemalog.bt.lint_runs as lint_runs
from schemalog.api.behaviour_trees import read_semantics, read_tree
from schemalog.bt.lint_runs import run_findings
from schemalog.bt.semantics import RUNNING, SUCCESS, Rule
from schemalog.errors import SchemalogError
from schemalog.formats.btxml import read_bt

HERE = Path(__file__).resolve().parent
CORPUS = HERE / "corpus"
NODES = CORPUS / "nav2" / "nav2_tree_nodes.xml"
FIXTURES = HERE / "lint_fixtures"
NAV2_FIXTURE = FIXTURES / "runs_nav2_fallback_behind_always_success.xml"
REPEAT_FIXTURE = FIXTURES / "runs_repeat_forever.xml"
MAIN_OF = {"log_test.xml": "Main", "t15_nodes_mocking.xml": "MainTree"}      # as tests/bt/test_btxml.py


def tree(body: str, file: str = "t.xml", version: str = "4"):
    return read_bt(f'<root BTCPP_format="{version}">\n<BehaviorTree ID="Main">\n{body}\n</BehaviorTree>\n</root>',
                   file)


def found(findings, code: str) -> list[tuple[str, int, int, str]]:
    return [(f.pos.file, f.pos.line, f.pos.column, f.severity) for f in findings if f.code == code]


# -- unreachable -----------------------------------------------------------------------------

@pytest.mark.parametrize("body, line, column, why", [
    # a Fallback child after AlwaysSuccess: the Sequence is named, not its leaves
    ("<Fallback>\n  <AlwaysSuccess/>\n  <Sequence>\n    <A/>\n    <B/>\n  </Sequence>\n</Fallback>", 5, 3,
     "never gets past AlwaysSuccess"),
    # a Sequence child after AlwaysFailure
    ("<Sequence>\n  <AlwaysFailure/>\n  <A/>\n</Sequence>", 5, 3, "never gets past AlwaysFailure"),
    # the else branch behind a condition its sibling decides
    ("<IfThenElse>\n  <Inverter><AlwaysFailure/></Inverter>\n  <A/>\n  <B/>\n</IfThenElse>", 6, 3, "never ticks it"),
    # a Switch case whose key no value can match: an earlier case has the same key
    ('<Switch2 variable="{v}" case_1="1" case_2="1">\n  <A/>\n  <B/>\n  <C/>\n</Switch2>', 5, 3,
     "never selects its case"),
])
def test_unreachable_names_the_topmost_node_no_run_ticks(body, line, column, why):
    findings = run_findings(tree(body))
    assert found(findings, "unreachable") == [("t.xml", line, column, "warning")]
    assert why in next(f.message for f in findings if f.code == "unreachable")


@pytest.mark.parametrize("body", [
    "<Fallback>\n  <C/>\n  <A/>\n</Fallback>",                         # a condition may fail: every outcome possible
    "<Sequence>\n  <A/>\n  <B/>\n</Sequence>",
    '<Switch2 variable="{v}" case_1="1" case_2="2">\n  <A/>\n  <B/>\n  <C/>\n</Switch2>',
    "<ReactiveSequence>\n  <C/>\n  <A/>\n</ReactiveSequence>",
])
def test_unreachable_is_silent_where_every_node_runs_on_some_run(body):
    assert run_findings(tree(body)) == []


def test_a_tree_called_twice_is_reached_if_either_call_reaches_it():
    """A SubTree call behind AlwaysSuccess is named; the tree it calls is not, as the other call
    reaches it."""
    d = read_bt('<root BTCPP_format="4" main_tree_to_execute="Main"><BehaviorTree ID="Main"><Sequence>\n'
                '<SubTree ID="S" _autoremap="true"/>\n<Fallback><AlwaysSuccess/><SubTree ID="S" _autoremap="true"/>'
                '</Fallback>\n</Sequence></BehaviorTree>\n<BehaviorTree ID="S"><A/></BehaviorTree></root>', "two.xml")
    assert found(run_findings(d), "unreachable") == [("two.xml", 3, 27, "warning")]


# -- endless -----------------------------------------------------------------------------------

@pytest.mark.parametrize("body, version, where", [
    # BT.CPP 4: Repeat returns RUNNING with a wake-up signal after each success, Tree::tickOnce
    # ticks again at once, for ever (repeat_node.cpp, Tree::tickRoot)
    ('<Repeat num_cycles="-1">\n  <AlwaysSuccess/>\n</Repeat>', "4", "Tree::tickOnce"),
    ('<RetryUntilSuccessful num_attempts="-1">\n  <AlwaysFailure/>\n</RetryUntilSuccessful>', "4", "Tree::tickOnce"),
    # BT.CPP 3.8 loops inside the tick (BT.CPP #395): the root tick itself never returns
    ('<Repeat num_cycles="-1">\n  <AlwaysSuccess/>\n</Repeat>', "3", "the root tick never returns"),
])
def test_endless_is_an_error_where_no_environment_ends_the_loop(body, version, where):
    findings = run_findings(tree(body, version=version))
    assert found(findings, "endless") == [("t.xml", 3, 1, "error")]
    assert where in next(f.message for f in findings if f.code == "endless")


def test_endless_is_a_warning_where_the_leaves_decide():
    """RetryUntilSuccessful -1 over a Condition: on the runs where it fails at once every time,
    tickOnce never returns (BT.CPP #395), but a success ends it: the model does not know."""
    findings = run_findings(tree('<RetryUntilSuccessful num_attempts="-1">\n  <C/>\n</RetryUntilSuccessful>'))
    assert found(findings, "endless") == [("t.xml", 3, 1, "warning")]
    assert "tick C -> FAILURE" in findings[0].message


@pytest.mark.parametrize("body", [
    '<Repeat num_cycles="3">\n  <AlwaysSuccess/>\n</Repeat>',
    '<Repeat num_cycles="-1">\n  <Sleep msec="10"/>\n</Repeat>',          # RUNNING between turns: the call returns
    "<KeepRunningUntilFailure>\n  <AlwaysSuccess/>\n</KeepRunningUntilFailure>",   # no wake-up signal
])
def test_endless_is_silent_where_every_executor_call_returns(body):
    assert found(run_findings(tree(body)), "endless") == []


def test_a_tree_that_never_finishes_is_a_warning_and_a_finishing_one_is_silent():
    endless = run_findings(tree("<KeepRunningUntilFailure>\n  <AlwaysSuccess/>\n</KeepRunningUntilFailure>"))
    assert found(endless, "endless-tree") == [("t.xml", 3, 1, "warning")]
    assert "by design" in endless[0].message and "endless-tree" in endless[0].hint
    assert found(run_findings(tree("<KeepRunningUntilFailure>\n  <A/>\n</KeepRunningUntilFailure>")),
                 "endless-tree") == []


# -- halt-safety -------------------------------------------------------------------------------

def _leaky(run, n):
    """A custom control that returns SUCCESS as soon as its child runs, leaving it RUNNING."""
    run.set_status(n, RUNNING)
    status = run.tick(n.kids[0])
    return SUCCESS if status is RUNNING else status


def test_halt_safety_finds_a_child_a_custom_control_leaves_running():
    d = tree("<Sequence>\n  <Leaky>\n    <A/>\n  </Leaky>\n  <B/>\n</Sequence>")
    findings = run_findings(d, {"Leaky": Rule(_leaky)})
    assert found(findings, "halt-safety") == [("t.xml", 5, 5, "error")]
    assert "Leaky" in findings[0].message and "RUNNING" in findings[0].message


@pytest.mark.parametrize("body", [
    "<Parallel success_count=\"1\">\n  <A/>\n  <B/>\n</Parallel>",
    "<ReactiveSequence>\n  <C/>\n  <A/>\n</ReactiveSequence>",
    "<Leaky>\n  <A/>\n</Leaky>",                   # an opaque custom control may do anything: not claimed
])
def test_halt_safety_is_silent_on_btcpps_own_nodes_and_opaque_ones(body):
    assert found(run_findings(tree(body)), "halt-safety") == []


CONTROLS = ("Sequence", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory", "Parallel",
            "IfThenElse", "WhileDoElse", "PipelineSequence", "RecoveryNode", "RoundRobin")
DECORATORS = ("Inverter", "ForceSuccess", "RetryUntilSuccessful", "Repeat", "KeepRunningUntilFailure", "RunOnce",
              "Timeout", "Delay", "RateController")
ATTRS = {"RetryUntilSuccessful": ' num_attempts="2"', "Repeat": ' num_cycles="2"', "Timeout": ' msec="5"',
         "Delay": ' delay_msec="5"', "RateController": ' hz="1"', "Parallel": ' success_count="1"'}


@st.composite
def trees(draw, depth=0):
    if depth >= 2 or draw(st.integers(0, 2)) == 0:
        return f"<{draw(st.sampled_from(('A', 'B', 'C', 'AlwaysSuccess', 'AlwaysFailure')))}/>"
    if draw(st.booleans()):
        t = draw(st.sampled_from(DECORATORS))
        return f"<{t}{ATTRS.get(t, '')}>{draw(trees(depth + 1))}</{t}>"
    t = draw(st.sampled_from(CONTROLS))
    count = {"IfThenElse": 3, "WhileDoElse": 3, "RecoveryNode": 2}.get(t) or draw(st.integers(1, 3))
    return f"<{t}{ATTRS.get(t, '')}>{''.join(draw(trees(depth + 1)) for _ in range(count))}</{t}>"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(trees())
def test_btcpps_own_nodes_never_leave_a_child_running_unhalted(body):
    """Over random trees of BT.CPP's and Nav2's controls and decorators: no halt-safety finding,
    which is why the rule reports nothing for BT.CPP's own nodes (docs/lint.md)."""
    try:
        d = tree(body)
    except SchemalogError:
        return                                   # a child count the reader refuses
    assert found(run_findings(d, read_semantics(profiles=["nav2"]), max_states=3_000), "halt-safety") == []


# -- by parts, and limits ----------------------------------------------------------------------

@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(trees())
def test_by_parts_claims_no_more_than_the_whole_runs(body):
    """Past WHOLE_STATES the rules go by parts: what parts call unreachable or endless-tree is
    so on the whole runs too (the parts over-approximate; they may miss, never invent)."""
    try:
        d = tree(body)
    except SchemalogError:
        return
    rules = read_semantics(profiles=["nav2"])
    whole = run_findings(d, rules)
    if any(f.code == "not-decided" for f in whole):
        return
    saved = lint_runs.WHOLE_STATES
    try:
        lint_runs.WHOLE_STATES = 1
        parts = run_findings(d, rules)
    finally:
        lint_runs.WHOLE_STATES = saved
    for code in ("unreachable", "endless-tree"):
        assert set(found(parts, code)) <= set(found(whole, code)), code


def test_a_limit_makes_a_not_decided_warning_and_no_claim():
    """Cut short (max_states too small for a part), no rule claims what was not explored."""
    d = tree("<Fallback>\n  <Sequence><A/><B/><A/><B/></Sequence>\n  <AlwaysSuccess/>\n  <C/>\n</Fallback>")
    saved = lint_runs.WHOLE_STATES
    try:
        lint_runs.WHOLE_STATES = 1
        findings = run_findings(d, max_states=2)
    finally:
        lint_runs.WHOLE_STATES = saved
    assert [f.code for f in findings] == ["not-decided"]
    assert findings[0].severity == "warning" and "unreachable" in findings[0].message
    # decided with the states it needs: the C behind AlwaysSuccess is unreachable
    assert found(run_findings(d), "unreachable") == [("t.xml", 6, 3, "warning")]


# -- the fixtures ------------------------------------------------------------------------------

def test_the_nav2_fixture_names_the_roundrobin_behind_always_success():
    d = read_tree(NAV2_FIXTURE, [NODES])
    findings = run_findings(d, read_semantics(profiles=["nav2"]))
    assert [(f.code, f.pos.line, f.pos.column, f.severity) for f in findings] == [("unreachable", 32, 9, "warning")]
    assert 'RoundRobin "RecoveryActions"' in findings[0].message and "SkipRecoveries" in findings[0].message
    # the tree as Nav2 ships it: nothing
    assert run_findings(read_tree(CORPUS / "nav2" / NAV2_FIXTURE.name.replace(
        "runs_nav2_fallback_behind_always_success", "navigate_to_pose_w_replanning_and_recovery"), [NODES]),
        read_semantics(profiles=["nav2"])) == []


def test_the_repeat_fixture_hangs_and_its_second_call_is_never_reached():
    findings = run_findings(read_tree(REPEAT_FIXTURE, main="Main"))
    assert sorted((f.code, f.pos.line, f.pos.column, f.severity) for f in findings) == [
        ("endless", 19, 13, "error"), ("endless-tree", 11, 9, "warning"), ("unreachable", 13, 13, "warning")]
    endless = next(f for f in findings if f.code == "endless")
    assert "Tree::tickOnce" in endless.message and "Sleep" in endless.message       # the run: after the Sleep
    assert run_findings(read_tree(CORPUS / "btcpp" / "examples" / "test_files" / "log_test.xml", main="Main")) == []


# -- real BT.CPP shows the faults --------------------------------------------------------------

TICK_ONCE = """
import sys, behaviortreepy as bt
factory = bt.BehaviorTreeFactory()
factory.register_behavior_tree_from_text(open(sys.argv[1]).read())
tree = factory.create_tree("Main")
for i in range(2000):
    status = tree.tick_once()                    # Nav2's BehaviorTreeEngine::run calls tickOnce
    print(i, status, flush=True)
    if status != bt.NodeStatus.RUNNING:
        break
    tree.sleep(10)
"""


def tick_once(xml: Path, tmp_path: Path, timeout: float) -> tuple[bool, list[str]]:
    """Tick the file's tree with Tree::tickOnce until it finishes, in real BT.CPP: (whether a
    call hung past `timeout` seconds, the statuses the calls returned)."""
    pytest.importorskip("behaviortreepy")
    script = tmp_path / "tick_once.py"
    script.write_text(TICK_ONCE)
    proc = subprocess.Popen([sys.executable, str(script), str(xml)], stdout=subprocess.PIPE, text=True)
    try:
        out, _ = proc.communicate(timeout=timeout)
        return False, out.split("\n")
    except subprocess.TimeoutExpired:
        proc.kill()
        out, _ = proc.communicate()
        return True, out.split("\n")


def test_btcpp_hangs_in_tick_once_where_endless_says_so(tmp_path):
    """The repeat fixture in BT.CPP 4: the Sleep returns RUNNING (each tickOnce returns), then the
    Repeat's wake-up signals keep one tickOnce call for ever; as shipped, the tree finishes."""
    hung, lines = tick_once(REPEAT_FIXTURE, tmp_path, timeout=20)
    assert hung and lines and all("RUNNING" in line for line in lines if line)
    hung, lines = tick_once(CORPUS / "btcpp" / "examples" / "test_files" / "log_test.xml", tmp_path, timeout=20)
    assert not hung and "SUCCESS" in lines[-2]




def ticked_in_btcpp(harness: str, xml: Path, tmp_path: Path, seeds: int) -> set[str]:
    """The names of the leaves BT.CPP 4.8.2 ticks in `seeds` runs of random draws (the harness's
    scheme: tests/bt/test_btcpp_harness.py), 40 root ticks each."""
    draws = tmp_path / "draws.txt"
    rngs = [random.Random(s) for s in range(seeds)]
    draws.write_text("".join(f"{s} {' '.join(str(rng.randrange(6)) for _ in range(1000))}\n" for s, rng in enumerate(rngs)))
    done = subprocess.run([harness, "--tree", str(xml), "--models", str(NODES), "--draws", str(draws),
                           "--max-ticks", "40"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    events = (json.loads(line) for line in done.stdout.splitlines() if line.startswith("{"))   # not BT.CPP's warnings
    return {e["name"] for e in events if e["ev"] == "tick"}


def test_btcpp_never_ticks_what_unreachable_names(harness, tmp_path):
    """200 runs of the Nav2 fixture in BT.CPP: no recovery action is ever ticked; the same draws
    on the tree as Nav2 ships it tick them all."""
    leaves = {"ClearLocalCostmap-Subtree", "ClearGlobalCostmap-Subtree", "Spin", "Wait", "BackUp"}
    assert not leaves & ticked_in_btcpp(harness, NAV2_FIXTURE, tmp_path, 200)
    assert leaves <= ticked_in_btcpp(harness, CORPUS / "nav2" / "navigate_to_pose_w_replanning_and_recovery.xml",
                                     tmp_path, 200)


# -- the corpus: no error on a tree BT.CPP runs ------------------------------------------------

def corpus() -> list[tuple[Path, bool]]:
    out = []
    for p in sorted(CORPUS.rglob("*.xml")):
        if p == NODES or "combat" in p.parts:
            continue
        out.append((p, p.parent.name == "nav2" or "btcpp3" in p.parts))
    return out


@pytest.mark.parametrize("path, nav2", corpus(), ids=lambda x: str(x.relative_to(CORPUS)) if isinstance(x, Path) else "")
def test_the_corpus_gives_no_error_and_only_the_listed_warnings(path, nav2):
    try:
        d = read_tree(path, [NODES] if nav2 else [], main=MAIN_OF.get(path.name))
    except SchemalogError:
        pytest.skip("not a program schemalog reads on its own (tests/bt/test_btxml.py)")
    findings = run_findings(d, read_semantics(profiles=["nav2"]) if nav2 else None)
    assert not [f for f in findings if f.severity == "error"]
    # docs/lint.md, "Run rules": the one warning, and why it is true
    expected = [("not-decided", "endless")] if path.name == "nav2_goal_patience_v4.xml" else []
    assert [(f.code, f.message.split(":")[1].strip()) for f in findings] == expected


def test_the_combat_robot_gives_no_error_and_its_true_warnings():
    """The 596-node combat robot (all its files, --task rmuc_2026): its KeepRunningUntilFailure
    never succeeds, so what follows it in two recovery Sequences never runs; the main tree loops
    by design."""
    d = read_tree(CORPUS / "combat" / "behavior_trees", main="rmuc_2026")
    findings = run_findings(d)
    assert sorted((f.code, Path(f.pos.file).name, f.pos.line, f.severity) for f in findings) == [
        ("endless-tree", "rmuc_2026.xml", 58, "warning"),
        ("unreachable", "rmuc_2026_recovery.xml", 95, "warning"),
        ("unreachable", "rmuc_2026_recovery.xml", 135, "warning")]


def test_a_program_silences_a_tree_that_loops_by_design_but_never_an_error(tmp_path):
    """issue 43: a tree that never completes is a warning many robots want (a main loop); an
    entries file's `silence:` drops it and says so; an endless root tick (an error) stays."""

    fixture = Path(__file__).resolve().parent / "lint_fixtures" / "runs_repeat_forever.xml"
    quiet = tmp_path / "entries.yaml"
    quiet.write_text("silence:\n  endless-tree: the robot's main loop, by design\n", encoding="utf-8")
    r = subprocess.run([sys.executable, "-m", "schemalog", "lint", str(fixture), "--task", "Main", "--provided",
                        str(quiet)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 1
    assert "[endless-tree]" not in r.stdout and "[endless]" in r.stdout
    assert f"note: 1 endless-tree finding silenced by {quiet}:2" in r.stderr
    quiet.write_text("silence:\n  endless: no\n", encoding="utf-8")
    r = subprocess.run([sys.executable, "-m", "schemalog", "lint", str(fixture), "--task", "Main", "--provided",
                        str(quiet)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 1 and f"{quiet}:2:3: error: 'endless': `silence:` takes" in r.stderr
