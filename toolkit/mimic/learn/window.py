"""The piece of a recording that compensation looks at, with its gaps closed.

Compensated targets come from derivatives of the observed motion (``learn.compensate``,
``learn.pd_compensate``), which need evenly spaced samples. A black-box recording may skip a
monitor frame now and then, and it holds more than the motion (the robot put down, moved by
the referee: teleports). Only the window being learned matters, so compensation sees only
``window`` of it: the samples from ``start_s`` to ``end_s`` and ``margin_s`` either side (the
derivatives' fits and the command delay reach that far past the window's ends). Gaps inside
that piece are closed by resampling it on its median step (joint angles linearly
interpolated); each is named (where and how long) in ``metadata["resampled_gaps"]`` so that
``mimic train`` says so in one line (``learn.checks.input_warnings``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mimic.learn.dataset import Dataset

__all__ = ["window", "find_gaps", "GAP_RATIO", "MARGIN_S", "GAPS_KEY", "describe_gaps"]

#: A step longer than this many median steps is a gap.
GAP_RATIO = 1.5
#: Samples kept either side of the window for the derivatives and the command delay [s].
MARGIN_S = 0.3
#: Where a dataset lists the gaps closed by resampling: [[start s, length s], ...].
GAPS_KEY = "resampled_gaps"


def find_gaps(time_s: np.ndarray) -> list[tuple[float, float]]:
    """(start [s], length [s]) of every step longer than ``GAP_RATIO`` median steps."""
    t = np.asarray(time_s, dtype=float)
    if len(t) < 3:
        return []
    steps = np.diff(t)
    dt = float(np.median(steps))
    at = np.nonzero(steps > GAP_RATIO * dt)[0]
    return [(float(t[i]), float(steps[i])) for i in at]


def describe_gaps(gaps) -> str:
    """``12.36 s (0.08 s)``, ... for a list of (start, length)."""
    return ", ".join(f"{at:.2f} s ({size:.2f} s)" for at, size in gaps)


def window(
    ds: Dataset, start_s: float | None, end_s: float | None, margin_s: float = MARGIN_S
) -> Dataset:
    """The samples of ``ds`` from ``start_s - margin_s`` to ``end_s + margin_s`` (times kept
    as they are, from the recording's first sample), resampled on the median step where a
    gap lies inside; the gaps go to ``metadata[GAPS_KEY]``."""
    t = ds.time_s
    lo = -np.inf if start_s is None else float(start_s) - margin_s
    hi = np.inf if end_s is None else float(end_s) + margin_s
    keep = (t >= lo - 1e-9) & (t <= hi + 1e-9)
    if keep.sum() >= 2:
        ds = replace(ds, time_s=t[keep], targets=ds.targets[keep])
    gaps = find_gaps(ds.time_s)
    if not gaps:
        return ds
    t = ds.time_s
    dt = float(np.median(np.diff(t)))
    grid = t[0] + dt * np.arange(int(np.floor((t[-1] - t[0]) / dt + 1e-6)) + 1)
    targets = np.stack(
        [np.interp(grid, t, ds.targets[:, i]) for i in range(ds.targets.shape[1])], axis=1
    )
    if ds.period_s is None:  # the ended flag: on the last sample, as before
        targets[:, -1] = 0.0
        targets[-1, -1] = float(ds.targets[-1, -1] > 0.5)
    gaps_meta = [[round(at, 4), round(size, 4)] for at, size in gaps]
    return replace(ds, time_s=grid, targets=targets, metadata={**ds.metadata, GAPS_KEY: gaps_meta})
