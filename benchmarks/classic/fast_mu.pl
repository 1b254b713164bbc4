% fast_mu: the MU puzzle of mu.pl (derive MUIIU from MI in the MIU system) with the search
% pruned: a string longer than the bound allows, or whose count of I's can no longer reach
% the theorem's, is dropped (the count of I's, modulo 3, is what rules 2 and 3 change).
% Written for schemalog from the puzzle's statement; MIT.
bench(Proof) :- theorem([m, u, i, i, u], 8, Proof).

theorem(T, Max, Proof) :- length(T, N), between(1, Max, D), derive([m, i], T, N, D, Proof), !.

derive(S, S, _, _, []).
derive(S, T, N, D, [R|Rs]) :-
    D > 0, D1 is D - 1, rule(R, S, S1),
    length(S1, L), L =< N + 3 * D1,
    derive(S1, T, N, D1, Rs).

rule(1, S, S1) :- last_i(S), app(S, [u], S1).
rule(2, [m|X], [m|Y]) :- app(X, X, Y).
rule(3, S, S1) :- app(A, [i, i, i|B], S), app(A, [u|B], S1).
rule(4, S, S1) :- app(A, [u, u|B], S), app(A, B, S1).

last_i([i]) :- !.
last_i([_|T]) :- last_i(T).

app([], L, L).
app([H|T], L, [H|R]) :- app(T, L, R).
