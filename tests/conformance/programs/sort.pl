% msort/2, sort/2, sort/4, keysort/2, predsort/3.
by_length(O, A, B) :- atom_length(A, LA), atom_length(B, LB), compare(O, LA-A, LB-B).
