"""The foot track a cyclic model carries: where its recording had the feet under the torso.

A walk engine balances mostly by where it puts the swing foot: the torso's place over the
support foot is compared with the plan, and the swing foot lands farther along the error and
its rate (a capture-point rule; the T1 other team's walk does this). A learned copy replays
joint angles and has no plan, but the recording it was learned from shows where the feet were
under the torso at every point of the cycle: the **foot track**, the mean over the recorded
cycles of each foot's position relative to the torso in the walk frame (the torso's heading,
upright: x forward, y left), by phase. ``mimic train`` stores it in a cyclic model learned
from a recording with body poses (``/tf``; ``learn.foot_track``); the balance layer
(``agents.balance``) then compares the support foot, measured through the leg's joint angles
and the IMU exactly as the track was computed (``world.kinematics.FootKinematics``), with the
track at the model's phase, and moves the swing foot (``BalanceGains.place_*``; off unless a
model file or the caller sets them).

The foot moves in joint space: the leg's hip, knee and ankle pitch/roll shifts that move the
foot by (dx, dy) in the torso frame while keeping its height and its sole's tilt (the
least-squares solution of the foot's Jacobian at the current angles,
``FootKinematics.shift_map``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from mimic.errors import MimicError

__all__ = ["TRACK_BINS", "FootTrack"]

#: Most phase bins of a stored foot track (fewer when a cycle holds fewer samples: the T1
#: other team's 0.84 s cycle at the monitor's 25 Hz gets 21); empty bins are interpolated.
TRACK_BINS = 24


@dataclass(frozen=True)
class FootTrack:
    """Each foot's mean (x, y) relative to the torso in the walk frame [m] over one cycle,
    at ``bins`` evenly spaced phases (phase 0: the model's time 0)."""

    left_m: np.ndarray  # (bins, 2)
    right_m: np.ndarray  # (bins, 2)

    def at(self, phase: float) -> np.ndarray:
        """(2, 2): left and right (x, y) at ``phase`` (cycles; wraps), interpolated [m]."""
        n = len(self.left_m)
        u = (phase % 1.0) * n
        i = int(u) % n
        w = u - int(u)
        j = (i + 1) % n
        both = np.stack([self.left_m, self.right_m])
        return (1 - w) * both[:, i] + w * both[:, j]

    @cached_property
    def mean_m(self) -> np.ndarray:
        """(2, 2): left and right (x, y) averaged over the cycle [m]."""
        return np.stack([self.left_m.mean(axis=0), self.right_m.mean(axis=0)])

    def symmetric(self) -> FootTrack:
        """The track of a left-right symmetric cycle: each foot averaged with the other foot
        half a cycle later, mirrored (y negated), as ``learn.dataset.symmetric_cycle`` does
        with the angles."""
        n = len(self.left_m)
        later = np.stack([self.at(k / n + 0.5) for k in range(n)])  # (bins, 2 feet, 2)
        mirror = np.array([1.0, -1.0])
        return FootTrack(
            (self.left_m + later[:, 1] * mirror) / 2, (self.right_m + later[:, 0] * mirror) / 2
        )

    def to_metadata(self) -> dict:
        return {
            "left_m": np.round(self.left_m, 5).tolist(),
            "right_m": np.round(self.right_m, 5).tolist(),
        }

    @classmethod
    def from_metadata(cls, value: dict, where: str = "foot track") -> FootTrack:
        try:
            left, right = (np.asarray(value[k], float) for k in ("left_m", "right_m"))
        except (KeyError, TypeError, ValueError):
            raise MimicError(f"{where}: a foot track needs left_m and right_m lists") from None
        if left.ndim != 2 or left.shape[1] != 2 or left.shape != right.shape or len(left) < 2:
            raise MimicError(f"{where}: a foot track is two (bins, 2) lists of x, y [m]")
        return cls(left, right)
