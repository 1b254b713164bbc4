% boyer: rewrite a formula to if-then-else normal form with a set of lemmas, then check that
% it is a tautology by case analysis on its conditions (the method of Gabriel's "boyer"
% benchmark, 1985, after Boyer and Moore's prover). The lemmas here are a smaller set of our
% own (list, arithmetic and boolean identities), so this is not the published lemma base.
% The rewriting takes terms apart with functor/3 and arg/3. The answer: whether the formula
% is a tautology, and the size of its rewritten form. Written for schemalog; MIT.
bench(Result-Size) :-
    wff(Wff), rewrite(Wff, New), size(New, 0, Size),
    ( tautology(New, [], []) -> Result = true ; Result = false ).

wff(implies(and(implies(X, Y), and(implies(Y, Z), and(implies(Z, U), implies(U, W)))),
            implies(X, W))) :-
    X = f(plus(plus(a, b), plus(c, zero))),
    Y = f(times(times(a, b), plus(c, d))),
    Z = f(reverse(append(append(a, b), nil))),
    U = equal(plus(a, b), difference(x, y)),
    W = lessp(remainder(a, b), member(a, length(b))).

rewrite(A, A) :- atomic(A), !.
rewrite(Old, New) :-
    functor(Old, F, N), functor(Mid, F, N), rewrite_args(N, Old, Mid),
    ( equal(Mid, Next), rewrite(Next, New) ; New = Mid ), !.

rewrite_args(0, _, _) :- !.
rewrite_args(N, Old, Mid) :-
    arg(N, Old, OldArg), arg(N, Mid, MidArg), rewrite(OldArg, MidArg),
    N1 is N - 1, rewrite_args(N1, Old, Mid).

tautology(Wff, Ts, Fs) :-
    (   truep(Wff, Ts) -> true
    ;   falsep(Wff, Fs) -> fail
    ;   Wff = if(If, Then, Else) ->
        (   truep(If, Ts) -> tautology(Then, Ts, Fs)
        ;   falsep(If, Fs) -> tautology(Else, Ts, Fs)
        ;   tautology(Then, [If|Ts], Fs), tautology(Else, Ts, [If|Fs])
        )
    ), !.

truep(t, _) :- !.
truep(Wff, Ts) :- memberchk_(Wff, Ts).
falsep(f, _) :- !.
falsep(Wff, Fs) :- memberchk_(Wff, Fs).

memberchk_(X, [Y|Ys]) :- ( X == Y -> true ; memberchk_(X, Ys) ).

size(T, S0, S) :- atomic(T), !, S is S0 + 1.
size(T, S0, S) :- functor(T, _, N), S1 is S0 + 1, size_args(N, T, S1, S).
size_args(0, _, S, S) :- !.
size_args(N, T, S0, S) :- arg(N, T, A), size(A, S0, S1), N1 is N - 1, size_args(N1, T, S1, S).

% The lemmas: equal(Old, New) rewrites an instance of Old into New.
equal(and(P, Q), if(P, if(Q, t, f), f)).
equal(or(P, Q), if(P, t, if(Q, t, f))).
equal(not(P), if(P, f, t)).
equal(implies(P, Q), if(P, if(Q, t, f), t)).
equal(if(if(A, B, C), D, E), if(A, if(B, D, E), if(C, D, E))).
equal(plus(plus(X, Y), Z), plus(X, plus(Y, Z))).
equal(plus(X, zero), fix(X)).
equal(times(X, plus(Y, Z)), plus(times(X, Y), times(X, Z))).
equal(times(times(X, Y), Z), times(X, times(Y, Z))).
equal(times(X, one), fix(X)).
equal(append(append(X, Y), Z), append(X, append(Y, Z))).
equal(append(X, nil), X).
equal(reverse(append(A, B)), append(reverse(B), reverse(A))).
equal(reverse(nil), nil).
equal(length(reverse(X)), length(X)).
equal(length(append(X, Y)), plus(length(X), length(Y))).
equal(member(X, append(A, B)), or(member(X, A), member(X, B))).
equal(member(X, reverse(Y)), member(X, Y)).
equal(difference(X, X), zero).
equal(difference(plus(X, Y), X), fix(Y)).
equal(equal(plus(A, B), zero), and(zerop(A), zerop(B))).
equal(equal(X, X), t).
equal(lessp(remainder(_, Y), Y), not(zerop(Y))).
equal(remainder(_, one), zero).
equal(zerop(X), or(equal(X, zero), not(numberp(X)))).
equal(fix(X), if(numberp(X), X, zero)).
equal(numberp(plus(_, _)), t).
equal(numberp(times(_, _)), t).
equal(numberp(length(_)), t).
equal(f(X), g(X, X)).
