% Assorted builtins and library predicates both engines may offer.
dummy_misc(1).
