% functor/3 and arg/3.
mk(N, T) :- functor(T, point, N).
