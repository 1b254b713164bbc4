% findall/3 (and findall/4, aggregate_all/3).
p(1, a).
p(2, b).
p(3, a).
