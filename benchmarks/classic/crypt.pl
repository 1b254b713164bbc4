% crypt: a cryptomultiplication (the "crypt" puzzle of Peter Van Roy's benchmark set, as its
% published description states it): find every
%
%         O E E          O: an odd digit, E: an even digit,
%       x   E E          leading digits not zero
%       -------
%       E O E E          the first partial product
%       E O E            the second, shifted one place
%       -------
%       O O E E          the product
%
% by generating digits and checking each product's digits with integer arithmetic.
% Written for schemalog from that statement; MIT.
bench(Solutions) :- findall(M1*M2=P, crypt(M1, M2, P), Solutions).

crypt(M1, M2, P) :-
    odd(A), A > 0, even(B), even(C),
    M1 is 100 * A + 10 * B + C,
    even(D), D > 0, even(E),
    P1 is M1 * E, digits(P1, [e, o, e, e]),
    P2 is M1 * D, digits(P2, [e, o, e]),
    M2 is 10 * D + E,
    P is P2 * 10 + P1, digits(P, [o, o, e, e]).

% digits(N, Pattern): N has as many digits as Pattern, each of the parity given.
digits(N, Pattern) :- reverse_(Pattern, [], Reversed), check(Reversed, N).

check([], 0).
check([K|Ks], N) :- N > 0, D is N mod 10, parity(K, D), N1 is N // 10, check(Ks, N1).

parity(e, D) :- D mod 2 =:= 0.
parity(o, D) :- D mod 2 =:= 1.

reverse_([], A, A).
reverse_([X|Xs], A, R) :- reverse_(Xs, [X|A], R).

odd(1). odd(3). odd(5). odd(7). odd(9).
even(0). even(2). even(4). even(6). even(8).
