% Cut at the start, middle and end of a clause body.
p(1).
p(2).
p(3).
q(a).
q(b).
start(X) :- !, p(X).
start(9).
middle(X, Y) :- p(X), !, q(Y).
middle(9, 9).
end(X) :- p(X), q(_), !.
end(9).
two_cuts(X, Y) :- p(X), !, q(Y), !.
two_cuts(9, 9).
cut_fail(X) :- X > 2, !, fail.
cut_fail(_).
max(X, Y, X) :- X >= Y, !.
max(_, Y, Y).
classify(N, neg) :- N < 0, !.
classify(0, zero) :- !.
classify(_, pos).
after(X) :- p(X), X > 1, !.
after(0).
nocut(X) :- p(X).
nocut(9).
outer(X) :- start(X).
outer(100).
cut_then_fail(X) :- p(X), X > 1, !, X > 5.
cut_then_fail(7).
