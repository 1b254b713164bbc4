% qsort: quicksort with difference lists of a list of 50 integers (the size of D.H.D.
% Warren's qsort benchmark), the list drawn here by a linear congruential generator.
% Written for schemalog; MIT.
bench(Sorted) :- numbers(50, 17, L), qsort(L, Sorted, []).

numbers(0, _, []) :- !.
numbers(N, Seed, [X|Xs]) :- X is Seed mod 100, Next is (Seed * 1103 + 12345) mod 65536,
    N1 is N - 1, numbers(N1, Next, Xs).

qsort([X|L], R, R0) :-
    partition(L, X, L1, L2), qsort(L2, R1, R0), qsort(L1, R, [X|R1]).
qsort([], R, R).

partition([X|L], Y, [X|L1], L2) :- X =< Y, !, partition(L, Y, L1, L2).
partition([X|L], Y, L1, [X|L2]) :- partition(L, Y, L1, L2).
partition([], _, [], []).
