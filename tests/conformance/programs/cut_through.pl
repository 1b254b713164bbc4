% A cut reached through a variable bound at run time (issue 37): a goal term is turned into a
% body when call/1 (findall/3, \+, catch/3, forall/2, assertz/1) runs it, and a variable bound
% by then is its value there, so `!` cuts the call's own alternatives; a variable still unbound
% then is call(V), whose cut is local. A clause body's variable goal was turned when it was read.
s(A, A).
p(1).
p(2).
p(3).
body_var(X, C) :- p(X), C.
body_disj(C, X) :- ( C ; X = 9 ).
