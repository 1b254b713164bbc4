% Backtracking order: clause order, left-to-right conjunctions.
colour(red).
colour(green).
colour(blue).
size(small).
size(large).
item(C, S) :- colour(C), size(S).
nat(0).
nat(N) :- nat(M), N is M + 1.
path(a, b).
path(b, c).
path(c, d).
path(a, d).
reach(X, Y) :- path(X, Y).
reach(X, Z) :- path(X, Y), reach(Y, Z).
choice(1) :- write(one), nl.
choice(2) :- write(two), nl.
choice(3).
