% zebra: the five-houses puzzle ("who owns the zebra?", Life International, 1962), the
% whole search by unification over a list of house(Colour, Nation, Pet, Drink, Smoke).
% Written for schemalog from the puzzle's statement; MIT.
bench(Owner-Drinker) :-
    findall(H, houses(H), [Hs]),
    member_(house(_, Owner, zebra, _, _), Hs),
    member_(house(_, Drinker, _, water, _), Hs).

houses(Hs) :-
    Hs = [house(_, norwegian, _, _, _), _, house(_, _, _, milk, _), _, _],
    member_(house(red, english, _, _, _), Hs),
    member_(house(_, spanish, dog, _, _), Hs),
    member_(house(green, _, _, coffee, _), Hs),
    member_(house(_, ukrainian, _, tea, _), Hs),
    right_of(house(green, _, _, _, _), house(ivory, _, _, _, _), Hs),
    member_(house(_, _, snails, _, winstons), Hs),
    member_(house(yellow, _, _, _, kools), Hs),
    next_to(house(_, _, _, _, chesterfields), house(_, _, fox, _, _), Hs),
    next_to(house(_, _, _, _, kools), house(_, _, horse, _, _), Hs),
    member_(house(_, _, _, orange_juice, luckies), Hs),
    member_(house(_, japanese, _, _, parliaments), Hs),
    next_to(house(_, norwegian, _, _, _), house(blue, _, _, _, _), Hs),
    member_(house(_, _, zebra, _, _), Hs),
    member_(house(_, _, _, water, _), Hs).

right_of(A, B, [B, A|_]).
right_of(A, B, [_|Y]) :- right_of(A, B, Y).
next_to(A, B, [A, B|_]).
next_to(A, B, [B, A|_]).
next_to(A, B, [_|Y]) :- next_to(A, B, Y).
member_(X, [X|_]).
member_(X, [_|Y]) :- member_(X, Y).
