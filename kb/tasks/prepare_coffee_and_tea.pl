% The paper's learned task (Sec. IV-C): prepare a cup of coffee and a cup of tea.
%
% How this file was built. The task structure is the one of the authors' public SEED
% long-term memory (task-teaching-and-supervision, Attentional_System/seed_segment/
% LTM.prolog), written here in the paper's schema(m, l, p) form:
%   prepareboth -> preparecoffee, preparetea            (both always released)
%   preparecoffee -> add(water), add(coffee), use(spoon) (use released by water.used
%                                                         and coffee.used)
%   preparetea -> add(water), add(tea)                  (add(tea) released by water.used)
%   add(O) -> subtask(take, O), subtask(pour, O)        (released by kukahand.free, O.taken)
%   use(O) -> subtask(take, O), subtask(mix, O)
% and its goals (take -> O.taken; pour, mix, add, use -> O.used; preparecoffee ->
% spoon.used; preparetea -> tea.used; gripper(open) -> kukahand.free;
% gripper(close) -> not kukahand.free). SEED gives prepareboth no goal; here it is
% the conjunction of its two sub-tasks' goals.
% The learned actions under each sub-task follow Figure 2's pattern: for a take,
% an approach and a grasp motion on the object, then gripper(close); for a pour or a
% mix, five motions at the cup, then gripper(open). Each action is released by the
% previous one's `done`, the first always.
%
% That gives 63 behaviours and depth 5, the paper's figures before merging.
% examples/coffee_and_tea_seed.prolog holds the same domain in SEED's own syntax.

task(prepareboth).

object(water).
object(coffee).
object(tea).
object(spoon).
object(cup).

agent(gripper(_), gripper).

initial(kukahand.free).

schema(prepareboth,
       [ (preparecoffee, true),
         (preparetea, true) ],
       spoon.used and tea.used).

schema(preparecoffee,
       [ (add(water), true),
         (add(coffee), true),
         (use(spoon), water.used and coffee.used) ],
       spoon.used).

schema(preparetea,
       [ (add(water), true),
         (add(tea), water.used) ],
       tea.used).

schema(add(O),
       [ (subtask(take, O), kukahand.free),
         (subtask(pour, O), O.taken) ],
       O.used).

schema(use(O),
       [ (subtask(take, O), kukahand.free),
         (subtask(mix, O), O.taken) ],
       O.used).

% Learned sub-tasks (Sec. II-D): the segmented actions attached to each sub-task.
schema(subtask(take, water),
       [ (a1(water), true),
         (a2(water), a1.done),
         (gripper(close), a2.done) ],
       water.taken).

schema(subtask(pour, water),
       [ (a3(cup), true),
         (a4(cup), a3.done),
         (a5(cup), a4.done),
         (a6(cup), a5.done),
         (a7(cup), a6.done),
         (gripper(open), a7.done) ],
       water.used).

schema(subtask(take, coffee),
       [ (a8(coffee), true),
         (a9(coffee), a8.done),
         (gripper(close), a9.done) ],
       coffee.taken).

schema(subtask(pour, coffee),
       [ (a10(cup), true),
         (a11(cup), a10.done),
         (a12(cup), a11.done),
         (a13(cup), a12.done),
         (a14(cup), a13.done),
         (gripper(open), a14.done) ],
       coffee.used).

schema(subtask(take, spoon),
       [ (a15(spoon), true),
         (a16(spoon), a15.done),
         (gripper(close), a16.done) ],
       spoon.taken).

schema(subtask(mix, spoon),
       [ (a17(cup), true),
         (a18(cup), a17.done),
         (a19(cup), a18.done),
         (a20(cup), a19.done),
         (a21(cup), a20.done),
         (gripper(open), a21.done) ],
       spoon.used).

schema(subtask(take, tea),
       [ (a22(tea), true),
         (a23(tea), a22.done),
         (gripper(close), a23.done) ],
       tea.taken).

schema(subtask(pour, tea),
       [ (a24(cup), true),
         (a25(cup), a24.done),
         (a26(cup), a25.done),
         (a27(cup), a26.done),
         (a28(cup), a27.done),
         (gripper(open), a28.done) ],
       tea.used).

% Primitive behaviours: the learned motions and the gripper commands.
schema(gripper(close), [], not kukahand.free).
schema(gripper(open), [], kukahand.free).
schema(a1(water), [], a1.done).
schema(a2(water), [], a2.done).
schema(a3(cup), [], a3.done).
schema(a4(cup), [], a4.done).
schema(a5(cup), [], a5.done).
schema(a6(cup), [], a6.done).
schema(a7(cup), [], a7.done).
schema(a8(coffee), [], a8.done).
schema(a9(coffee), [], a9.done).
schema(a10(cup), [], a10.done).
schema(a11(cup), [], a11.done).
schema(a12(cup), [], a12.done).
schema(a13(cup), [], a13.done).
schema(a14(cup), [], a14.done).
schema(a15(spoon), [], a15.done).
schema(a16(spoon), [], a16.done).
schema(a17(cup), [], a17.done).
schema(a18(cup), [], a18.done).
schema(a19(cup), [], a19.done).
schema(a20(cup), [], a20.done).
schema(a21(cup), [], a21.done).
schema(a22(tea), [], a22.done).
schema(a23(tea), [], a23.done).
schema(a24(cup), [], a24.done).
schema(a25(cup), [], a25.done).
schema(a26(cup), [], a26.done).
schema(a27(cup), [], a27.done).
schema(a28(cup), [], a28.done).

% Integrity constraints: the initial states `schemalog verify --states all` covers are the
% assignments of the task's atoms (other than the actions' `done`) that satisfy these.
ingredient(water).  ingredient(coffee).  ingredient(tea).  ingredient(spoon).
% What is used was taken first.
constraint(not O.used or O.taken) :- ingredient(O).
% A taken ingredient not yet used is in the hand: then the hand is not free ...
constraint(not (O.taken and not O.used and kukahand.free)) :- ingredient(O).
% ... and it holds one thing at a time.
constraint(not (A.taken and not A.used and B.taken and not B.used)) :-
    ingredient(A), ingredient(B), A @< B.
