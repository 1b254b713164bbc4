% bagof/3: free variables, ^, failure on no solutions.
age(peter, 7).
age(ann, 11).
age(pat, 8).
age(tom, 5).
age(mike, 11).
class(a, ann).
class(b, tom).
class(a, pat).
class(b, mike).
class(a, peter).
