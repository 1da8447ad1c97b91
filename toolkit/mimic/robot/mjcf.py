"""MJCF (MuJoCo XML) for the robot, generated from the description and the joint table.

Joints are speed-controlled as in the simulator: each hinge has a velocity servo whose
command (rad/s) is capped at 6.1395 rad/s and whose torque is limited. Contact settings
follow MuJoCo's modelling advice for small legged robots: implicit integration (so the stiff
velocity servos are stable), elliptic friction cones, joint armature and a little damping.
"""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

from mimic.robot.actuators import SpeedServos
from mimic.robot.description import BODIES, Body
from mimic.robot.joints import JOINTS

__all__ = [
    "robot_worldbody_xml",
    "robot_actuator_xml",
    "robot_sensor_xml",
    "robot_default_xml",
    "FOOT_SITES",
    "IMU_SITE",
]

#: Sites under the soles carrying the foot-contact (touch) sensors, left then right.
FOOT_SITES = ("left_sole", "right_sole")
#: Site at the torso centre carrying the gyro, accelerometer and orientation sensors.
IMU_SITE = "imu"


def _f(values) -> str:
    return " ".join(f"{v:.6g}" for v in values)


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _geom_xml(body: Body) -> str:
    pos = _sub(body.centre, body.anchor)
    cls = "collide" if body.collides else "visual"
    if body.shape == "box":
        size = _f(s / 2 for s in body.size)
        return (
            f'<geom name="{body.name}" class="{cls}" type="box" size="{size}" '
            f'pos="{_f(pos)}" mass="{body.mass_kg}"/>'
        )
    if body.shape == "sphere":
        return (
            f'<geom name="{body.name}" class="{cls}" type="sphere" size="{body.size[0]}" '
            f'pos="{_f(pos)}" mass="{body.mass_kg}"/>'
        )
    radius, length = body.size
    return (
        f'<geom name="{body.name}" class="{cls}" type="capsule" size="{radius} {length / 2}" '
        f'pos="{_f(pos)}" mass="{body.mass_kg}"/>'
    )


def _body_xml(body: Body, children: dict[str, list[Body]], parent_anchor, indent: str) -> str:
    pos = _sub(body.anchor, parent_anchor)
    lines = [f'{indent}<body name="{body.name}" pos="{_f(pos)}">']
    inner = indent + "  "
    if body.joint is None:
        lines.append(f'{inner}<freejoint name="root"/>')
        lines.append(f'{inner}<site name="{IMU_SITE}" size="0.01"/>')
    else:
        joint = next(j for j in JOINTS if j.name == body.joint)
        lines.append(
            f'{inner}<joint name="{joint.name}" axis="{_f(body.axis)}" '
            f'range="{joint.lower_rad!r} {joint.upper_rad!r}"/>'
        )
    lines.append(inner + _geom_xml(body))
    if body.name.endswith("_foot"):
        side = body.name.removesuffix("_foot")
        sole = _sub(body.centre, body.anchor)
        sole = (sole[0], sole[1], sole[2] - body.size[2] / 2)
        lines.append(
            f'{inner}<site name="{side}_sole" type="box" pos="{_f(sole)}" '
            f'size="{_f((body.size[0] / 2, body.size[1] / 2, 0.005))}" rgba="0 0 0 0"/>'
        )
    for child in children.get(body.name, []):
        lines.append(_body_xml(child, children, body.anchor, inner))
    lines.append(f"{indent}</body>")
    return "\n".join(lines)


def robot_worldbody_xml(torso_pos_m=(0.0, 0.0, 0.385)) -> str:
    """The robot's body tree, rooted at a free-floating torso placed at ``torso_pos_m``."""
    children: dict[str, list[Body]] = {}
    for b in BODIES:
        if b.parent:
            children.setdefault(b.parent, []).append(b)
    torso = BODIES[0]
    xml = _body_xml(torso, children, (0.0, 0.0, 0.0), "    ")
    return xml.replace(
        f'<body name="torso" pos="{_f((0, 0, 0))}">',
        f'<body name="torso" pos="{_f(torso_pos_m)}">',
        1,
    )


def robot_default_xml(config: SpeedServos = SpeedServos()) -> str:
    """Default classes: joint settings and collide / visual geometry.

    Robot geoms have contype 2 and conaffinity 1, so they touch the world (conaffinity 3)
    but never each other: like the simulator, parts of one robot do not collide.
    """
    return f"""
    <default>
      <joint type="hinge" limited="true" armature="{config.armature_kg_m2}"
             damping="{config.damping_nm_s_rad}"/>
      <default class="collide">
        <geom contype="2" conaffinity="1" condim="3" friction="1.0 0.02 0.001"
              rgba="0.85 0.85 0.9 1" group="0"/>
      </default>
      <default class="visual">
        <geom contype="0" conaffinity="0" rgba="0.3 0.3 0.35 1" group="1"/>
      </default>
    </default>"""


def robot_actuator_xml(config: SpeedServos = SpeedServos()) -> str:
    """One velocity servo per joint, in joint-table order (actuator i drives JOINTS[i])."""
    v, t = config.max_speed_rad_s, config.max_torque_nm
    rows = [
        f"    <velocity name={quoteattr(j.name)} joint={quoteattr(j.name)} "
        f'kv="{config.kv_nm_s_rad}" ctrlrange="{-v} {v}" forcerange="{-t} {t}"/>'
        for j in JOINTS
    ]
    return "  <actuator>\n" + "\n".join(rows) + "\n  </actuator>"


def robot_sensor_xml() -> str:
    """IMU in the torso and a touch sensor under each sole."""
    rows = [
        f'    <gyro name="gyro" site="{IMU_SITE}"/>',
        f'    <accelerometer name="accelerometer" site="{IMU_SITE}"/>',
        f'    <framequat name="torso_quat" objtype="site" objname="{IMU_SITE}"/>',
        *[f'    <touch name="{site}_touch" site="{site}"/>' for site in FOOT_SITES],
    ]
    return "  <sensor>\n" + "\n".join(rows) + "\n  </sensor>"
