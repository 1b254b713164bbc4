% Text output: write/1, writeq/1, print/1, write_canonical/1, format/2, nl/0.
show(X) :- writeq(X), nl.
