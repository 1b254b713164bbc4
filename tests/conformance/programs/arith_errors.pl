% Arithmetic errors.
safe_div(X, Y, Z) :- catch(Z is X / Y, error(E, _), Z = E).
