% sieve: the primes up to 1000 by Eratosthenes' sieve kept in the database: every candidate
% asserted as a fact, the smallest left retracted as the next prime, its multiples
% retracted (assert/retract on a predicate of a thousand clauses). The answer: how many
% primes and the last. Written for schemalog from the sieve's description; MIT.
:- dynamic(cand/1).

bench(N-Last) :- primes(1000, Ps), length(Ps, N), last_(Ps, Last).

primes(Max, Ps) :- retractall(cand(_)), fill(2, Max), sift(Max, Ps).

fill(I, Max) :- I > Max, !.
fill(I, Max) :- assertz(cand(I)), I1 is I + 1, fill(I1, Max).

sift(Max, [P|Ps]) :- retract(cand(P)), !, M is P * P, strike(M, P, Max), sift(Max, Ps).
sift(_, []).

strike(M, _, Max) :- M > Max, !.
strike(M, P, Max) :- ( retract(cand(M)) -> true ; true ), M1 is M + P, strike(M1, P, Max).

last_([X], X) :- !.
last_([_|T], X) :- last_(T, X).
