% Arithmetic comparison.
positive(X) :- X > 0.
