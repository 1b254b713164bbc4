% HAND-EDITED, deliberately unsound: written by `schemalog compress tasks/serve_water.pl -o broken/serve_water_compressed.pl`,
% then the releaser of a3_a4_a5(bottle) was cut from `glass.taken and not glass.filled` to
% `not glass.filled`: the compressed task may pour before the glass is taken, which the original never does.
% Compressed by schemalog (Algorithm 1, propagate full) from tasks/serve_water.pl (then edited by hand, above), task serve(water).
% Bi = 13, Bm = 7, D = 3, RD = (Bi - Bm) / (Bi - D) = 0.60.
% `schemalog decompress` restores the original tree from the origins/2 facts.

task(serve(water)).

object(glass).
object(bottle).

agent(gripper(close),gripper).
agent(gripper(open),gripper).

schema(serve(water),
       [ (subtask(take_fill_place,glass), hand.free or glass.taken or glass.filled) ],
       glass.served).

schema(subtask(take_fill_place,glass),
       [ (a1_a2(glass), hand.free and not glass.taken),
         (gripper(close), hand.free and not glass.taken and a2.done),
         (a3_a4_a5(bottle), not glass.filled),
         (a6_a7(glass), glass.filled and not glass.served),
         (gripper(open), glass.filled and not glass.served and a7.done) ],
       glass.served).
schema(a1_a2(glass),[],a2.done).
schema(gripper(close),[],not hand.free).
schema(a3_a4_a5(bottle),[],a5.done).
schema(a6_a7(glass),[],a7.done).
schema(gripper(open),[],hand.free).

task_origins(serve(water),[origin(serve(water),true,glass.served,1,0,0)]).

origins(serve(water),[[origin(subtask(take,glass),hand.free,glass.taken,1,0,0),origin(subtask(fill,glass),glass.taken,glass.filled,1,1,0),origin(subtask(place,glass),glass.filled,glass.served,1,2,0)]]).
origins(subtask(take_fill_place,glass),[[origin(a1(glass),true,a1.done,1,0,0),origin(a2(glass),a1.done,a2.done,1,1,0)],[origin(gripper(close),a2.done,not hand.free,1,2,0)],[origin(a3(bottle),true,a3.done,1,0,1),origin(a4(bottle),a3.done,a4.done,1,1,1),origin(a5(bottle),a4.done,a5.done,1,2,1)],[origin(a6(glass),true,a6.done,1,0,2),origin(a7(glass),a6.done,a7.done,1,1,2)],[origin(gripper(open),a7.done,hand.free,1,2,2)]]).

initial(hand.free).
