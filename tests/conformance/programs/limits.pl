% Issue 21: cyclic terms, code points and huge counts, where swipl is the reference.
dummy_limits(1).
