% The paper's Figure 2 (left): mix the content of a cup with a spoon.
%
% Learned by demonstration (Sec. II-C/D): taking the spoon was segmented into two
% arm motions and a gripper command, mixing into five arm motions and a gripper
% command. Each learned action is released by the previous one's `done` (the first
% one is always released), as the teaching rule of Sec. II-D assigns. Post-conditions
% follow the paper's footnote 1: `ai.done` for an action, `not hand.free` for
% closing the gripper, `spoon.taken` for the take sub-task.
%
% 12 behaviours, depth 3.

task(use(spoon)).

object(spoon).
object(cup).

% The gripper is a different agent from the arm (Sec. III-B), so gripper commands
% are never merged with arm motions.
agent(gripper(_), gripper).

initial(hand.free).

schema(use(spoon),
       [ (subtask(take, spoon), hand.free),
         (subtask(mix, spoon), spoon.taken) ],
       spoon.used).

schema(subtask(take, spoon),
       [ (a1(spoon), true),
         (a2(spoon), a1.done),
         (gripper(close), a2.done) ],
       spoon.taken).

schema(subtask(mix, spoon),
       [ (a3(cup), true),
         (a4(cup), a3.done),
         (a5(cup), a4.done),
         (a6(cup), a5.done),
         (a7(cup), a6.done),
         (gripper(open), a7.done) ],
       spoon.used).

% Primitive behaviours: the learned motions and the gripper commands.
schema(a1(spoon), [], a1.done).
schema(a2(spoon), [], a2.done).
schema(a3(cup), [], a3.done).
schema(a4(cup), [], a4.done).
schema(a5(cup), [], a5.done).
schema(a6(cup), [], a6.done).
schema(a7(cup), [], a7.done).
schema(gripper(close), [], not hand.free).
schema(gripper(open), [], hand.free).

% Integrity constraints: the initial states `schemalog verify --states all` covers are the
% assignments of the task's atoms (other than the actions' `done`) that satisfy these.
constraint(not spoon.used or spoon.taken).                  % what is used was taken
constraint(not (spoon.taken and not spoon.used and hand.free)).   % a held spoon fills the hand
constraint(spoon.taken or hand.free).                       % nothing else is ever held
