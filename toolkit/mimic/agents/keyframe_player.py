"""Plays a keyframe movement: spline references tracked by the proportional controller."""

from __future__ import annotations

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.tracking import TrackingController
from mimic.motion.keyframe import Movement
from mimic.world.world import Observation

__all__ = ["KeyframePlayer"]


class KeyframePlayer(Agent):
    """Our own team's keyframe motions; exposes its references (we own the code)."""

    team = "mimic"

    def __init__(self, movement: Movement, tracking: TrackingController = TrackingController(),
                 hold_s: float = 0.0) -> None:
        """``hold_s``: keep tracking the last keyframe this long after the movement ends."""
        super().__init__()
        self.movement, self.tracking, self.hold_s = movement, tracking, hold_s
        self.name = movement.name
        self.start_posture = movement.start_posture
        self._start_s = 0.0
        self._spline = movement.spline()

    def reset(self, obs: Observation) -> None:
        self._start_s = obs.time_s
        self._spline = self.movement.spline(obs.joint_angles_rad)
        self.done = False

    def act(self, obs: Observation) -> np.ndarray:
        t = obs.time_s - self._start_s
        self.reference_rad = self._spline(t)
        self.done = t >= self.movement.duration_s + self.hold_s - 1e-9
        return self.tracking.speeds(self.reference_rad, obs.joint_angles_rad)
