% assertz/asserta/retract.
:- dynamic fact/1.
:- dynamic counter/1.
fact(1).
fact(2).
fact(3).
counter(0).
inc :- retract(counter(N)), N1 is N + 1, assertz(counter(N1)).
static_p(1).
