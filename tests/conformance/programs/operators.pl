% Operators: op/3 directives change how the clauses after them read, and how terms are
% written (writeq/1, print/1, write/1; write_canonical/1 and ignore_ops(true) ignore them).
:- op(700, xfx, my_ins).
:- op(200, xf, fact).
:- op(900, fy, nicht).
:- op(650, yfx, ++).
:- op(710, xfy, ===>).
:- op(700, xfx, gone).
:- op(0, xfx, gone).

show(X) :- writeq(X), nl.
all(X) :- writeq(X), write('  '), print(X), write('  '), write(X), write('  '),
    write_canonical(X), write('  '), write_term(X, [ignore_ops(true)]), write('  '),
    write_term(X, [quoted(true), ignore_ops(true)]), nl.

t(ins, X) :- X = (a my_ins b).
t(fact, X) :- X = (3 fact).
t(fact2, X) :- X = (- 3 fact).
t(nicht, X) :- X = (nicht nicht a).
t(nicht_paren, X) :- X = (nicht (a, b)).
t(atoms, X) :- X = f(my_ins, nicht, fact, ++).
t(functional, X) :- X = my_ins(a, b).
t(yfx, X) :- X = (a ++ b ++ c).
t(yfx_right, X) :- X = (a ++ (b ++ c)).
t(xfy, X) :- X = (a ===> b ===> c).
t(mixed, X) :- X = (a ++ b my_ins c ===> d).
t(gone, X) :- X = gone(a, b).
t(quoted_op, X) :- X = 'my_ins'(1, 2).
