% query: a database query (the shape of D.H.D. Warren's "query" benchmark): the pairs of
% countries whose population densities differ by less than 5%, from a table of population
% (hundred thousands) and area (thousand square miles). The figures are round numbers made
% up for this file. Written for schemalog; MIT.
bench(Pairs) :- findall(C1-C2, query(C1, C2), Pairs).

query(C1, C2) :-
    density(C1, D1), density(C2, D2),
    D1 > D2, T1 is 20 * D1, T2 is 21 * D2, T1 < T2.

density(C, D) :- pop(C, P), area(C, A), D is (P * 100) // A.

pop(afghanistan, 380). pop(algeria, 420). pop(argentina, 510). pop(australia, 290).
pop(bangladesh, 1230). pop(brazil, 2320). pop(burma, 620). pop(canada, 390).
pop(china, 18200). pop(colombia, 410). pop(egypt, 650). pop(ethiopia, 420).
pop(france, 980). pop(germany, 1360). pop(india, 13400). pop(indonesia, 2560).
pop(iran, 690). pop(italy, 1170). pop(japan, 2460). pop(mexico, 1210).
pop(nigeria, 1330). pop(pakistan, 1460). pop(philippines, 920). pop(poland, 720).
pop(spain, 710). pop(sweden, 160). pop(thailand, 960). pop(turkey, 840).
pop(uk, 1150). pop(ussr, 5520). pop(usa, 4260). pop(vietnam, 850).
area(afghanistan, 254). area(algeria, 919). area(argentina, 1072). area(australia, 2968).
area(bangladesh, 55). area(brazil, 3286). area(burma, 262). area(canada, 3852).
area(china, 3692). area(colombia, 440). area(egypt, 387). area(ethiopia, 472).
area(france, 211). area(germany, 138). area(india, 1269). area(indonesia, 788).
area(iran, 628). area(italy, 116). area(japan, 144). area(mexico, 762).
area(nigeria, 357). area(pakistan, 311). area(philippines, 116). area(poland, 121).
area(spain, 195). area(sweden, 174). area(thailand, 198). area(turkey, 301).
area(uk, 94). area(ussr, 8650). area(usa, 3615). area(vietnam, 128).
