"""An episode's live time limit: what a trial's budget still leaves it, read while it plays.

A trial with a simulated-time budget counts episodes in index order until one would end past
the budget. On several workers an episode starts before the ones before it have ended, so
when it starts the trial knows only an upper bound of what the budget will leave it; the
bound shrinks as those episodes end (and drops to zero when the trial learns the episode
cannot count). An episode that plays in such a trial reads ``episode_cap_s()`` at each of
its decisions (a kick, a walk) and stops once its time reaches the cap.

Stopping there changes no episode that counts: the cap never falls below what the budget
truly leaves (plus a cycle), and an episode cut at its cap ends past the budget, so it would
not have counted anyway. Outside such a trial (one worker, a count of episodes, a test)
there is no cap: ``math.inf``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager

__all__ = ["episode_cap_s", "episode_cap"]

_reader: Callable[[], float] | None = None


def episode_cap_s() -> float:
    """The most simulated time [s] the episode playing now may reach (``math.inf``: no cap
    beyond its config's limit)."""
    return math.inf if _reader is None else _reader()


@contextmanager
def episode_cap(reader: Callable[[], float] | None) -> Iterator[None]:
    """While the block runs, ``episode_cap_s()`` returns ``reader()`` (None: no cap)."""
    global _reader
    outer, _reader = _reader, reader
    try:
        yield
    finally:
        _reader = outer
