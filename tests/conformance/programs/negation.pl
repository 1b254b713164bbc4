% Negation as failure.
bird(tweety).
bird(polly).
penguin(polly).
flies(X) :- bird(X), \+ penguin(X).
person(ann).
person(bob).
person(carl).
married(ann, bob).
single(X) :- person(X), \+ married(X, _), \+ married(_, X).
diff(X, Y) :- \+ X = Y.
