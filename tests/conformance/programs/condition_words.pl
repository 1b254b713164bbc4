% A Prolog file that removes the condition language's operator words (docs/syntax.md,
% Deviations): then not, and, or read and write as in SWI-Prolog.
:- op(0, fy, not).
:- op(0, xfy, and).
:- op(0, xfy, or).
p(not(and(a, or(b, c)))).
