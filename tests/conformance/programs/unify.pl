% Unification corner cases.
t(f(a, b)).
t(g(X, X)).
t([1, 2, 3]).
t("str").
t(1.0).
t(1).
same(X, X).
