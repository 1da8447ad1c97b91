"""How the league server names a robot's joints on the wire, read from the robot's MJCF.

The server reports joint angles under the names of the MJCF's ``jointpos`` sensors
(``q_rlj4``) and takes motor commands under the names of its actuators without their
``_tau``/``_pos``/``_vel`` suffix (``rle4``); each sensor and actuator says which joint it
acts on (``joint=``), so both maps come from the file, never from a table of ours.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import mujoco

from mimic.league.errors import LeagueError
from mimic.robot.mjcf_reader import load_model
from mimic.robot.model import RobotDescription

__all__ = ["WireNames", "wire_names", "ACTUATOR_SUFFIXES"]

#: The three actuators the server drives per joint: ``<effector>_tau``, ``_pos``, ``_vel``.
ACTUATOR_SUFFIXES = ("_tau", "_pos", "_vel")


@dataclass(frozen=True)
class WireNames:
    """A robot's names on the wire.

    Attributes:
        effectors: (N,) effector name of each joint, in the robot's joint order (``rle4``).
        joint_by_sensor: jointpos sensor name (``q_rlj4``) -> joint name.
        speed_sensor_joint: jointvel sensor name (``dq_rlj4``) -> joint name.
        model_name: the name an agent gives in ``(init MODEL TEAM UNUM)`` (``T1``).
    """

    effectors: tuple[str, ...]
    joint_by_sensor: dict[str, str]
    speed_sensor_joint: dict[str, str]
    model_name: str


def wire_names(robot: RobotDescription) -> WireNames:
    """The wire names of a league robot (one read from an MJCF file)."""
    if robot.mjcf_path is None:
        raise LeagueError(
            f"the {robot.name} is not a league robot (it has no MJCF file); league robots: t1, k1"
        )
    return _wire_names(robot)


@cache
def _wire_names(robot: RobotDescription) -> WireNames:
    m = load_model(robot.mjcf_path)
    by_joint: dict[str, str] = {}
    for a in range(m.nu):
        if m.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
            continue
        name, joint = m.actuator(a).name, m.joint(int(m.actuator_trnid[a, 0])).name
        base = next((name[: -len(s)] for s in ACTUATOR_SUFFIXES if name.endswith(s)), name)
        by_joint.setdefault(joint, base)
    missing = [j for j in robot.joint_names if j not in by_joint]
    if missing:
        raise LeagueError(f"{robot.mjcf_path}: no actuator drives {', '.join(missing)}")
    sensors: dict[int, dict[str, str]] = {
        mujoco.mjtSensor.mjSENS_JOINTPOS: {},
        mujoco.mjtSensor.mjSENS_JOINTVEL: {},
    }
    for s in range(m.nsensor):
        kind = int(m.sensor_type[s])
        if kind in sensors:
            sensors[kind][m.sensor(s).name] = m.joint(int(m.sensor_objid[s])).name
    return WireNames(
        effectors=tuple(by_joint[j] for j in robot.joint_names),
        joint_by_sensor=sensors[mujoco.mjtSensor.mjSENS_JOINTPOS],
        speed_sensor_joint=sensors[mujoco.mjtSensor.mjSENS_JOINTVEL],
        model_name=robot.mjcf_path.parent.name,
    )
