"""The other team's analytic leg inverse kinematics.

Their own solver, in the style of champion walk engines: the target is rotated 45 degrees
about x so the tilted hip yaw-pitch axis becomes a vertical one, the law of cosines gives the
knee, the ankle pitch follows from the leg triangle and the ankle roll from the hip position
seen from the foot; the hip angles come out of the remaining rotation as z-x-y Euler angles.

Frames: the torso frame (x forward, y left, z up), metres, origin at the torso centre. A foot
pose is the ankle-roll joint point and the foot's orientation. Angles follow the simulator's
convention (radians, positive hip pitch swings the leg forward, negative knee bends it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.geometry import rot_x, rot_y, rot_z
from mimic.robot.description import body_by_name

__all__ = ["LegGeometry", "LEG", "rot_x", "rot_y", "rot_z", "leg_ik", "leg_fk", "SIDES"]

#: The two legs; +1 is the left (y > 0) and -1 the right.
SIDES = {"left": 1.0, "right": -1.0}


@dataclass(frozen=True)
class LegGeometry:
    """Link offsets of one leg, read once from the robot description (torso frame, zero pose)."""

    # Hip joints' common anchor of the left leg [m]; the right one mirrors y.
    hip_m: tuple[float, float, float]
    # Hip anchor to knee anchor (x, z) [m].
    thigh_m: tuple[float, float]
    # Knee anchor to ankle-pitch anchor (x, z) [m].
    shank_m: tuple[float, float]
    # Ankle-pitch anchor down to the ankle-roll anchor [m] (the two axes do not cross).
    ankle_drop_m: float
    # Ankle-roll anchor to the sole centre (x, z) [m].
    sole_m: tuple[float, float]

    @classmethod
    def from_description(cls) -> LegGeometry:
        hip = np.array(body_by_name("left_hip1").anchor)
        knee = np.array(body_by_name("left_shank").anchor)
        ankle = np.array(body_by_name("left_ankle").anchor)
        roll = np.array(body_by_name("left_foot").anchor)
        foot = body_by_name("left_foot")
        sole = np.array(foot.centre) - np.array([0.0, 0.0, foot.size[2] / 2])

        def pair(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
            return float(b[0] - a[0]), float(b[2] - a[2])

        return cls(
            tuple(float(v) for v in hip),
            pair(hip, knee),
            pair(knee, ankle),
            float(ankle[2] - roll[2]),
            pair(roll, sole),
        )

    def hip(self, side: float) -> np.ndarray:
        """(3,) hip anchor of a leg (``side`` +1 left, -1 right) [m]."""
        x, y, z = self.hip_m
        return np.array([x, side * abs(y), z])


LEG = LegGeometry.from_description()


def _hyp_frame(side: float) -> tuple[np.ndarray, float]:
    """Q = Rx(phi) turning the hip yaw-pitch axis into -z (left) or +z (right); the sign."""
    # Left axis (0, s, -s) = Rx(45 deg) (0, 0, -1); right axis (0, s, s) = Rx(-45 deg) (0, 0, 1).
    return (math.radians(45.0), -1.0) if side > 0 else (math.radians(-45.0), 1.0)


def leg_ik(
    side: float, ankle_m: np.ndarray, foot_rot: np.ndarray, geom: LegGeometry = LEG
) -> np.ndarray:
    """Joint angles of one leg putting its ankle-roll point and foot at a pose.

    Args:
        side: +1 left leg, -1 right leg.
        ankle_m: (3,) ankle-roll joint point in the torso frame [m].
        foot_rot: (3, 3) foot orientation in the torso frame.

    Returns:
        (6,) hip yaw-pitch, hip roll, hip pitch, knee, ankle pitch, ankle roll [rad]
        (unclipped; out-of-reach targets give a straight leg pointing at them).
    """
    hip = geom.hip(side)
    # Hip seen from the foot: ankle roll makes its y vanish (hip, knee and ankle share y).
    h_foot = foot_rot.T @ (hip - np.asarray(ankle_m, dtype=float))
    q6 = math.atan2(h_foot[1], h_foot[2])
    h_ankle = rot_x(q6) @ h_foot
    # Leg triangle in the pitch plane, measured from the ankle-pitch point.
    u = -(h_ankle - np.array([0.0, 0.0, geom.ankle_drop_m]))  # hip -> ankle pitch, ankle frame
    tx, tz = geom.thigh_m
    sx, sz = geom.shank_m
    l1, l2 = math.hypot(tx, tz), math.hypot(sx, sz)
    delta = math.atan2(tx, -tz) - math.atan2(sx, -sz)
    reach = float(np.hypot(u[0], u[2]))
    cos_k = (reach * reach - l1 * l1 - l2 * l2) / (2 * l1 * l2)
    q4 = delta - math.acos(max(-1.0, min(1.0, cos_k)))
    # w: hip -> ankle pitch in the thigh frame (x, z); pitch rotations are CCW in (x, z).
    ck, sk = math.cos(q4), math.sin(q4)
    wx = tx + ck * sx - sk * sz
    wz = tz + sk * sx + ck * sz
    q5 = math.atan2(wx, -wz) - math.atan2(u[0], -u[2]) - q4
    # Remaining rotation: R_hyp(q1) Rx(q2) Ry(-q3) = foot_rot Rx(-q6) Ry(q4 + q5).
    m = foot_rot @ rot_x(-q6) @ rot_y(q4 + q5)
    phi, sign = _hyp_frame(side)
    e = rot_x(-phi) @ m  # = Rz(sign q1) Rx(q2 - phi) Ry(-q3)
    beta = math.asin(max(-1.0, min(1.0, e[2, 1])))
    alpha = math.atan2(-e[0, 1], e[1, 1])
    gamma = math.atan2(-e[2, 0], e[2, 2])
    return np.array([sign * alpha, beta + phi, -gamma, q4, q5, q6])


def _axis_rot(axis: np.ndarray, a: float) -> np.ndarray:
    x, y, z = axis
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)


def leg_fk(side: float, q: np.ndarray, geom: LegGeometry = LEG) -> tuple[np.ndarray, np.ndarray]:
    """Ankle-roll point (3,) [m] and foot orientation (3, 3) in the torso frame for (6,) angles."""
    s = math.sqrt(0.5)
    axis = np.array([0.0, s, -s]) if side > 0 else np.array([0.0, s, s])
    r = _axis_rot(axis, q[0]) @ rot_x(q[1]) @ rot_y(-q[2])
    p = geom.hip(side) + r @ np.array([geom.thigh_m[0], 0.0, geom.thigh_m[1]])
    r = r @ rot_y(-q[3])
    p = p + r @ np.array([geom.shank_m[0], 0.0, geom.shank_m[1]])
    r = r @ rot_y(-q[4])
    p = p + r @ np.array([0.0, 0.0, -geom.ankle_drop_m])
    return p, r @ rot_x(q[5])
