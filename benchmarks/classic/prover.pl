% prover: a propositional theorem prover by Wang's algorithm (H. Wang, 1960: sequents of
% formulas, each connective taken apart on the side it stands until atoms are left),
% run on a dozen formulas; the answer says which are theorems. Written for schemalog from
% that description; MIT.
bench(Results) :- findall(F-R, (problem(F), (prove(F) -> R = yes ; R = no)), Results).

prove(F) :- wang([], [], [], [F]).

% wang(LeftAtoms, LeftFormulas, RightAtoms, RightFormulas)
wang(LA, [F|L], RA, R) :- left(F, LA, L, RA, R).
wang(LA, [], RA, [F|R]) :- right(F, LA, RA, R).
wang(LA, [], RA, []) :- common(LA, RA).

left(not(A), LA, L, RA, R) :- !, wang(LA, L, RA, [A|R]).
left(and(A, B), LA, L, RA, R) :- !, wang(LA, [A, B|L], RA, R).
left(or(A, B), LA, L, RA, R) :- !, wang(LA, [A|L], RA, R), wang(LA, [B|L], RA, R).
left(imp(A, B), LA, L, RA, R) :- !, wang(LA, L, RA, [A|R]), wang(LA, [B|L], RA, R).
left(iff(A, B), LA, L, RA, R) :- !, left(and(imp(A, B), imp(B, A)), LA, L, RA, R).
left(A, LA, L, RA, R) :- ( memberchk(A, RA) -> true ; wang([A|LA], L, RA, R) ).

right(not(A), LA, RA, R) :- !, wang(LA, [A], RA, R).
right(and(A, B), LA, RA, R) :- !, wang(LA, [], RA, [A|R]), wang(LA, [], RA, [B|R]).
right(or(A, B), LA, RA, R) :- !, wang(LA, [], RA, [A, B|R]).
right(imp(A, B), LA, RA, R) :- !, wang(LA, [A], RA, [B|R]).
right(iff(A, B), LA, RA, R) :- !, right(and(imp(A, B), imp(B, A)), LA, RA, R).
right(A, LA, RA, R) :- ( memberchk(A, LA) -> true ; wang(LA, [], [A|RA], R) ).

common(LA, RA) :- member(X, LA), memberchk(X, RA), !.

problem(imp(p, p)).
problem(or(p, not(p))).
problem(imp(and(p, q), p)).
problem(imp(p, and(p, q))).
problem(iff(not(and(p, q)), or(not(p), not(q)))).
problem(iff(not(or(p, q)), and(not(p), not(q)))).
problem(imp(imp(imp(p, q), p), p)).
problem(imp(and(imp(p, q), imp(q, r)), imp(p, r))).
problem(iff(imp(p, imp(q, r)), imp(and(p, q), r))).
problem(imp(or(p, q), and(p, q))).
problem(iff(and(p, or(q, r)), or(and(p, q), and(p, r)))).
problem(iff(or(p, and(q, r)), and(or(p, q), or(p, r)))).
problem(imp(and(imp(a, b), and(imp(b, c), and(imp(c, d), imp(d, e)))), imp(a, e))).
problem(iff(iff(p, q), iff(q, p))).
problem(imp(and(or(p, q), and(imp(p, r), imp(q, r))), r)).
problem(imp(and(or(p, q), and(imp(p, r), imp(q, s))), and(r, s))).
