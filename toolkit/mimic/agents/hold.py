"""The simplest agents: hold a pose, or hold whatever pose the robot is in."""

from __future__ import annotations

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.world.base import Observation

__all__ = ["HoldPose", "Limp"]


class HoldPose(Agent):
    """Tracks one fixed pose forever (lets a freshly placed robot settle on its feet)."""

    name = "hold"

    def __init__(self, pose_rad: np.ndarray, robot: str = "nao") -> None:
        super().__init__()
        self.pose_rad = np.asarray(pose_rad, dtype=float)
        self.robot = robot

    def reset(self, obs: Observation) -> None:
        self.done = False

    def act(self, obs: Observation) -> JointCommand:
        self.reference_rad = self.pose_rad
        return JointCommand.references(self.pose_rad)


class Limp(Agent):
    """Keeps the joints where they are (zero speed on speed servos): waiting on a fallen
    robot while the ball rolls on."""

    name = "limp"

    def __init__(self, robot: str = "nao") -> None:
        super().__init__()
        self.robot = robot

    def reset(self, obs: Observation) -> None:
        self.done = False

    def act(self, obs: Observation) -> JointCommand:
        return JointCommand.references(obs.joint_angles_rad)
