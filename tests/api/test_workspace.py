"""schemalog's relations: the paper's trees, compression, state and runs, asked in Prolog."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from schemalog.task.compress import compress
from schemalog.formats.documents import to_pl
from schemalog.evaluate.generate import generate
from schemalog.logic.parse import parse_term
from schemalog.api.workspace import COMPRESSED, Options, Workspace
from schemalog.formats.render import tree_document
from schemalog.logic.terms import term_to_text
from schemalog.task.tree import count_nodes, depth, walk

from conftest import COFFEE, MIX


def ask(ws: Workspace, query: str, limit: int | None = None) -> list[str]:
    return [term_to_text(a) for a in ws.engine().answers(parse_term(query), limit)]


@pytest.fixture(scope="module")
def mix() -> Workspace:
    return Workspace([str(MIX)])


def test_sequential_is_definition_1_over_the_figure_2_tree(mix):
    # Figure 2: the two sub-tasks, a1-a2, and the chain a3 ... a7 (not the gripper commands,
    # which are another agent's).
    pairs = ask(mix, "findall(A-B, (sequential(X, Y), in_tree(X, _, original), node(X, A), node(Y, B)), Ps)")
    assert pairs[0].endswith(",[subtask(take,spoon)-subtask(mix,spoon),a1(spoon)-a2(spoon),a3(cup)-a4(cup),"
                             "a4(cup)-a5(cup),a5(cup)-a6(cup),a6(cup)-a7(cup)])")
    # after compression no sibling pair is sequential any more (Algorithm 1 merged them all)
    assert ask(mix, "sequential(X, Y), in_tree(X, _, compressed)") == []


def test_compression_relations_match_the_compressor(mix):
    assert ask(mix, "merged(T, _, Parts)") == [
        "merged(use(spoon),13,[subtask(take,spoon),subtask(mix,spoon)])",
        "merged(use(spoon),14,[a1(spoon),a2(spoon)])",
        "merged(use(spoon),16,[a3(cup),a4(cup),a5(cup),a6(cup),a7(cup)])"]
    assert ask(mix, "reduction_degree(use(spoon), RD)") == ["reduction_degree(use(spoon),0.6666666666666666)"]
    assert ask(mix, "compressed(T, R), findall(B, in_tree(B, T, compressed), Bs)") == [
        "compressed(use(spoon),12),findall(B,in_tree(B,use(spoon),compressed),[12,13,14,15,16,17])"]
    assert ask(mix, "k(13, K), k(16, K5)") == ["k(13,2),k(16,5)"]   # two sub-tasks; a3 ... a7


def test_tree_structure_relations(mix):
    assert ask(mix, "original(_, R), findall(C, child(R, C), Cs)") == [
        "original(use(spoon),0),findall(C,child(0,C),[1,5])"]
    assert ask(mix, "parent(4, P), node(P, L)") == ["parent(4,1),node(1,subtask(take,spoon))"]
    assert ask(mix, "depth(B, 3), in_tree(B, _, original), \\+ leaf(B)") == []
    assert ask(mix, "pre(15, C)") == ["pre(15,a2.done and hand.free and not spoon.taken)"]
    assert ask(mix, "post(4, C)") == ["post(4,not hand.free)"]
    assert ask(mix, "objects(2, Os), agent(4, A)") == ["objects(2,[spoon]),agent(4,gripper)"]


def test_agent_keeps_the_files_declarations_first(mix):
    answers = ask(mix, "agent(B, gripper)")
    assert answers[0].startswith("agent(gripper(")          # the file's own clause
    assert answers[1:] == ["agent(4,gripper)", "agent(11,gripper)", "agent(15,gripper)", "agent(17,gripper)"]
    assert "agent/2" in mix.clashes


def test_state_relations_follow_the_executive():
    ws = Workspace([str(MIX)])
    assert ask(ws, "holds(hand.free), \\+ holds(spoon.taken)") != []
    assert ask(ws, "enabled(B)") == ["enabled(2)"]
    assert ask(ws, "next_action(B)") == ["next_action(2)"]
    ws.set_state(parse_term_atoms("hand.free, a1.done, a2.done"))
    assert ask(ws, "enabled(B), node(B, L)") == ["enabled(4),node(4,gripper(close))"]
    ws.set_focus(ws.focus, COMPRESSED)
    ws.reset()
    assert ask(ws, "next_action(B), node(B, L)") == ["next_action(14),node(14,a1_a2(spoon))"]
    emphases = ask(ws, "emphasis(B, E)")
    assert len(emphases) == 6 and emphases[0] == "emphasis(12,1.0)"


def parse_term_atoms(text: str):
    from schemalog.run.world import state_atoms

    return state_atoms(parse_term(text), "test")


def test_run_and_verify(mix):
    trace = "[a1(spoon),a2(spoon),gripper(close),a3(cup),a4(cup),a5(cup),a6(cup),a7(cup),gripper(open)]"
    assert ask(mix, "run(use(spoon), O)") == [f"run(use(spoon),completed({trace}))"]
    assert ask(mix, "compressed(T, R), run(R, completed(Trace)), length(Trace, N)")[0].endswith(",9)")
    assert ask(mix, "verify(use(spoon), R)") == ["verify(use(spoon),proved)"]
    with pytest.raises(Exception, match="existence_error"):
        ask(mix, "run(nothing, O)")


def test_the_papers_pre_rule_is_refuted_by_verify():
    # Issue 5: with the paper's propagation rule (pre) the compressed coffee task is unsound.
    ws = Workspace([str(COFFEE)], Options(propagate="pre"))
    result = ask(ws, "verify(prepareboth, R)")[0]
    assert result.startswith("verify(prepareboth,counterexample(soundness,[")


# s2 waits for lid.open, which nothing ever makes true: no run of the task completes.
LID = """task(stuck).
schema(stuck, [(s1, true), (s2, s1.done and lid.open)], s2.done).
schema(s1, [], s1.done).  schema(s2, [], s2.done).
"""


def test_verify_of_a_task_that_cannot_complete_is_no_proof_not_proved(tmp_path):
    path = tmp_path / "stuck.pl"
    path.write_text(LID)
    ws = Workspace([str(path)])
    assert ask(ws, "verify(stuck, R)") == ["verify(stuck,no_proof(task_cannot_complete))"]
    assert ask(ws, "verify(stuck, proved)") == []
    path.write_text(LID + "initial(lid.open).\n")     # now it completes, and the proof says something
    assert ask(Workspace([str(path)]), "verify(stuck, R)") == ["verify(stuck,proved)"]


def test_a_compressed_file_is_read_with_its_provenance(tmp_path, mix):
    view = mix.focus
    written = tmp_path / "compressed.pl"
    written.write_text(to_pl(tree_document(view.compressed)))
    ws = Workspace([str(written)])
    assert ask(ws, "reduction_degree(T, RD)") == ["reduction_degree(use(spoon),0.6666666666666666)"]
    # The tree alone carries no initial/1: with nothing true, hand.free never holds.
    assert ask(ws, "verify(use(spoon), R)") == ["verify(use(spoon),no_proof(task_cannot_complete))"]
    written.write_text(to_pl(tree_document(view.compressed)) + "initial(hand.free).\n")
    assert ask(Workspace([str(written)]), "verify(use(spoon), R)") == ["verify(use(spoon),proved)"]


WAVE = """task(wave).
schema(wave, [(w1, true), (w2, w1.done), (w3, w2.done)], w3.done).
schema(w1, [], w1.done).  schema(w2, [], w2.done).  schema(w3, [], w3.done).
"""


def test_ids_are_unique_across_files_and_trees(tmp_path):
    wave = tmp_path / "wave.pl"
    wave.write_text(WAVE)
    ws = Workspace([str(MIX), str(wave)])
    assert [term_to_text(v.task) for v in ws.views] == ["use(spoon)", "wave"]
    ids = ask(ws, "findall(B, node(B, _), Bs), sort(Bs, S), length(Bs, N), length(S, N)")
    assert ids, "node ids repeat"
    assert ask(ws, "task(T)") == ["task(use(spoon))", "task(wave)"]


def test_loading_a_file_again_replaces_its_clauses(tmp_path):
    wave = tmp_path / "wave.pl"
    wave.write_text(WAVE + "colour(red).\n")
    ws = Workspace([str(MIX)])
    ws.load(str(wave))
    ws.load(str(wave))                      # the same file again: not a redefinition of itself
    assert ask(ws, "colour(C)") == ["colour(red)"]
    wave.write_text(WAVE.replace("(w3, w2.done)", "(w3, w2.done), (w4, w3.done)")
                    + "schema(w4, [], w4.done).\ncolour(blue).\n")
    ws.load(str(tmp_path / "." / "wave.pl"))  # edited, and named another way
    assert ws.files == [str(MIX), str(wave)]
    assert ask(ws, "colour(C)") == ["colour(blue)"]
    assert ask(ws, "original(wave, R), findall(C, child(R, C), Cs), length(Cs, N)")[0].endswith(",4)")


def test_pure_prolog_files_get_no_relations(tmp_path):
    program = tmp_path / "family.pl"
    program.write_text("parent(tom, bob). parent(bob, ann).\n"
                       "grandparent(X, Z) :- parent(X, Y), parent(Y, Z).\n")
    ws = Workspace([str(program)])
    assert ws.views == [] and ws.notes == []
    assert ask(ws, "grandparent(X, Z)") == ["grandparent(tom,ann)"]
    with pytest.raises(Exception, match="existence_error"):     # no task: no relations at all
        ask(ws, "enabled(B)")


@settings(max_examples=25, deadline=None)
@given(d=st.integers(2, 4), b=st.integers(1, 3), rd=st.sampled_from([0.0, 0.3, 0.7]), seed=st.integers(0, 5))
def test_relations_describe_generated_trees_exactly(tmp_path_factory, d, b, rd, seed):
    tree = generate(d, b, rd, seed=seed)
    path = tmp_path_factory.mktemp("gen") / "t.pl"
    path.write_text(to_pl(tree_document(tree)))
    ws = Workspace([str(path)])
    result = compress(tree)
    n_orig, n_comp = count_nodes(tree), count_nodes(result.tree)
    assert _count(ws, "in_tree(_, _, original)") == n_orig
    assert _count(ws, "in_tree(_, _, compressed)") == n_comp
    assert _count(ws, "leaf(B), in_tree(B, _, original)") == sum(1 for n in walk(tree) if not n.children)
    assert _count(ws, "child(P, C), \\+ parent(C, P)") == 0
    assert _count(ws, "merged(_, _, _)") == sum(1 for n in walk(result.tree) if n.merged_from)
    rd_text = ask(ws, "reduction_degree(_, RD)")[0]
    assert abs(float(rd_text.rsplit(",", 1)[1].rstrip(")")) - result.reduction_degree) < 1e-9
    deepest = ask(ws, "original(_, R), aggregate_all(max(D), (in_tree(B, _, original), depth(B, D)), M)")[0]
    assert deepest.endswith(f",{depth(tree)})")


def _count(ws: Workspace, goal: str) -> int:
    return len(ws.engine().answers(parse_term(goal)))


def test_a_clause_asserted_for_a_relation_is_kept_and_the_relation_still_answers():
    ws = Workspace([str(MIX)])
    # as for a file's clause: assert/1 accepts it (no permission error), and holds/1 still
    # reads the state: hand.free is true at the start, x never is
    assert ask(ws, "assertz(holds(x))") == ["assertz(holds(x))"]
    assert ask(ws, "holds(x)") == []
    assert ask(ws, "holds(hand.free)") == ["holds(hand.free)"]
