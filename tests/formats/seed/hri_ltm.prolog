% A SEED long-term memory in the style of the authors' files (written for schemalog's
% tests): the operator and consult directives, server code, abstract and concrete
% schemas, rule schemas that read a spoken sentence with ECLiPSe's string built-ins
% and ask the memory itself, a helper predicate, float importances, a string releaser,
% a sub-task nothing defines, and goals with object variables.
:-op(500,xfy,.).
:-op(600,fx,-).
:-['Map2Memory.prolog'].

:- dynamic schema/2.
:- dynamic goal/2.

%Server
getSemantics(X):-
	yield([],_),
	schema(X,SemDef),
	yield(SemDef,_),!.

getGoal(X):-
	yield([],_),
	goal(X,Goal),
	yield(Goal,_),!.

rememberSchema(Instance,NewSon,Releaser):-
	retract(schema(Instance,[H|Rest])),!,
	append([H|Rest],[[NewSon,1,[Releaser]]],NewList),
	asserta(schema(Instance,NewList)).

%abstract schemas
schema(serve(Obj),[
	[listen(Obj),1,["TRUE"]],
	[en("bring me the tea cup"),2.5,["TRUE"]],
	[handOver(Obj),1,[heard.Obj,"-kukahand.free"]],
	[wave,0.5,["TRUE"]]
	]).

schema(handOver(Obj),[
	[kuka(gripper(open)),1,[-kukahand.free]],
	[say(done),1,[human.Obj]]
	]).

%concrete schemas
schema(listen(_),[]).
schema(kuka(_),[]).
schema(say(_),[]).
schema($(_),[]).

schema(speech(take),[]).
schema(speech(bring),[]).
schema(speech(stop),[]).

schema(object(tea),[]).
schema(object(cup),[]).
schema(object(teacup),[]).

%language: one verb
schema(en(Sentence),[
	[speech(TermAction),2,["TRUE"]]]):-
		string(Sentence),
		split_string(Sentence," ","",[_,Action]),
		term_string(TermAction,Action),
		schema(speech(TermAction),_).

%language: a verb and a two-word object ("bring me the tea cup")
schema(en(Sentence),[
	[speech(TermAction),2,["TRUE"]],
	[object(TermObject),1.5,["TRUE"]]]):-
		string(Sentence),
		split_string(Sentence," ","",[Action,"me","the",Ob_pt1,Ob_pt2]),
		term_string(TermAction,Action),
		concat_string([Ob_pt1,Ob_pt2],Object),
		known(Object),
		term_string(TermObject,Object).

known(Object):-
	atom_string(Atom,Object),
	schema(object(Atom),_).

goal(listen(Obj),[heard.Obj]).
goal(handOver(Obj),[human.Obj]).
goal(kuka(gripper(open)),[kukahand.free]).
goal(say(X),[said.X]).
goal(speech(A),[understood.A]).
