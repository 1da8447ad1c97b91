"""A walk's steps, found where its feet touch down, and each step's own phase.

A learned walk (most league teams') never repeats a step exactly: its steps last 0.3-0.5 s or
more around their mean, as it reacts to its sensors and steers. A model indexed by time, or by
one fixed period, smears such steps into each other: at a fixed period the samples of one
phase come from different points of different steps. Here each step is found and timed on its
own:

* **touchdowns**: the height of each foot above the other, in the upright frame (the robot's
  joint angles and its torso's tilt through forward kinematics: every recording with a torso
  pose has them). A foot that rose more than half the typical lift has landed when it comes
  back within a fifth of it, and lifted off when it rose past that; the crossings are
  interpolated between samples;
* **phase per step**: from one touchdown to the next the phase runs over half a cycle: 0 to
  0.5 from the left foot's touchdown to the right's, 0.5 to 1 from the right's to the left's,
  piecewise linearly through the swing foot's lift-off (at the walk's mean share of double
  support), so that every step's lift-off and touchdown fall on the same phases. The warped
  time ``period_s * (cycles + phase)`` makes the walk one cycle of the mean step pair
  (``period_s`` = two mean steps), which every cyclic tool here learns unchanged.

Samples before the first and after the last touchdown, and steps that are no part of the walk
(the feet touching down out of turn, or a step more than ``MAX_STEP_RATIO`` times the median
step: a stop, a stumble) are left out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.errors import DatasetError

__all__ = ["StepTiming", "find_steps", "MIN_LIFT_M", "MAX_STEP_RATIO"]

#: Feet that never rise further than this above each other [m] do not walk.
MIN_LIFT_M = 0.01
#: A step longer or shorter than this many times the median step is no part of the walk.
MAX_STEP_RATIO = 2.0
_RISE, _LAND = 0.5, 0.2


@dataclass(frozen=True)
class StepTiming:
    """The steps of a walk and its samples' warped time.

    Attributes:
        touchdown_s: (S + 1,) the touchdowns bounding the S steps [s, the samples' clock].
        left_first: whether the first touchdown is the left foot's (then they alternate).
        keep: (T,) the samples that lie inside a step of the walk.
        warped_s: (T,) each sample's warped time [s]: ``period_s * (cycles + phase)``; NaN
            where ``keep`` is False.
        period_s: two mean steps [s].
        durations_s: (S,) each kept step's duration [s].
    """

    touchdown_s: np.ndarray
    left_first: bool
    keep: np.ndarray
    warped_s: np.ndarray
    period_s: float
    durations_s: np.ndarray

    @property
    def count(self) -> int:
        return len(self.durations_s)

    def summary(self) -> dict:
        """Step statistics for a model's metadata and for people: count, mean, standard
        deviation, fastest and slowest step [s]."""
        d = self.durations_s
        return {
            "count": int(len(d)),
            "mean_s": round(float(d.mean()), 4),
            "std_s": round(float(d.std()), 4),
            "min_s": round(float(d.min()), 4),
            "max_s": round(float(d.max()), 4),
        }

    def describe(self) -> str:
        """One line: ``57 steps, 0.406 s mean, sd 0.041 s (0.32-0.48 s)``."""
        s = self.summary()
        return (
            f"{s['count']} steps, {s['mean_s']:.3f} s mean, sd {s['std_s']:.3f} s "
            f"({s['min_s']:.2f}-{s['max_s']:.2f} s)"
        )


def _crossing(time_s: np.ndarray, value: np.ndarray, i: int, level: float) -> float:
    """When ``value`` crossed ``level`` between samples ``i - 1`` and ``i`` [s], linearly."""
    a, b = value[i - 1], value[i]
    return float(time_s[i - 1] + (time_s[i] - time_s[i - 1]) * (a - level) / (a - b))


def _swings(time_s: np.ndarray, above_m: np.ndarray, lift_m: float) -> list[tuple[float, float]]:
    """(lift-off, touchdown) times [s] of each swing of a foot ``above_m`` over the other (T,)
    that rose more than ``_RISE * lift_m``: its upward and downward crossings of ``_LAND *
    lift_m``, interpolated."""
    rise, land = _RISE * lift_m, _LAND * lift_m
    out, up, lift_off = [], False, None
    for i in range(1, len(time_s)):
        if above_m[i] >= land > above_m[i - 1]:
            lift_off = _crossing(time_s, above_m, i, land)
        if above_m[i] > rise:
            up = True
        elif up and above_m[i] < land <= above_m[i - 1]:
            if lift_off is not None:
                out.append((lift_off, _crossing(time_s, above_m, i, land)))
            up, lift_off = False, None
    return out


def find_steps(time_s: np.ndarray, feet_z_m: np.ndarray, where: str = "recording") -> StepTiming:
    """The steps of a walk from its feet's heights.

    Args:
        time_s: (T,) sample times [s], increasing.
        feet_z_m: (T, 2) the left and the right foot's height [m] in any frame whose z is up
            (relative to the torso is fine: only their difference counts).
        where: names the input in errors.

    Raises:
        DatasetError: the feet do not lift, or fewer than two steps of a walk are found.
    """
    t = np.asarray(time_s, float)
    z = np.asarray(feet_z_m, float)
    above = z[:, 0] - z[:, 1]  # the left foot above the right
    lift_m = float(np.percentile(np.abs(above), 95))
    if not lift_m > MIN_LIFT_M:
        raise DatasetError(
            f"{where}: the feet never rise more than {MIN_LIFT_M * 100:.0f} cm above each other "
            "here: no steps to find (cut the recording to the walk with --start/--end)"
        )
    # Swings of either foot by touchdown: (touchdown, left?, lift-off).
    events = sorted(
        [(down, True, up) for up, down in _swings(t, above, lift_m)]
        + [(down, False, up) for up, down in _swings(t, -above, lift_m)]
    )
    # A step runs from one touchdown to the next of the other foot, whose lift-off lies
    # between them.
    starts, sides = np.array([e[0] for e in events]), [e[1] for e in events]
    if len(starts) < 3:
        raise DatasetError(
            f"{where}: found {max(0, len(starts) - 1)} steps (the feet touch down "
            f"{len(starts)} times); a walk needs two at least: record or cut a longer walk"
        )
    lift_offs = np.array([e[2] for e in events[1:]])
    durations = np.diff(starts)
    alternate = np.array([sides[i] != sides[i + 1] for i in range(len(durations))])
    alternate &= (lift_offs > starts[:-1]) & (lift_offs < starts[1:])
    median = float(np.median(durations[alternate])) if alternate.any() else 0.0
    valid = (
        alternate & (durations < MAX_STEP_RATIO * median) & (durations > median / MAX_STEP_RATIO)
    )
    if valid.sum() < 2:
        raise DatasetError(
            f"{where}: found {int(valid.sum())} regular steps between {len(starts)} "
            "touchdowns; a walk needs two at least: record or cut a longer walk"
        )
    period_s = 2.0 * float(durations[valid].mean())
    # Both feet down for this share of the step, on average: where the lift-off's phase lies.
    support = float(np.mean((lift_offs - starts[:-1])[valid] / durations[valid]))
    warped = np.full(len(t), np.nan)
    cycles = 0
    for i in range(len(durations)):
        if sides[i] and i > 0:  # a left touchdown begins a new cycle
            cycles += 1
        if not valid[i]:
            continue
        at = (t >= starts[i]) & (t < starts[i + 1])
        # Piecewise linear: touchdown -> lift-off over the mean double support, then the swing.
        step = np.interp(t[at], [starts[i], lift_offs[i], starts[i + 1]], [0.0, support, 1.0])
        warped[at] = period_s * (cycles + (0.0 if sides[i] else 0.5) + 0.5 * step)
    keep = np.isfinite(warped)
    return StepTiming(starts, bool(sides[0]), keep, warped, period_s, durations[valid])
