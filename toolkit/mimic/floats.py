"""numpy's numbers, bit for bit, for the code that runs every 20 ms cycle.

A walking cycle does a few hundred operations on single numbers and short vectors. On those,
numpy's per-call overhead (np.clip and np.mean cost microseconds on a handful of numbers) and
even Python's ``min``/``max`` builtins cost more than the arithmetic. These helpers give
exactly the numbers the usual spelling gives, in less time; each says which spelling it
replaces.
"""

from __future__ import annotations

import numpy as np

__all__ = ["clamp", "acos_domain", "clip_symmetric", "mean_rows"]


def clamp(x: float, lo: float, hi: float) -> float:
    """``min(max(x, lo), hi)``, which is also ``np.clip(x, lo, hi)`` for one number, to the
    bit (a value equal to a bound stays as it is, a NaN stays NaN), without the builtins'
    call overhead."""
    x = lo if lo > x else x
    return hi if hi < x else x


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
