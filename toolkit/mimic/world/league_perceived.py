"""The robot as a league player perceives it: what both league worlds read from the latest
``Perception`` (the in-process one from MjData, the server's from its stream)."""

from __future__ import annotations

import numpy as np

from mimic.league.client import Perception
from mimic.league.errors import LeagueError
from mimic.robot.actuators import JointCommand
from mimic.world.base import CYCLE_S, Observation

__all__ = ["PerceivedRobot"]


class PerceivedRobot:
    """Mixin for a ``World`` that keeps its player's latest perception in ``_perception``.

    The T1 has no foot touch sensors in the league, so an observation's foot forces are zero.
    """

    _perception: Perception

    def perception(self) -> Perception:
        """The latest perception, as an agent on a server receives it."""
        return self._perception

    def _observation(self, time_s: float, ball_pos_m: np.ndarray) -> Observation:
        p = self._perception
        return Observation(
            time_s=time_s,
            joint_angles_rad=p.joint_angles_rad.copy(),
            joint_speeds_rad_s=p.joint_speeds_rad_s.copy(),
            gyro_rad_s=p.gyro_rad_s.copy(),
            accelerometer_m_s2=p.accelerometer_m_s2.copy(),
            torso_quat_wxyz=p.torso_quat_wxyz.copy(),
            foot_forces_n=np.zeros(2),
            torso_pos_m=p.torso_pos_m.copy(),
            ball_pos_m=ball_pos_m,
        )

    def _placing(self) -> bool:
        """A placement asked for is not carried out yet (as far as this world can tell)."""
        return False

    def _hold_until_placed(self, x_m: float, y_m: float, pose: np.ndarray, who: str) -> None:
        """Hold ``pose`` until the torso is within the config's tolerance of (``x_m``,
        ``y_m``) [m, field frame], the placement ``who`` (the server) carries out, and no
        placement waits (a robot put where it stands is there before it is put).

        Raises:
            LeagueError: not there within the config's ``place_timeout_s``.
        """
        hold = JointCommand.references(pose)
        for _ in range(max(1, round(self.config.place_timeout_s / CYCLE_S))):
            self.step(hold)
            if (
                np.hypot(*(self._perception.torso_pos_m[:2] - (x_m, y_m)))
                < self.config.place_tolerance_m
                and not self._placing()
            ):
                return
        raise LeagueError(
            f"{who} did not move {self.team} #{self.player} to "
            f"({x_m:.2f}, {y_m:.2f}) within {self.config.place_timeout_s:g} s"
        )

    def joint_angles_rad(self) -> np.ndarray:
        return self._perception.joint_angles_rad.copy()

    def torso_pos_m(self) -> np.ndarray:
        return self._perception.torso_pos_m.copy()

    def torso_quat_wxyz(self) -> np.ndarray:
        return self._perception.torso_quat_wxyz.copy()

    def _torso_height_and_quat(self) -> tuple[float, list[float]]:
        seen = self._perception
        return float(seen.torso_pos_m[2]), seen.torso_quat_wxyz.tolist()
