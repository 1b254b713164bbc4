% Unknown procedures and type/instantiation errors of builtins.
:- dynamic known/1.
defined(1).
calls_unknown(X) :- missing_helper(X).
