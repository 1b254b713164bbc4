% call/N with closures.
add(X, Y, Z) :- Z is X + Y.
twice(G, X, Z) :- call(G, X, Y), call(G, Y, Z).
succ_of(X, Y) :- Y is X + 1.
p(a).
p(b).
rel(a, 1).
rel(b, 2).
