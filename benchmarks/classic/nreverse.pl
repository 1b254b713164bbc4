% nreverse: naive reverse of a 30-element list (496 logical inferences).
% Written for schemalog from the textbook description of the "nrev" LIPS benchmark
% (D.H.D. Warren's naive reverse); MIT, as the rest of this project.
bench(R) :- numlist_(1, 30, L), nrev(L, R).

nrev([], []).
nrev([H|T], R) :- nrev(T, RT), app(RT, [H], R).

app([], L, L).
app([H|T], L, [H|R]) :- app(T, L, R).

numlist_(N, N, [N]) :- !.
numlist_(I, N, [I|T]) :- I1 is I + 1, numlist_(I1, N, T).
