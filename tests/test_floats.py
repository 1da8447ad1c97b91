"""The per-cycle helpers give numpy's (or the builtins') numbers, to the last bit."""

from __future__ import annotations

import math

import numpy as np

from mimic.floats import (
    RecentMeans,
    acos_domain,
    clamp,
    clip_element,
    clip_symmetric,
    mean_rows,
    ordered_sum,
)

SPECIAL = (0.0, -0.0, 1.0, -1.0, 0.3, -0.3, math.inf, -math.inf, math.nan, 1e-300)


def _same(a, b) -> bool:
    return np.array(a, dtype=float).tobytes() == np.array(b, dtype=float).tobytes()


def test_clamp_is_min_max_and_np_clip() -> None:
    values = list(SPECIAL) + np.random.default_rng(1).normal(size=300).tolist()
    for x in values:
        for lo, hi in ((0.0, 1.0), (-0.0, 0.0), (-0.3, 0.3), (-1.0, -0.0), (-math.inf, 0.3)):
            assert _same(clamp(x, lo, hi), min(max(x, lo), hi))
            assert _same(clamp(x, lo, hi), np.clip(x, lo, hi))


def test_acos_domain_is_the_builtins() -> None:
    for x in list(SPECIAL) + np.random.default_rng(2).normal(size=300).tolist():
        assert _same(acos_domain(x), max(-1.0, min(1.0, x)))


def test_symmetric_clip_is_np_clip() -> None:
    rng = np.random.default_rng(6)
    for limit in (6.1395, 4.889 * 0.02, 0.12):
        values = rng.normal(0.0, 2 * limit, 500)
        values[:4] = (limit, -limit, 0.0, -0.0)
        assert clip_symmetric(values, limit).tobytes() == np.clip(values, -limit, limit).tobytes()


def test_mean_rows_is_np_mean() -> None:
    rng = np.random.default_rng(5)
    for k in range(2000):
        n, width = 1 + k % 16, 2 + 2 * (k % 2)
        rows = rng.normal(size=(n, width)) * 10.0 ** rng.uniform(-4, 4, size=(n, width))
        if k % 7 == 0:
            rows = rng.choice([0.0, -0.0, 1e-300, -1.0], size=(n, width))
        rows = [tuple(row) for row in rows.tolist()]
        assert np.array(mean_rows(rows)).tobytes() == np.mean(rows, axis=0).tobytes()


def test_clip_element_is_np_clip_with_arrays_of_bounds() -> None:
    """Ties go to the bound there (0.0 for -0.0 at a bound of 0.0): ``clip_element`` too."""
    bounds = (0.0, -0.0, 0.04, 0.13, 1.0, math.inf)
    rng = np.random.default_rng(8)
    values = list(SPECIAL) + [0.04, -0.04, 0.13, -0.13] + rng.normal(0, 0.1, 200).tolist()
    for high in bounds:
        for x in values:
            lows, highs = np.array([-high]), np.array([high])
            expected = np.clip(np.array([x]), lows, highs)
            assert _same(clip_element(x, -high, high), expected)


def test_ordered_sum_adds_in_order() -> None:
    rng = np.random.default_rng(9)
    for n in range(1, 30):
        values = (rng.normal(size=n) * 10.0 ** rng.uniform(-8, 8, size=n)).tolist()
        total = 0.0
        for value in values:
            total += value
        assert _same(ordered_sum(values), total)


def test_recent_means_are_mean_rows_of_the_window() -> None:
    rng = np.random.default_rng(10)
    for width, window in ((2, 14), (4, 14), (3, 1), (2, 5)):
        means, rows = RecentMeans(width, window), []
        for k in range(60):
            if k == 37:
                means.clear()
                rows = []
            row = tuple((rng.normal(size=width) * 10.0 ** rng.uniform(-3, 3)).tolist())
            rows = (rows + [row])[-window:]
            assert np.array(means.add(*row)).tobytes() == np.array(mean_rows(rows)).tobytes()
