% between/3.
small(X) :- between(1, 3, X).
