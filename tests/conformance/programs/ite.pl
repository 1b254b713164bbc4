% If-then-else, if-then without else, nested conditionals, soft cut.
t(X, R) :- ( X > 0 -> R = pos ; X < 0 -> R = neg ; R = zero ).
g(1).
g(2).
first_g(R) :- ( g(X) -> R = X ; R = none ).
no_else(X, R) :- ( X > 0 -> R = pos ).
soft(X, R) :- ( g(X) *-> R = yes ; R = no ).
soft2(R) :- ( fail *-> R = yes ; R = no ).
