% sendmore: SEND + MORE = MONEY (H.E. Dudeney, 1924), solved column by column from the
% right, each letter a distinct digit taken from the digits left, with carries.
% Written for schemalog from the puzzle's statement; MIT.
bench([S, E, N, D, M, O, R, Y]) :-
    Digits = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9],
    take(D, Digits, R1), take(E, R1, R2),
    Y0 is D + E, Y is Y0 mod 10, C1 is Y0 // 10, take(Y, R2, R3),
    take(N, R3, R4), take(R, R4, R5),
    E0 is N + R + C1, E =:= E0 mod 10, C2 is E0 // 10,
    take(O, R5, R6),
    N0 is E + O + C2, N =:= N0 mod 10, C3 is N0 // 10,
    take(S, R6, R7), S > 0, take(M, R7, _), M > 0,
    O0 is S + M + C3, O =:= O0 mod 10, M =:= O0 // 10.

take(X, [X|Xs], Xs).
take(X, [Y|Ys], [Y|Zs]) :- take(X, Ys, Zs).
