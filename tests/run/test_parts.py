"""Parts and phases (run/parts.py): the split verification against the whole explorer.

SCHEMALOG_VERIFY_EXAMPLES sets how many random trees the cross-check draws (300 by default).
"""

import os
from dataclasses import replace

import pytest
from hypothesis import HealthCheck, assume, event, given, settings, strategies as st

from schemalog.evaluate.generate import generate
from schemalog.logic.parse import parse_term
from schemalog.run import parts
from schemalog.run.symbolic import Unsupported
from schemalog.run.verify import Verifier, verify_by_parts
from schemalog.run.world import World
from schemalog.task import conditions as cond
from schemalog.task.compress import compress
from schemalog.task.tree import Behaviour

from conftest import assert_replays, settled
from schemalog.testing.strategies import starts, trees

EXAMPLES = int(os.environ.get("SCHEMALOG_VERIFY_EXAMPLES", "300"))


def c(text):
    return cond.from_term(parse_term(text))


def t(text):
    return parse_term(text)


def shape(piece) -> str:
    """A piece as nested letters: P a part, G(...) a group, C(...) a chain."""
    if isinstance(piece, parts.Part):
        return "P"
    inner = piece.pieces if isinstance(piece, parts.Group) else piece.phases
    return ("G(" if isinstance(piece, parts.Group) else "C(") + " ".join(shape(p) for p in inner) + ")"


def _must(condition: bool) -> None:
    assert condition


def assert_same_verdicts(tree, compressed, initial, method, require=assume):
    """By parts (if it splits) and whole give the same verdicts; its counterexamples replay.
    `require`: what a run that reached a state limit means (hypothesis: draw another)."""
    whole = Verifier(tree, compressed, World(tree), max_states=5_000).verify(initial)
    require(whole.exhaustive)
    try:
        split = verify_by_parts(tree, compressed, World(tree), initial, max_states=5_000, method=method)
    except Unsupported:          # symbolic: a part's root may not settle monotonically
        return None
    if split is None:
        return None
    require(split.exhaustive)
    assert (split.sound, split.complete) == (whole.sound, whole.complete)
    assert split.original_completes == _completes(tree, initial[0])
    ce = split.properties["soundness"].counterexample
    if ce is not None:
        assert_replays(tree, compressed, ce, initial)
    ce = split.properties["completion"].counterexample
    if ce is not None and ce.path:
        assert_replays(tree, compressed, ce, initial, sound_run=split.sound)
    return split


def _completes(tree, start) -> bool:
    from schemalog.run.vacuity import original_completes
    return original_completes(tree, World(tree), start, 50_000) is True


@settings(max_examples=EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])
@given(st.data(), st.one_of(trees(chains=5), trees(chains=8, toggles=False)), st.sampled_from(["none", "pre", "full"]),
       st.sampled_from(["explicit", "symbolic"]))
def test_parts_and_phases_agree_with_the_whole_on_random_trees(data, tree, propagate, method):
    compressed = compress(tree, propagate).tree
    initial = settled(tree, data.draw(starts(tree))[:1])
    piece = parts.decompose(tree, compressed, initial[0])
    event("chain" if piece is not None and "C(" in shape(piece) else "no chain")
    assert_same_verdicts(tree, compressed, initial, method)


@st.composite
def chained_trees(draw):
    """Sub-tasks mostly in chains (each released by the one before), two to four levels; now
    and then an action that toggles hand.free or waits for it, a branch, a cross link."""
    levels = draw(st.integers(2, 4))
    ids = iter(range(10_000))

    def node(level, releaser, n):
        count = draw(st.integers(1, 3)) if level < levels else 0
        names = [next(ids) for _ in range(count)]
        kids = []
        for i in range(count):
            kind = draw(st.integers(0, 9))
            if i and kind < 7:
                rel = f"b{names[i - 1]}.done"
            elif i and kind == 7:
                rel = f"b{draw(st.sampled_from(names[:i]))}.done"
            elif kind == 8:
                rel = "hand.free"
            else:
                rel = "true"
            kids.append(node(level + 1, rel, names[i]))
        post = f"b{n}.done"
        if not kids and draw(st.integers(0, 9)) == 0:
            post += draw(st.sampled_from([" and not hand.free", " and hand.free"]))
        label = f"b{n}(cup)" if level > 1 else f"b{n}"
        return Behaviour(t(label), objects=(t("cup"),), releaser=c(releaser), post=c(post), children=tuple(kids))

    return node(1, "true", next(ids))


@settings(max_examples=EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large])
@given(st.data(), chained_trees(), st.sampled_from(["none", "pre", "full", "full"]),
       st.sampled_from(["explicit", "symbolic"]))
def test_phases_agree_with_the_whole_on_chains_of_subtasks(data, tree, propagate, method):
    compressed = compress(tree, propagate).tree
    pool = sorted({lit.atom for lit in cond.literals(tree.children[0].post)} | {t("hand.free")}, key=str)
    initial = settled(tree, [data.draw(st.lists(st.sampled_from(pool), max_size=2))])
    piece = parts.decompose(tree, compressed, initial[0])
    event("chain" if piece is not None and "C(" in shape(piece) else "no chain")
    assert_same_verdicts(tree, compressed, initial, method)


def test_generated_tasks_split_into_parts_and_phases():
    tree = generate(5, 3, 0.5, seed=1)
    compressed = compress(tree).tree
    piece = parts.decompose(tree, compressed, World(tree).atoms)
    assert isinstance(piece, parts.Group) and "C(" in shape(piece)
    assert max(len(p.atoms) for p in parts.parts_of(piece)) <= 10
    for method in ("explicit", "symbolic"):
        report = verify_by_parts(tree, compressed, World(tree), [World(tree).atoms], method=method)
        assert report.exhaustive and report.sound and report.complete and report.original_completes


# --- the premises: where a chain is not split --------------------------------------

def chain_of_subtasks(second_releaser="s1.done"):
    """r -> s1 -> s2, each sub-task two actions in sequence, on one object: compression merges
    s1 and s2 into s1_s2 and each one's actions."""
    def sub(n, releaser):
        a = Behaviour(t(f"a{n}(cup)"), objects=(t("cup"),), post=c(f"a{n}.done"))
        b = Behaviour(t(f"b{n}(cup)"), objects=(t("cup"),), releaser=c(f"a{n}.done"), post=c(f"b{n}.done"))
        return Behaviour(t(f"s{n}(cup)"), objects=(t("cup"),), releaser=c(releaser), post=c(f"s{n}.done"),
                         children=(a, b))
    return Behaviour(t("r"), post=c("r.done"), children=(sub(1, "true"), sub(2, second_releaser)))


def test_a_chain_of_subtasks_runs_phase_by_phase():
    tree = chain_of_subtasks()
    compressed = compress(tree).tree
    assert [k.label for k in compressed.children] == [t("s1_s2(cup)")]
    piece = parts.decompose(tree, compressed, World(tree).atoms)
    assert shape(piece) == "C(P P)" and piece.ends == (t("s1.done"), t("s2.done"))
    report = assert_same_verdicts(tree, compressed, [World(tree).atoms], "explicit", _must)
    assert report.sound and report.complete


def test_under_the_papers_propagation_the_first_phase_stays_in_view():
    """Under `pre`, the first sub-task's merged actions keep only its releaser as context: in
    the second phase they are inactive because they are accomplished, which the premises (read
    off the conditions) do not show. The chain is explored whole; the verdict is the same."""
    tree = chain_of_subtasks()
    compressed = compress(tree, "pre").tree
    assert parts.decompose(tree, compressed, World(tree).atoms) is None
    whole = Verifier(tree, compressed, World(tree)).verify([World(tree).atoms])
    assert whole.sound and whole.complete


def test_without_propagation_the_second_phase_is_not_split_off():
    """Under `none` the second sub-task's actions are active in the first phase: the group is
    explored whole, and the aliasing found."""
    tree = chain_of_subtasks()
    compressed = compress(tree, "none").tree
    assert parts.decompose(tree, compressed, World(tree).atoms) is None
    whole = Verifier(tree, compressed, World(tree)).verify([World(tree).atoms])
    assert not whole.sound


def test_a_post_condition_read_below_the_next_phase_is_not_a_chain():
    tree = chain_of_subtasks()
    s1, s2 = tree.children
    a2 = replace(s2.children[0], releaser=c("s1.done"))
    tree = replace(tree, children=(s1, replace(s2, children=(a2, s2.children[1]))))
    assert parts.decompose(tree, compress(tree).tree, World(tree).atoms) is None


def test_a_releaser_the_group_sets_does_not_start_a_chain():
    tree = chain_of_subtasks()
    s1, s2 = tree.children
    s1 = replace(s1, releaser=c("b2.done"))          # s1 waits for an action of s2: a cycle
    tree = replace(tree, children=(s1, s2))
    assert parts.decompose(tree, compress(tree).tree, World(tree).atoms) is None


def test_a_compressed_tree_that_reads_another_parts_atom_is_not_split():
    """An edited compressed file: a behaviour of one part waits for an atom of the other."""
    other = Behaviour(t("o(bowl)"), objects=(t("bowl"),), post=c("o.done"), children=(
        Behaviour(t("w(bowl)"), objects=(t("bowl"),), post=c("w.done")),))
    tree = replace(chain_of_subtasks(), children=(*chain_of_subtasks().children, other))
    good = compress(tree).tree
    merged = good.children[0]
    first = merged.children[0]
    edited = replace(good, children=(replace(merged, children=(
        replace(first, releaser=cond.conjoin([first.releaser, c("not w.done")])), *merged.children[1:])),
        good.children[1]))
    assert parts.decompose(tree, good, World(tree).atoms) is not None
    assert parts.decompose(tree, edited, World(tree).atoms) is None
    whole = Verifier(tree, edited, World(tree)).verify([World(tree).atoms])
    assert not whole.complete      # split, its parts would each have been proved


def test_an_edited_second_phase_gets_the_verdict_of_the_whole():
    """The second phase's compressed actions also wait for s1.done: still a chain, and the split
    verdict is the whole explorer's."""
    tree = chain_of_subtasks()
    compressed = compress(tree).tree
    merged = compressed.children[0]
    kids = list(merged.children)
    kids[1] = replace(kids[1], releaser=cond.conjoin([kids[1].releaser, c("s1.done")]))
    edited = replace(compressed, children=(replace(merged, children=tuple(kids)),))
    assert shape(parts.decompose(tree, edited, World(tree).atoms)) == "C(P P)"
    report = assert_same_verdicts(tree, edited, [World(tree).atoms], "explicit", _must)
    assert report.sound and report.complete


# --- shapes: a part explored once stands for every part of its shape ----------------

@pytest.mark.parametrize("method", ["explicit", "symbolic"])
def test_facts_of_a_shape_renamed_are_real_runs_of_each_part(method):
    from schemalog.run.verify import Counterexample, _Explored

    tree = generate(5, 3, 0.5, seed=1)
    compressed = compress(tree).tree
    piece = parts.decompose(tree, compressed, World(tree).atoms)
    explored = _Explored(method, 5_000, 1_000_000)
    found = [(part, explored.facts(part)) for part in parts.parts_of(piece)]
    assert explored.explored == len(explored.shapes) < len(found)      # parts share shapes
    for part, facts in found:
        assert facts.done is not None and facts.o_init and facts.c_init
        ce = Counterexample(facts.start, facts.path(facts.done), facts.done)
        assert_replays(part.original, part.compressed, ce, [facts.start])
        direct = explored.explore(part)
        assert (direct.states, direct.o_init, direct.c_init) == (facts.states, facts.o_init, facts.c_init)
        assert (direct.quiet is None, direct.can is None) == (facts.quiet is None, facts.can is None)


def test_a_violation_is_explored_in_its_own_part_not_renamed():
    """Two sub-tasks of one shape under `none`: the aliasing of each is found in its own names."""
    first = chain_of_subtasks()
    second = Behaviour(t("q"), post=c("q.done"), children=tuple(
        replace(k, label=t(f"x{i}(pan)"), objects=(t("pan"),), releaser=c("true") if i == 0 else c("x0.done"),
                post=c(f"x{i}.done"), children=tuple(
                    replace(a, label=t(f"y{i}{j}(pan)"), objects=(t("pan"),),
                            releaser=c("true") if j == 0 else c(f"y{i}0.done"), post=c(f"y{i}{j}.done"))
                    for j, a in enumerate(k.children)))
        for i, k in enumerate(first.children)))
    tree = Behaviour(t("top"), post=c("top.done"), children=(replace(first, label=t("p"), post=c("p.done")), second))
    compressed = compress(tree, "none").tree
    report = assert_same_verdicts(tree, compressed, [World(tree).atoms], "explicit", _must)
    assert report is not None and not report.sound
