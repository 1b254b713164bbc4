% mu: Hofstadter's MU puzzle (Goedel, Escher, Bach, 1979): derive the theorem MUIIU from
% the axiom MI with the four rules of the MIU system, depth-first with a bound on the
% derivation's length, raised one step at a time (iterative deepening). The answer is the
% derivation, as the rules applied. Written for schemalog from the puzzle's statement; MIT.
bench(Proof) :- theorem([m, u, i, i, u], 8, Proof).

theorem(T, Max, Proof) :- between(1, Max, D), derive([m, i], T, D, Proof), !.

derive(S, S, _, []).
derive(S, T, D, [R|Rs]) :- D > 0, D1 is D - 1, rule(R, S, S1), derive(S1, T, D1, Rs).

rule(1, S, S1) :- app(_, [i], S), app(S, [u], S1).
rule(2, [m|X], [m|Y]) :- app(X, X, Y).
rule(3, S, S1) :- app(A, [i, i, i|B], S), app(A, [u|B], S1).
rule(4, S, S1) :- app(A, [u, u|B], S), app(A, B, S1).

app([], L, L).
app([H|T], L, [H|R]) :- app(T, L, R).
