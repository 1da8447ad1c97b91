"""The URDF twin of a robot that comes as an MJCF file, written to ``/robot_description``.

Links are the MJCF bodies (same names, so TF frames match), joints its hinges (same names,
axes in the child frame, limits and torque limits). Inertials are the MJCF's. The shapes
are the collision geometry: boxes, spheres and cylinders as they are; a capsule becomes a
cylinder with a sphere at each end (URDF has no capsule); a mesh collision geom becomes its
bounding box, so the twin needs no mesh files and reads anywhere. The root link is the MJCF's
free-floating root; recordings connect it to ``world`` through TF.
"""

from __future__ import annotations

import math
from pathlib import Path
from xml.sax.saxutils import quoteattr

import mujoco
import numpy as np

from mimic.errors import MimicError
from mimic.robot.mjcf_reader import collision_geoms, load_model, read_mjcf

__all__ = ["mjcf_urdf", "rpy_from_quat"]

#: The MJCF states no joint speed limit, URDF requires one [rad/s]; this is above any Booster
#: joint motor's rated speed, so it limits nothing.
_UNSTATED_SPEED_RAD_S = 20.0


def _f(values) -> str:
    return " ".join(f"{float(v):.6g}" for v in values)


def rpy_from_quat(q_wxyz) -> tuple[float, float, float]:
    """URDF roll, pitch, yaw [rad] (fixed axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll))."""
    w, x, y, z = (float(v) for v in q_wxyz)
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def _origin(pos, quat) -> str:
    return f'<origin xyz="{_f(pos)}" rpy="{_f(rpy_from_quat(quat))}"/>'


def _rotate(quat, v) -> np.ndarray:
    out = np.zeros(3)
    mujoco.mju_rotVecQuat(out, np.asarray(v, dtype=float), np.asarray(quat, dtype=float))
    return out


def _shapes(m: mujoco.MjModel, g: int) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """(pos, quat, <geometry> element) in the body frame for one collision geom."""
    pos, quat, size, kind = m.geom_pos[g], m.geom_quat[g], m.geom_size[g], m.geom_type[g]
    T = mujoco.mjtGeom
    if kind == T.mjGEOM_BOX:
        return [(pos, quat, f'<box size="{_f(2 * size)}"/>')]
    if kind == T.mjGEOM_SPHERE:
        return [(pos, quat, f'<sphere radius="{size[0]:.6g}"/>')]
    if kind in (T.mjGEOM_CYLINDER, T.mjGEOM_CAPSULE):
        r, half = size[0], size[1]
        shapes = [(pos, quat, f'<cylinder radius="{r:.6g}" length="{2 * half:.6g}"/>')]
        if kind == T.mjGEOM_CAPSULE:
            end = _rotate(quat, (0, 0, half))
            shapes += [(pos + s * end, quat, f'<sphere radius="{r:.6g}"/>') for s in (1, -1)]
        return shapes
    if kind == T.mjGEOM_MESH:  # its bounding box, in the geom frame
        centre, half = m.geom_aabb[g, :3], m.geom_aabb[g, 3:]
        return [(pos + _rotate(quat, centre), quat, f'<box size="{_f(2 * half)}"/>')]
    return []  # planes, ellipsoids, height fields: not on these robots


def _link(m: mujoco.MjModel, b: int) -> str:
    ixx, iyy, izz = m.body_inertia[b]
    lines = [
        f"  <link name={quoteattr(m.body(b).name)}>",
        f"    <inertial>{_origin(m.body_ipos[b], m.body_iquat[b])}"
        f'<mass value="{m.body_mass[b]:.6g}"/>'
        f'<inertia ixx="{ixx:.6g}" ixy="0" ixz="0" iyy="{iyy:.6g}" iyz="0" '
        f'izz="{izz:.6g}"/></inertial>',
    ]
    for g in collision_geoms(m, b):
        for pos, quat, geometry in _shapes(m, g):
            for tag in ("visual", "collision"):
                material = '<material name="grey"/>' if tag == "visual" else ""
                lines.append(
                    f"    <{tag}>{_origin(pos, quat)}<geometry>{geometry}</geometry>"
                    f"{material}</{tag}>"
                )
    lines.append("  </link>")
    return "\n".join(lines)


def _joint(m: mujoco.MjModel, b: int) -> str:
    parent, child = m.body(m.body_parentid[b]).name, m.body(b).name
    origin = _origin(m.body_pos[b], m.body_quat[b])
    if m.body_jntnum[b] == 0:  # welded to its parent
        return (
            f'  <joint name={quoteattr(child + "_fixed")} type="fixed"><parent '
            f"link={quoteattr(parent)}/><child link={quoteattr(child)}/>{origin}</joint>"
        )
    j = m.body_jntadr[b]
    if (
        m.body_jntnum[b] > 1
        or m.jnt_type[j] != mujoco.mjtJoint.mjJNT_HINGE
        or np.any(m.jnt_pos[j] != 0)
    ):
        raise MimicError(f"body {child}: only one hinge at the body origin has a URDF twin")
    lower, upper = m.jnt_range[j]
    return (
        f'  <joint name={quoteattr(m.joint(j).name)} type="revolute">'
        f"<parent link={quoteattr(parent)}/><child link={quoteattr(child)}/>{origin}"
        f'<axis xyz="{_f(m.jnt_axis[j])}"/>'
        f'<limit lower="{lower:.6f}" upper="{upper:.6f}" '
        f'effort="{m.jnt_actfrcrange[j, 1]:g}" velocity="{_UNSTATED_SPEED_RAD_S:g}"/>'
        f"</joint>"
    )


def mjcf_urdf(path: Path, robot_name: str) -> str:
    """URDF text of the robot in the MJCF file ``path`` (root: its free-floating body)."""
    read_mjcf(path)  # checks it is one robot with one root
    m = load_model(path)
    parts = [
        '<?xml version="1.0"?>',
        f"<robot name={quoteattr(robot_name)}>",
        '  <material name="grey"><color rgba="0.75 0.75 0.8 1"/></material>',
    ]
    parts += [_link(m, b) for b in range(1, m.nbody)]
    parts += [_joint(m, b) for b in range(1, m.nbody) if m.body_parentid[b] != 0]
    parts.append("</robot>")
    return "\n".join(parts) + "\n"
