% Integer arithmetic: +, -, *, //, mod, rem, div, bit operations.
double(X, Y) :- Y is 2 * X.
