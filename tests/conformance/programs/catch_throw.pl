% throw/1 and catch/3.
risky(X) :- X > 5, throw(too_big(X)).
risky(X) :- X < 0, throw(error(domain_error(positive, X), risky/1)).
risky(_).
safe(X, R) :- catch(risky(X), E, R = caught(E)), ( var(R) -> R = ok ; true ).
rethrow :- catch(throw(a), b, true).
first_big(L) :- catch(( member(X, [1, 2, 3]), X >= 2, throw(found(X)) ), found(Y), L = Y).
