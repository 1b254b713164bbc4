% Atom builtins.
greeting(hello).
