"""Closed-loop balance around any motion that exposes references (a learned motion).

Open-loop replay cannot correct itself; the walk engines use IMU feedback for that. This thin
layer adds the same kind of feedback to any agent: torso lean and its rate (from the IMU) shift
the hip and ankle references, then the usual proportional tracking turns them into speeds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.tracking import TrackingController
from mimic.robot.joints import joint_index
from mimic.world.world import Observation

__all__ = ["BalanceGains", "BalancedAgent", "torso_lean_rad"]


@dataclass(frozen=True)
class BalanceGains:
    """Feedback gains: reference shift [rad] per rad of lean, and per rad/s of lean rate."""

    ankle_pitch: float = 0.4
    hip_pitch: float = 0.3
    ankle_roll: float = 0.3
    hip_roll: float = 0.3
    rate_s: float = 0.05
    # Largest shift applied to any joint [rad].
    limit_rad: float = 0.25


def torso_lean_rad(obs: Observation) -> tuple[float, float]:
    """(forward lean, leftward lean) of the torso from vertical [rad], from the IMU quaternion."""
    w, x, y, z = obs.torso_quat_wxyz
    # World up expressed in the torso frame is the third row of the rotation matrix.
    up_x = 2 * (x * z - w * y)
    up_y = 2 * (y * z + w * x)
    return float(-np.arcsin(np.clip(up_x, -1, 1))), float(-np.arcsin(np.clip(up_y, -1, 1)))


class BalancedAgent(Agent):
    """Wraps an agent; adds IMU feedback on hip and ankle pitch and roll references."""

    def __init__(self, inner: Agent, gains: BalanceGains = BalanceGains(),
                 tracking: TrackingController = TrackingController()) -> None:
        super().__init__()
        self.inner, self.gains, self.tracking = inner, gains, tracking
        self.name, self.team, self.period_s = inner.name, inner.team, inner.period_s
        sides = ("left", "right")
        self._ankle_pitch = np.array([joint_index(f"{s}_ankle_pitch") for s in sides])
        self._hip_pitch = np.array([joint_index(f"{s}_hip_pitch") for s in sides])
        self._ankle_roll = np.array([joint_index(f"{s}_ankle_roll") for s in sides])
        self._hip_roll = np.array([joint_index(f"{s}_hip_roll") for s in sides])

    def reset(self, obs: Observation) -> None:
        self.inner.reset(obs)
        self.done = False

    def correction_rad(self, obs: Observation) -> np.ndarray:
        """(22,) reference shifts [rad] for the current lean."""
        g = self.gains
        forward, left = torso_lean_rad(obs)
        # The gyro's y axis is positive for pitching nose-down, its x axis for rolling right.
        forward += g.rate_s * obs.gyro_rad_s[1]
        left -= g.rate_s * obs.gyro_rad_s[0]
        shift = np.zeros(22)
        # Leaning forward: press the toes down and bring the torso back over the hips.
        shift[self._ankle_pitch] = -g.ankle_pitch * forward
        shift[self._hip_pitch] = -g.hip_pitch * forward
        # Leaning left: roll both ankles and hips to push the body back to the right.
        shift[self._ankle_roll] = g.ankle_roll * left
        shift[self._hip_roll] = -g.hip_roll * left
        return np.clip(shift, -g.limit_rad, g.limit_rad)

    def act(self, obs: Observation) -> np.ndarray:
        speeds = self.inner.act(obs)
        self.done = self.inner.done
        if self.inner.reference_rad is None:
            return speeds
        self.reference_rad = self.inner.reference_rad + self.correction_rad(obs)
        return self.tracking.speeds(self.reference_rad, obs.joint_angles_rad)
