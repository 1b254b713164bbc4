% fib: the 21st Fibonacci number by doubly recursive calls (integer arithmetic, deep
% recursion). Written for schemalog; MIT.
bench(F) :- fib(21, F).

fib(0, 0) :- !.
fib(1, 1) :- !.
fib(N, F) :- N1 is N - 1, N2 is N - 2, fib(N1, F1), fib(N2, F2), F is F1 + F2.
