% INRIA-suite corners: abolish/1 of a dynamic predicate, existence errors through call/1,
% =.. of numbers with an empty list.
:- dynamic foo/1.
foo(1).
