"""A robot's links as the viewer needs them: mass, centre of mass and shapes, each in its link
frame (the TF frame of the same name), read from the MuJoCo model the robot is simulated with.

Reading the compiled model (not a robot's own tables) is what makes the view work for any robot:
our NAO's primitive boxes, spheres and capsules, and the league robots' meshes, come out the
same way. Frames: MuJoCo's (x forward, y left, z up) [m]; quaternions (w, x, y, z).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import mujoco
import numpy as np

from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.world.scene import PhysicsConfig, build_model

__all__ = ["Shape", "LinkBody", "link_bodies"]

_KINDS = {
    mujoco.mjtGeom.mjGEOM_BOX: "box",
    mujoco.mjtGeom.mjGEOM_SPHERE: "sphere",
    mujoco.mjtGeom.mjGEOM_CAPSULE: "capsule",
    mujoco.mjtGeom.mjGEOM_CYLINDER: "cylinder",
    mujoco.mjtGeom.mjGEOM_ELLIPSOID: "ellipsoid",
    mujoco.mjtGeom.mjGEOM_MESH: "mesh",
}


@dataclass(frozen=True, eq=False)
class Shape:
    """One geom in its link frame.

    Attributes:
        kind: ``box``, ``sphere``, ``capsule``, ``cylinder``, ``ellipsoid`` or ``mesh``.
        size_m: (3,) MuJoCo geom size: half extents (box, ellipsoid); radius (sphere);
            radius and half length along the geom's z (capsule, cylinder) [m].
        pos_m: (3,) geom centre [m]; quat_wxyz: (4,) geom orientation.
        collides: whether it takes part in contacts (else it is only drawn).
        vertices_m: (V, 3) mesh vertices in the link frame [m] (meshes only).
        faces: (F, 3) mesh triangle indices (meshes only).
    """

    kind: str
    size_m: np.ndarray
    pos_m: np.ndarray
    quat_wxyz: np.ndarray
    collides: bool
    vertices_m: np.ndarray | None = None
    faces: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class LinkBody:
    """One link: name (its TF frame), mass [kg], centre of mass (3,) in its frame [m], shapes."""

    name: str
    mass_kg: float
    com_m: np.ndarray
    shapes: tuple[Shape, ...]


def link_bodies(robot: str | RobotDescription) -> tuple[LinkBody, ...]:
    """Every link of ``robot`` (its ``links`` order), from its MuJoCo model (cached by name)."""
    return _link_bodies(get_robot(robot).name)


@cache
def _link_bodies(robot_name: str) -> tuple[LinkBody, ...]:

    robot = get_robot(robot_name)
    m = build_model(robot, PhysicsConfig.for_robot(robot))
    out = []
    for link in robot.links:
        body = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, link.name)
        geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] == body and m.geom_type[g] in _KINDS]
        # A link drawn by meshes also carries simplified collision shapes: draw one of the two.
        meshes = [g for g in geoms if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH]
        out.append(
            LinkBody(
                link.name,
                float(m.body_mass[body]),
                m.body_ipos[body].copy(),
                tuple(_shape(m, g) for g in (meshes or geoms)),
            )
        )
    return tuple(out)


def _shape(m: mujoco.MjModel, g: int) -> Shape:
    pos, quat = m.geom_pos[g].copy(), m.geom_quat[g].copy()
    collides = bool(m.geom_contype[g] or m.geom_conaffinity[g])
    kind = _KINDS[m.geom_type[g]]
    if kind != "mesh":
        return Shape(kind, m.geom_size[g].copy(), pos, quat, collides)
    mesh = m.geom_dataid[g]
    v0, nv = m.mesh_vertadr[mesh], m.mesh_vertnum[mesh]
    f0, nf = m.mesh_faceadr[mesh], m.mesh_facenum[mesh]
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, quat)
    # Mesh vertices are in the mesh frame; the geom pose puts that frame in the link frame.
    vertices = m.mesh_vert[v0 : v0 + nv] @ rot.reshape(3, 3).T + pos
    return Shape(
        kind, m.geom_size[g].copy(), pos, quat, collides, vertices, m.mesh_face[f0 : f0 + nf].copy()
    )
