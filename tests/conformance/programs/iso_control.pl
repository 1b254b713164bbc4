% ISO control constructs, all-solutions, exceptions, flags and operators (ISO 7.8, 8.1, 8.10, 8.14, 8.17).
q(1).
q(2).
q(3).
r(1, a).
r(2, b).
r(1, c).
cleanup_log(_).
