"""95 % confidence intervals for trial tables, without scipy.

* Rates (kick accuracy, walk fall rate): the Wilson score interval, which stays inside
  0..100 % and is sensible for 0 % and 100 % and for small counts.
* Means (kick distance, walk speed, lateral error): the Student t interval,
  mean +- t(0.975, n - 1) * s / sqrt(n). The t quantile comes from a table for 1..30 degrees
  of freedom and from the Cornish-Fisher expansion above (error < 1e-4 there).

Both return ``(nan, nan)`` when there is too little data (no trials; fewer than two samples
for a mean).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["Z_95", "t_quantile_95", "wilson_interval", "mean_interval", "ratio_interval"]

#: Two-sided 95 % quantile of the standard normal distribution.
Z_95 = 1.959963984540054
#: t(0.975, df) for df = 1..30.
_T_95 = (
    12.706,
    4.303,
    3.182,
    2.776,
    2.571,
    2.447,
    2.365,
    2.306,
    2.262,
    2.228,
    2.201,
    2.179,
    2.160,
    2.145,
    2.131,
    2.120,
    2.110,
    2.101,
    2.093,
    2.086,
    2.080,
    2.074,
    2.069,
    2.064,
    2.060,
    2.056,
    2.052,
    2.048,
    2.045,
    2.042,
)


def t_quantile_95(df: int) -> float:
    """The 0.975 quantile of Student's t with ``df`` >= 1 degrees of freedom."""
    if df < 1:
        raise ValueError(f"degrees of freedom must be >= 1, got {df}")
    if df <= len(_T_95):
        return _T_95[df - 1]
    z = Z_95
    g1 = (z**3 + z) / 4
    g2 = (5 * z**5 + 16 * z**3 + 3 * z) / 96
    return z + g1 / df + g2 / df**2


def wilson_interval(successes: int, trials: int, z: float = Z_95) -> tuple[float, float]:
    """95 % Wilson score interval of a rate, as fractions in 0..1."""
    if trials <= 0:
        return (math.nan, math.nan)
    p = successes / trials
    denom = 1 + z * z / trials
    centre = (p + z * z / (2 * trials)) / denom
    half = z / denom * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials))
    return (max(0.0, centre - half), min(1.0, centre + half))


def mean_interval(values: Sequence[float]) -> tuple[float, float]:
    """95 % t interval of the mean of ``values``."""
    x = np.asarray(values, dtype=float)
    x = x[np.isfinite(x)]
    if len(x) < 2:
        return (math.nan, math.nan)
    half = t_quantile_95(len(x) - 1) * float(x.std(ddof=1)) / math.sqrt(len(x))
    mean = float(x.mean())
    return (mean - half, mean + half)


def ratio_interval(
    values: Sequence[float], base: Sequence[float], *, paired: bool = False
) -> tuple[float, float]:
    """95 % interval of mean(values) / mean(base), by the delta method.

    ``paired``: ``values[i]`` and ``base[i]`` come from the same episode (the same seed, so
    the same disturbances): their covariance narrows the interval. Otherwise the samples are
    independent and the degrees of freedom are the smaller sample's, less one.
    """
    a, b = np.asarray(values, dtype=float), np.asarray(base, dtype=float)
    if paired:
        if a.shape != b.shape:
            raise ValueError(f"paired samples differ in length: {a.shape} and {b.shape}")
        keep = np.isfinite(a) & np.isfinite(b)
        a, b = a[keep], b[keep]
    else:
        a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if len(a) < 2 or len(b) < 2 or b.mean() == 0:
        return (math.nan, math.nan)
    ma, mb = float(a.mean()), float(b.mean())
    r = ma / mb
    if paired:
        cov = float(np.cov(a, b, ddof=1)[0, 1])
        var = (a.var(ddof=1) + r * r * b.var(ddof=1) - 2 * r * cov) / (len(a) * mb * mb)
        df = len(a) - 1
    else:
        var = (a.var(ddof=1) / len(a) + r * r * b.var(ddof=1) / len(b)) / (mb * mb)
        df = min(len(a), len(b)) - 1
    half = t_quantile_95(df) * math.sqrt(max(float(var), 0.0))
    return (r - half, r + half)
