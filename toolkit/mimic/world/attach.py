"""A robot from an MJCF file (the league's T1 and K1) on our field.

A field, its goals and ball (``scene_xml`` without a robot; the league's for league robots)
with the robot's MJCF attached by ``mujoco.MjSpec``: its root body with its free joint, its
defaults, contact excludes and geoms as they are (they collide with the ground, the ball and
each other, as in the league). What we change, and why:

* The league's ``<name>_tau``, ``_pos`` and ``_vel`` actuators go; one position actuator per
  joint, named exactly as the joint, takes their place: kp = the robot's kp, kv = its kd,
  force range = its torque limit. MuJoCo's position actuator with kv applies
  kp (q_ref - q) - kv dq, the league's law kp (q - q_cur) + kd (dq - dq_cur) + tau with
  dq = 0 and tau = 0; its kv term is integrated implicitly, so stiff gains stay stable.
* The robot's own sensors go (their names clash with ours); ours are added: ``gyro``,
  ``accelerometer`` and ``torso_quat`` at the robot's IMU site, and a touch sensor under each
  sole (``FOOT_TOUCH_SENSORS``) on a thin box site spanning the sole.
* Mesh files get absolute paths: an attached spec's mesh directory is not its file's.
"""

from __future__ import annotations

from pathlib import Path

import mujoco

from mimic.robot.actuators import PDMotors
from mimic.robot.mjcf import FOOT_SITES
from mimic.robot.mjcf_reader import sole_box
from mimic.robot.model import RobotDescription
from mimic.world.field import Field, field_for_robot
from mimic.world.scene import PhysicsConfig, scene_xml

__all__ = ["attached_robot_model", "SOLE_SITE_MARGIN_M", "SOLE_SITE_HALF_HEIGHT_M"]

#: The touch site overhangs the sole by this much on each side [m], so contacts at the
#: sole's edges count.
SOLE_SITE_MARGIN_M = 0.005
#: Half height of the touch site, centred on the sole plane [m]: contact points lie within a
#: few millimetres of it (half the penetration depth).
SOLE_SITE_HALF_HEIGHT_M = 0.01


def _mesh_paths_absolute(part: mujoco.MjSpec, mjcf_path: Path) -> None:
    folder = mjcf_path.parent / (part.meshdir or "")
    for mesh in part.meshes:
        if mesh.file and not Path(mesh.file).is_absolute():
            mesh.file = str(folder / mesh.file)
    part.meshdir = ""


def _add_sole_sites(part: mujoco.MjSpec, robot: RobotDescription) -> None:
    for site_name, foot in zip(FOOT_SITES, robot.foot_links):
        (x, y, z), (hx, hy) = sole_box(robot.mjcf_path, foot)
        part.body(foot).add_site(
            name=site_name,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=[x, y, z],
            size=[hx + SOLE_SITE_MARGIN_M, hy + SOLE_SITE_MARGIN_M, SOLE_SITE_HALF_HEIGHT_M],
            group=3,
        )


def _add_motors(spec: mujoco.MjSpec, robot: RobotDescription) -> None:
    motors = robot.actuator
    if not isinstance(motors, PDMotors):
        raise TypeError(f"{robot.name}: a robot from an MJCF file has PD motors")
    for i, joint in enumerate(robot.joint_names):
        act = spec.add_actuator(name=joint, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.set_to_position(kp=float(motors.kp_nm_rad[i]), kv=float(motors.kd_nm_s_rad[i]))
        t = float(motors.max_torque_nm[i])
        act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        act.forcerange = [-t, t]


def _add_sensors(spec: mujoco.MjSpec, robot: RobotDescription) -> None:
    S, site = mujoco.mjtSensor, mujoco.mjtObj.mjOBJ_SITE
    for name, kind, obj in [
        ("gyro", S.mjSENS_GYRO, robot.imu_site),
        ("accelerometer", S.mjSENS_ACCELEROMETER, robot.imu_site),
        ("torso_quat", S.mjSENS_FRAMEQUAT, robot.imu_site),
        *[(f"{s}_touch", S.mjSENS_TOUCH, s) for s in FOOT_SITES],
    ]:
        spec.add_sensor(name=name, type=kind, objtype=site, objname=obj)


def attached_robot_model(
    robot: RobotDescription, physics: PhysicsConfig, field: Field | None = None
) -> mujoco.MjModel:
    """The compiled scene: ``field`` (default: the robot's, ``field_for_robot``) and its
    ball with ``robot`` (which has ``mjcf_path``)."""
    field = field or field_for_robot(robot.world)
    spec = mujoco.MjSpec.from_string(scene_xml(physics, servos=None, field=field))
    part = mujoco.MjSpec.from_file(str(robot.mjcf_path))
    _mesh_paths_absolute(part, robot.mjcf_path)
    for element in [*part.actuators, *part.sensors]:
        part.delete(element)
    _add_sole_sites(part, robot)
    # No prefix: joints, bodies and sites keep the names the description uses.
    spec.worldbody.add_frame().attach_body(part.body(robot.root_link), "", "")
    _add_motors(spec, robot)
    _add_sensors(spec, robot)
    return spec.compile()
