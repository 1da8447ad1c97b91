"""The joint table: the one place that knows the robot's 22 hinges.

Order, canonical names, the simulator's names (hj1..rlj6), limits and mirror relations all
live here; everything else (MJCF, URDF, recordings, datasets, networks) reads this table.

Angle convention: the simulator's perceptor convention (RoboCup Soccer 3D, robot type 0),
in radians. Positive hip pitch swings the leg forward, negative knee pitch bends the knee,
positive ankle pitch lifts the toes, shoulder pitch -pi/2 hangs the arms down.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.errors import UnknownJointError

__all__ = [
    "Joint",
    "JOINTS",
    "JOINT_NAMES",
    "SIM_NAMES",
    "NUM_JOINTS",
    "joint_index",
    "lower_limits_rad",
    "upper_limits_rad",
    "mirror_permutation",
    "mirror_signs",
    "mirror_angles",
    "resolve_joint_names",
    "UnknownJointError",
]


@dataclass(frozen=True)
class Joint:
    """One hinge of the robot.

    Attributes:
        name: canonical name, e.g. ``left_knee_pitch``.
        sim_name: the simulator's effector/perceptor name, e.g. ``llj4``.
        group: ``head``, ``left_arm``, ``right_arm``, ``left_leg`` or ``right_leg``.
        lower_rad: lower joint stop [rad].
        upper_rad: upper joint stop [rad].
        mirror: name of the joint that mirrors this one across the sagittal plane.
        mirror_sign: +1 if the mirrored pose uses the same angle, -1 if the negated angle.
    """

    name: str
    sim_name: str
    group: str
    lower_rad: float
    upper_rad: float
    mirror: str
    mirror_sign: int


def _deg(lo: float, hi: float) -> tuple[float, float]:
    return math.radians(lo), math.radians(hi)


def _pair(part: str, sim: str, group: str, left_deg, right_deg, mirror_sign: int):
    """Left and right joints of one kind; the left one first, as in the study's order."""
    left = Joint(
        f"left_{part}", f"l{sim}", f"left_{group}", *_deg(*left_deg), f"right_{part}", mirror_sign
    )
    right = Joint(
        f"right_{part}", f"r{sim}", f"right_{group}", *_deg(*right_deg), f"left_{part}", mirror_sign
    )
    return left, right


def _arm(side: int) -> list[Joint]:
    pairs = [
        _pair("shoulder_pitch", "aj1", "arm", (-120, 120), (-120, 120), +1),
        _pair("shoulder_roll", "aj2", "arm", (-1, 95), (-95, 1), -1),
        _pair("elbow_yaw", "aj3", "arm", (-120, 120), (-120, 120), -1),
        _pair("elbow_roll", "aj4", "arm", (-90, 1), (-1, 90), -1),
    ]
    return [p[side] for p in pairs]


def _leg(side: int) -> list[Joint]:
    pairs = [
        _pair("hip_yaw_pitch", "lj1", "leg", (-90, 1), (-90, 1), +1),
        _pair("hip_roll", "lj2", "leg", (-25, 45), (-45, 25), -1),
        _pair("hip_pitch", "lj3", "leg", (-25, 100), (-25, 100), +1),
        _pair("knee_pitch", "lj4", "leg", (-130, 1), (-130, 1), +1),
        _pair("ankle_pitch", "lj5", "leg", (-45, 75), (-45, 75), +1),
        _pair("ankle_roll", "lj6", "leg", (-45, 25), (-25, 45), -1),
    ]
    return [p[side] for p in pairs]


#: The 22 joints in the study's order: head, left arm, right arm, left leg, right leg.
JOINTS: tuple[Joint, ...] = (
    Joint("head_yaw", "hj1", "head", *_deg(-120, 120), "head_yaw", -1),
    Joint("head_pitch", "hj2", "head", *_deg(-45, 45), "head_pitch", +1),
    *_arm(0),
    *_arm(1),
    *_leg(0),
    *_leg(1),
)

NUM_JOINTS: int = len(JOINTS)
JOINT_NAMES: tuple[str, ...] = tuple(j.name for j in JOINTS)
SIM_NAMES: tuple[str, ...] = tuple(j.sim_name for j in JOINTS)
_INDEX = {j.name: i for i, j in enumerate(JOINTS)} | {j.sim_name: i for i, j in enumerate(JOINTS)}


def joint_index(name: str) -> int:
    """Index of a joint in ``JOINTS`` from its canonical or simulator name."""
    try:
        return _INDEX[name]
    except KeyError:
        raise UnknownJointError(
            f"unknown joint {name!r}; known: {', '.join(JOINT_NAMES)} (or hj1..rlj6)"
        ) from None


def resolve_joint_names(names: list[str] | tuple[str, ...]) -> np.ndarray:
    """Map a foreign list of joint names onto our order.

    Returns an int array ``perm`` of shape (22,) with ``ours = theirs[perm]``.

    Raises:
        UnknownJointError: if a name is unknown or one of our joints is missing.
    """
    positions = {}
    for k, name in enumerate(names):
        if name in _INDEX:
            positions.setdefault(_INDEX[name], k)
    missing = [JOINT_NAMES[i] for i in range(NUM_JOINTS) if i not in positions]
    if missing:
        raise UnknownJointError(f"missing joints: {', '.join(missing)}")
    return np.array([positions[i] for i in range(NUM_JOINTS)], dtype=np.int64)


def _readonly(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def lower_limits_rad() -> np.ndarray:
    """(22,) lower joint stops [rad]."""
    return _LOWER


def upper_limits_rad() -> np.ndarray:
    """(22,) upper joint stops [rad]."""
    return _UPPER


def mirror_permutation() -> np.ndarray:
    """(22,) indices: ``mirrored[i] = angles[perm[i]] * signs[i]``."""
    return _MIRROR_PERM


def mirror_signs() -> np.ndarray:
    """(22,) +1/-1 signs applied after ``mirror_permutation``."""
    return _MIRROR_SIGN


def mirror_angles(angles_rad: np.ndarray) -> np.ndarray:
    """Joint angles of the pose mirrored across the sagittal plane; shape (..., 22)."""
    return np.asarray(angles_rad)[..., _MIRROR_PERM] * _MIRROR_SIGN


_LOWER = _readonly(np.array([j.lower_rad for j in JOINTS]))
_UPPER = _readonly(np.array([j.upper_rad for j in JOINTS]))
_MIRROR_PERM = _readonly(np.array([_INDEX[j.mirror] for j in JOINTS]))
_MIRROR_SIGN = _readonly(np.array([float(j.mirror_sign) for j in JOINTS]))
