% maplist/2..4, foldl/4, include/3, exclude/3.
double(X, Y) :- Y is 2 * X.
pos(X) :- X > 0.
add(X, Y, Z) :- Z is X + Y.
pair(X, Y, X-Y).
