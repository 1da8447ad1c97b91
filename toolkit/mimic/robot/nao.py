"""Our NAO: the study simulator's robot (type 0) as a ``RobotDescription``.

Its numbers live in ``joints.py`` (the joint table) and ``description.py`` (bodies, anchors,
axes, masses); this module only assembles them. Every body frame has the torso's orientation
at the zero pose, so link origins are pure translations between hinge anchors.
"""

from __future__ import annotations

import math
from functools import cache

from mimic.robot.actuators import SpeedServos
from mimic.robot.description import BODIES
from mimic.robot.joints import JOINTS
from mimic.robot.model import FallThresholds, JointSpec, LinkSpec, RobotDescription
from mimic.robot.urdf import robot_urdf

__all__ = ["nao", "NAO_STAND_DEG"]

#: The ready pose [deg] by joint kind (left side; the right side mirrors it).
NAO_STAND_DEG = {
    "shoulder_pitch": -90.0,
    "shoulder_roll": 8.0,
    "hip_pitch": 19.0,
    "knee_pitch": -40.0,
    "ankle_pitch": 21.0,
}


def _stand_pose_rad() -> tuple[float, ...]:
    pose = []
    for j in JOINTS:
        kind = j.name.removeprefix("left_").removeprefix("right_")
        sign = j.mirror_sign if j.name.startswith("right_") else 1
        pose.append(math.radians(NAO_STAND_DEG.get(kind, 0.0)) * sign)
    return tuple(pose)


def _links() -> tuple[LinkSpec, ...]:
    anchors = {b.name: b.anchor for b in BODIES}
    return tuple(
        LinkSpec(
            b.name,
            b.parent,
            tuple(a - p for a, p in zip(b.anchor, anchors[b.parent]))
            if b.parent
            else (0.0, 0.0, 0.0),
            (1.0, 0.0, 0.0, 0.0),
            b.mass_kg,
        )
        for b in BODIES
    )


def _joints() -> tuple[JointSpec, ...]:
    body_of = {b.joint: b for b in BODIES if b.joint}
    return tuple(
        JointSpec(
            j.name,
            j.lower_rad,
            j.upper_rad,
            body_of[j.name].axis,
            body_of[j.name].parent,
            body_of[j.name].name,
            j.mirror,
            j.mirror_sign,
            j.group,
            (j.sim_name,),
        )
        for j in JOINTS
    )


@cache
def nao() -> RobotDescription:
    """The NAO of the study's simulator: 22 speed-servo hinges, 4.6 kg."""

    return RobotDescription(
        name="nao",
        title="NAO (SimSpark type 0, ours)",
        joints=_joints(),
        links=_links(),
        stand_pose_rad=_stand_pose_rad(),
        actuator=SpeedServos(),
        falls=FallThresholds(
            fallen_below_m=0.22,
            fallen_tilt_rad=math.radians(60),
            upright_above_m=0.28,
            upright_tilt_rad=math.radians(25),
        ),
        imu_site="imu",
        foot_links=("left_foot", "right_foot"),
        urdf=robot_urdf,
        world="nao",
    )
