% A SEED memory as SWI-Prolog 7 (traditional dot) lists it: Obj.prop became the list cell
% [Obj|prop], variables are renamed A, B, ..., importances keep their floats.
:- dynamic schema/2.

schema(preparetea, [[add(water), 1, ["TRUE"]], [add(tea), 1.5, [[water|used]]]]).
schema(add(A), [[subtask(take, A), 1, [[kukahand|free]]], [subtask(pour, A), 0.75, [[A|taken]]]]).
schema(subtask(_, _), []).

:- dynamic goal/2.

goal(preparetea, [[tea|used]]).
goal(add(A), [[A|used]]).
goal(subtask(take, A), [[A|taken], -[kukahand|free]]).
goal(subtask(pour, A), [[A|used], [kukahand|free]]).
