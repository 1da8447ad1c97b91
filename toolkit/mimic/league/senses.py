"""What a league player perceives, read straight from rcsssmj's MjData (no message, no text).

rcsssmj's ``BaseSimulation.generate_perceptions`` reads the player's MuJoCo sensors, truncates
them (joint angles and speeds in degrees to 0.01, gyro in deg/s to 0.01, accelerometer to 0.01,
orientation quaternion and position to 0.001, the clock to 0.01 s) and the server sends them as
text; ``client.parse_perception`` turns that text into a ``Perception`` (radians, the robot's
joint order, a unit quaternion). ``Senses.read`` does both at once with the same arithmetic on
the same numbers, so the values are the ones a player on a server receives, bit for bit
(Python prints a float so that it reads back the same). Vision and hearing are left out.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mimic.league.client import Perception
from mimic.league.errors import LeagueError
from mimic.league.names import WireNames
from mimic.robot.model import RobotDescription

__all__ = ["Senses"]

_S = mujoco.mjtSensor


class Senses:
    """A player's sensors in a compiled rcsssmj model, read as a server's perception.

    Args:
        model: the simulation's MjModel (after the player joined).
        robot: the player's robot; names: its wire names.
        prefix: the player's name prefix in the model (``r-0-1-``).
    """

    def __init__(
        self, model: mujoco.MjModel, robot: RobotDescription, names: WireNames, prefix: str
    ) -> None:
        angles: list[tuple[str, int]] = []
        speeds: list[int] = []
        single: dict[int, int] = {}  # sensor type -> address (the last one, as a parser keeps)
        for s in range(model.nsensor):  # the robot spec's order, as generate_perceptions
            name = model.sensor(s).name
            if not name.startswith(prefix):
                continue
            kind, adr = int(model.sensor_type[s]), int(model.sensor_adr[s])
            if kind == _S.mjSENS_JOINTPOS:
                angles.append((name[len(prefix) :], adr))
            elif kind == _S.mjSENS_JOINTVEL:
                speeds.append(adr)
            else:
                single[kind] = adr
        joints, angle_adr, speed_adr = [], [], []
        # Each angle is sent with the speed of the same rank, as rcsssmj zips the two lists.
        for rank, (sensor, adr) in enumerate(angles):
            joint = names.joint_by_sensor.get(sensor)
            if joint is None or not robot.has_joint(joint) or rank >= len(speeds):
                continue
            joints.append(robot.joint_index(joint))
            angle_adr.append(adr)
            speed_adr.append(speeds[rank])
        missing = sorted(set(range(robot.num_joints)) - set(joints))
        if missing or len(joints) != len(set(joints)):
            raise LeagueError(
                f"the {robot.name}'s sensors in rcsssmj's model do not give each joint one "
                f"angle and one speed (missing: {[robot.joint_names[i] for i in missing]})"
            )
        needed = (_S.mjSENS_GYRO, _S.mjSENS_ACCELEROMETER, _S.mjSENS_FRAMEQUAT, _S.mjSENS_FRAMEPOS)
        lacking = [k.name for k in needed if int(k) not in single]
        if lacking:
            raise LeagueError(f"the {robot.name} in rcsssmj's model lacks {', '.join(lacking)}")
        n = robot.num_joints
        order = np.argsort(joints)  # the robot's joint order
        angle_adr, speed_adr = np.array(angle_adr)[order], np.array(speed_adr)[order]

        def span(kind: int, size: int) -> list[int]:
            return list(range(single[kind], single[kind] + size))

        # One gather, one pass of arithmetic per element as rcsssmj and the parser do it:
        # angles, speeds and gyro to degrees (x 180/pi, np.degrees' arithmetic), truncated to
        # 0.01 and back to radians (x pi/180, np.radians' and math.radians'); accelerometer
        # truncated to 0.01; orientation and position to 0.001. Multiplying by 1.0 is exact.
        groups = [
            ([*angle_adr, *speed_adr, *span(_S.mjSENS_GYRO, 3)], 180 / math.pi, 100.0),
            (span(_S.mjSENS_ACCELEROMETER, 3), 1.0, 100.0),
            ([*span(_S.mjSENS_FRAMEQUAT, 4), *span(_S.mjSENS_FRAMEPOS, 3)], 1.0, 1000.0),
        ]
        self._adr = np.array([a for adr, _, _ in groups for a in adr])
        self._to_unit = np.array([u for adr, u, _ in groups for _ in adr])
        self._scale = np.array([c for adr, _, c in groups for _ in adr])
        self._from_unit = np.where(self._to_unit == 1.0, 1.0, math.pi / 180)
        self._n = n

    def read(self, data: mujoco.MjData, play_mode: str = "") -> Perception:
        """The perception of ``data``'s current sensor values."""
        sent = np.trunc(data.sensordata[self._adr] * self._to_unit * self._scale)
        sent = sent / self._scale * self._from_unit
        n = self._n
        quat = sent[2 * n + 6 : 2 * n + 10]
        norm = math.sqrt(quat.dot(quat))  # np.linalg.norm's arithmetic for a vector
        return Perception(
            time_s=int(data.time * 100) / 100.0,
            joint_angles_rad=sent[:n],
            joint_speeds_rad_s=sent[n : 2 * n],
            gyro_rad_s=sent[2 * n : 2 * n + 3],
            accelerometer_m_s2=sent[2 * n + 3 : 2 * n + 6],
            torso_quat_wxyz=quat / norm if norm > 0 else np.array([1.0, 0, 0, 0]),
            torso_pos_m=sent[2 * n + 10 :],
            play_mode=play_mode,
        )
