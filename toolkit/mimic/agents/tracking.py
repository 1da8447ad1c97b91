"""The proportional tracking controller that turns angle references into joint speeds.

As in the study's agents: speed = gain * (reference - angle), clipped to the simulator's cap.
The same controller plays keyframe motions and learned motions, so a learned copy meets
exactly the attenuation the original met.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.robot.mjcf import MAX_JOINT_SPEED_RAD_S

__all__ = ["TrackingController", "DEFAULT_GAIN_PER_S"]

#: Proportional gain [1/s]: a 0.1 rad error asks for 2.5 rad/s.
DEFAULT_GAIN_PER_S = 25.0


@dataclass(frozen=True)
class TrackingController:
    """speed = gain * (reference - angle), clipped to +- max_speed."""

    # Proportional gain [1/s].
    gain_per_s: float = DEFAULT_GAIN_PER_S
    # Speed cap [rad/s].
    max_speed_rad_s: float = MAX_JOINT_SPEED_RAD_S

    def speeds(self, reference_rad: np.ndarray, angles_rad: np.ndarray) -> np.ndarray:
        """(22,) joint speed commands [rad/s] for (22,) references and angles [rad]."""
        return np.clip(self.gain_per_s * (reference_rad - angles_rad),
                       -self.max_speed_rad_s, self.max_speed_rad_s)
