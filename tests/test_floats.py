"""The per-cycle helpers give numpy's (or the builtins') numbers, to the last bit."""

from __future__ import annotations

import math

import numpy as np

from mimic.floats import acos_domain, clamp, clip_symmetric, mean_rows

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
