"""What a robot's MJCF file says about it: joints, kinematic tree, sides, feet and IMU.

Everything is read from the compiled model, never from hard-coded indices, so a robot that
comes as an MJCF file (the league's T1 and K1) is described by its own file. Frames: MuJoCo's
(x forward, y left, z up); body poses in the parent body frame; angles [rad].

The left/right mirror of a joint is found by its name (``Left`` <-> ``Right``, any case),
its sign by the axes: reflecting a rotation about axis ``a`` by angle ``q`` across the
sagittal plane (y -> -y, an improper transform ``M``) gives the rotation about ``M a`` by
``-q``. So if the mirror joint's axis is ``M a`` its angle is ``-q`` (roll and yaw joints), and
if it is ``-M a`` the angle is ``q`` (pitch joints): sign = -(a_mirror . M a).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import mujoco
import numpy as np

from mimic.errors import MimicError
from mimic.robot.model import LinkSpec

__all__ = [
    "MjcfRobot",
    "MjcfHinge",
    "read_mjcf",
    "load_model",
    "mirror_name",
    "sole_box",
    "stand_height_m",
    "collision_geoms",
    "geom_box_corners",
]

_SAGITTAL = np.array([1.0, -1.0, 1.0])  # the reflection y -> -y, as a diagonal
_SIDE = re.compile(r"Left|Right|left|right|LEFT|RIGHT")
_SWAP = {
    "Left": "Right",
    "Right": "Left",
    "left": "right",
    "right": "left",
    "LEFT": "RIGHT",
    "RIGHT": "LEFT",
}


def mirror_name(name: str) -> str:
    """The name of the mirror element: ``Left`` and ``Right`` swapped (itself if neither)."""
    return _SIDE.sub(lambda m: _SWAP[m.group(0)], name)


@dataclass(frozen=True)
class MjcfHinge:
    """One hinge as the MJCF has it.

    axis: (3,) in the child body frame; world_axis: (3,) in the world at the zero pose.
    """

    name: str
    lower_rad: float
    upper_rad: float
    axis: tuple[float, float, float]
    world_axis: tuple[float, float, float]
    parent_link: str
    child_link: str
    max_torque_nm: float


@dataclass(frozen=True)
class MjcfRobot:
    """A robot read from its MJCF file.

    Attributes:
        path: the MJCF file.
        hinges: the hinge joints in MJCF order.
        links: the bodies, parents before children; ``links[0]`` is the free-floating root.
        mirror: joint name -> its mirror joint's name.
        mirror_sign: joint name -> +1 (same angle mirrored) or -1 (negated).
        group: joint name -> ``head``, ``waist``, ``left_arm``, ``right_arm``,
            ``left_leg`` or ``right_leg``.
        foot_links: (left, right) foot bodies.
        imu_site: the site carrying the MJCF's own gyro.
    """

    path: Path
    hinges: tuple[MjcfHinge, ...]
    links: tuple[LinkSpec, ...]
    mirror: dict[str, str]
    mirror_sign: dict[str, int]
    group: dict[str, str]
    foot_links: tuple[str, str]
    imu_site: str


@cache  # compiling the K1's mesh geoms takes a second; the model is only read
def load_model(path: Path) -> mujoco.MjModel:
    """The compiled robot model (cached; read it, do not change it)."""
    try:
        return mujoco.MjModel.from_xml_path(str(path))
    except ValueError as err:  # MuJoCo's compile errors
        raise MimicError(f"cannot load the robot MJCF {path}: {err}") from None


@cache
def read_mjcf(path: Path) -> MjcfRobot:
    """Read the robot in ``path`` (cached: the file is part of an installed package)."""
    m = load_model(path)
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)  # zero pose: the mirror-symmetric configuration

    def body(b) -> str:
        return m.body(int(b)).name

    hinges = tuple(
        MjcfHinge(
            m.joint(j).name,
            float(m.jnt_range[j, 0]),
            float(m.jnt_range[j, 1]),
            _unit(m.jnt_axis[j]),
            _unit(d.xaxis[j]),
            body(m.body_parentid[m.jnt_bodyid[j]]),
            body(m.jnt_bodyid[j]),
            float(m.jnt_actfrcrange[j, 1]),
        )
        for j in range(m.njnt)
        if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE
    )
    roots = [b for b in range(1, m.nbody) if m.body_parentid[b] == 0]
    if len(roots) != 1:
        raise MimicError(f"{path}: expected one robot root body, found {len(roots)}")
    links = tuple(
        LinkSpec(
            body(b),
            None if m.body_parentid[b] == 0 else body(m.body_parentid[b]),
            tuple(float(v) for v in m.body_pos[b]),
            tuple(float(v) for v in m.body_quat[b]),
            float(m.body_mass[b]),
        )
        for b in range(1, m.nbody)
    )
    mirror, sign = _mirrors(path, hinges)
    group, feet = _groups(m, d, hinges)
    return MjcfRobot(path, hinges, links, mirror, sign, group, feet, _imu_site(m, path))


def _unit(v) -> tuple[float, float, float]:
    a = np.asarray(v, dtype=float)
    return tuple(float(x) for x in a / np.linalg.norm(a))


def _mirrors(path: Path, hinges) -> tuple[dict[str, str], dict[str, int]]:
    by_name = {h.name: h for h in hinges}
    mirror, sign = {}, {}
    for h in hinges:
        other = by_name.get(mirror_name(h.name))
        if other is None:
            raise MimicError(f"{path}: joint {h.name} has no mirror joint {mirror_name(h.name)}")
        dot = float(np.dot(other.world_axis, _SAGITTAL * np.array(h.world_axis)))
        if abs(abs(dot) - 1) > 0.01:  # the axes must be mirror images, up to direction
            raise MimicError(
                f"{path}: joints {h.name} and {other.name} are not mirror "
                f"images (axes {h.world_axis}, {other.world_axis})"
            )
        mirror[h.name], sign[h.name] = other.name, -round(dot)
    return mirror, sign


def _groups(m: mujoco.MjModel, d: mujoco.MjData, hinges) -> tuple[dict[str, str], tuple[str, str]]:
    """Limb of every joint, from the chains root -> leaf: the two lowest leaves are the feet,
    the highest the head, the others hands; sides by the sign of y at the zero pose."""
    parents = set(m.body_parentid[1:].tolist())
    leaves = sorted((b for b in range(1, m.nbody) if b not in parents), key=lambda b: d.xpos[b, 2])
    if len(leaves) < 4:
        raise MimicError("expected a humanoid: two feet, a head and hands as leaf bodies")

    def side(b) -> str:
        return "left" if d.xpos[b, 1] > 0 else "right"

    limb = {b: f"{side(b)}_leg" for b in leaves[:2]}
    limb |= {b: f"{side(b)}_arm" for b in leaves[2:-1]}
    limb[leaves[-1]] = "head"
    on_chain: dict[str, list[str]] = {h.name: [] for h in hinges}
    for leaf, name in limb.items():
        b = leaf
        while b != 0:
            for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b]):
                if m.joint(j).name in on_chain:
                    on_chain[m.joint(j).name].append(name)
            b = m.body_parentid[b]
    # A joint on the chains of several limbs (the T1's waist, above both legs) is the waist.
    group = {joint: limbs[0] if len(limbs) == 1 else "waist" for joint, limbs in on_chain.items()}
    feet = sorted(leaves[:2], key=lambda b: -d.xpos[b, 1])  # left (+y) first
    return group, (m.body(feet[0]).name, m.body(feet[1]).name)


def _imu_site(m: mujoco.MjModel, path: Path) -> str:
    for s in range(m.nsensor):
        if m.sensor_type[s] == mujoco.mjtSensor.mjSENS_GYRO:
            return m.site(m.sensor_objid[s]).name
    raise MimicError(f"{path}: no gyro sensor, so no IMU site")


def collision_geoms(m: mujoco.MjModel, body_id: int) -> list[int]:
    """The geoms of a body that take part in contacts."""
    return [
        g
        for g in range(m.ngeom)
        if m.geom_bodyid[g] == body_id and (m.geom_contype[g] or m.geom_conaffinity[g])
    ]


def geom_box_corners(m: mujoco.MjModel, g: int) -> np.ndarray:
    """(8, 3) corners of a geom's bounding box in its body frame [m]."""
    centre, half = m.geom_aabb[g, :3], m.geom_aabb[g, 3:]
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, m.geom_quat[g])
    return (centre + signs * half) @ rot.reshape(3, 3).T + m.geom_pos[g]


@cache
def sole_box(path: Path, foot_link: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """((x, y, z), (half_x, half_y)) of a foot's sole in the foot frame [m]: the bottom face
    of the box bounding the foot's collision geoms."""
    m = load_model(path)
    corners = np.vstack([geom_box_corners(m, g) for g in collision_geoms(m, m.body(foot_link).id)])
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    centre = (lo + hi) / 2
    return (
        (float(centre[0]), float(centre[1]), float(lo[2])),
        (float(hi[0] - lo[0]) / 2, float(hi[1] - lo[1]) / 2),
    )


def stand_height_m(
    path: Path, root: str, feet: tuple[str, str], joint_angles_rad: dict[str, float]
) -> float:
    """Height [m] of the root body's origin above the lowest sole point, in a pose (root
    upright)."""
    m = load_model(path)
    d = mujoco.MjData(m)
    for name, q in joint_angles_rad.items():
        d.qpos[m.jnt_qposadr[m.joint(name).id]] = q
    mujoco.mj_kinematics(m, d)
    lowest = np.inf
    for foot in feet:
        b = m.body(foot).id
        for g in collision_geoms(m, b):
            world = geom_box_corners(m, g) @ d.xmat[b].reshape(3, 3).T + d.xpos[b]
            lowest = min(lowest, float(world[:, 2].min()))
    return float(d.xpos[m.body(root).id, 2] - lowest)
