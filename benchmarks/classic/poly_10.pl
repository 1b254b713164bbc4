% poly_10: raise the polynomial 1 + x + y + z to the 10th power (Gabriel's benchmarks, 1985:
% polynomial arithmetic on a recursive representation), each polynomial poly(Var, Terms),
% Terms a list of term(Exponent, Coefficient) by rising exponent, a coefficient an integer
% or a polynomial in a later variable. The answer: the number of monomials and the sum of
% their coefficients (286 and 4^10). Written for schemalog from that description; MIT.
bench(N-Sum) :- test_poly(P), power(10, P, R), coefficients(R, 0, N, 0, Sum).

test_poly(poly(x, [term(0, poly(y, [term(0, poly(z, [term(0, 1), term(1, 1)])), term(1, 1)])),
                   term(1, 1)])).

power(1, P, P) :- !.
power(N, P, R) :- N1 is N - 1, power(N1, P, R1), mul(P, R1, R).

add(poly(V, T1), poly(V, T2), poly(V, T)) :- !, add_terms(T1, T2, T).
add(poly(V1, T1), poly(V2, T2), poly(V1, T)) :- V1 @< V2, !, add_to_zero(T1, poly(V2, T2), T).
add(P, poly(V2, T2), poly(V2, T)) :- !, add_to_zero(T2, P, T).
add(poly(V1, T1), C, poly(V1, T)) :- !, add_to_zero(T1, C, T).
add(C1, C2, C) :- C is C1 + C2.

add_to_zero([term(0, C)|T], Q, [term(0, C1)|T]) :- !, add(C, Q, C1).
add_to_zero(T, Q, [term(0, Q)|T]).

add_terms([], T, T) :- !.
add_terms(T, [], T) :- !.
add_terms([term(E, C1)|T1], [term(E, C2)|T2], [term(E, C)|T]) :- !,
    add(C1, C2, C), add_terms(T1, T2, T).
add_terms([term(E1, C1)|T1], [term(E2, C2)|T2], [term(E1, C1)|T]) :- E1 < E2, !,
    add_terms(T1, [term(E2, C2)|T2], T).
add_terms(T1, [X|T2], [X|T]) :- add_terms(T1, T2, T).

mul(poly(V, T1), poly(V, T2), poly(V, T)) :- !, mul_terms(T1, T2, T).
mul(poly(V1, T1), poly(V2, T2), poly(V1, T)) :- V1 @< V2, !, mul_const(T1, poly(V2, T2), T).
mul(P, poly(V2, T2), poly(V2, T)) :- !, mul_const(T2, P, T).
mul(poly(V1, T1), C, poly(V1, T)) :- !, mul_const(T1, C, T).
mul(C1, C2, C) :- C is C1 * C2.

mul_const([], _, []).
mul_const([term(E, C)|T], P, [term(E, C1)|T1]) :- mul(C, P, C1), mul_const(T, P, T1).

mul_terms([], _, []).
mul_terms([term(E, C)|T], T2, R) :-
    mul_term_by(T2, E, C, R1), mul_terms(T, T2, R2), add_terms(R1, R2, R).

mul_term_by([], _, _, []).
mul_term_by([term(E2, C2)|T], E, C, [term(E3, C3)|R]) :-
    E3 is E + E2, mul(C, C2, C3), mul_term_by(T, E, C, R).

coefficients(poly(_, T), N0, N, S0, S) :- !, coefficient_terms(T, N0, N, S0, S).
coefficients(C, N0, N, S0, S) :- N is N0 + 1, S is S0 + C.

coefficient_terms([], N, N, S, S).
coefficient_terms([term(_, C)|T], N0, N, S0, S) :-
    coefficients(C, N0, N1, S0, S1), coefficient_terms(T, N1, N, S1, S).
