"""A recorded cyclic motion's foot track (``model.foot_track.FootTrack``): each foot under the
torso, averaged by phase."""

from __future__ import annotations

import numpy as np

from mimic.errors import MimicError
from mimic.learn.dataset import bin_count, phase_bins
from mimic.model.foot_track import TRACK_BINS, FootTrack
from mimic.robot.model import RobotDescription
from mimic.world.kinematics import FootKinematics

__all__ = ["foot_track"]


def foot_track(
    time_s: np.ndarray,
    angles_rad: np.ndarray,
    torso_quat_wxyz: np.ndarray,
    robot: RobotDescription | str,
    period_s: float,
    bins: int = TRACK_BINS,
) -> FootTrack:
    """The foot track of a recorded cyclic motion: each foot relative to the torso
    (``FootKinematics.feet_m`` of the recorded angles and torso orientations), averaged by
    phase (``time_s / period_s``, cycles) into ``bins``; bins no sample fell in are
    interpolated around the cycle."""
    kin = FootKinematics(robot)
    feet = np.stack([kin.feet_m(q, quat) for q, quat in zip(angles_rad, torso_quat_wxyz)])
    bins = bin_count(time_s, period_s, bins)
    k = phase_bins(time_s, period_s, bins)
    # Medians: a recording may end with a stumble or a fall that is no part of the cycle.
    have = np.bincount(k, minlength=bins) > 0
    if have.sum() < 2:
        raise MimicError("a foot track needs samples at two phases of the cycle at least")
    median = np.stack([np.median(feet[k == b], axis=0) for b in np.flatnonzero(have)])
    centres = np.flatnonzero(have) / bins
    at = np.arange(bins) / bins
    filled = np.stack(
        [
            np.stack(
                [np.interp(at, centres, median[:, s, a], period=1.0) for a in range(2)], axis=1
            )
            for s in range(2)
        ]
    )
    return FootTrack(filled[0], filled[1])
