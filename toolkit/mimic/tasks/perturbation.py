"""A scenario's start-pose perturbation in the units people read: degrees and metres."""

from __future__ import annotations

import math
from dataclasses import dataclass

from mimic.episode import PoseNoise

__all__ = ["Perturbation", "NO_PERTURBATION"]


@dataclass(frozen=True)
class Perturbation:
    """Half-widths of the uniform noise added to a start pose (all zero: no noise)."""

    # Every joint angle [deg].
    joint_deg: float = 1.0
    # Robot x and y [m].
    position_m: float = 0.01
    # Robot heading [deg].
    yaw_deg: float = 2.0
    # Ball x and y [m].
    ball_m: float = 0.01

    def noise(self) -> PoseNoise:
        """The same as a scene's uniform pose noise."""
        return PoseNoise(
            position_m=self.position_m,
            yaw_rad=math.radians(self.yaw_deg),
            joint_rad=math.radians(self.joint_deg),
            ball_m=self.ball_m,
            distribution="uniform",
        )


NO_PERTURBATION = Perturbation(0.0, 0.0, 0.0, 0.0)
