% The example project's own task: take a glass, fill it from a bottle, put it down.
% Each learned action is released by the previous one's done (docs/syntax.md, Learned sub-tasks).

task(serve(water)).

object(glass).
object(bottle).

agent(gripper(_), gripper).

initial(hand.free).

schema(serve(water),
       [ (subtask(take, glass), hand.free),
         (subtask(fill, glass), glass.taken),
         (subtask(place, glass), glass.filled) ],
       glass.served).

schema(subtask(take, glass),
       [ (a1(glass), true),
         (a2(glass), a1.done),
         (gripper(close), a2.done) ],
       glass.taken).
schema(subtask(fill, glass),
       [ (a3(bottle), true),
         (a4(bottle), a3.done),
         (a5(bottle), a4.done) ],
       glass.filled).
schema(subtask(place, glass),
       [ (a6(glass), true),
         (a7(glass), a6.done),
         (gripper(open), a7.done) ],
       glass.served).

schema(a1(glass), [], a1.done).
schema(a2(glass), [], a2.done).
schema(a3(bottle), [], a3.done).
schema(a4(bottle), [], a4.done).
schema(a5(bottle), [], a5.done).
schema(a6(glass), [], a6.done).
schema(a7(glass), [], a7.done).
schema(gripper(close), [], not hand.free).
schema(gripper(open), [], hand.free).
