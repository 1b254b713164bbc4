% The partially specified structure of the paper's learned tasks (Sec. II-D, IV-C):
% prepare a cup of coffee, a cup of tea, or both, down to the sub-tasks a teacher
% demonstrates (take, pour, mix), which have no actions yet.
%
%   schemalog simulate-demo --scene kb/scenes/kitchen.yaml --task preparecoffee -o coffee.csv
%   schemalog learn coffee.csv --structure kb/tasks/coffee_structure.pl --task preparecoffee -o learned.pl
%
% `schemalog learn` attaches each demonstrated action to the enabled sub-task with the
% highest activation; a gripper command ends its sub-task, asserting the post-condition
% written here (water.taken after the grasp). Learning preparecoffee and then preparetea
% (with learned.pl as the structure) gives kb/tasks/prepare_coffee_and_tea.pl: the
% 63 behaviours of prepareboth (docs/learning.md).

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

% The sub-tasks a demonstration teaches: no actions yet, only their goals.
schema(subtask(take, O), [], O.taken).
schema(subtask(pour, O), [], O.used).
schema(subtask(mix, O), [], O.used).

% The gripper commands a demonstration may contain.
schema(gripper(close), [], not kukahand.free).
schema(gripper(open), [], kukahand.free).

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
