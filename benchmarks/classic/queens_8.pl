% queens_8: all solutions of the 8-queens problem by permutation and a safety test;
% the answer is the number of solutions and the first. Written for schemalog from the
% puzzle's statement; MIT.
bench(N-First) :- findall(Q, queens(8, Q), All), length(All, N), All = [First|_].

queens(N, Qs) :- range(1, N, Ns), place(Ns, [], Qs).

place([], Qs, Qs).
place(Unplaced, Safe, Qs) :-
    pick(Q, Unplaced, Rest), safe(Safe, Q, 1), place(Rest, [Q|Safe], Qs).

safe([], _, _).
safe([Q|Qs], Q0, D) :- Q0 =\= Q + D, Q0 =\= Q - D, D1 is D + 1, safe(Qs, Q0, D1).

pick(X, [X|Xs], Xs).
pick(X, [Y|Ys], [Y|Zs]) :- pick(X, Ys, Zs).

range(N, N, [N]) :- !.
range(I, N, [I|T]) :- I < N, I1 is I + 1, range(I1, N, T).
