% derive: symbolic differentiation, with simplification of the result, of four expressions
% (the four of D.H.D. Warren's differentiation benchmarks, 1977). Written for schemalog from
% the textbook rules; MIT.
bench(Ds) :-
    findall(D, (expr(E), d(E, x, D0), simplify(D0, D)), Ds).

expr(((x * x) * x) * x).
expr(((x / x) / x) / x).
expr(log(log(log(x)))).
expr((x + 1) * ((x ^ 2 + 2) * (x ^ 3 + 3))).

d(U + V, X, DU + DV) :- !, d(U, X, DU), d(V, X, DV).
d(U - V, X, DU - DV) :- !, d(U, X, DU), d(V, X, DV).
d(U * V, X, DU * V + U * DV) :- !, d(U, X, DU), d(V, X, DV).
d(U / V, X, (DU * V - U * DV) / V ^ 2) :- !, d(U, X, DU), d(V, X, DV).
d(U ^ N, X, DU * N * U ^ N1) :- !, integer(N), N1 is N - 1, d(U, X, DU).
d(log(U), X, DU / U) :- !, d(U, X, DU).
d(X, X, 1) :- !.
d(_, _, 0).

simplify(E, S) :- compound(E), E =.. [Op, A, B], !,
    simplify(A, SA), simplify(B, SB), rule(Op, SA, SB, S).
simplify(E, E).

rule(*, 0, _, 0) :- !.
rule(*, _, 0, 0) :- !.
rule(*, 1, B, B) :- !.
rule(*, A, 1, A) :- !.
rule(+, 0, B, B) :- !.
rule(+, A, 0, A) :- !.
rule(-, A, 0, A) :- !.
rule(^, A, 1, A) :- !.
rule(Op, A, B, S) :- integer(A), integer(B), memberchk(Op, [+, -, *]), !, E =.. [Op, A, B], S is E.
rule(Op, A, B, S) :- S =.. [Op, A, B].
