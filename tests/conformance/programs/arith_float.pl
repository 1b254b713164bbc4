% Float arithmetic, mixed arithmetic, powers, rounding.
area(R, A) :- A is pi * R * R.
