"""numpy's numbers, bit for bit, for the code that runs every 20 ms cycle.

A walking cycle does a few hundred operations on single numbers and short vectors. On those,
numpy's per-call overhead (np.clip and np.mean cost microseconds on a handful of numbers) and
even Python's ``min``/``max`` builtins cost more than the arithmetic. These helpers give
exactly the numbers the usual spelling gives, in less time; each says which spelling it
replaces.
"""

from __future__ import annotations

import sys
from collections import deque

import numpy as np

__all__ = [
    "clamp",
    "clip_element",
    "acos_domain",
    "clip_symmetric",
    "ordered_sum",
    "mean_rows",
    "RecentMeans",
]


def clamp(x: float, lo: float, hi: float) -> float:
    """``min(max(x, lo), hi)``, which is also ``np.clip(x, lo, hi)`` for one number, to the
    bit (a value equal to a bound stays as it is, a NaN stays NaN), without the builtins'
    call overhead."""
    x = lo if lo > x else x
    return hi if hi < x else x


def clip_element(x: float, lo: float, hi: float) -> float:
    """One element of ``np.clip(values, lows, highs)`` with arrays of bounds, to the bit: a
    value equal to a bound becomes the bound (the sign of a zero can change, unlike
    ``clamp``), a NaN stays NaN."""
    x = x if x > lo or x != x else lo
    return x if x < hi or x != x else hi


def acos_domain(x: float) -> float:
    """``max(-1.0, min(1.0, x))``: ``x`` kept inside the domain of acos and asin (a NaN
    becomes 1.0, as with the builtins)."""
    x = x if x < 1.0 else 1.0
    return x if x > -1.0 else -1.0


def clip_symmetric(values, limit: float) -> np.ndarray:
    """``np.clip(values, -limit, limit)`` for a ``limit`` > 0, the same numbers without
    np.clip's Python dispatch. With non-zero bounds, maximum-then-minimum is clip exactly: a
    value equal to a bound is that bound."""
    return np.minimum(np.maximum(values, -limit), limit)


if sys.version_info < (3, 12):

    def ordered_sum(values) -> float:
        """The floats ``values`` added in order to a zero, one rounding per addition (as
        numpy adds a column). Before Python 3.12 ``sum()`` does exactly that, in C."""
        return sum(values, 0.0)

else:

    def ordered_sum(values) -> float:
        """The floats ``values`` added in order to a zero, one rounding per addition (as
        numpy adds a column). Not ``sum()``: from Python 3.12 on it compensates the
        rounding."""
        total = 0.0
        for value in values:
            total += value
        return total


def mean_rows(rows: list[tuple[float, ...]]) -> tuple[float, ...]:
    """Column means of ``rows`` (at least one), bit for bit what ``np.mean(rows, axis=0)``
    gives: numpy adds each column in order to a zero, then divides by the count."""
    n = len(rows)
    means = []
    for column in zip(*rows):
        means.append(ordered_sum(column) / n)
    return tuple(means)


class RecentMeans:
    """Column means of the last ``window`` rows added: ``mean_rows`` of those rows, bit for
    bit, with the rows kept column by column (a row comes every cycle, the means are read
    as often)."""

    def __init__(self, width: int, window: int) -> None:
        self._columns = tuple(deque(maxlen=window) for _ in range(width))

    def add(self, *row: float) -> tuple[float, ...]:
        """Add a row of ``width`` floats (the oldest drops out of a full window); returns
        the column means over the window."""
        means = []
        for column, value in zip(self._columns, row):
            column.append(value)
            means.append(ordered_sum(column) / len(column))
        return tuple(means)

    def clear(self) -> None:
        for column in self._columns:
            column.clear()
