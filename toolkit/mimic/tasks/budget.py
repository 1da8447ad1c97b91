"""An episode's live time limit: what a trial's budget still leaves it, read while it plays;
and the points where an episode could have ended, so that a trial can count it up to there.

A trial with a simulated-time budget counts episodes in index order until one would end past
the budget; an episode that gives its checkpoints (``CHECKPOINTS``) is then counted to the
budget's end, as of its last checkpoint within the budget, and the trial ends there. On several workers an episode
starts before the ones before it have ended, so when it starts the trial knows only an upper
bound of what the budget will leave it; the bound shrinks as those episodes play on and end
(and drops to zero when the trial learns the episode cannot count). An episode that plays in
such a trial reads ``episode_cap_s(played_s)`` at each of its decisions (a kick, a walk),
saying how far it has played (so that the caps of the episodes after it can shrink by that),
and stops once its time reaches the cap.

Stopping there changes nothing a trial counts: the cap never falls below what the budget
truly leaves (plus a cycle), and an episode cut at its cap ends past the budget, so it counts
only up to a checkpoint within the budget, which a cap can only stop after. That holds only
if a cap's one effect is where an episode stops: every episode that reads it must use it so
(a limit on how long it still plays), never to choose what it does before then. Outside
such a trial (one worker, a count of episodes, a test) there is no cap: ``math.inf``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager

__all__ = ["episode_cap_s", "episode_cap", "CHECKPOINTS", "Checkpoint"]

#: The key of an episode's summary that holds its checkpoints (``Checkpoint``s, in time
#: order): its rows and summary as of each, which hold until the next (nothing a trial
#: counts changes in between but the duration). A trial takes the key out of the summary
#: before it keeps it.
CHECKPOINTS = "checkpoints"

#: (time [s] of the episode at that point, its rows, its summary) as of then.
Checkpoint = tuple[float, list[dict], dict]

_reader: Callable[[float | None], float] | None = None


def episode_cap_s(played_s: float | None = None) -> float:
    """The most simulated time [s] the episode playing now may reach (``math.inf``: no cap
    beyond its config's limit). ``played_s``: how far it has played [s]; the trial may lower
    the caps of the episodes after it by that much (it will end no sooner)."""
    return math.inf if _reader is None else _reader(played_s)


@contextmanager
def episode_cap(reader: Callable[[float | None], float] | None) -> Iterator[None]:
    """While the block runs, ``episode_cap_s(played_s)`` returns ``reader(played_s)`` (None:
    no cap)."""
    global _reader
    outer, _reader = _reader, reader
    try:
        yield
    finally:
        _reader = outer
