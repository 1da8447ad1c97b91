"""Plays a keyframe movement: spline references, tracked by the robot's actuator model."""

from __future__ import annotations

from mimic.agents.base import Agent, JointCommand
from mimic.motion.keyframe import Movement
from mimic.world.base import Observation

__all__ = ["KeyframePlayer"]


class KeyframePlayer(Agent):
    """Our own team's keyframe motions; exposes its references (we own the code)."""

    team = "mimic"

    def __init__(self, movement: Movement, hold_s: float = 0.0) -> None:
        """``hold_s``: keep tracking the last keyframe this long after the movement ends."""
        super().__init__()
        self.movement, self.hold_s = movement, hold_s
        self.name = movement.name
        self.robot = movement.robot
        self.start_posture = movement.start_posture
        self._start_s = 0.0
        self._spline = movement.spline()
        self._duration_s = movement.duration_s

    def reset(self, obs: Observation) -> None:
        self._start_s = obs.time_s
        self._spline = self.movement.spline(obs.joint_angles_rad)
        self._duration_s = self.movement.duration_s
        self.done = False

    def act(self, obs: Observation) -> JointCommand:
        t = obs.time_s - self._start_s
        self.reference_rad = self._spline(t)
        self.done = t >= self._duration_s + self.hold_s - 1e-9
        return JointCommand.references(self.reference_rad)
