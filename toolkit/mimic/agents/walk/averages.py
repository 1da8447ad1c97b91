"""Averages over the last gait period, on plain floats.

The walk steers on the torso pose averaged over the last gait period (14 cycles); numpy's
``mean`` costs more per call than the sum itself, so it is done here, in the same order.
"""

from __future__ import annotations

__all__ = ["mean_rows"]


def mean_rows(rows: list[tuple[float, ...]]) -> tuple[float, ...]:
    """Column means of ``rows`` (at least one), bit for bit what ``np.mean(rows, axis=0)``
    gives: numpy adds each column in order to a zero, then divides by the count. (Not
    ``sum()``: from Python 3.12 on it compensates the rounding, numpy does not.)"""
    n = len(rows)
    means = []
    for column in zip(*rows):
        total = 0.0
        for value in column:
            total += value
        means.append(total / n)
    return tuple(means)
