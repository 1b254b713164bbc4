/*  Conformance driver: run one query against one program in SWI-Prolog and
    write its answers in the canonical form that tests/test_conformance.py
    also prints for schemalog.

    swipl -q -g cf_driver:main -t halt driver.pl -- Program Query Cap Seconds ResultFile
    swipl -q -g cf_driver:batch -t halt driver.pl -- Program Dir Cap Seconds

The batch form loads Program once, reads one query a line from Dir/queries.txt
and runs query N inside snapshot/1 (so its asserts and retracts cannot leak
into the next query) writing Dir/N.res and the query's output to Dir/N.out.

    ResultFile gets one line per answer, "A<TAB>[X=...,Y=...]", then one
    ending line: "E<TAB>true" (no more answers), "E<TAB>limit" (Cap answers
    reached), "E<TAB>timeout", "E<TAB>exception:<Ball>" or
    "E<TAB>syntax_error" (the query does not read).  The query's own output
    (write/1, format/2, ...) goes to standard output.

    Canonical form (see canon/3): no operators, lists as [a,b|T], atoms,
    numbers and strings as writeq/1 prints them, compounds as name(arg,...),
    variables named _A, _B, ... in order of first appearance in the answer.
    An error(Formal, Context) ball keeps only Formal: error(Formal,_).
*/
:- module(cf_driver, [main/0, batch/0]).
:- use_module(library(time)).
:- use_module(library(lists)).
:- use_module(library(unix)).
:- use_module(library(readutil)).

main :-
    current_prolog_flag(argv, Argv),
    append(_, [Prog, QText, CapA, TimeA, ResFile], Argv),
    !,
    atom_number(CapA, Cap),
    atom_number(TimeA, Time),
    set_stream(user_output, encoding(utf8)),
    setup_call_cleanup(
        open(ResFile, write, Out, [encoding(utf8)]),
        run_file(Prog, QText, Cap, Time, Out),
        close(Out)).

batch :-
    current_prolog_flag(argv, Argv),
    append(_, [Prog, Dir, CapA, TimeA], Argv),
    !,
    atom_number(CapA, Cap),
    atom_number(TimeA, Time),
    set_prolog_flag(gc_thread, false),
    load_files(user:Prog, [silent(true)]),
    directory_file_path(Dir, 'queries.txt', QFile),
    read_file_to_string(QFile, All, [encoding(utf8)]),
    split_string(All, "\n", "", Lines0),
    exclude(==(""), Lines0, Lines),
    forall(nth1(N, Lines, QText), run_isolated(N, Dir, QText, Cap, Time)).

run_isolated(N, Dir, QText, Cap, Time) :-
    format(atom(ResName), '~d.res', [N]),
    format(atom(OutName), '~d.out', [N]),
    directory_file_path(Dir, ResName, ResFile),
    directory_file_path(Dir, OutName, OutFile),
    % snapshot/1 discards the query's asserts and retracts afterwards, so queries cannot
    % leak into each other; it replaces fork/1, which can deadlock the child of a process
    % with threads (the alarm and gc threads).
    setup_call_cleanup(
        open(ResFile, write, Res, [encoding(utf8)]),
        with_output_to(string(Printed),
                       catch(snapshot(run_query(QText, Cap, Time, Res)), _, true)),
        close(Res)),
    setup_call_cleanup(open(OutFile, write, OutS, [encoding(utf8)]),
                       write(OutS, Printed),
                       close(OutS)).

run_file(Prog, QText, Cap, Time, Out) :-
    load_files(user:Prog, [silent(true)]),
    run_query(QText, Cap, Time, Out).

run_query(QText, Cap, Time, Out) :-
    (   catch(term_string(Goal, QText, [variable_names(Bs0), module(user)]), _, fail)
    ->  exclude(hidden_name, Bs0, Bs),
        nb_setval(cf_count, 0),
        catch(call_with_time_limit(Time, run(Goal, Bs, Cap, Out, End0)),
              Ball, End0 = exception(Ball)),
        ending(End0, End)
    ;   End = syntax_error
    ),
    flush_output(user_output),
    format(Out, "E\t~w~n", [End]).

hidden_name(Name=_) :- sub_atom(Name, 0, 1, _, '_').

run(Goal, Bs, Cap, Out, End) :-
    (   user:Goal,
        answer_text(Bs, Text),
        format(Out, "A\t~w~n", [Text]),
        flush_output(Out),
        nb_getval(cf_count, N0), N is N0 + 1, nb_setval(cf_count, N),
        N >= Cap
    ->  End = limit
    ;   End = true
    ).

ending(exception(time_limit_exceeded), timeout) :- !.
ending(exception(Ball), Text) :- !,
    (   nonvar(Ball), Ball = error(Formal, _)
    ->  Reduced = error(Formal, _)
    ;   Reduced = Ball
    ),
    canon_text(Reduced, Body),
    atom_concat('exception:', Body, Text).
ending(End, End).

answer_text(Bs, Text) :-
    binding_pairs(Bs, Pairs),
    canon_text(Pairs, Text).

binding_pairs([], []).
binding_pairs([N=V|Bs], [N-V|Ps]) :- binding_pairs(Bs, Ps).

% canon_text(+Term, -Atom): the canonical text; a pair list Name-Value prints
% as [Name=Value,...] with Name unquoted (it is a variable name).
canon_text(Term, Text) :-
    term_variables(Term, Vars),
    with_output_to(string(S), canon_top(Term, Vars)),
    atom_string(Text, S).

canon_top(Pairs, Vars) :-
    is_list(Pairs), Pairs \== [], Pairs = [_-_|_], !,
    write('['),
    canon_pairs(Pairs, Vars),
    write(']').
canon_top([], _) :- !, write('[]').
canon_top(Term, Vars) :- canon(Term, Vars).

canon_pairs([N-V|T], Vars) :-
    write(N), write('='), canon(V, Vars),
    (   T == [] -> true ; write(','), canon_pairs(T, Vars) ).

canon(T, Vars) :- var(T), !, var_index(Vars, T, 0, I), var_name(I, Name), write(Name).
canon(T, _) :- atomic(T), !, writeq(T).
canon([H|T], Vars) :- !, write('['), canon(H, Vars), canon_tail(T, Vars), write(']').
canon(T, Vars) :-
    compound_name_arguments(T, Name, Args),
    writeq(Name), write('('), canon_args(Args, Vars), write(')').

canon_tail(T, Vars) :- var(T), !, write('|'), canon(T, Vars).
canon_tail([], _) :- !.
canon_tail([H|T], Vars) :- !, write(','), canon(H, Vars), canon_tail(T, Vars).
canon_tail(T, Vars) :- write('|'), canon(T, Vars).

canon_args([A], Vars) :- !, canon(A, Vars).
canon_args([A|As], Vars) :- canon(A, Vars), write(','), canon_args(As, Vars).

var_index([V|Vs], T, I0, I) :- ( V == T -> I = I0 ; I1 is I0 + 1, var_index(Vs, T, I1, I) ).

var_name(I, Name) :-
    L is 0'A + I mod 26, N is I // 26,
    (   N =:= 0 -> format(atom(Name), '_~c', [L]) ; format(atom(Name), '_~c~d', [L, N]) ).
