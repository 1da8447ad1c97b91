"""Go to a pose on the field with the walk engine, steering from ground-truth localisation.

Far from the target the robot turns toward it and walks forward (slowing when the target is
off to the side); near it, it strafes and turns onto the final heading with speeds
proportional to the remaining error; inside the tolerance it stops. ``arrived`` becomes True
once the engine stands still within the tolerance; if the halt left it outside, it walks
again (a few retries at most).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.walk.engine import WalkEngine
from mimic.world.world import Observation

__all__ = ["GoToConfig", "GoToPose", "pose_behind_ball", "wrap_angle"]


def wrap_angle(a: float) -> float:
    """Angle wrapped to [-pi, pi) [rad]."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def pose_behind_ball(ball_xy, target_xy, ball_offset_m) -> tuple[float, float, float]:
    """Torso pose (x, y, heading) [m, m, rad] in the field frame that faces ``target_xy``
    from the ball with the ball at ``ball_offset_m`` = (forward, left) in the robot frame."""
    bx, by = ball_xy
    heading = math.atan2(target_xy[1] - by, target_xy[0] - bx)
    c, s = math.cos(heading), math.sin(heading)
    ox, oy = ball_offset_m
    return bx - (c * ox - s * oy), by - (s * ox + c * oy), heading


@dataclass(frozen=True)
class GoToConfig:
    """Steering gains and tolerances."""

    # Arrival tolerance: position [m] and heading [rad].
    tolerance_m: float = 0.03
    tolerance_rad: float = math.radians(5)
    # Stop is triggered at this fraction of the tolerance (the halt adds a little drift).
    stop_fraction: float = 0.5
    # Beyond this distance [m] walk facing the target; inside it, align with the heading.
    far_m: float = 0.5
    # Top speeds: forward [m/s], sideways [m/s], turning [rad/s].
    max_vx_m_s: float = 0.45
    max_vy_m_s: float = 0.15
    max_yaw_rate_rad_s: float = 1.2
    # Proportional gains: speed per metre of error [1/s], turn rate per radian [1/s].
    position_gain_per_s: float = 1.5
    heading_gain_per_s: float = 2.0
    # Smallest useful speed near the target (the walk quantises steps) [m/s].
    min_speed_m_s: float = 0.04
    # How many times to walk again when a halt ends outside the tolerance.
    max_retries: int = 4


class GoToPose(Agent):
    """Walks the robot to ``set_target(x, y, heading)`` and stops there."""

    name = "goto"
    team = "mimic"

    def __init__(self, engine: WalkEngine, config: GoToConfig = GoToConfig()) -> None:
        super().__init__()
        self.engine = engine
        self.config = config
        self.period_s = engine.period_s
        self._target = None
        self._retries = 0
        self._stopping = False
        self._arrived = False

    def set_target(self, x_m: float, y_m: float, heading_rad: float) -> None:
        """Target torso pose in the field frame [m, m, rad]."""
        self._target = (float(x_m), float(y_m), float(heading_rad))
        self._retries = 0
        self._stopping = False
        self._arrived = False
        self.done = False

    @property
    def arrived(self) -> bool:
        """Standing still within the tolerance of the target."""
        return self._arrived

    def errors(self, obs: Observation) -> tuple[float, float, float]:
        """Target in the robot frame: (forward [m], left [m], heading error [rad])."""
        x, y, heading = self._target
        yaw = obs.torso_yaw_rad
        dx, dy = x - obs.torso_pos_m[0], y - obs.torso_pos_m[1]
        c, s = math.cos(yaw), math.sin(yaw)
        return c * dx + s * dy, -s * dx + c * dy, wrap_angle(heading - yaw)

    def reset(self, obs: Observation) -> None:
        self.engine.reset(obs)
        self._stopping = False
        self._arrived = False
        self.done = False

    def act(self, obs: Observation) -> np.ndarray:
        if self._target is not None:
            self._steer(obs)
        speeds = self.engine.act(obs)
        self.reference_rad = self.engine.reference_rad
        self.done = self._arrived
        return speeds

    def _steer(self, obs: Observation) -> None:
        cfg = self.config
        fx, fy, dh = self.errors(obs)
        dist = math.hypot(fx, fy)
        inside = dist < cfg.tolerance_m and abs(dh) < cfg.tolerance_rad
        if self._stopping:
            if self.engine.state == "standing":
                if inside:
                    self._arrived = True
                elif self._retries < cfg.max_retries:
                    self._retries += 1
                    self._stopping = False
                else:
                    self._arrived = True  # best effort; errors() tells how close
            return
        if (dist < cfg.stop_fraction * cfg.tolerance_m
                and abs(dh) < cfg.stop_fraction * cfg.tolerance_rad):
            self.engine.stop()
            self._stopping = True
            return
        if dist > cfg.far_m:
            bearing = math.atan2(fy, fx)
            yaw_rate = cfg.heading_gain_per_s * bearing
            vx = cfg.max_vx_m_s * max(0.0, math.cos(bearing)) ** 2
            vx = min(vx, cfg.position_gain_per_s * dist)
            vy = 0.0
        else:
            yaw_rate = cfg.heading_gain_per_s * dh
            vx = cfg.position_gain_per_s * fx
            vy = cfg.position_gain_per_s * fy
            if dist > cfg.stop_fraction * cfg.tolerance_m:
                scale = max(1.0, cfg.min_speed_m_s / max(math.hypot(vx, vy), 1e-9))
                vx, vy = vx * scale, vy * scale
        self.engine.set_velocity(float(np.clip(vx, -0.5 * cfg.max_vx_m_s, cfg.max_vx_m_s)),
                                 float(np.clip(vy, -cfg.max_vy_m_s, cfg.max_vy_m_s)),
                                 float(np.clip(yaw_rate, -cfg.max_yaw_rate_rad_s,
                                               cfg.max_yaw_rate_rad_s)))
