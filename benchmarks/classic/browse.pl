% browse: build a database of "units", each with a property list drawn by a pseudo-random
% generator, and match patterns with wildcards (? one item, * any run of items) against
% every unit's properties (the task of Gabriel's "browse" benchmark, 1985: list building
% and pattern matching). The answer: the number of matches of each pattern.
% Written for schemalog from that description; MIT.
bench(Counts) :-
    units(100, 7, Units),
    findall(N, (pattern(P), count(Units, P, 0, N)), Counts).

units(0, _, []) :- !.
units(N, Seed, [Props|Us]) :-
    Len is 4 + Seed mod 5, props(Len, Seed, Seed1, Props),
    N1 is N - 1, units(N1, Seed1, Us).

props(0, S, S, []) :- !.
props(N, S, S2, [P|Ps]) :-
    S1 is (S * 1103 + 12345) mod 65536, K is S1 mod 7, item(K, S1, P),
    N1 is N - 1, props(N1, S1, S2, Ps).

item(0, _, a) :- !.
item(1, _, b) :- !.
item(2, _, c) :- !.
item(3, S, [a, X]) :- !, K is S mod 3, item(K, S, X).
item(4, _, [b, c]) :- !.
item(5, _, d) :- !.
item(_, _, [c, a, b]).

pattern([*, a, *, b, *]).
pattern([?, *, [?, a], *]).
pattern([*, [b, ?], ?, *, c]).
pattern([a, *, ?, [*, b], *]).
pattern([*, c, *, c, *, a, *]).

count([], _, N, N).
count([U|Us], P, N0, N) :- ( match(P, U) -> N1 is N0 + 1 ; N1 = N0 ), count(Us, P, N1, N).

match([], []).
match([*|P], D) :- !, tails(D, T), match(P, T).
match([?|P], [_|D]) :- !, match(P, D).
match([X|P], [Y|D]) :- atom(X), !, X == Y, match(P, D).
match([X|P], [Y|D]) :- match(X, Y), match(P, D).

tails(D, D).
tails([_|D], T) :- tails(D, T).
