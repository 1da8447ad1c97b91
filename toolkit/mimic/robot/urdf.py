"""The URDF twin of the robot, generated from the same description as the MJCF model.

Link names are the body names (``torso``, ``neck``, ``head``, ``left_shoulder``, ...), so TF
frames in recordings and links in the URDF match; joint names are the canonical joint names.
Every link frame sits at its hinge anchor with the torso's orientation at the zero pose (as in
the MJCF), so each joint origin is a pure translation. The root link is ``torso``; recordings
connect it to ``world`` through TF. URDF has no capsule: a capsule becomes a cylinder with a
sphere at each end (visual and collision), while its inertia is the exact capsule's.
"""

from __future__ import annotations

import math

from mimic.robot.actuators import SpeedServos
from mimic.robot.description import BODIES, Body
from mimic.robot.joints import JOINTS

__all__ = ["robot_urdf", "ROBOT_NAME", "shape_inertia"]

ROBOT_NAME = "mimic_nao"


def _f(values) -> str:
    return " ".join(f"{v:.6g}" for v in values)


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def shape_inertia(body: Body) -> tuple[float, float, float]:
    """(ixx, iyy, izz) [kg m^2] of a body's solid primitive about its centre, axis-aligned."""
    m = body.mass_kg
    if body.shape == "box":
        x, y, z = body.size
        return (m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12)
    if body.shape == "sphere":
        i = 0.4 * m * body.size[0] ** 2
        return (i, i, i)
    r, h = body.size  # capsule along z: cylinder of length h plus two hemispheres
    v_cyl, v_sph = math.pi * r * r * h, 4.0 / 3.0 * math.pi * r**3
    mc, ms = m * v_cyl / (v_cyl + v_sph), m * v_sph / (v_cyl + v_sph)
    izz = mc * r * r / 2 + ms * 0.4 * r * r
    ixx = mc * (r * r / 4 + h * h / 12) + ms * (0.4 * r * r + h * h / 4 + 3 * h * r / 8)
    return (ixx, ixx, izz)


def _geometry(body: Body, tag: str) -> list[str]:
    """<visual> or <collision> elements of a body (its frame origin is the joint anchor)."""
    c = _sub(body.centre, body.anchor)
    if body.shape == "box":
        shapes = [(c, f'<box size="{_f(body.size)}"/>')]
    elif body.shape == "sphere":
        shapes = [(c, f'<sphere radius="{body.size[0]:.6g}"/>')]
    else:
        r, h = body.size
        shapes = [
            (c, f'<cylinder radius="{r:.6g}" length="{h:.6g}"/>'),
            ((c[0], c[1], c[2] + h / 2), f'<sphere radius="{r:.6g}"/>'),
            ((c[0], c[1], c[2] - h / 2), f'<sphere radius="{r:.6g}"/>'),
        ]
    material = '<material name="grey"/>' if tag == "visual" else ""
    return [
        f'    <{tag}><origin xyz="{_f(pos)}" rpy="0 0 0"/><geometry>{geom}</geometry>'
        f"{material}</{tag}>"
        for pos, geom in shapes
    ]


def _link(body: Body) -> str:
    ixx, iyy, izz = shape_inertia(body)
    lines = [
        f'  <link name="{body.name}">',
        f'    <inertial><origin xyz="{_f(_sub(body.centre, body.anchor))}" rpy="0 0 0"/>'
        f'<mass value="{body.mass_kg:.6g}"/>'
        f'<inertia ixx="{ixx:.6g}" ixy="0" ixz="0" iyy="{iyy:.6g}" iyz="0" izz="{izz:.6g}"/>'
        f"</inertial>",
        *_geometry(body, "visual"),
    ]
    if body.collides:
        lines += _geometry(body, "collision")
    lines.append("  </link>")
    return "\n".join(lines)


def _joint(body: Body, actuator: SpeedServos) -> str:
    joint = next(j for j in JOINTS if j.name == body.joint)
    parent = next(b for b in BODIES if b.name == body.parent)
    return (
        f'  <joint name="{joint.name}" type="revolute">'
        f'<parent link="{parent.name}"/><child link="{body.name}"/>'
        f'<origin xyz="{_f(_sub(body.anchor, parent.anchor))}" rpy="0 0 0"/>'
        f'<axis xyz="{_f(body.axis)}"/>'
        f'<limit lower="{joint.lower_rad:.6f}" upper="{joint.upper_rad:.6f}" '
        f'effort="{actuator.max_torque_nm:g}" velocity="{actuator.max_speed_rad_s:g}"/>'
        f"</joint>"
    )


def robot_urdf(actuator: SpeedServos = SpeedServos()) -> str:
    """The robot as URDF text: 23 links (root ``torso``) and 22 revolute joints."""
    parts = [
        '<?xml version="1.0"?>',
        f'<robot name="{ROBOT_NAME}">',
        '  <material name="grey"><color rgba="0.75 0.75 0.8 1"/></material>',
    ]
    parts += [_link(b) for b in BODIES]
    parts += [_joint(b, actuator) for b in BODIES if b.joint is not None]
    parts.append("</robot>")
    return "\n".join(parts) + "\n"
