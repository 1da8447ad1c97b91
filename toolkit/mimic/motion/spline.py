"""Natural cubic splines (C2) through keyframes, vectorised over the joints."""

from __future__ import annotations

import bisect

import numpy as np

__all__ = ["NaturalCubicSpline"]


class NaturalCubicSpline:
    """C2 interpolation of (n,) knot times and (n, k) values; zero curvature at both ends.

    Outside the knot range the spline holds the first or last value.
    """

    def __init__(self, times_s: np.ndarray, values: np.ndarray) -> None:
        t = np.asarray(times_s, dtype=float)
        y = np.asarray(values, dtype=float)
        if t.ndim != 1 or len(t) < 2 or np.any(np.diff(t) <= 0):
            raise ValueError("spline knots need at least two strictly increasing times")
        self.t, self.y = t, y
        self.m = self._second_derivatives(t, y)  # (n, k)
        # The knot times as Python floats: a player reads them every cycle.
        self._knots_s = t.tolist()

    @staticmethod
    def _second_derivatives(t: np.ndarray, y: np.ndarray) -> np.ndarray:
        n = len(t)
        m = np.zeros_like(y)
        if n < 3:
            return m
        h = np.diff(t)
        # Tridiagonal system for the interior second derivatives (Thomas algorithm).
        a = h[:-1].copy()
        b = 2 * (h[:-1] + h[1:])
        c = h[1:].copy()
        d = 6 * ((y[2:] - y[1:-1]) / h[1:, None] - (y[1:-1] - y[:-2]) / h[:-1, None])
        for i in range(1, n - 2):
            w = a[i] / b[i - 1]
            b[i] -= w * c[i - 1]
            d[i] -= w * d[i - 1]
        x = np.zeros_like(d)
        x[-1] = d[-1] / b[-1]
        for i in range(n - 4, -1, -1):
            x[i] = (d[i] - c[i] * x[i + 1]) / b[i]
        m[1:-1] = x
        return m

    def __call__(self, time_s: float) -> np.ndarray:
        """(k,) interpolated values at ``time_s``."""
        t, y, m = self._knots_s, self.y, self.m
        if time_s <= t[0]:
            return y[0].copy()
        if time_s >= t[-1]:
            return y[-1].copy()
        i = bisect.bisect_right(t, time_s) - 1  # the segment holding time_s
        h = t[i + 1] - t[i]
        a, b = (t[i + 1] - time_s) / h, (time_s - t[i]) / h
        return a * y[i] + b * y[i + 1] + ((a**3 - a) * m[i] + (b**3 - b) * m[i + 1]) * h * h / 6
