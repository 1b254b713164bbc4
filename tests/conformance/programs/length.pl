% length/2 in all modes.
two(L) :- length(L, 2).
