% nth0/3, nth1/3 and last/2.
letters([a, b, c]).
