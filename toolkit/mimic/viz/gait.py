"""Walk views: footsteps (where a foot stood still on the ground) and the centre-of-mass path."""

from __future__ import annotations

import numpy as np

from mimic.geometry import rotate
from mimic.robot.model import RobotDescription
from mimic.viz.bodies import link_bodies

__all__ = ["footsteps", "centre_of_mass_path"]


def centre_of_mass_path(poses: dict, robot: str | RobotDescription) -> np.ndarray:
    """(T, 3) centre of mass [m] of ``robot`` from world-frame link tracks (``TfTrack``-like:
    pos_m (T, 3), quat_wxyz (T, 4)) and its link masses and centres (links without a track
    are left out)."""
    total, weighted = 0.0, 0.0
    for body in link_bodies(robot):
        track = poses.get(body.name)
        if track is None:
            continue
        centre = np.broadcast_to(body.com_m, track.pos_m.shape)
        weighted = weighted + body.mass_kg * (track.pos_m + rotate(track.quat_wxyz, centre))
        total += body.mass_kg
    return weighted / total


def footsteps(
    track, *, max_height_m: float = 0.05, max_speed_m_s: float = 0.05, min_duration_s: float = 0.04
) -> np.ndarray:
    """(K, 3) places where a foot stood: its frame low and nearly still for a while.

    ``track`` is a world-frame ``TfTrack`` of a foot link (frame at its ankle joint).
    Returns the mean position (x, y, 0) of each stance.
    """
    t = track.times_ns * 1e-9
    pos = track.pos_m
    speed = np.r_[
        0.0, np.linalg.norm(np.diff(pos[:, :2], axis=0), axis=1) / np.maximum(np.diff(t), 1e-9)
    ]
    still = (pos[:, 2] < max_height_m) & (speed < max_speed_m_s)
    steps, start = [], None
    for i, s in enumerate(np.r_[still, False]):
        if s and start is None:
            start = i
        elif not s and start is not None:
            if t[i - 1] - t[start] >= min_duration_s:
                steps.append([*pos[start:i, :2].mean(axis=0), 0.0])
            start = None
    return np.array(steps).reshape(-1, 3)
