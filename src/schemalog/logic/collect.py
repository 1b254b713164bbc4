"""Forget the bindings no live goal can reach, so a long deterministic loop runs in constant memory.

    Roots  = the machine's goal list, its choicepoints, the query, and what a suspended
             nondeterministic built-in holds (its generator's locals)
    Live   = set[Var]: every variable reachable from the roots through terms and bindings
    Marks  = trail positions (a choicepoint's `cp[1]`), renumbered when the trail shrinks

The machine keeps every binding in one dict and every bound variable on the trail
(unify.py). Nothing else lets go of them: a binding made by a call that exited
deterministically stays in the dict until the query ends, so `loop(K) :- work, K1 is K-1,
loop(K1)` grew by every binding of every `work` (issue 37: 1.2 GB for 10,000 naive
reverses). The machine itself already does last-call optimisation for free: a clause's last
call continues with its caller's continuation, and no frame is kept besides the goal list.
What was missing is the WAM's two remedies for the bindings: a trail entry only where a
choicepoint could undo it, and a heap that forgets what no goal reaches. Both come out of
one pass here, run when the trail has grown by a threshold since the last pass:

- mark: every variable reachable from the roots is live;
- sweep: a binding on the trail above `base` (the trail's height when this machine started)
  whose variable is not live is deleted from the dict and the trail. No goal can meet that
  variable again, and no choicepoint needs to unbind it: backtracking to a choicepoint
  only has to restore what the choicepoint's own goals can see, and they are roots;
- renumber: each choicepoint's trail mark becomes the count of kept entries below it.

Only the newest machine runs a pass. The older ones wait: in a built-in that runs it
(findall/3, forall/2), whose goal (and so its arguments) each machine records before
calling a built-in, or suspended with an answer (setup_call_cleanup/3's goal). Every trail
mark they or their built-ins hold was taken before the newest machine started, so it is at
most `base` and stays true. A built-in's own Python locals are no roots: those that run a
machine take what they read after it from their arguments (findall's template), which are.
The cost is linear in what is live plus what is swept, and the threshold is at least four
times what the last pass found live, so it is amortised over the bindings made in between.
"""

from __future__ import annotations

from bisect import bisect_left
from types import GeneratorType

from .terms import Struct, Var
from .unify import Bindings

MIN_GROWTH = 10_000   # trail entries between two passes at least (about 2 MB of bindings)
LIVE_FACTOR = 4       # and this many times what the last pass traversed (boyer: 2 cost 7%, 4 nothing)


def collect(machines: list, cps: list, b: Bindings, base: int, control: dict[type, tuple[str, ...]],
            recatch: int) -> int:
    """Delete the bindings above `base` that no machine's query, goals or choicepoints reach,
    renumber `cps`' trail marks, and return how much was traversed (the next pass waits for
    the trail to grow by more)."""
    values, trail = b.values, b.trail
    get = values.get
    live: set[Var] = set()
    seen: set[int] = set()
    stack: list = []
    for machine in machines:
        stack += (machine.query, machine.goals, machine.cps)
    push, pop = stack.append, stack.pop
    cells = 0
    while stack:
        x = pop()
        kind = type(x)
        if kind is Struct:
            if id(x) in seen:
                continue
            seen.add(id(x))
            cells += 1
            # the arguments inline: most are atoms and numbers, never pushed
            for arg in x.args:
                kind = type(arg)
                if kind is Struct:
                    push(arg)
                elif kind is Var and arg not in live:
                    live.add(arg)
                    bound = get(arg)
                    if bound is not None:
                        push(bound)
        elif kind is Var:
            if x not in live:
                live.add(x)
                bound = get(x)
                if bound is not None:
                    push(bound)
        elif kind is tuple or kind is list:
            if id(x) not in seen:
                seen.add(id(x))
                cells += 1
                stack.extend(x)
        elif kind in control:
            # Or, IfThenElse, IfThen, Not: their branches are tuples of goal entries
            stack.extend(getattr(x, field) for field in control[kind])
        elif kind is GeneratorType:
            # a suspended nondeterministic built-in (between/3, clause/2, retract/1): its
            # arguments and whatever it walks are in its frame
            frame = x.gi_frame
            if frame is not None and id(x) not in seen:
                seen.add(id(x))
                stack.extend(frame.f_locals.values())
        elif kind is dict:
            stack.extend(x.values())
        # atoms, numbers, strings, the machine's markers and compiled clauses hold no variable
    tail = trail[base:]
    kept = [i for i, v in enumerate(tail) if v in live]   # positions above base that stay
    if len(kept) == len(tail):
        return len(live) + cells
    for v in tail:
        if v not in live:
            del values[v]
    trail[base:] = [tail[i] for i in kept]

    def renumber(cp: tuple) -> tuple:
        # a mark m above base becomes base + the number of kept positions below m
        mark = cp[1]
        if mark <= base:
            return cp
        return (cp[0], base + bisect_left(kept, mark - base)) + cp[2:]

    for i, cp in enumerate(cps):
        cp = renumber(cp)
        if cp[0] == recatch:
            # (kind, mark, height, frame): the catch frame it puts back holds a mark too
            cp = cp[:3] + (renumber(cp[3]),)
        cps[i] = cp
    return len(live) + cells
