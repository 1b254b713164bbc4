% =.. and copy_term/2 (and term_variables/2).
wrap(F, X, T) :- T =.. [F, X].
