"""The nav2 profile (src/schemalog/bt/profiles/nav2.yaml): Nav2's own node types and their rules,
read from Nav2's source; `read_semantics(profiles=["nav2"])` and `--profile nav2` (issue 48)."""

from __future__ import annotations

import re

import pytest

from conftest import ROOT
from schemalog.api.behaviour_trees import PROFILES, profile_path, read_semantics, read_tree, prove_trees
from schemalog.bt.ports import BUILTIN
from schemalog.bt.semantics import CONDITION, RETICKED_ACTION, RULES, STATEFUL_ACTION, SYNC_ACTION
from schemalog.errors import SchemalogError

NAV2 = ROOT / "tests" / "bt" / "corpus" / "nav2"
NODES = NAV2 / "nav2_tree_nodes.xml"
PROFILE = profile_path("nav2")

# Nav2's controls and decorators the profile leaves opaque (its comment says why), and the four
# schemalog's own table defines
OPAQUE = {"NonblockingSequence", "PersistentSequence", "PauseResumeController", "DistanceController",
          "SpeedController", "GoalUpdatedController", "GoalUpdater", "PathLongerOnApproach", "SingleTrigger"}
IN_RULES = {"PipelineSequence", "RecoveryNode", "RoundRobin", "RateController"}
# Types the profile gives that the corpus's nav2_tree_nodes.xml (Nav2 88e5d9e, older than the
# profile's a3a9704) does not declare: added to Nav2 since, or (the last three) removed since
# and declared in no models file of the corpus
NEWER_THAN_THE_CORPUS_MODELS = {
    "AppendGoalPoseToGoals", "AreErrorCodesPresent", "ArePosesNear", "AssistedTeleop", "CancelAssistedTeleop",
    "CancelBackUp", "CancelComputeAndTrackRoute", "CancelControl", "CancelDriveOnHeading", "CancelFollowObject",
    "CancelSpin", "CancelWait", "CheckPoseOccupancy", "CheckStopStatus", "ClearCostmapAroundPose",
    "ClearCostmapAroundRobot", "ClearCostmapExceptRegion", "ComputeAndTrackRoute", "ComputeRoute",
    "ConcatenatePaths", "DockRobot", "DriveOnHeading", "ExtractRouteNodesAsGoals", "FollowObject",
    "GetCurrentPose", "GetNextFewGoals", "GetPoseFromPath", "GlobalUpdatedGoal", "IsBatteryCharging",
    "IsGoalNearby", "IsWithinPathTrackingBounds", "PathExpiringTimer", "PathHandlerSelector",
    "ProgressCheckerSelector", "RemoveInCollisionGoals", "SmoothPath", "SmootherSelector",
    "ToggleCollisionMonitor", "TruncatePathLocal", "UndockRobot", "ValidatePath", "WouldAControllerRecoveryHelp",
    "WouldAPlannerRecoveryHelp", "WouldARouteRecoveryHelp", "WouldASmootherRecoveryHelp",
    "IsPathValid", "IsPoseOccupied", "IsStopped"}


def corpus_models() -> dict[str, str]:
    """nav2_tree_nodes.xml's node types and their kinds."""
    return {m.group(2): m.group(1)
            for m in re.finditer(r'<(Action|Condition|Control|Decorator) ID="([^"]+)"', NODES.read_text())}


def test_the_profile_loads_and_gives_every_type_a_leaf_rule():
    rules = read_semantics(profiles=["nav2"])
    assert PROFILES == ("nav2",) and len(rules) == 71
    assert all(rule in (RETICKED_ACTION, SYNC_ACTION, STATEFUL_ACTION, CONDITION) for rule in rules.values())
    assert not set(rules) & set(BUILTIN) and not set(rules) & set(RULES)
    kinds = {k: sum(rule is r for rule in rules.values()) for k, r in
             (("StatefulAction", STATEFUL_ACTION), ("ReTickedAction", RETICKED_ACTION), ("SyncAction", SYNC_ACTION),
              ("Condition", CONDITION))}
    assert kinds == {"StatefulAction": 16, "ReTickedAction": 11, "SyncAction": 23, "Condition": 21}
    # Nav2's BtActionNode returns its last result when ticked again unreset (the profile's header)
    assert rules["FollowPath"] is STATEFUL_ACTION and rules["ComputePathToPose"] is STATEFUL_ACTION
    assert rules["ClearEntireCostmap"] is RETICKED_ACTION and rules["GoalUpdated"] is CONDITION
    assert rules["PlannerSelector"] is SYNC_ACTION     # a SyncActionNode: never RUNNING


def test_the_profile_says_where_each_entry_comes_from():
    text = PROFILE.read_text()
    assert "a3a97043ee93d92fe8d70ec56d183933169beb1c" in text
    entries = [line for line in text.splitlines() if line and not line.startswith("#")]
    assert len(entries) == 71
    for line in entries:
        assert re.fullmatch(r"\w+:\s+(StatefulAction|ReTickedAction|SyncAction|Condition)\s+# nav2_\w+/\S+\.cpp, "
                            r"\S.*", line), line
    for name in OPAQUE | IN_RULES:
        assert re.search(rf"\b{name}\b", text), name      # each named with why it is not an entry


def test_every_type_of_the_corpus_models_is_in_the_profile_or_accounted_for():
    models, rules = corpus_models(), read_semantics(profiles=["nav2"])
    assert len(models) == 31
    for name, kind in models.items():
        if kind in ("Action", "Condition"):
            assert name in rules, name
            assert kind == "Action" or rules[name] is CONDITION, name
        else:
            assert name in IN_RULES | OPAQUE, name
    assert set(rules) - set(models) == NEWER_THAN_THE_CORPUS_MODELS


def test_every_custom_type_of_the_nav2_corpus_trees_is_known():
    used = set()
    for tree in NAV2.glob("*.xml"):
        if tree != NODES:
            used |= set(re.findall(r"<([A-Z]\w*)", tree.read_text()))
    rules = read_semantics(profiles=["nav2"])
    unknown = used - set(rules) - set(RULES) - set(BUILTIN) - OPAQUE - {"BehaviorTree", "TreeNodesModel"}
    assert unknown == {"SequenceStar"}     # BT.CPP 3's, in the one BT.CPP 3 file of the corpus


def test_a_user_file_extends_and_overrides_the_profile(tmp_path):
    mine = tmp_path / "mine.yaml"
    mine.write_text("MyNode: Condition\nFollowPath: SyncAction\n")
    notes: list[str] = []
    rules = read_semantics([mine], profiles=["nav2", "nav2"], notes=notes)
    assert rules["MyNode"] is CONDITION and rules["FollowPath"] is SYNC_ACTION and rules["Spin"] is STATEFUL_ACTION
    assert len(notes) == 1 and notes[0].startswith(f"note: {mine}:2:1: FollowPath follows SyncAction as this "
                                                   f"file says, not the nav2 profile's rule ({PROFILE}:")
    # the user's own files still may not give a type twice
    other = tmp_path / "other.yaml"
    other.write_text("FollowPath: Action\n")
    with pytest.raises(SchemalogError, match=r"FollowPath is given its semantics twice: first at .*mine.yaml:2:1"):
        read_semantics([mine, other], profiles=["nav2"])
    with pytest.raises(SchemalogError, match="unknown profile 'ros1'; the profiles schemalog ships: nav2"):
        read_semantics(profiles=["ros1"])


def _wrapped(tmp_path):
    """Nav2's navigate_w_replanning_time.xml with ComputePathToPose's RateController made a
    Sequence (a), and taken away (b): under a PipelineSequence, which ticks a finished child again
    without a reset, a Sequence restarts it, while a bare BtActionNode returns its last result."""
    text = (NAV2 / "navigate_w_replanning_time.xml").read_text()
    a, b = tmp_path / "a.xml", tmp_path / "b.xml"
    a.write_text(text.replace('<RateController hz="1.0">', "<Sequence>").replace("</RateController>", "</Sequence>"))
    b.write_text(re.sub(r"\s*<RateController hz=\"1.0\">|\s*</RateController>", "", text))
    return a, b


def test_the_profile_decides_what_a_re_ticked_nav2_action_does(tmp_path):
    a, b = _wrapped(tmp_path)
    da, db = read_tree(a, [NODES]), read_tree(b, [NODES])
    everything_reticked = {m.type: RETICKED_ACTION for d in (da, db) for m in d.models if m.kind == "Action"}
    assert prove_trees(da, db, rules=everything_reticked).equal     # re-ticked: no difference
    default = prove_trees(da, db)                       # either registration (the default): told apart
    assert not default.equal and ("ComputePathToPose", "stateful") in default.counterexample.kinds
    verdict = prove_trees(da, db, rules=read_semantics(profiles=["nav2"]))
    assert not verdict.equal and "a tick ComputePathToPose" in verdict.reason and "b tick FollowPath" in verdict.reason
