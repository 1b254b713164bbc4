% Definition 1 of "Symbolic Task Compression in Structured Task Learning" (Sec. III-B),
% as schemalog applies it. Queried over a task tree given as facts:
%
%   node(Id, Label)        parent(Id, ParentId)     agent(Id, Agent)
%   objects(Id, [O, ...])  post(Id, Condition)      entry(Id, Condition)
%   kind(Id, action | subtask)
%
% where `entry` is the behaviour's own releaser (for a merged behaviour, its first
% constituent's original releaser): comparing a post-condition with a releaser after
% context propagation or OR-merging would stop a1, a2 being sequential once their
% parents merge. Conditions are in canonical form, so equal conditions unify.
%
% The compressor uses an indexed equivalent of this rule (compress.sequential_pairs);
% a property test checks that the two always agree.

:- dynamic no_merge/1.
:- dynamic node/2, parent/2, agent/2, objects/2, post/2, entry/2, kind/2.

% sequential(B1, B2): B1 and B2 are sequential, B1 first.
sequential(B1, B2) :-
    parent(B1, P), parent(B2, P), B1 \== B2,   % 1) children of the same node
    agent(B1, A), agent(B2, A),                % 2) performed by the same agent
    objects(B1, Os), objects(B2, Os),          % 3) act on the same objects
    post(B1, C), entry(B2, C),                 % 4) the post-condition of one is the
    C \== true, C \== false,                   %    (entry) pre-condition of the other
    kind(B1, K), kind(B2, K),                  % schemalog: actions with actions, sub-tasks
    \+ protected(B1), \+ protected(B2).         %    with sub-tasks (docs/compression.md)

% A behaviour is protected from merging by a fact no_merge(Label) in the task file.
protected(B) :- node(B, Label), no_merge(Label).
