% chat_parser: parse English questions with a definite clause grammar (the kind of
% grammar of Pereira and Warren's Chat-80, whose parser is the "chat_parser" benchmark);
% a small grammar of our own, not Chat-80's. The answer: the parse trees.
% Written for schemalog; MIT. Uses DCG rules (-->).
bench(Trees) :- findall(T, (sentence_(S), sentence(T, S, [])), Trees).

sentence_([which, countries, border, the, ocean]).
sentence_([what, is, the, capital, of, a, country, that, borders, a, sea]).
sentence_([does, the, river, that, flows, through, a, country, border, the, sea]).

sentence(q(W, VP)) --> wh(W), verb_phrase(VP).
sentence(yn(NP, VP)) --> [does], noun_phrase(NP), verb_phrase(VP).
wh(which(N)) --> [which], noun(N).
wh(what) --> [what].
verb_phrase(vp(V, NP)) --> verb(V), noun_phrase(NP).
verb_phrase(is(NP)) --> [is], noun_phrase(NP).
noun_phrase(np(D, N, M)) --> det(D), noun(N), modifier(M).
modifier(rel(VP)) --> [that], verb_phrase(VP).
modifier(pp(P, NP)) --> prep(P), noun_phrase(NP).
modifier(none) --> [].
det(the) --> [the].
det(a) --> [a].
noun(N) --> [N], { noun_word(N) }.
verb(V) --> [V], { verb_word(V) }.
prep(P) --> [P], { member(P, [of, through, in]) }.
noun_word(W) :- member(W, [countries, country, ocean, capital, sea, river]).
verb_word(W) :- member(W, [border, borders, flows]).
