"""bt/diff.py: the places where two programs part, in a reader's words, each decided on runs;
the direction by trace inclusion; the whole verdict the same as verify's."""

from __future__ import annotations

from hypothesis import given, settings, strategies as st

from schemalog.bt.diff import CHANGES, SAME, SAME_HERE, changes_of, diff_documents
from schemalog.bt.model import Document, Node
from schemalog.bt.prove import explain, prove_by_parts, prove_equal

LIMITS = dict(max_states=50_000, max_events_per_tick=30)


def act(name: str, **ports: str) -> Node:
    return Node(name, tuple(ports.items()), (), "Action")


def cond(name: str) -> Node:
    return Node(name, (), (), "Condition")


def n(node_type: str, *children: Node, **attrs: str) -> Node:
    return Node(node_type, tuple(attrs.items()), children)


def doc(root: Node) -> Document:
    return Document((("Main", root),), "Main")


def diff(a: Node, b: Node, **options):
    return diff_documents(doc(a), doc(b), **{**LIMITS, **options})


GO, PLAN, UPDATED = act("FollowPath", path="{path}"), act("ComputePathToPose", goal="{goal}"), cond("GoalUpdated")


def test_a_retry_count_is_said_as_a_reviewer_reads_it_and_shown_on_a_run():
    a = n("Sequence", PLAN, n("RecoveryNode", GO, act("Clear"), number_of_retries="6"))
    b = n("Sequence", PLAN, n("RecoveryNode", GO, act("Clear"), number_of_retries="5"))
    d = diff(a, b)
    assert not d.verdict.equal and d.verdict.complete
    (place,) = d.places
    assert place.changes == ("B retries FollowPath 5 times instead of 6",)
    assert place.effect == CHANGES
    # the run that shows it: A recovers a 6th time where B's RecoveryNode gives up after 5
    shown = explain(place.verdict)
    assert "a goes on with tick Clear, b's root tick ends with FAILURE" in shown
    assert shown.count("b: tick Clear") == 5 and shown.count("a: tick Clear") == 6


def test_a_reordering_is_one_place_said_as_what_b_ticks_first():
    a = n("Sequence", PLAN, UPDATED, GO)
    b = n("Sequence", UPDATED, PLAN, GO)
    d = diff(a, b)
    (place,) = d.places
    assert place.a is a and place.b is b
    assert place.changes == ("B ticks GoalUpdated before ComputePathToPose",)
    assert d.first_divergence() == ('tick ComputePathToPose goal="{goal}"', "tick GoalUpdated")


def test_a_wrapper_that_changes_nothing_is_a_pure_refactoring_and_the_pair_is_proved():
    a = n("Sequence", n("Fallback", cond("IsReady"), act("Prepare")), GO)
    b = n("Sequence", n("Sequence", n("Fallback", cond("IsReady"), act("Prepare"))), GO)
    d = diff(a, b)
    assert d.equal and d.direction == "equal"
    (place,) = d.places
    assert place.effect == SAME and place.changes == ("B wraps Fallback in Sequence",)


def test_an_edit_behind_a_branch_that_never_runs_is_the_same_here_but_not_everywhere():
    a = n("Sequence", n("Fallback", n("AlwaysSuccess"), act("Never")), GO)
    b = n("Sequence", n("Fallback", n("AlwaysSuccess"), act("Other")), GO)
    d = diff(a, b)
    assert d.equal
    (place,) = d.places
    assert place.effect == SAME_HERE            # Never and Other differ wherever they run
    assert place.changes == ("B has Other where A has Never",)


def test_two_independent_changes_are_two_places_each_with_its_own_run():
    a = n("Sequence", n("Repeat", act("Spin"), num_cycles="2"), n("Timeout", GO, msec="100"),
          n("Fallback", cond("IsDocked"), act("Dock")))
    b = n("Sequence", n("Repeat", act("Spin"), num_cycles="3"), n("Timeout", GO, msec="100"),
          n("Fallback", cond("IsDocked"), act("Undock")))
    d = diff(a, b)
    assert [p.effect for p in d.places] == [CHANGES, CHANGES]
    by_change = {p.changes: p for p in d.places}
    repeat = by_change[("B repeats Spin 3 times instead of 2",)]
    dock = by_change[("B has Undock where A has Dock",)]
    # each place's run is of A against A with that edit alone: the Dock run never repeats Spin a 3rd time
    assert "Undock" not in explain(repeat.verdict) and "Dock" in explain(dock.verdict)
    # after its 2nd cycle A goes on to FollowPath; B's Repeat asks for a 3rd tick (BT.CPP 4 yields between cycles)
    assert repeat.verdict.reason.startswith('a goes on with tick FollowPath path="{path}", b\'s root tick ends with '
                                            'RUNNING')


def test_a_condition_where_an_action_stood_only_removes_runs():
    a = n("Sequence", Node("Check", (), (), "Action"), GO)
    b = n("Sequence", Node("Check", (), (), "Condition"), GO)
    assert diff(a, b).direction == "b within a"
    assert diff(b, a).direction == "a within b"
    assert changes_of(a.children[0], b.children[0]) == ["B has <Condition> Check where A has <Action> Check"]


def test_a_different_event_first_means_neither_direction():
    d = diff(n("Sequence", PLAN, GO), n("Sequence", GO, PLAN))
    assert d.direction == "neither"


def test_a_limit_leaves_places_undecided_and_the_pair_unproved():
    a = n("Sequence", PLAN, n("RecoveryNode", GO, act("Clear"), number_of_retries="6"))
    b = n("Sequence", PLAN, n("RecoveryNode", GO, act("Clear"), number_of_retries="5"))
    d = diff(a, b, max_states=5)
    assert not d.complete and d.direction == "unknown"
    assert all(p.effect == "undecided" for p in d.places)


def test_attribute_changes_are_named_with_both_values():
    a = n("Sequence", act("Say", text="hi", volume="3"))
    b = n("Sequence", act("Say", text="hello", pitch="2"))
    assert changes_of(a.children[0], b.children[0]) == [
        'B sets text="hello" on Say (A: "hi")', 'B drops volume="3" from Say', 'B adds pitch="2" to Say']


# -- hypothesis: diff's verdict is verify's, and each place's effect is what its proof says ----

LEAVES = st.sampled_from([act("A"), act("B"), cond("IsOk")])


def _trees(depth: int):
    if depth == 0:
        return LEAVES
    sub = _trees(depth - 1)
    composite = st.builds(lambda t, kids: Node(t, (), tuple(kids)), st.sampled_from(["Sequence", "Fallback"]),
                          st.lists(sub, min_size=1, max_size=3))
    return st.one_of(LEAVES, composite, st.builds(lambda k: Node("Inverter", (), (k,)), sub))


@st.composite
def edited(draw):
    """A tree and an edit of it: a leaf replaced, children reversed, a node wrapped in a Sequence."""
    tree = draw(_trees(3))

    def edit(node: Node) -> Node:
        if node.children and draw(st.booleans()):
            k = draw(st.integers(0, len(node.children) - 1))
            kids = list(node.children)
            kids[k] = edit(kids[k])
            return node.with_children(tuple(kids))
        how = draw(st.sampled_from(["leaf", "reverse", "wrap"]))
        if how == "leaf":
            return draw(LEAVES)
        if how == "reverse" and node.children:
            return node.with_children(tuple(reversed(node.children)))
        return Node("Sequence", (), (node,))
    return tree, edit(tree)


@settings(max_examples=60, deadline=None)
@given(edited())
def test_diff_gives_verifys_verdict_and_every_place_its_own_proof(pair):
    a, b = pair
    d = diff(a, b)
    v = prove_by_parts(doc(a), doc(b), **LIMITS)
    assert (d.verdict.equal, d.verdict.complete) == (v.equal, v.complete)
    for p in d.places:
        if p.effect == SAME:
            # equal in every context: the subtrees prove equal as parts under any parent
            w = prove_equal(doc(p.a), doc(p.b), contextual=True, unreset=False, halts=True, **LIMITS)
            assert w.equal and w.complete, explain(w)
        if p.effect == CHANGES:
            assert not p.verdict.equal and p.verdict.counterexample is not None
    if d.equal:
        assert all(p.effect in (SAME, SAME_HERE) for p in d.places)
    elif d.complete:
        assert any(p.effect == CHANGES for p in d.places) or len(d.places) > 1   # edits may only differ together


# -- the corpus: every Nav2 tree against edits of it, written out and read back as files ----------

def test_every_place_on_nav2_edits_names_both_files_lines_and_the_verdict_is_verifys(tmp_path):
    """Each Nav2 tree of the corpus and 3 edits of it (the edit generator the proofs are checked
    against BT.CPP with), each written as a file and read back: every place diff reports names a
    line in both files, and diff's verdict on the pair is verify's."""
    import random
    import sys
    from pathlib import Path

    from schemalog.api.behaviour_trees import prove_trees, read_tree
    from schemalog.api.tree_diff import diff_trees
    from schemalog.formats.btxml import write_bt

    here = Path(__file__).resolve().parent
    sys.path.insert(0, str(here))
    from test_proofs_against_btcpp import edit

    nav2 = here / "corpus" / "nav2"
    nodes = [nav2 / "nav2_tree_nodes.xml"]
    trees = sorted(p for p in nav2.glob("*.xml") if p.name != "nav2_tree_nodes.xml"
                   and "goal_patience" not in p.name)
    checked = 0
    for tree in trees:
        a = read_tree(tree, nodes)
        made, seed = 0, 0
        while made < 3 and seed < 60:
            kind, root = edit(random.Random(seed), a.root)
            seed += 1
            if root == a.root:
                continue
            b_file = tmp_path / f"{tree.stem}-{seed}.xml"
            b_doc = a.with_trees(tuple((i, root if i == a.main else r) for i, r in a.trees))
            b_file.write_text(write_bt(b_doc), encoding="utf-8")
            b = read_tree(b_file, nodes)
            d = diff_trees(a, b, 20_000)
            v = prove_trees(a, b, 20_000)
            assert (d.diff.verdict.equal, d.diff.verdict.complete) == (v.equal, v.complete), (tree.name, kind)
            for p in d.places:
                assert p.a.line > 0 and p.b.line > 0 and p.a.file == str(tree) and p.b.file == str(b_file), \
                    (tree.name, kind, p)
                assert p.changes, (tree.name, kind, p)
            made += 1
            checked += 1
    assert checked == 3 * len(trees)


@settings(max_examples=30, deadline=None)
@given(edited(), st.integers(1, 200))
def test_max_states_is_one_budget_for_the_whole_diff(pair, limit):
    a, b = pair
    d = diff(a, b, max_states=limit)
    assert d.verdict.states <= limit


def test_a_child_moved_and_edited_is_one_place_saying_both():
    """Spin and Wait swapped, Spin's spin_dist changed too: one place, the reordering and the
    value both said (pairwise, it read "B has Wait where A has Spin", the 3.14 only in the run)."""
    a = n("RoundRobin", act("Spin", spin_dist="1.57"), act("Wait", wait_duration="5"), act("BackUp"))
    b = n("RoundRobin", act("Wait", wait_duration="5"), act("Spin", spin_dist="3.14"), act("BackUp"))
    (place,) = diff(n("Sequence", GO, a), n("Sequence", GO, b)).places
    assert place.a is a and place.changes == ("B ticks Wait before Spin", 'B sets spin_dist="3.14" on Spin (A: "1.57")')


def test_an_edit_in_a_tree_the_main_tree_never_calls_is_not_run_not_a_refactoring():
    other = n("RetryUntilSuccessful", act("C"), num_attempts="3")
    a = Document((("Main", n("Sequence", GO)), ("Other", other)), "Main")
    b = Document((("Main", n("Sequence", GO)), ("Other", n("RetryUntilSuccessful", act("C"), num_attempts="2"))),
                 "Main")
    d = diff_documents(a, b, **LIMITS)
    (place,) = d.places
    assert d.equal and place.effect == "not run" and place.tree == "Other" and place.verdict is None
    assert not d.refactorings
    # called from the main tree, the same edit changes behaviour
    call = Node("SubTree", (("ID", "Other"),))
    a2, b2 = (Document((("Main", n("Sequence", GO, call)), ("Other", t)), "Main") for t in (other, b.trees[1][1]))
    (place,) = diff_documents(a2, b2, **LIMITS).places
    assert place.effect == CHANGES and place.changes == ("B tries C 2 times instead of 3",)
