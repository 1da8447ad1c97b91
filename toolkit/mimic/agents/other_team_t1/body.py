"""The T1 team's body layer: foot poses to the robot's joint references, and back.

The legs come from the team's IK (``ik.LegChain``); head, waist and arms hold the robot's
stand pose, the arms optionally swinging in shoulder pitch. Joint indices are looked up by
the robot's own joint names, once.
"""

from __future__ import annotations

import numpy as np

from mimic.agents.other_team_t1.ik import SIDES, leg_chains
from mimic.robot.model import RobotDescription

__all__ = ["Body", "LEG_PARTS"]

#: The leg hinges' kinds, hip to ankle, as the T1's joint names spell them.
LEG_PARTS = ("Hip_Pitch", "Hip_Roll", "Hip_Yaw", "Knee_Pitch", "Ankle_Pitch", "Ankle_Roll")


class Body:
    """Foot poses in the torso frame to (N,) joint references, warm-starting the IK.

    Attributes:
        leg: side -> {part: joint index} (``LEG_PARTS``), side +1 left, -1 right.
        shoulder_pitch: side -> joint index of the shoulder pitch.
    """

    def __init__(self, robot: RobotDescription) -> None:
        self.robot = robot
        self.chains = leg_chains(robot)
        self.leg = {
            side: {part: robot.joint_index(f"{SIDES[side].title()}_{part}") for part in LEG_PARTS}
            for side in SIDES
        }
        self.shoulder_pitch = {
            side: robot.joint_index(f"{SIDES[side].title()}_Shoulder_Pitch") for side in SIDES
        }
        for side, chain in self.chains.items():  # the names and the tree must agree
            assert list(chain.joints) == [self.leg[side][p] for p in LEG_PARTS]
        self.stand_rad = robot.stand_pose()
        self._last = {side: self.stand_rad[c.joints] for side, c in self.chains.items()}

    def reset(self, angles_rad: np.ndarray) -> None:
        """Warm-start the IK from these (N,) joint angles [rad]."""
        for side, chain in self.chains.items():
            self._last[side] = np.asarray(angles_rad, dtype=float)[chain.joints].copy()

    def foot_pose(self, side: float, angles_rad: np.ndarray):
        """(3,) position [m] and (3, 3) rotation of a foot in the torso frame."""
        chain = self.chains[side]
        return chain.fk(angles_rad[chain.joints], angles_rad[chain.fixed])

    def joints(
        self,
        feet: dict[float, tuple[np.ndarray, np.ndarray]],
        arm_swing_rad: dict[float, float] | None = None,
    ) -> np.ndarray:
        """(N,) joint references [rad] for foot poses {side: ((3,) position, (3, 3) rotation)}
        in the torso frame; the rest of the body in its stand pose (arms swung forward by
        ``arm_swing_rad`` [rad] per side)."""
        q = self.stand_rad.copy()
        for side, (pos, rot) in feet.items():
            chain = self.chains[side]
            self._last[side] = chain.ik(pos, rot, self._last[side], fixed_rad=q[chain.fixed])
            q[chain.joints] = self._last[side]
        for side, swing in (arm_swing_rad or {}).items():
            q[self.shoulder_pitch[side]] -= swing
        return self.robot.clip(q)
