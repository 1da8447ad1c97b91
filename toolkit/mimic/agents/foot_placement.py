"""Foot placement for a learned walk: the swing foot lands where the torso's error says.

A walk engine balances mostly by where it puts the swing foot: the torso's place over the
support foot is compared with the plan, and the swing foot lands farther along the error and
its rate (a capture-point rule; the T1 other team's walk does this). A learned copy replays
joint angles and has no plan, but the recording it was learned from shows where the feet were
under the torso at every point of the cycle: the **foot track**, the mean over the recorded
cycles of each foot's position relative to the torso in the walk frame (the torso's heading,
upright: x forward, y left), by phase. ``mimic train`` stores it in a cyclic model learned
from a recording with body poses (``/tf``); the balance layer (``agents.balance``) then
compares the support foot, measured through the leg's joint angles and the IMU exactly as the
track was computed, with the track at the model's phase, and moves the swing foot
(``BalanceGains.place_*``; off unless a model file or the caller sets them).

The foot moves in joint space: the leg's hip, knee and ankle pitch/roll shifts that move the
foot by (dx, dy) in the torso frame while keeping its height and its sole's tilt (the
least-squares solution of the foot's Jacobian at the current angles).

Frames: the torso (root link) frame, and the walk frame (the torso's heading, z up). Feet are
the robot description's ``foot_links`` origins.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import mujoco
import numpy as np

from mimic.errors import MimicError
from mimic.geometry import yaw_from_quat
from mimic.learn.dataset import bin_count, phase_bins
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot

__all__ = [
    "FOOT_TRACK_KEY",
    "FootKinematics",
    "FootTrack",
    "foot_track",
]

#: Where a cyclic model file carries its recording's foot track (``metadata``).
FOOT_TRACK_KEY = "foot_track"
#: Most phase bins of a stored foot track (fewer when a cycle holds fewer samples: the T1
#: other team's 0.84 s cycle at the monitor's 25 Hz gets 21); empty bins are interpolated.
TRACK_BINS = 24
#: Leg joints that move a foot (by role, the name after ``left_``/``right_``).
_MOVE_ROLES = ("hip_pitch", "hip_roll", "knee_pitch", "ankle_pitch", "ankle_roll")


class FootKinematics:
    """Both feet relative to the torso, from joint angles and the torso's orientation, on the
    robot's own MuJoCo model (kinematics only)."""

    def __init__(self, robot: RobotDescription | str) -> None:
        from mimic.world.mujoco_world import MujocoWorld

        self.robot = get_robot(robot)
        world = MujocoWorld(self.robot)
        self.model, self.data = world.model, mujoco.MjData(world.model)
        self._root_q = world.root_qpos_adr
        self._qpos = np.asarray(world.qpos_idx)
        self._qvel = np.asarray(world.qvel_idx)
        m = self.model
        self._root = m.body(self.robot.root_link).id
        self._feet = [m.body(name).id for name in self.robot.foot_links]
        by_name = {n.lower(): i for i, n in enumerate(self.robot.joint_names)}
        self.move_joints = {}
        for side, name in ((1.0, "left"), (-1.0, "right")):
            found = [by_name.get(f"{name}_{role}") for role in _MOVE_ROLES]
            if None in found:
                raise MimicError(f"foot placement needs the {robot} legs' {_MOVE_ROLES} joints")
            self.move_joints[side] = np.asarray(found)
        self._jacp, self._jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))

    def _pose(self, angles_rad: np.ndarray, quat_wxyz) -> None:
        d = self.data
        d.qpos[:] = self.model.qpos0
        d.qpos[self._root_q : self._root_q + 3] = 0.0
        d.qpos[self._root_q + 3 : self._root_q + 7] = quat_wxyz
        d.qpos[self._qpos] = angles_rad
        mujoco.mj_kinematics(self.model, self.data)

    def feet_m(self, angles_rad: np.ndarray, torso_quat_wxyz) -> np.ndarray:
        """(2, 2): (x, y) of the left and the right foot relative to the torso in the walk
        frame [m]."""
        quat = np.asarray(torso_quat_wxyz, float)
        self._pose(angles_rad, quat)
        yaw = yaw_from_quat(quat)
        c, s = math.cos(yaw), math.sin(yaw)
        rel = self.data.xpos[self._feet, :2] - self.data.xpos[self._root, :2]
        return np.stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]], axis=1)

    def feet_height_m(self, angles_rad: np.ndarray, torso_quat_wxyz) -> np.ndarray:
        """(2,): the left and the right foot's height relative to the torso, z up [m]."""
        self._pose(angles_rad, np.asarray(torso_quat_wxyz, float))
        return self.data.xpos[self._feet, 2] - self.data.xpos[self._root, 2]

    def shift_map(self, angles_rad: np.ndarray) -> dict[float, np.ndarray]:
        """Per side (+1 left, -1 right) a (N, 2) map: joint shifts [rad] per metre that move
        that foot along the torso's x and y, its height and sole tilt (roll, pitch) kept."""
        self._pose(angles_rad, (1.0, 0.0, 0.0, 0.0))
        mujoco.mj_comPos(self.model, self.data)  # the Jacobians need the joint axes in space
        out = {}
        for side, body in zip((1.0, -1.0), self._feet):
            mujoco.mj_jacBody(self.model, self.data, self._jacp, self._jacr, body)
            cols = self._qvel[self.move_joints[side]]
            jac = np.vstack([self._jacp[:, cols], self._jacr[:2, cols]])  # x y z, roll pitch
            inv = np.linalg.pinv(jac)[:, :2]  # columns: unit x and unit y
            full = np.zeros((self.robot.num_joints, 2))
            full[self.move_joints[side]] = inv
            out[side] = full
        return out


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
