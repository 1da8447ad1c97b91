"""Walk views: footsteps (where a foot stood still on the ground) and the centre-of-mass path."""

from __future__ import annotations

import numpy as np

from mimic.robot.description import BODIES

__all__ = ["footsteps", "centre_of_mass_path"]


def _rotate(quat_wxyz: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate (3,) vector ``v`` by each of (N, 4) quaternions; returns (N, 3)."""
    w, xyz = quat_wxyz[:, :1], quat_wxyz[:, 1:]
    t = 2 * np.cross(xyz, np.broadcast_to(v, xyz.shape))
    return v + w * t + np.cross(xyz, t)


def centre_of_mass_path(poses: dict) -> np.ndarray:
    """(N, 3) robot centre of mass [m] from world-frame body tracks (``TfTrack``-like: pos_m,
    quat_wxyz) and the body masses and centres of the description."""
    total, weighted = 0.0, 0.0
    for body in BODIES:
        track = poses.get(body.name)
        if track is None:
            continue
        centre = np.subtract(body.centre, body.anchor)
        weighted = weighted + body.mass_kg * (track.pos_m + _rotate(track.quat_wxyz, centre))
        total += body.mass_kg
    return weighted / total


def footsteps(track, *, max_height_m: float = 0.05, max_speed_m_s: float = 0.05,
              min_duration_s: float = 0.04) -> np.ndarray:
    """(K, 3) places where a foot stood: its frame low and nearly still for a while.

    ``track`` is a world-frame ``TfTrack`` of a foot body (frame at the ankle-roll joint).
    Returns the mean position (x, y, 0) of each stance.
    """
    t = track.times_ns * 1e-9
    pos = track.pos_m
    speed = np.r_[0.0, np.linalg.norm(np.diff(pos[:, :2], axis=0), axis=1) / np.maximum(np.diff(t), 1e-9)]
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
