% String builtins.
name_of(X, S) :- atom_string(X, S).
