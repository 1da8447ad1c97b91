"""The league's robots, Booster T1 and K1, as ``RobotDescription``s read from RCSSServerMJ.

Joints, limits, axes, the link tree with masses, sides, mirror signs, feet and the IMU come
from the MJCF files the ``rcsssmj`` package ships (``mjcf_reader``); torque limits are the
joints' ``actuatorfrcrange``. Only what an MJCF does not say is stated here, per joint kind
(left side; the right side mirrors it): the stand pose and the PD gains.

Gains: the league server applies torque = kp (q_ref - q) + kd (dq_ref - dq) + tau with the
gains the agent sends, so they are ours to choose. Legs sit between Booster's training gains
(booster_gym T1: kp 100 / kd 2 on hips and knees) and its stand-up ("prepare") gains (kp 350
on hips and knees, 350-450 on ankles); arms and head are soft (kp 10-40). Ankle pitch is the
exception to "soft ankles": with only PD motors and no balance feedback the robot is an
inverted pendulum on its ankles, which topples unless the two ankles together are stiffer
than m g h (T1: 31.6 kg, centre of mass 0.58 m up: 180 N m/rad, so 90 each; K1: 45 each).
Ours are about twice that, since knees and hips also give a little: the T1 at kp 100 or 120
falls over within 3 s, at 150 it stands leaning 2 degrees, at 200 upright.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache, partial
from importlib import resources
from pathlib import Path

import numpy as np

from mimic.errors import MimicError
from mimic.robot.actuators import PDMotors
from mimic.robot.mjcf_reader import MjcfRobot, read_mjcf, stand_height_m
from mimic.robot.mjcf_urdf import mjcf_urdf
from mimic.robot.model import FallThresholds, JointSpec, RobotDescription

__all__ = ["league_robot", "LEAGUE_ROBOTS", "league_mjcf_path"]


@dataclass(frozen=True)
class _Tuning:
    """What the MJCF does not say about a robot.

    Attributes:
        title: what it is.
        folder: its folder under ``rcsssmj/resources/robots``.
        stand_rad: joint kind -> angle of the left (or centre) joint in the stand pose [rad].
        gains: joint kind -> (kp [N m/rad], kd [N m s/rad]).
    """

    title: str
    folder: str
    stand_rad: dict[str, float]
    gains: dict[str, tuple[float, float]]


#: A joint's kind is the one of these its name contains (``ALeft_Shoulder_Pitch``).
_KINDS = (
    "Head_yaw",
    "Head_pitch",
    "Shoulder_Pitch",
    "Shoulder_Roll",
    "Elbow_Pitch",
    "Elbow_Yaw",
    "Waist",
    "Hip_Pitch",
    "Hip_Roll",
    "Hip_Yaw",
    "Knee_Pitch",
    "Ankle_Pitch",
    "Ankle_Roll",
)

# Ready pose (Booster's own default): knees bent 0.4 rad, hip and ankle pitch sharing it so
# the soles stay parallel to the upright torso; the knees' and ankles' sag under the load
# cancel, so the torso stays upright with the centre of mass 2-3 cm ahead of the ankles,
# over the soles. Arms hang 0.2 rad forward, forearms turned in, clear of body and thighs.
_T1 = _Tuning(
    title="Booster T1 (RoboCup league)",
    folder="T1",
    stand_rad={
        "Hip_Pitch": -0.2,
        "Knee_Pitch": 0.4,
        "Ankle_Pitch": -0.2,
        "Shoulder_Pitch": 0.2,
        "Shoulder_Roll": -1.35,
        "Elbow_Yaw": -0.5,
    },
    gains={
        "Head_yaw": (20, 0.5),
        "Head_pitch": (20, 0.5),
        "Shoulder_Pitch": (40, 1),
        "Shoulder_Roll": (40, 1),
        "Elbow_Pitch": (30, 1),
        "Elbow_Yaw": (30, 1),
        "Waist": (150, 4),
        "Hip_Pitch": (200, 5),
        "Hip_Roll": (200, 5),
        "Hip_Yaw": (150, 4),
        "Knee_Pitch": (200, 5),
        "Ankle_Pitch": (200, 4),
        "Ankle_Roll": (50, 1.5),
    },
)
# The K1 (two thirds of the T1's mass, shorter legs): the same legs, arms out as Booster
# has them; gains scaled down with the load.
_K1 = _Tuning(
    title="Booster K1 (RoboCup league)",
    folder="K1",
    stand_rad={
        "Hip_Pitch": -0.2,
        "Knee_Pitch": 0.4,
        "Ankle_Pitch": -0.2,
        "Shoulder_Pitch": 0.2,
        "Shoulder_Roll": -1.3,
        "Elbow_Yaw": -0.3,
    },
    gains={
        "Head_yaw": (10, 0.3),
        "Head_pitch": (10, 0.3),
        "Shoulder_Pitch": (20, 0.5),
        "Shoulder_Roll": (20, 0.5),
        "Elbow_Pitch": (20, 0.5),
        "Elbow_Yaw": (20, 0.5),
        "Hip_Pitch": (120, 3),
        "Hip_Roll": (120, 3),
        "Hip_Yaw": (80, 2),
        "Knee_Pitch": (120, 3),
        "Ankle_Pitch": (100, 2.5),
        "Ankle_Roll": (40, 1),
    },
)
_TUNING = {"t1": _T1, "k1": _K1}
#: Names of the league robots.
LEAGUE_ROBOTS = tuple(_TUNING)

# Fall thresholds as fractions of the stand pose's torso height, as our NAO's (0.22 and
# 0.28 m of 0.37 m).
_FALLEN_BELOW, _UPRIGHT_ABOVE = 0.6, 0.8
_FALLEN_TILT, _UPRIGHT_TILT = math.radians(60), math.radians(25)


def league_mjcf_path(name: str) -> Path:
    """The MJCF file of a league robot in the installed ``rcsssmj`` package."""
    try:
        package = resources.files("rcsssmj")
    except ModuleNotFoundError:
        raise MimicError(
            f"the {name} robot comes with the league simulator: pip install rcsssmj"
        ) from None
    path = Path(str(package / "resources" / "robots" / _TUNING[name].folder / "robot.xml"))
    if not path.is_file():
        raise MimicError(f"rcsssmj has no {path}; pip install --upgrade rcsssmj")
    return path


def _kind(joint: str) -> str:
    kinds = [k for k in _KINDS if k in joint]
    if len(kinds) != 1:
        raise MimicError(f"joint {joint}: cannot tell its kind (one of {', '.join(_KINDS)})")
    return kinds[0]


def _stand_pose(mjcf: MjcfRobot, table: dict[str, float]) -> tuple[float, ...]:
    """(N,) stand pose [rad]: left and centre joints from the table (0 if not in it), right
    joints the mirror of their left joint, so the pose is its own mirror image."""
    return tuple(
        float(
            table.get(_kind(h.name), 0.0)
            * (mjcf.mirror_sign[h.name] if mjcf.group[h.name].startswith("right_") else 1)
        )
        + 0.0  # no -0.0 in printed poses
        for h in mjcf.hinges
    )


def _gains(mjcf: MjcfRobot, table: dict[str, tuple[float, float]]) -> np.ndarray:
    """(N, 2) kp, kd per joint."""
    missing = sorted({_kind(h.name) for h in mjcf.hinges} - set(table))
    if missing:
        raise MimicError(f"{mjcf.path}: no PD gains for {', '.join(missing)} joints")
    return np.array([table[_kind(h.name)] for h in mjcf.hinges], dtype=float)


def league_robot(name: str) -> RobotDescription:
    """The league robot ``t1`` or ``k1`` (any case; read once, then cached)."""
    key = name.lower()
    if key not in _TUNING:
        raise MimicError(
            f"unknown league robot {name!r}; league robots: {', '.join(LEAGUE_ROBOTS)}"
        )
    return _league_robot(key)


@cache
def _league_robot(key: str) -> RobotDescription:
    tuning, path = _TUNING[key], league_mjcf_path(key)
    mjcf = read_mjcf(path)
    stand, gains = _stand_pose(mjcf, tuning.stand_rad), _gains(mjcf, tuning.gains)
    joints = tuple(
        JointSpec(
            h.name,
            h.lower_rad,
            h.upper_rad,
            h.axis,
            h.parent_link,
            h.child_link,
            mjcf.mirror[h.name],
            mjcf.mirror_sign[h.name],
            mjcf.group[h.name],
        )
        for h in mjcf.hinges
    )
    height = stand_height_m(
        path, mjcf.links[0].name, mjcf.foot_links, {h.name: q for h, q in zip(mjcf.hinges, stand)}
    )
    return RobotDescription(
        name=key,
        title=tuning.title,
        joints=joints,
        links=mjcf.links,
        stand_pose_rad=stand,
        actuator=PDMotors(
            kp_nm_rad=_readonly(gains[:, 0]),
            kd_nm_s_rad=_readonly(gains[:, 1]),
            max_torque_nm=_readonly([h.max_torque_nm for h in mjcf.hinges]),
        ),
        falls=FallThresholds(
            fallen_below_m=_FALLEN_BELOW * height,
            fallen_tilt_rad=_FALLEN_TILT,
            upright_above_m=_UPRIGHT_ABOVE * height,
            upright_tilt_rad=_UPRIGHT_TILT,
        ),
        imu_site=mjcf.imu_site,
        foot_links=mjcf.foot_links,
        urdf=partial(mjcf_urdf, path, f"booster_{key}"),
        mjcf_path=path,
        world="league",
    )


def _readonly(values) -> np.ndarray:
    a = np.array(values, dtype=float)
    a.setflags(write=False)
    return a
