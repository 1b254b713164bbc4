% ISO atom and text built-ins: modes and error cases (ISO 8.16), SWI-Prolog 9 as the reference.
word(iso).
