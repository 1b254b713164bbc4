% Disjunction.
a(1).
a(2).
b(3).
b(4).
ab(X) :- a(X) ; b(X).
nested(X) :- ( a(X) ; ( b(X) ; X = 5 ) ).
d(X, Y) :- ( X = 1, Y = a ; X = 2, Y = b ; X = 3 ).
