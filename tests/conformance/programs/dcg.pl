% Grammar rules (-->) and phrase/2,3: an expression grammar, digits with pushback, and the
% body constructs ({}, !, [], strings, \+, ->, ;, call//N, variables, non-terminals with args).
expr(V) --> term(T), expr_rest(T, V).
expr_rest(Acc, V) --> "+", !, term(T), { A1 is Acc + T }, expr_rest(A1, V).
expr_rest(Acc, V) --> "-", !, term(T), { A1 is Acc - T }, expr_rest(A1, V).
expr_rest(V, V) --> [].
term(V) --> factor(F), term_rest(F, V).
term_rest(Acc, V) --> "*", !, factor(F), { A1 is Acc * F }, term_rest(A1, V).
term_rest(V, V) --> [].
factor(V) --> "(", !, expr(V), ")".
factor(V) --> digits(Ds), { Ds \= [], number_codes(V, Ds) }.

digits([D|T]) --> digit(D), !, digits(T).
digits([]) --> [].
digit(D) --> [D], { code_type_digit(D) }.
code_type_digit(D) :- integer(D), D >= 0'0, D =< 0'9.

% Pushback: peek at the next item without consuming it.
peek(X), [X] --> [X].
two_peeks(A, B) --> peek(A), [A], peek(B).

greeting --> [hello], name.
name --> [world].
name --> [prolog].

anything([]) --> [].
anything([H|T]) --> [H], anything(T).

not_b --> \+ [b], [_].
ab_or_c(X) --> ( [a] -> { X = a } ; [c] -> { X = c } ; { X = none } ).
opt --> ( [] ; [x] ).
with_call(X) --> call(item, X).
item(X, [X|T], T).
meta(G) --> G, G.
abc --> "abc".
cut_first(X) --> [X], !.
cut_first(none) --> [].
opt2 --> [] | [x].
