% Cut inside control constructs: the condition of ->, its branches, \+,
% call/1 (opaque), disjunction, catch/3, findall/3.
p(1).
p(2).
p(3).
cond_cut(X) :- ( p(X), ! -> true ; true ).
cond_cut(9).
then_cut(X, Y) :- ( p(X) -> p(Y), ! ; true ).
then_cut(9, 9).
else_cut(X) :- ( fail -> true ; p(X), ! ).
else_cut(9).
ite_clause(X) :- ( true -> p(X) ; true ).
ite_clause(9).
neg_cut(X) :- p(X), \+ ( p(Y), Y > X, ! ).
neg_cut(9).
call_cut(X) :- call((p(X), !)).
call_cut(9).
call_cut_then(X) :- call(!), p(X).
call_cut_then(9).
disj_cut(X) :- ( p(X), ! ; X = 7 ).
disj_cut(9).
disj_cut2(X) :- ( X = 7 ; p(X), ! ).
disj_cut2(9).
var_goal_cut(X) :- G = !, p(X), G.
var_goal_cut(9).
findall_cut(L) :- findall(X, (p(X), !), L).
once_p(X) :- once(p(X)).
nested(X, Y) :- p(X), ( p(Y), Y > X -> ! ; fail ).
nested(9, 9).
catch_cut(X) :- catch((p(X), !), _, true).
catch_cut(9).
call_n_cut(X) :- call(',', p(X), !).
call_n_cut(9).
