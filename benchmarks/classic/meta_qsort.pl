% meta_qsort: a meta-interpreter (solve/1 over clause/2) running quicksort of 50 integers:
% the cost of interpreting Prolog in Prolog. Written for schemalog; MIT.
:- dynamic(qsort/3).
:- dynamic(partition/4).
:- dynamic(numbers/3).

bench(Sorted) :- solve(numbers(50, 17, L)), solve(qsort(L, Sorted, [])).

solve(true) :- !.
solve((A, B)) :- !, solve(A), solve(B).
solve(G) :- builtin(G), !, call(G).
solve(G) :- clause(G, Body), solve(Body).

builtin(_ =< _).
builtin(_ > _).
builtin(_ is _).

numbers(0, _, []).
numbers(N, Seed, [X|Xs]) :- N > 0, X is Seed mod 100, Next is (Seed * 1103 + 12345) mod 65536,
    N1 is N - 1, numbers(N1, Next, Xs).

qsort([X|L], R, R0) :- partition(L, X, L1, L2), qsort(L2, R1, R0), qsort(L1, R, [X|R1]).
qsort([], R, R).

partition([X|L], Y, [X|L1], L2) :- X =< Y, partition(L, Y, L1, L2).
partition([X|L], Y, L1, [X|L2]) :- X > Y, partition(L, Y, L1, L2).
partition([], _, [], []).
