"""The MuJoCo scene: field with lines, two goals, the ball and the robot.

Our NAO's robot part is generated from its description (``robot/mjcf.py``); a robot that
comes as an MJCF file (the league's T1 and K1) is attached to the same field
(``world/attach.py``). Either way the model has, for every joint, one actuator named after
the joint, and the sensors ``gyro``, ``accelerometer``, ``torso_quat`` (at the robot's IMU site)
and a touch sensor under each sole (``FOOT_TOUCH_SENSORS``).

The field's lines, goals and ball come from a ``Field`` (the study's ``NAO_FIELD`` by
default; the league's for league robots, ``field_for_robot``). Our own ball has condim 6
(sliding, torsional and rolling friction) so a kicked ball slows down and stops like on grass
instead of rolling forever; a field that states its ball's and ground's contact parameters
(the league's) gets those, and the league's air (``PhysicsConfig.for_robot``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco

from mimic.robot.actuators import SpeedServos
from mimic.robot.mjcf import (
    FOOT_SITES,
    robot_actuator_xml,
    robot_default_xml,
    robot_sensor_xml,
    robot_worldbody_xml,
)
from mimic.robot.model import RobotDescription
from mimic.world.field import NAO_FIELD, Contact, Field, field_for_robot

__all__ = ["PhysicsConfig", "scene_xml", "build_model", "FOOT_TOUCH_SENSORS"]

#: Touch sensors under the left and right sole, in every scene.
FOOT_TOUCH_SENSORS = tuple(f"{site}_touch" for site in FOOT_SITES)


@dataclass(frozen=True)
class PhysicsConfig:
    """Simulation settings."""

    # Physics step [s]; the 20 ms agent cycle is a whole number of these.
    timestep_s: float = 0.004
    # Ball rolling friction [m]: rolling resistance torque = this * normal force.
    ball_rolling_friction_m: float = 0.0025
    # Ball torsional friction [m].
    ball_torsional_friction_m: float = 0.005
    # Sliding friction of feet and body on the grass.
    ground_friction: float = 1.0
    # Air density [kg/m^3] and viscosity [Pa s] (MuJoCo's fluid forces; 0: no air).
    air_density_kg_m3: float = 0.0
    air_viscosity_pa_s: float = 0.0

    @classmethod
    def for_robot(cls, robot: RobotDescription) -> PhysicsConfig:
        """The settings a robot is simulated with: the study's 4 ms step for our NAO, the
        league server's step and air for robots loaded from its MJCF files (read from
        RCSSServerMJ's soccer world for robots of the ``league`` world)."""
        if robot.mjcf_path is None:
            return cls()
        if robot.world != "league":
            return cls(timestep_s=0.005)
        from mimic.league.field import league_air

        air = league_air()
        return cls(
            timestep_s=air.timestep_s,
            air_density_kg_m3=air.density_kg_m3,
            air_viscosity_pa_s=air.viscosity_pa_s,
        )


def _field_lines_xml(f: Field) -> str:
    """Thin, non-colliding boxes just above the grass."""
    half_l, half_w, w = f.length_m / 2, f.width_m / 2, f.line_width_m / 2
    boxes = [
        (0, half_w, half_l, w),
        (0, -half_w, half_l, w),  # touch lines
        (half_l, 0, w, half_w),
        (-half_l, 0, w, half_w),
        (0, 0, w, half_w),  # goal + halfway
    ]
    for sx in (1, -1):  # penalty areas
        x_in = sx * (half_l - f.penalty_depth_m)
        boxes.append((x_in, 0, w, f.penalty_width_m / 2))
        for sy in (1, -1):
            boxes.append(
                (
                    sx * (half_l - f.penalty_depth_m / 2),
                    sy * f.penalty_width_m / 2,
                    f.penalty_depth_m / 2,
                    w,
                )
            )
    rows = [
        f'<geom class="line" pos="{x} {y} 0.001" size="{sx} {sy} 0.001"/>' for x, y, sx, sy in boxes
    ]
    n, radius = 24, f.centre_circle_radius_m
    for k in range(n):  # centre circle as short segments
        a = 2 * math.pi * (k + 0.5) / n
        seg = radius * math.sin(math.pi / n)
        rows.append(
            f'<geom class="line" pos="{radius * math.cos(a):.4f} '
            f'{radius * math.sin(a):.4f} 0.001" size="{w} {seg:.4f} 0.001" '
            f'euler="0 0 {a:.4f}"/>'
        )
    return "\n    ".join(rows)


def _goal_xml(f: Field, name: str, sign: int) -> str:
    """Posts, crossbar and a back net; ``sign`` +1 for the opponent goal at +x."""
    x = sign * f.length_m / 2
    half_w, h, d, r = f.goal_width_m / 2, f.goal_height_m, f.goal_depth_m, f.goal_post_radius_m
    back = x + sign * d
    return f"""
    <body name="{name}" pos="0 0 0">
      <geom class="goal" type="cylinder" pos="{x} {half_w + r} {h / 2}" size="{r} {h / 2}"/>
      <geom class="goal" type="cylinder" pos="{x} {-half_w - r} {h / 2}" size="{r} {h / 2}"/>
      <geom class="goal" type="box" pos="{x} 0 {h + r}" size="{r} {half_w + 2 * r} {r}"/>
      <geom class="net" type="box" pos="{back} 0 {h / 2}" size="0.01 {half_w} {h / 2}"/>
      <geom class="net" type="box" pos="{x + sign * d / 2} {half_w + r} {h / 2}"
            size="{d / 2} 0.01 {h / 2}"/>
      <geom class="net" type="box" pos="{x + sign * d / 2} {-half_w - r} {h / 2}"
            size="{d / 2} 0.01 {h / 2}"/>
    </body>"""


def build_model(
    robot: RobotDescription, physics: PhysicsConfig, field: Field | None = None
) -> mujoco.MjModel:
    """The compiled scene with ``robot`` in it, on ``field`` (default: the robot's,
    ``field_for_robot``)."""
    field = field or field_for_robot(robot.world)
    if robot.mjcf_path is None:
        return mujoco.MjModel.from_xml_string(scene_xml(physics, robot.actuator, field))
    from mimic.world.attach import attached_robot_model

    return attached_robot_model(robot, physics, field)


def _contact_xml(c: Contact) -> str:
    """A geom's contact attributes."""
    friction = " ".join(f"{v:g}" for v in c.friction)
    solref = " ".join(f"{v:g}" for v in c.solref)
    priority = f' priority="{c.priority}"' if c.priority else ""
    return f'friction="{friction}" condim="{c.condim}" solref="{solref}"{priority}'


def _air_xml(config: PhysicsConfig) -> str:
    if not (config.air_density_kg_m3 or config.air_viscosity_pa_s):
        return ""
    return f' density="{config.air_density_kg_m3:g}" viscosity="{config.air_viscosity_pa_s:g}"'


def scene_xml(
    config: PhysicsConfig = PhysicsConfig(),
    servos: SpeedServos | None = SpeedServos(),
    field: Field = NAO_FIELD,
) -> str:
    """The whole world as one MJCF document, with our NAO (or, for ``servos=None``, without
    a robot: the field a robot from an MJCF file is attached to), on ``field``."""
    f = field
    half_l, half_w = f.length_m / 2 + 2, f.width_m / 2 + 2
    b = config
    ground = (
        _contact_xml(f.ground_contact)
        if f.ground_contact
        else f'friction="{b.ground_friction} 0.02 0.001" condim="3"'
    )
    touches = 'contype="1" conaffinity="3"'
    ball = (
        f"{touches} {_contact_xml(f.ball_contact)}"
        if f.ball_contact
        else f'condim="6" {touches} friction="0.8 {b.ball_torsional_friction_m} '
        f'{b.ball_rolling_friction_m}"\n            solref="0.005 0.6"'
    )
    return f"""<mujoco model="mimic_soccer">
  <compiler angle="radian" autolimits="true"/>
  <!-- impratio stays at 1: a high ratio made 4 ms steps unstable with the stiff servos. -->
  <option timestep="{b.timestep_s}" integrator="implicitfast" cone="elliptic"{_air_xml(b)}
          iterations="20" ls_iterations="10">
    <flag eulerdamp="disable"/>
  </option>
  <size memory="8M"/>
  <visual>
    <global offwidth="1280" offheight="720"/>
  </visual>
  <asset>
    <texture name="grass" type="2d" builtin="checker" rgb1="0.2 0.5 0.2" rgb2="0.22 0.52 0.22"
             width="256" height="256"/>
    <material name="grass" texture="grass" texrepeat="30 20"/>
  </asset>
  {robot_default_xml(servos) if servos else ""}
  <default>
    <default class="line">
      <geom type="box" contype="0" conaffinity="0" rgba="1 1 1 1" group="2"/>
    </default>
    <default class="goal">
      <geom contype="1" conaffinity="3" rgba="1 1 0.2 1" group="2"/>
    </default>
    <default class="net">
      <geom contype="1" conaffinity="3" rgba="0.9 0.9 0.9 0.3" group="2"/>
    </default>
  </default>
  <worldbody>
    <light pos="0 0 10" dir="0 0 -1" directional="true"/>
    <geom name="ground" type="plane" size="{half_l} {half_w} 0.1" material="grass"
          {ground} contype="1" conaffinity="3"/>
    {_field_lines_xml(f)}
    {_goal_xml(f, "opponent_goal", +1)}
    {_goal_xml(f, "own_goal", -1)}
    <body name="ball" pos="0 0 {f.ball_radius_m}">
      <freejoint name="ball"/>
      <geom name="ball" type="sphere" size="{f.ball_radius_m}" mass="{f.ball_mass_kg}"
            {ball} rgba="1 0.5 0 1"/>
    </body>
{robot_worldbody_xml() if servos else ""}
  </worldbody>
{robot_actuator_xml(servos) if servos else ""}
{robot_sensor_xml() if servos else ""}
</mujoco>
"""
