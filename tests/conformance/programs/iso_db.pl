% ISO clause creation and destruction, clause/2 and the predicate inspection built-ins.
:- dynamic counter/1, fact/1, empty/0.
counter(0).
fact(1).
fact(2).
fact(3).
st(a).
st(b).
rule(X) :- fact(X), X > 1.
rule(9).
