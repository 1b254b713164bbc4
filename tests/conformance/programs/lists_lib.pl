% Other list library predicates.
numbers([3, 1, 4, 1, 5]).
