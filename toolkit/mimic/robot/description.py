"""The robot's bodies and hinge geometry, from the simulator's type-0 numbers.

One description feeds both the MJCF model and the URDF twin. All positions are in the
torso frame at the zero pose, MuJoCo convention: x forward, y left, z up, metres, origin
at the torso centre. (The simulator's RSG frame is X right, Y forward, Z up: x = Y, y = -X.)
"""

from __future__ import annotations

from dataclasses import dataclass

from mimic.robot.joints import JOINTS, Joint

__all__ = [
    "Body",
    "BODIES",
    "SOLE_HEIGHT_M",
    "TORSO_STAND_HEIGHT_M",
    "body_by_name",
    "joint_axis",
    "total_mass_kg",
]

#: Sole below the torso centre at the zero pose [m].
SOLE_HEIGHT_M = 0.385
#: Torso centre above the ground standing with straight legs [m].
TORSO_STAND_HEIGHT_M = SOLE_HEIGHT_M


@dataclass(frozen=True)
class Body:
    """A rigid body of the robot.

    Attributes:
        name: body name, also the TF child frame name.
        parent: parent body name (None for the torso, the free-floating root).
        joint: canonical name of the hinge joining it to its parent (None for the torso).
        anchor: (3,) joint anchor in the torso frame at zero pose [m]; the body frame origin.
        axis: (3,) hinge axis in the torso frame at zero pose (unit vector).
        shape: ``box``, ``sphere`` or ``capsule``.
        size: box (x, y, z) full lengths [m]; sphere (r,); capsule (r, length).
        centre: (3,) geometric and mass centre in the torso frame at zero pose [m].
        mass_kg: mass [kg].
        collides: whether its geometry takes part in contacts.
    """

    name: str
    parent: str | None
    joint: str | None
    anchor: tuple[float, float, float]
    axis: tuple[float, float, float]
    shape: str
    size: tuple[float, ...]
    centre: tuple[float, float, float]
    mass_kg: float
    collides: bool


def _rsg(x: float, y: float, z: float) -> tuple[float, float, float]:
    """Simulator RSG coordinates (X right, Y forward, Z up) to ours."""
    return (y, -x, z)


def _box(sx: float, sy: float, sz: float) -> tuple[float, float, float]:
    """Box full lengths given in RSG axes, reordered to ours."""
    return (sy, sx, sz)


# Axes in our frame. RSG X (right) becomes -y; RSG Y (forward) becomes x.
_PITCH = (0.0, -1.0, 0.0)  # RSG (1, 0, 0)
_ROLL = (1.0, 0.0, 0.0)  # RSG (0, 1, 0)
_YAW = (0.0, 0.0, 1.0)  # RSG (0, 0, 1)
_S = 0.7071067811865476


def _side_bodies(side: str, s: float) -> list[Body]:
    """Arm and leg bodies of one side; ``s`` is +1 for right (RSG +X) and -1 for left."""

    def p(x, y, z):
        return _rsg(s * x, y, z)

    hyp_axis = (0.0, _S, _S) if s > 0 else (0.0, _S, -_S)
    sh, el = p(0.098, 0, 0.075), p(0.098, 0.09, 0.084)
    hip, knee = p(0.055, -0.01, -0.115), p(0.055, -0.005, -0.235)
    ankle_p, ankle_r = p(0.055, -0.005, -0.335), p(0.055, -0.005, -0.34)
    n = f"{side}_"
    return [
        Body(
            n + "shoulder",
            "torso",
            n + "shoulder_pitch",
            sh,
            _PITCH,
            "sphere",
            (0.01,),
            sh,
            0.070,
            False,
        ),
        Body(
            n + "upper_arm",
            n + "shoulder",
            n + "shoulder_roll",
            sh,
            _YAW,
            "box",
            _box(0.07, 0.08, 0.06),
            p(0.108, 0.02, 0.075),
            0.150,
            True,
        ),
        Body(
            n + "elbow",
            n + "upper_arm",
            n + "elbow_yaw",
            el,
            _ROLL,
            "sphere",
            (0.01,),
            el,
            0.035,
            False,
        ),
        Body(
            n + "lower_arm",
            n + "elbow",
            n + "elbow_roll",
            el,
            _YAW,
            "box",
            _box(0.05, 0.11, 0.05),
            p(0.098, 0.14, 0.084),
            0.200,
            True,
        ),
        Body(
            n + "hip1",
            "torso",
            n + "hip_yaw_pitch",
            hip,
            hyp_axis,
            "sphere",
            (0.01,),
            hip,
            0.090,
            False,
        ),
        Body(
            n + "hip2", n + "hip1", n + "hip_roll", hip, _ROLL, "sphere", (0.01,), hip, 0.125, False
        ),
        Body(
            n + "thigh",
            n + "hip2",
            n + "hip_pitch",
            hip,
            _PITCH,
            "box",
            _box(0.07, 0.07, 0.14),
            p(0.055, 0.0, -0.155),
            0.275,
            True,
        ),
        Body(
            n + "shank",
            n + "thigh",
            n + "knee_pitch",
            knee,
            _PITCH,
            "box",
            _box(0.08, 0.07, 0.11),
            p(0.055, 0.005, -0.28),
            0.225,
            True,
        ),
        Body(
            n + "ankle",
            n + "shank",
            n + "ankle_pitch",
            ankle_p,
            _PITCH,
            "sphere",
            (0.01,),
            ankle_p,
            0.125,
            False,
        ),
        Body(
            n + "foot",
            n + "ankle",
            n + "ankle_roll",
            ankle_r,
            _ROLL,
            "box",
            _box(0.08, 0.16, 0.02),
            p(0.055, 0.025, -0.375),
            0.200,
            True,
        ),
    ]


#: Every body, parents before children.
BODIES: tuple[Body, ...] = (
    Body(
        "torso",
        None,
        None,
        (0, 0, 0),
        (0, 0, 1),
        "box",
        _box(0.10, 0.10, 0.18),
        (0, 0, 0),
        1.2171,
        True,
    ),
    Body(
        "neck",
        "torso",
        "head_yaw",
        (0, 0, 0.09),
        _YAW,
        "capsule",
        (0.015, 0.08),
        (0, 0, 0.09),
        0.050,
        True,
    ),
    Body(
        "head",
        "neck",
        "head_pitch",
        (0, 0, 0.15),
        _PITCH,
        "sphere",
        (0.065,),
        (0, 0, 0.155),
        0.350,
        True,
    ),
    *_side_bodies("left", -1.0),
    *_side_bodies("right", +1.0),
)

_BY_NAME = {b.name: b for b in BODIES}
_BY_JOINT = {b.joint: b for b in BODIES if b.joint}
assert set(_BY_JOINT) == {j.name for j in JOINTS}, "every joint moves exactly one body"


def body_by_name(name: str) -> Body:
    """The body called ``name``."""
    return _BY_NAME[name]


def joint_axis(joint: Joint) -> tuple[float, float, float]:
    """(3,) hinge axis of ``joint`` in the torso frame at zero pose."""
    return _BY_JOINT[joint.name].axis


def total_mass_kg() -> float:
    """Sum of all body masses [kg] (4.6071 for the simulator's robot)."""
    return sum(b.mass_kg for b in BODIES)
