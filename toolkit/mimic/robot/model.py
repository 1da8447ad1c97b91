"""A robot as data: everything the rest of mimic needs to know about one humanoid.

Joint names and order, limits, axes, the kinematic tree with masses, the stand pose, the
left/right mirror map and the actuator model. Datasets, networks, model files, recordings,
worlds and viewers read their joint count and names from here; nothing outside a robot's
description knows it.

Frames: positions in metres, MuJoCo convention (x forward, y left, z up); angles in radians
in the robot's own joint convention (its MJCF's).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from mimic.errors import MimicError, UnknownJointError
from mimic.robot.actuators import ActuatorModel

__all__ = ["JointSpec", "LinkSpec", "RobotDescription", "UnknownJointError", "FallThresholds"]


@dataclass(frozen=True)
class JointSpec:
    """One hinge.

    Attributes:
        name: the robot's own name, as in its MJCF (``left_knee_pitch``, ``Left_Knee_Pitch``).
        lower_rad, upper_rad: joint stops [rad].
        axis: (3,) hinge axis in the child link frame (unit vector).
        parent_link, child_link: the links the hinge joins.
        mirror: the joint that mirrors this one across the sagittal plane (itself for a
            centre joint).
        mirror_sign: +1 if the mirrored pose uses the same angle, -1 if the negated one.
        group: ``head``, ``left_arm``, ``right_arm``, ``waist``, ``left_leg`` or ``right_leg``.
        aliases: other names that mean this joint (the study simulator's ``llj4``).
    """

    name: str
    lower_rad: float
    upper_rad: float
    axis: tuple[float, float, float]
    parent_link: str
    child_link: str
    mirror: str
    mirror_sign: int
    group: str
    aliases: tuple[str, ...] = ()


@dataclass(frozen=True)
class LinkSpec:
    """One rigid body of the kinematic tree.

    Attributes:
        name: body name in the MJCF, also the TF frame.
        parent: parent link, or None for the free-floating root.
        pos_m: (3,) origin in the parent link frame at the zero pose [m].
        quat_wxyz: (4,) orientation in the parent link frame at the zero pose.
        mass_kg: mass [kg].
    """

    name: str
    parent: str | None
    pos_m: tuple[float, float, float]
    quat_wxyz: tuple[float, float, float, float]
    mass_kg: float


@dataclass(frozen=True)
class FallThresholds:
    """When the robot counts as fallen, and as standing upright again (torso centre)."""

    # Fallen: torso centre below this height [m] ...
    fallen_below_m: float
    # ... or its z axis tilted more than this from vertical [rad].
    fallen_tilt_rad: float
    # Upright: torso centre above this height [m] and tilted less than this [rad].
    upright_above_m: float
    upright_tilt_rad: float


@dataclass(frozen=True, eq=False)
class RobotDescription:
    """A humanoid robot as data.

    Attributes:
        name: short name (``nao``, ``t1``, ``k1``), used on the command line and in files.
        title: what it is, in a few words.
        joints: the hinges in the robot's joint order (the order of every joint vector).
        links: the kinematic tree, parents before children; ``links[0]`` is the root.
        stand_pose_rad: (N,) the ready pose every motion starts from [rad].
        actuator: how commands reach the joints (``SpeedServos`` or ``PDMotors``).
        falls: fall and upright thresholds.
        imu_site: MJCF site carrying the gyro, accelerometer and orientation.
        foot_links: (left, right) links of the feet.
        mjcf_path: the robot's MJCF file, for robots loaded from one (None for generated).
        urdf: builds the URDF twin written to ``/robot_description``.
        world: the world whose robot this is by default (``nao``: our MuJoCo world;
            ``league``: RCSSServerMJ).
    """

    name: str
    title: str
    joints: tuple[JointSpec, ...]
    links: tuple[LinkSpec, ...]
    stand_pose_rad: tuple[float, ...]
    actuator: ActuatorModel
    falls: FallThresholds
    imu_site: str
    foot_links: tuple[str, str]
    urdf: Callable[[], str] = field(repr=False)
    mjcf_path: Path | None = None
    world: str = "nao"

    def __post_init__(self) -> None:
        if len(self.stand_pose_rad) != len(self.joints):
            raise ValueError(
                f"{self.name}: stand pose has {len(self.stand_pose_rad)} angles "
                f"for {len(self.joints)} joints"
            )

    # --- sizes and names ---------------------------------------------------------------
    @property
    def num_joints(self) -> int:
        return len(self.joints)

    @cached_property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @cached_property
    def mass_kg(self) -> float:
        return float(sum(link.mass_kg for link in self.links))

    @property
    def root_link(self) -> str:
        return self.links[0].name

    @cached_property
    def _index(self) -> dict[str, int]:
        index = {}
        for i, j in enumerate(self.joints):
            for n in (j.name, *j.aliases):
                index[n] = i
        return index

    def joint_index(self, name: str) -> int:
        """Index of a joint in the robot's order, from its name or an alias."""
        try:
            return self._index[name]
        except KeyError:
            raise UnknownJointError(
                f"unknown joint {name!r}: the {self.name} has none; its joints: "
                f"{', '.join(self.joint_names)}"
            ) from None

    def has_joint(self, name: str) -> bool:
        return name in self._index

    def resolve_joint_names(self, names) -> np.ndarray:
        """(N,) int ``perm`` with ``ours = theirs[perm]`` for a foreign list of joint names.

        Raises:
            UnknownJointError: one of our joints is missing from ``names``.
        """
        positions: dict[int, int] = {}
        for k, name in enumerate(names):
            if name in self._index:
                positions.setdefault(self._index[name], k)
        missing = [self.joint_names[i] for i in range(self.num_joints) if i not in positions]
        if missing:
            raise UnknownJointError(f"missing {self.name} joints: {', '.join(missing)}")
        return np.array([positions[i] for i in range(self.num_joints)], dtype=np.int64)

    # --- vectors ------------------------------------------------------------------------
    @cached_property
    def lower_limits_rad(self) -> np.ndarray:
        """(N,) lower joint stops [rad] (read-only)."""
        return _readonly([j.lower_rad for j in self.joints])

    @cached_property
    def upper_limits_rad(self) -> np.ndarray:
        """(N,) upper joint stops [rad] (read-only)."""
        return _readonly([j.upper_rad for j in self.joints])

    def stand_pose(self) -> np.ndarray:
        """(N,) the stand pose [rad] (a fresh copy)."""
        return np.array(self.stand_pose_rad, dtype=float)

    def zeros(self) -> np.ndarray:
        """(N,) zeros: a joint vector of this robot."""
        return np.zeros(self.num_joints)

    @cached_property
    def mirror_permutation(self) -> np.ndarray:
        """(N,) indices: ``mirrored[i] = angles[perm[i]] * signs[i]``."""
        return _readonly([self.joint_index(j.mirror) for j in self.joints], np.int64)

    @cached_property
    def mirror_signs(self) -> np.ndarray:
        """(N,) +1/-1 signs applied after ``mirror_permutation``."""
        return _readonly([float(j.mirror_sign) for j in self.joints])

    def mirror_angles(self, angles_rad: np.ndarray) -> np.ndarray:
        """Joint angles of the pose mirrored across the sagittal plane; shape (..., N)."""
        return np.asarray(angles_rad)[..., self.mirror_permutation] * self.mirror_signs

    def clip(self, angles_rad: np.ndarray) -> np.ndarray:
        """Angles clipped to the joint stops; shape (..., N)."""
        return np.clip(angles_rad, self.lower_limits_rad, self.upper_limits_rad)

    def check_vector(self, values: np.ndarray, what: str) -> np.ndarray:
        """``values`` as an (N,) float array, or a clear error naming the robot."""
        a = np.asarray(values, dtype=float)
        if a.shape != (self.num_joints,):
            raise MimicError(
                f"{what}: {self.name} has {self.num_joints} joints, got shape {a.shape}"
            )
        return a

    def describe(self) -> str:
        """One line: joints, mass, actuators."""
        return (
            f"{self.title}: {self.num_joints} joints, {self.mass_kg:.2f} kg, "
            f"{self.actuator.describe()}"
        )


def _readonly(values, dtype=float) -> np.ndarray:
    a = np.array(values, dtype=dtype)
    a.setflags(write=False)
    return a
