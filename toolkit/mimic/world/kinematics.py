"""Both feet relative to the torso, from joint angles and the torso's orientation: forward
kinematics on the robot's own MuJoCo model (no simulation).

``learn`` finds a recorded walk's steps (``learn.steps``) and its foot track
(``learn.foot_track``) with it from the angles and the torso's tilt a recording shows; the
balance layer (``agents.balance``) measures the support foot and moves the swing foot with it.

Frames: the torso (root link) frame, and the walk frame (the torso's heading, z up). Feet are
the robot description's ``foot_links`` origins.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mimic.errors import MimicError
from mimic.geometry import yaw_from_quat
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.world.mujoco_world import MujocoWorld

__all__ = ["FootKinematics"]

#: Leg joints that move a foot (by role, the name after ``left_``/``right_``).
_MOVE_ROLES = ("hip_pitch", "hip_roll", "knee_pitch", "ankle_pitch", "ankle_roll")


class FootKinematics:
    """Both feet relative to the torso, from joint angles and the torso's orientation, on the
    robot's own MuJoCo model (kinematics only)."""

    def __init__(self, robot: RobotDescription | str) -> None:
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
