% Standard order of terms, compare/3, ==, @<.
older(X, Y) :- compare(>, X, Y).
