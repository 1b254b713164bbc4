% Type checks.
kind(X, var) :- var(X), !.
kind(X, integer) :- integer(X), !.
kind(X, float) :- float(X), !.
kind(X, atom) :- atom(X), !.
kind(X, string) :- string(X), !.
kind(X, compound) :- compound(X), !.
