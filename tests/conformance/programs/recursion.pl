% Classic recursive programs.
nrev([], []).
nrev([H|T], R) :- nrev(T, RT), append(RT, [H], R).
fib(0, 0).
fib(1, 1).
fib(N, F) :- N > 1, N1 is N - 1, N2 is N - 2, fib(N1, F1), fib(N2, F2), F is F1 + F2.
fact(0, 1) :- !.
fact(N, F) :- N1 is N - 1, fact(N1, F1), F is N * F1.
hanoi(0, _, _, _, []) :- !.
hanoi(N, A, B, C, Moves) :-
    N1 is N - 1,
    hanoi(N1, A, C, B, M1),
    hanoi(N1, C, B, A, M2),
    append(M1, [A-B|M2], Moves).
perm([], []).
perm(L, [H|T]) :- select(H, L, R), perm(R, T).
queens(N, Qs) :- numlist(1, N, Ns), perm(Ns, Qs), safe(Qs).
safe([]).
safe([Q|Qs]) :- no_attack(Q, Qs, 1), safe(Qs).
no_attack(_, [], _).
no_attack(Q, [Q1|Qs], D) :- Q =\= Q1 + D, Q =\= Q1 - D, D1 is D + 1, no_attack(Q, Qs, D1).
qsort([], []).
qsort([H|T], S) :- split(H, T, L, G), qsort(L, SL), qsort(G, SG), append(SL, [H|SG], S).
split(_, [], [], []).
split(P, [X|Xs], [X|L], G) :- X =< P, !, split(P, Xs, L, G).
split(P, [X|Xs], L, [X|G]) :- split(P, Xs, L, G).
count(N, N) :- !.
count(I, N) :- I1 is I + 1, count(I1, N).
ackermann(0, N, R) :- !, R is N + 1.
ackermann(M, 0, R) :- !, M1 is M - 1, ackermann(M1, 1, R).
ackermann(M, N, R) :- M1 is M - 1, N1 is N - 1, ackermann(M, N1, R1), ackermann(M1, R1, R).
