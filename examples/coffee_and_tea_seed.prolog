% The coffee-and-tea domain in the SEED long-term-memory format (the authors'
% attentional framework): schema/2 with [[Sub, Importance, [Releasers]], ...] and
% goal/2 post-conditions, literals written Obj.prop and negated with a prefix minus.
%
% Written for schemalog from the structure described in docs/seed.md; it holds the
% same task as kb/tasks/prepare_coffee_and_tea.pl, so that
%     schemalog convert examples/coffee_and_tea_seed.prolog -o task.pl
% gives a file whose prepareboth tree is the shipped one (63 behaviours, depth 5).

:- op(500, xfy, .).
:- op(600, fx, -).

:- dynamic schema/2.
:- dynamic goal/2.

% Server code, as a SEED memory file carries it: not task knowledge, and skipped
% by the importer (it says so).
lookupSchema(X) :-
	schema(X, Definition),
	print(Definition), !.

rememberSchema(Name, Sub, Releaser) :-
	assertz(schema(Name, [[Sub, 1, [Releaser]]])).

% Abstract schemas
schema(prepareboth, [
	[preparecoffee, 1, ["TRUE"]],
	[preparetea, 1, ["TRUE"]]
	]).

schema(preparecoffee, [
	[add(water), 1, ["TRUE"]],
	[add(coffee), 1, ["TRUE"]],
	[use(spoon), 1, [water.used, coffee.used]]
	]).

schema(preparetea, [
	[add(water), 1, ["TRUE"]],
	[add(tea), 1, [water.used]]
	]).

schema(add(OBJ), [
	[subtask(take, OBJ), 1, [kukahand.free]],
	[subtask(pour, OBJ), 1, [OBJ.taken]]
	]).

schema(use(OBJ), [
	[subtask(take, OBJ), 1, [kukahand.free]],
	[subtask(mix, OBJ), 1, [OBJ.taken]]
	]).

% Learned schemas: the segmented actions attached during teaching
schema(subtask(take, water), [
	[a1(water), 1, ["TRUE"]],
	[a2(water), 1, [a1.done]],
	[gripper(close), 1, [a2.done]]
	]).

schema(subtask(pour, water), [
	[a3(cup), 1, ["TRUE"]],
	[a4(cup), 1, [a3.done]],
	[a5(cup), 1, [a4.done]],
	[a6(cup), 1, [a5.done]],
	[a7(cup), 1, [a6.done]],
	[gripper(open), 1, [a7.done]]
	]).

schema(subtask(take, coffee), [
	[a8(coffee), 1, ["TRUE"]],
	[a9(coffee), 1, [a8.done]],
	[gripper(close), 1, [a9.done]]
	]).

schema(subtask(pour, coffee), [
	[a10(cup), 1, ["TRUE"]],
	[a11(cup), 1, [a10.done]],
	[a12(cup), 1, [a11.done]],
	[a13(cup), 1, [a12.done]],
	[a14(cup), 1, [a13.done]],
	[gripper(open), 1, [a14.done]]
	]).

schema(subtask(take, spoon), [
	[a15(spoon), 1, ["TRUE"]],
	[a16(spoon), 1, [a15.done]],
	[gripper(close), 1, [a16.done]]
	]).

schema(subtask(mix, spoon), [
	[a17(cup), 1, ["TRUE"]],
	[a18(cup), 1, [a17.done]],
	[a19(cup), 1, [a18.done]],
	[a20(cup), 1, [a19.done]],
	[a21(cup), 1, [a20.done]],
	[gripper(open), 1, [a21.done]]
	]).

schema(subtask(take, tea), [
	[a22(tea), 1, ["TRUE"]],
	[a23(tea), 1, [a22.done]],
	[gripper(close), 1, [a23.done]]
	]).

schema(subtask(pour, tea), [
	[a24(cup), 1, ["TRUE"]],
	[a25(cup), 1, [a24.done]],
	[a26(cup), 1, [a25.done]],
	[a27(cup), 1, [a26.done]],
	[a28(cup), 1, [a27.done]],
	[gripper(open), 1, [a28.done]]
	]).

% Concrete schemas (behaviours) and objects
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

% Goals
goal(prepareboth, [spoon.used, tea.used]).
goal(preparecoffee, [spoon.used]).
goal(preparetea, [tea.used]).
goal(add(Obj), [Obj.used]).
goal(use(Obj), [Obj.used]).
goal(subtask(take, Obj), [Obj.taken]).
goal(subtask(pour, Obj), [Obj.used]).
goal(subtask(mix, Obj), [Obj.used]).
goal(gripper(open), [kukahand.free]).
goal(gripper(close), [-kukahand.free]).
goal(a1(water), [a1.done]).
goal(a2(water), [a2.done]).
goal(a3(cup), [a3.done]).
goal(a4(cup), [a4.done]).
goal(a5(cup), [a5.done]).
goal(a6(cup), [a6.done]).
goal(a7(cup), [a7.done]).
goal(a8(coffee), [a8.done]).
goal(a9(coffee), [a9.done]).
goal(a10(cup), [a10.done]).
goal(a11(cup), [a11.done]).
goal(a12(cup), [a12.done]).
goal(a13(cup), [a13.done]).
goal(a14(cup), [a14.done]).
goal(a15(spoon), [a15.done]).
goal(a16(spoon), [a16.done]).
goal(a17(cup), [a17.done]).
goal(a18(cup), [a18.done]).
goal(a19(cup), [a19.done]).
goal(a20(cup), [a20.done]).
goal(a21(cup), [a21.done]).
goal(a22(tea), [a22.done]).
goal(a23(tea), [a23.done]).
goal(a24(cup), [a24.done]).
goal(a25(cup), [a25.done]).
goal(a26(cup), [a26.done]).
goal(a27(cup), [a27.done]).
goal(a28(cup), [a28.done]).
