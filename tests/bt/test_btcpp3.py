"""BT.CPP 3 files: read as BT.CPP 3.8 reads them, proved under 3.8's rules (bt/semantics_v3.py), and
against their BT.CPP 4 conversions (docs/behaviour_trees.md, "BT.CPP 3 files").

The golden tests take one rule of 3.8 that differs from 4's: a minimal tree whose runs differ under
the two versions is refuted across them, and proved equal to itself under each. The source each
cites is BehaviorTree.CPP's tag 3.8.8 (commit 9d624dc7)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from schemalog.api.behaviour_trees import prove_trees, read_tree
from schemalog.bt.semantics import RULES
from schemalog.bt.semantics_v3 import RULES_V3
from schemalog.errors import SchemalogError
from schemalog.formats.btxml import read_bt

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "bt" / "corpus"
V3 = CORPUS / "btcpp3"
NODES = CORPUS / "nav2" / "nav2_tree_nodes.xml"


def doc(body: str, version: int | None = None, mark: str = ""):
    return read_bt(f'<root{mark} main_tree_to_execute="M">\n<BehaviorTree ID="M">\n{body}\n</BehaviorTree>\n</root>',
                   "t.xml", version=version)


def prove(a, b, **kw):
    return prove_trees(a, b, 100_000, **kw)


def across(v3_body: str, v4_body: str | None = None, **kw):
    """The verdict on a tree read under 3.8 against (its conversion) read under 4, after checking
    each is proved equal to itself under its own version."""
    a, b = doc(v3_body, 3), doc(v4_body or v3_body, 4)
    for d in (a, b):
        same = prove(d, d, **kw)
        assert same.equal and same.complete, same.reason
    return prove(a, b, **kw)


# ---------------------------------------------------------------------------------------------
# Golden: each rule of 3.8 that is not 4's

def test_sequence_star_does_not_yield_between_children():
    """SequenceStarNode::tick (3.8, src/controls/sequence_star_node.cpp: `case SUCCESS:
    current_child_idx_++; break;` and the loop goes on) ticks the next child in the same tick;
    4's SequenceWithMemory returns RUNNING after a child that succeeded from IDLE."""
    v = across("<SequenceStar><A/><B/></SequenceStar>", "<SequenceWithMemory><A/><B/></SequenceWithMemory>",
               run_once=True)
    assert not v.equal and v.complete
    assert "a goes on with tick B" in v.reason and "b's root tick ends with RUNNING" in v.reason
    assert v.under == "BT.CPP 3.8 (a) against BT.CPP 4 (b)"


def test_sequence_star_forgets_its_index_when_halted():
    """SequenceStarNode::halt (3.8: `current_child_idx_ = 0; ControlNode::halt();`): after a
    haltTree the sequence starts over at its first child; 4's SequenceWithMemory::halt keeps the
    index, so 4 goes on at the child it had reached."""
    from schemalog.bt.semantics import RUNNING, SUCCESS, Await, advance, halt_tree_step, initial, program, step

    def finish(move, prog, config, answers):
        s = move(prog, config)
        while isinstance(s, Await):
            config = advance(s.config, answers.pop(0) if s.options != (None,) else None)
            s = move(prog, config)
        return s.config

    def first_after_halt(d) -> str:
        prog, answers = program(d), [SUCCESS, RUNNING]          # A succeeds, B runs
        config = finish(step, prog, initial(), answers)
        while answers:                                        # 4 ticks B in a second root tick
            config = finish(step, prog, config, answers)
        config = finish(halt_tree_step, prog, config, [])      # the executor halts the tree
        return step(prog, config).event.node[1][0]

    assert first_after_halt(doc("<SequenceStar><A/><B/></SequenceStar>", 3)) == "A"
    assert first_after_halt(doc("<SequenceWithMemory><A/><B/></SequenceWithMemory>", 4)) == "B"


def test_parallel_counts_again_every_tick_in_child_order():
    """ParallelNode::tick (3.8, src/controls/parallel_node.cpp: success_childred_num counted from 0
    each tick, `if (success_childred_num == successThreshold())` child by child): with C done,
    A's success does not reach 2 before B is ticked; 4 keeps its counts and succeeds at A."""
    v = across('<Parallel success_threshold="2" failure_threshold="1"><A/><B/><C/></Parallel>',
               '<Parallel success_count="2" failure_count="1"><A/><B/><C/></Parallel>', run_once=True)
    assert not v.equal and "a tick B" in v.reason and "b halt B" in v.reason


def test_parallel_needs_its_success_threshold():
    """ParallelNode::tick (3.8): `if (!getInput(THRESHOLD_SUCCESS, ...)) throw RuntimeError(
    "Missing parameter [success_threshold] in ParallelNode")`; 4's success_count defaults to -1."""
    v = prove(doc("<Parallel><A/><B/></Parallel>", 3), doc("<Parallel><A/><B/></Parallel>", 4))
    assert not v.equal and "Missing parameter [success_threshold] in ParallelNode" in v.reason


@pytest.mark.parametrize("decorator, port", [("Repeat", "num_cycles"), ("RetryUntilSuccessful", "num_attempts")])
def test_repeat_and_retry_loop_within_one_tick(decorator, port):
    """RepeatNode::tick / RetryNode::tick (3.8, src/decorators/repeat_node.cpp, retry_node.cpp:
    `while (repeat_count_ < num_cycles_ ...)` with no return after a completed child): the
    child is ticked again in the same tick; 4 returns RUNNING in between (emitWakeUpSignal)."""
    v = across(f'<{decorator} {port}="2"><A/></{decorator}>', run_once=True)
    assert not v.equal and "a goes on with tick A" in v.reason and "b's root tick ends with RUNNING" in v.reason


def test_switch_compares_strings_not_numbers():
    """SwitchNode<N>::tick (3.8, controls/switch_node.h: `if (found && variable == value)`, two
    std::strings): "1" is not "1.0", so the default runs; 4 compares them as numbers."""
    v = across('<Switch2 variable="1" case_1="1.0" case_2="7"><A/><B/><C/></Switch2>', run_once=True)
    assert not v.equal and "a tick C" in v.reason and "b tick A" in v.reason


def test_while_do_else_needs_three_children():
    """WhileDoElseNode::tick (3.8, src/controls/while_do_else_node.cpp: `if (children_count != 3)
    throw std::logic_error("WhileDoElse must have 3 children")`); 4 takes 2 or 3."""
    v = across("<WhileDoElse><A/><B/></WhileDoElse>", run_once=True)
    assert not v.equal and "WhileDoElse must have 3 children" in v.reason


def test_blackboard_check_runs_its_child_only_on_a_match():
    """BlackboardPreconditionNode<T>::tick (3.8, decorators/blackboard_precondition.h): the child
    when value_A equals value_B, else return_on_mismatch; literals compare as T (3 == 3.0 as
    doubles, not as strings)."""
    for kind, a, b, runs in (("Double", "3", "3.0", True), ("String", "3", "3.0", False),
                             ("Int", "4", "4", True)):
        d = doc(f'<BlackboardCheck{kind} value_A="{a}" value_B="{b}" return_on_mismatch="SUCCESS"><A/>'
                f'</BlackboardCheck{kind}>', 3)
        other = doc("<A/>" if runs else "<AlwaysSuccess/>", 3)
        v = prove(d, other, run_once=True)
        assert v.equal and v.complete, (kind, v.reason)


def test_an_opaque_node_never_returns_skipped_under_3_8():
    """3.8's NodeStatus has no SKIPPED (include/behaviortree_cpp_v3/basic_types.h): a custom
    control node under 3.8 returns SUCCESS, FAILURE or RUNNING; under 4 it may return SKIPPED."""
    d3, d4 = doc("<MyControl><A/></MyControl>", 3), doc("<MyControl><A/></MyControl>", 4)
    v = prove(d3, d4)
    assert v.equal and v.complete and "ported" in v.assumed     # ported: no SKIPPED assumed under 4


def test_where_3_8_and_4_agree_a_tree_and_its_conversion_prove_equal():
    """Sequence, Fallback, ReactiveSequence, ReactiveFallback, IfThenElse, Inverter, Force*,
    KeepRunningUntilFailure, Timeout, Delay and SubTree run under 4's very rules (the module's
    docstring names the 3.8 source of each), so a tree of them proves equal across versions."""
    body = ('<Sequence><ReactiveSequence><C/><Fallback><A/><Inverter><B/></Inverter></Fallback>'
            '</ReactiveSequence><IfThenElse><C/><ForceSuccess><A/></ForceSuccess><B/></IfThenElse>'
            '<Timeout msec="100"><KeepRunningUntilFailure><A/></KeepRunningUntilFailure></Timeout>'
            '<ReactiveFallback><C/><Delay delay_msec="5"><B/></Delay></ReactiveFallback></Sequence>')
    v = across(body)
    assert v.equal and v.complete, v.reason
    for t in ("Sequence", "ReactiveSequence", "Timeout", "Delay", "SubTree"):
        assert RULES_V3[t] is RULES[t]


def test_a_subtree_call_of_3_8_binds_keys_by_name():
    """recursivelyCreateTree (3.8, src/xml_parsing.cpp): an isolated SubTree's attribute
    goal="target" is addSubtreeRemapping(goal, target), 4's goal="{target}"; __shared_blackboard
    is 4's _autoremap; SubTreePlus reads `{key}` as 4 does."""
    sub = '<BehaviorTree ID="S"><Go to="{goal}"/></BehaviorTree>'

    def two(call: str, version: int, mark: str = ""):
        return read_bt(f'<root{mark} main_tree_to_execute="M"><BehaviorTree ID="M">{call}</BehaviorTree>{sub}</root>',
                       "t.xml", version=version)
    for v3_call, v4_call in (('<SubTree ID="S" goal="target"/>', '<SubTree ID="S" goal="{target}"/>'),
                             ('<SubTree ID="S" __shared_blackboard="true"/>', '<SubTree ID="S" _autoremap="true"/>'),
                             ('<SubTreePlus ID="S" goal="{target}"/>', '<SubTree ID="S" goal="{target}"/>')):
        v = prove(two(v3_call, 3), two(v4_call, 4))
        assert v.equal and v.complete, (v3_call, v.reason)
    v = prove(two('<SubTree ID="S" goal="{target}"/>', 3), two('<SubTree ID="S" goal="{target}"/>', 4))
    assert not v.equal                         # 3.8 binds the key "{target}", braces and all


# ---------------------------------------------------------------------------------------------
# Reading

@pytest.mark.parametrize("body, version", [
    ("<SequenceStar><A/></SequenceStar>", 3), ('<SubTreePlus ID="M2"/>', 3),
    ("<Script code=\"x:=1\"/>", 4), ('<A _skipIf="x"/>', 4), ("<Sequence><A/></Sequence>", 4)])
def test_an_unmarked_file_is_read_under_the_version_it_tells(body, version):
    text = (f'<root main_tree_to_execute="M"><BehaviorTree ID="M">{body}</BehaviorTree>'
            f'<BehaviorTree ID="M2"><A/></BehaviorTree></root>')
    d = read_bt(text, "t.xml")
    assert d.version == version and d.unmarked == (body == "<Sequence><A/></Sequence>")


REFUSED = [
    ("both tells", "<Sequence>\n<SequenceStar><A/></SequenceStar>\n<Script code=\"x:=1\"/>\n</Sequence>", "",
     None, (5, 1), "cannot be told"),
    ("unknown format", "<A/>", ' BTCPP_format="2"', None, (1, 1), "--btcpp"),
    ("v4 node under 3.8", "<Sequence>\n<Sleep msec=\"5\"/>\n</Sequence>", "", 3, (4, 1), "Node not recognized: Sleep"),
    ("v4 attribute under 3.8", '<A _skipIf="x"/>', "", 3, (3, 1), "BT.CPP 4 attribute"),
    ("3.8's misspelling", '<RetryUntilSuccesful num_attempts="2"><A/></RetryUntilSuccesful>', "", 3, (3, 1),
     "comments out"),
    ("a port 3.8 does not declare", '<Parallel success_count="1"><A/></Parallel>', "", 3, (3, 1), "Possible typo?"),
    ("shared blackboard not a boolean", '<SubTree ID="S" __shared_blackboard="yes"/>', "", 3, (3, 1),
     "not a boolean"),
    ("v3 node under 4", "<SequenceStar><A/></SequenceStar>", "", 4, (3, 1), "BT.CPP 3 node"),
]


@pytest.mark.parametrize("what, body, mark, version, where, words", REFUSED, ids=[r[0] for r in REFUSED])
def test_what_cannot_be_read_is_refused_where_it_is(what, body, mark, version, where, words):
    text = f'<root{mark} main_tree_to_execute="M">\n<BehaviorTree ID="M">\n{body}\n</BehaviorTree>\n' \
           f'<BehaviorTree ID="S"><A/></BehaviorTree>\n</root>'
    with pytest.raises(SchemalogError) as err:
        read_bt(text, "t.xml", version=version)
    assert (err.value.line, err.value.column) == where and words in err.value.message, err.value.message


def test_the_option_wins_over_the_mark_with_a_note():
    notes: list[str] = []
    d = read_bt('<root BTCPP_format="4"><BehaviorTree ID="M"><A/></BehaviorTree></root>', "t.xml", version=3,
                notes=notes)
    assert d.version == 3 and notes == ['note: t.xml:1:1: BTCPP_format="4", read under BT.CPP 3.8 as --btcpp says']


# ---------------------------------------------------------------------------------------------
# The default for a file with no mark and no tell: proved under both where they can differ

def test_an_unmarked_tree_is_proved_under_both_versions_where_they_differ():
    # a Repeat and its unrolled Sequence: equal under 3.8, told apart under 4 (RUNNING in between)
    a = doc('<Repeat num_cycles="2"><A/></Repeat>')
    b = doc("<Sequence><A/><A/></Sequence>")
    assert a.unmarked and b.unmarked
    v = prove(a, b, run_once=True)
    assert not v.equal and v.complete and "(under BT.CPP 4:" in v.reason      # found under 4, said so
    three = prove(a.under(3), b.under(3), run_once=True)
    assert three.equal and three.complete                 # 3.8 alone would have proved it


def test_an_unmarked_tree_of_nodes_both_run_alike_is_proved_once_and_says_so():
    a = doc("<Sequence><A/><Sequence><B/></Sequence></Sequence>")
    b = doc("<Sequence><A/><B/></Sequence>")
    v = prove(a, b)
    assert v.equal and v.complete and "BT.CPP 3.8 loads it too" in v.assumed


# ---------------------------------------------------------------------------------------------
# Real files and the command line

def run(*args):
    return subprocess.run([sys.executable, "-m", "schemalog", *map(str, args)], capture_output=True, text=True,
                          cwd=ROOT, timeout=600)


def test_nav2s_migration_to_4_changes_how_goal_patience_waits():
    """Nav2's goal-patience tree before and at its migration to BT.CPP 4 (efd777e20): the only
    change, SequenceStar -> SequenceWithMemory, makes the sequence return RUNNING after
    CancelControl, so PathLongerOnApproach decides again before Wait runs."""
    r = run("verify", V3 / "nav2_goal_patience_v3.xml", V3 / "nav2_goal_patience_v4.xml", "--btcpp", "3:4",
            "--nodes", NODES, "--profile", "nav2")
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout.startswith("refuted after") and "under BT.CPP 3.8 (a) against BT.CPP 4 (b) semantics" in r.stdout
    assert "a tick Wait" in r.stdout and "b choice of PathLongerOnApproach" in r.stdout
    same = run("verify", V3 / "nav2_goal_patience_v3.xml", V3 / "nav2_goal_patience_v3.xml", "--nodes", NODES)
    assert same.returncode == 0 and same.stdout.startswith("proved equal under BT.CPP 3.8 semantics"), same.stdout


def test_btcpp_option_end_to_end(tmp_path):
    mission = V3 / "aerostack2_basic_mission.xml"
    r = run("verify", mission, mission, "--btcpp", "4")
    assert r.returncode == 1 and "aerostack2_basic_mission.xml:5:9: error:" in r.stderr and "Traceback" not in r.stderr
    bad = run("verify", mission, "--btcpp", "3:4")
    assert bad.returncode == 2 and "two files" in bad.stderr
    worse = run("verify", mission, mission, "--btcpp", "5")
    assert worse.returncode == 2 and "--btcpp" in worse.stderr
    marked = tmp_path / "m.xml"
    marked.write_text(mission.read_text().replace("<root ", '<root BTCPP_format="4" '))
    noted = run("verify", marked, mission, "--btcpp", "3", "--json")
    assert noted.returncode == 0 and 'BTCPP_format="4", read under BT.CPP 3.8 as --btcpp says' in noted.stderr
    assert '"btcpp": "BT.CPP 3.8"' in noted.stdout
    out = tmp_path / "small.xml"
    c = run("compress", CORPUS / "nav2" / "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml",
            "--nodes", NODES, "-o", out)
    assert c.returncode in (0, 3), c.stderr
    if out.exists():
        assert 'BTCPP_format="3"' in out.read_text()
        assert read_tree(out, [NODES]).version == 3
