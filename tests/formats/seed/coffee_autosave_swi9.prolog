% What SWI-Prolog 9 writes for SEED's saveLTM (listing(schema/2), listing(goal/2)) after consulting
% examples/coffee_and_tea_seed.prolog: it reads each Obj.prop as a dict call, so every literal
% became a variable and a '.'/3 goal. Produced with: swipl -g "consult(F), listing(schema/2), listing(goal/2)" -t halt
:- dynamic schema/2.

schema(prepareboth, [[preparecoffee, 1, ["TRUE"]], [preparetea, 1, ["TRUE"]]]).
schema(preparecoffee, [[add(water), 1, ["TRUE"]], [add(coffee), 1, ["TRUE"]], [use(spoon), 1, [A, B]]]) :-
    '.'(water, used, A),
    '.'(coffee, used, B).
schema(preparetea, [[add(water), 1, ["TRUE"]], [add(tea), 1, [A]]]) :-
    '.'(water, used, A).
schema(add(OBJ), [[subtask(take, OBJ), 1, [A]], [subtask(pour, OBJ), 1, [B]]]) :-
    '.'(kukahand, free, A),
    '.'(OBJ, taken, B).
schema(use(OBJ), [[subtask(take, OBJ), 1, [A]], [subtask(mix, OBJ), 1, [B]]]) :-
    '.'(kukahand, free, A),
    '.'(OBJ, taken, B).
schema(subtask(take, water), [[a1(water), 1, ["TRUE"]], [a2(water), 1, [A]], [gripper(close), 1, [B]]]) :-
    '.'(a1, done, A),
    '.'(a2, done, B).
schema(subtask(pour, water), [[a3(cup), 1, ["TRUE"]], [a4(cup), 1, [A]], [a5(cup), 1, [B]], [a6(cup), 1, [C]], [a7(cup), 1, [D]], [gripper(open), 1, [E]]]) :-
    '.'(a3, done, A),
    '.'(a4, done, B),
    '.'(a5, done, C),
    '.'(a6, done, D),
    '.'(a7, done, E).
schema(subtask(take, coffee), [[a8(coffee), 1, ["TRUE"]], [a9(coffee), 1, [A]], [gripper(close), 1, [B]]]) :-
    '.'(a8, done, A),
    '.'(a9, done, B).
schema(subtask(pour, coffee), [[a10(cup), 1, ["TRUE"]], [a11(cup), 1, [A]], [a12(cup), 1, [B]], [a13(cup), 1, [C]], [a14(cup), 1, [D]], [gripper(open), 1, [E]]]) :-
    '.'(a10, done, A),
    '.'(a11, done, B),
    '.'(a12, done, C),
    '.'(a13, done, D),
    '.'(a14, done, E).
schema(subtask(take, spoon), [[a15(spoon), 1, ["TRUE"]], [a16(spoon), 1, [A]], [gripper(close), 1, [B]]]) :-
    '.'(a15, done, A),
    '.'(a16, done, B).
schema(subtask(mix, spoon), [[a17(cup), 1, ["TRUE"]], [a18(cup), 1, [A]], [a19(cup), 1, [B]], [a20(cup), 1, [C]], [a21(cup), 1, [D]], [gripper(open), 1, [E]]]) :-
    '.'(a17, done, A),
    '.'(a18, done, B),
    '.'(a19, done, C),
    '.'(a20, done, D),
    '.'(a21, done, E).
schema(subtask(take, tea), [[a22(tea), 1, ["TRUE"]], [a23(tea), 1, [A]], [gripper(close), 1, [B]]]) :-
    '.'(a22, done, A),
    '.'(a23, done, B).
schema(subtask(pour, tea), [[a24(cup), 1, ["TRUE"]], [a25(cup), 1, [A]], [a26(cup), 1, [B]], [a27(cup), 1, [C]], [a28(cup), 1, [D]], [gripper(open), 1, [E]]]) :-
    '.'(a24, done, A),
    '.'(a25, done, B),
    '.'(a26, done, C),
    '.'(a27, done, D),
    '.'(a28, done, E).
schema(gripper(_), []).
schema(a1(water), []).
schema(a2(water), []).
schema(a3(cup), []).
schema(a4(cup), []).
schema(a5(cup), []).
schema(a6(cup), []).
schema(a7(cup), []).
schema(a8(coffee), []).
schema(a9(coffee), []).
schema(a10(cup), []).
schema(a11(cup), []).
schema(a12(cup), []).
schema(a13(cup), []).
schema(a14(cup), []).
schema(a15(spoon), []).
schema(a16(spoon), []).
schema(a17(cup), []).
schema(a18(cup), []).
schema(a19(cup), []).
schema(a20(cup), []).
schema(a21(cup), []).
schema(a22(tea), []).
schema(a23(tea), []).
schema(a24(cup), []).
schema(a25(cup), []).
schema(a26(cup), []).
schema(a27(cup), []).
schema(a28(cup), []).
schema(object(water), []).
schema(object(coffee), []).
schema(object(tea), []).
schema(object(spoon), []).
schema(object(cup), []).

:- dynamic goal/2.

goal(prepareboth, [A, B]) :-
    '.'(spoon, used, A),
    '.'(tea, used, B).
goal(preparecoffee, [A]) :-
    '.'(spoon, used, A).
goal(preparetea, [A]) :-
    '.'(tea, used, A).
goal(add(Obj), [A]) :-
    '.'(Obj, used, A).
goal(use(Obj), [A]) :-
    '.'(Obj, used, A).
goal(subtask(take, Obj), [A]) :-
    '.'(Obj, taken, A).
goal(subtask(pour, Obj), [A]) :-
    '.'(Obj, used, A).
goal(subtask(mix, Obj), [A]) :-
    '.'(Obj, used, A).
goal(gripper(open), [A]) :-
    '.'(kukahand, free, A).
goal(gripper(close), [-A]) :-
    '.'(kukahand, free, A).
goal(a1(water), [A]) :-
    '.'(a1, done, A).
goal(a2(water), [A]) :-
    '.'(a2, done, A).
goal(a3(cup), [A]) :-
    '.'(a3, done, A).
goal(a4(cup), [A]) :-
    '.'(a4, done, A).
goal(a5(cup), [A]) :-
    '.'(a5, done, A).
goal(a6(cup), [A]) :-
    '.'(a6, done, A).
goal(a7(cup), [A]) :-
    '.'(a7, done, A).
goal(a8(coffee), [A]) :-
    '.'(a8, done, A).
goal(a9(coffee), [A]) :-
    '.'(a9, done, A).
goal(a10(cup), [A]) :-
    '.'(a10, done, A).
goal(a11(cup), [A]) :-
    '.'(a11, done, A).
goal(a12(cup), [A]) :-
    '.'(a12, done, A).
goal(a13(cup), [A]) :-
    '.'(a13, done, A).
goal(a14(cup), [A]) :-
    '.'(a14, done, A).
goal(a15(spoon), [A]) :-
    '.'(a15, done, A).
goal(a16(spoon), [A]) :-
    '.'(a16, done, A).
goal(a17(cup), [A]) :-
    '.'(a17, done, A).
goal(a18(cup), [A]) :-
    '.'(a18, done, A).
goal(a19(cup), [A]) :-
    '.'(a19, done, A).
goal(a20(cup), [A]) :-
    '.'(a20, done, A).
goal(a21(cup), [A]) :-
    '.'(a21, done, A).
goal(a22(tea), [A]) :-
    '.'(a22, done, A).
goal(a23(tea), [A]) :-
    '.'(a23, done, A).
goal(a24(cup), [A]) :-
    '.'(a24, done, A).
goal(a25(cup), [A]) :-
    '.'(a25, done, A).
goal(a26(cup), [A]) :-
    '.'(a26, done, A).
goal(a27(cup), [A]) :-
    '.'(a27, done, A).
goal(a28(cup), [A]) :-
    '.'(a28, done, A).

