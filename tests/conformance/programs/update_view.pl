% The logical update view: a running call sees the clauses as they were when it started.
:- dynamic q/1.
:- dynamic r/1.
q(1).
q(2).
