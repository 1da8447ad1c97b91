"""Closed-form leg inverse kinematics (and the matching forward kinematics).

The leg chain, from the torso: hip yaw-pitch (axis tilted 45 deg in the y-z plane), hip roll
(x), hip pitch (-y), knee (-y), ankle pitch (-y), ankle roll (x). All geometry is read from
``mimic.robot.description``; the two 5 mm offsets (knee forward of the hip, ankle roll below
ankle pitch) are kept exactly:

* the knee offset lies in the sagittal plane of the thigh, so it only changes the law of
  cosines (an effective thigh length and a constant angle);
* the ankle-roll offset depends on the ankle roll angle itself, so the solve is repeated
  twice with the previous roll angle (the error shrinks by ~5 mm x angle^2 per pass).

The tilted hip yaw-pitch axis is absorbed as in the public NAO solvers: rotating the target by
45 deg about x turns the chain into a plain yaw-roll-pitch hip.

Frames: torso frame (x forward, y left, z up, origin at the torso centre). The foot frame is
the ``<side>_foot`` body frame: origin at the ankle-roll anchor, axes parallel to the torso's
at the zero pose. Angles follow the joint table (simulator convention), radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from math import acos, asin, atan2, cos, pi, sin, sqrt

import numpy as np

from mimic.robot.description import body_by_name
from mimic.robot.joints import joint_index, lower_limits_rad, upper_limits_rad

__all__ = [
    "LegGeometry",
    "leg_geometry",
    "leg_ik",
    "leg_ik_floats",
    "leg_fk",
    "leg_joint_indices",
    "sole_to_ankle",
    "rpy_matrix",
    "LEG_JOINTS",
]

#: Joint name suffixes of one leg, in chain (and joint table) order.
LEG_JOINTS = ("hip_yaw_pitch", "hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch", "ankle_roll")


def _rx(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def _axis_angle(axis: np.ndarray, a: float) -> np.ndarray:
    x, y, z = axis
    c, s, t = math.cos(a), math.sin(a), 1 - math.cos(a)
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
        ]
    )


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """(3, 3) rotation Rz(yaw) Ry(pitch) Rx(roll) [rad]."""
    return _rz(yaw) @ _ry(pitch) @ _rx(roll)


@dataclass(frozen=True)
class LegGeometry:
    """One leg's numbers, read from the body description (torso frame, metres)."""

    # +1 left, -1 right.
    side: int
    # (3,) hip anchor (hip yaw-pitch, roll and pitch axes meet here).
    hip: np.ndarray
    # (3,) hip yaw-pitch axis (unit).
    hyp_axis: np.ndarray
    # (3,) hip to knee at the zero pose (5 mm forward, 120 mm down).
    thigh: np.ndarray
    # (3,) knee to ankle pitch.
    shank: np.ndarray
    # (3,) ankle pitch to ankle roll (5 mm down).
    ankle: np.ndarray
    # (3,) ankle roll anchor to the sole centre, in the foot frame.
    sole: np.ndarray
    # Rotation about x [rad] that makes the yaw-pitch axis the hip's z axis (+-45 deg).
    sigma_rad: float
    # (6,) lower / upper joint limits [rad], chain order.
    lower_rad: np.ndarray
    upper_rad: np.ndarray

    # Derived numbers for the solver, as plain floats.
    def __post_init__(self) -> None:
        def put(name, value):
            object.__setattr__(self, name, value)

        put("hip_f", tuple(float(v) for v in self.hip))
        put("thigh_f", tuple(float(v) for v in self.thigh))
        put("shank_f", tuple(float(v) for v in self.shank))
        put("ankle_f", tuple(float(v) for v in self.ankle))
        put("lower_f", tuple(float(v) for v in self.lower_rad))
        put("upper_f", tuple(float(v) for v in self.upper_rad))
        put("l1", math.hypot(self.thigh[0], self.thigh[2]))
        put("l2", math.hypot(self.shank[0], self.shank[2]))
        put("beta", math.atan2(self.thigh[0], self.thigh[2]))
        put("gamma", math.atan2(self.shank[0], self.shank[2]))
        # The knee's law of cosines: the reach kept inside (|l1 - l2|, l1 + l2), the constant
        # terms, and the knee angle's offset from the two 5 mm offsets.
        l1, l2 = self.l1, self.l2
        put("reach_min_m", abs(l1 - l2) + 1e-3)
        put("reach_max_m", l1 + l2 - 1e-9)
        put("l_squares", l1 * l1 + l2 * l2)
        put("l_twice_product", 2 * l1 * l2)
        put("knee_offset_rad", self.gamma - self.beta)
        put("cos_sigma", math.cos(self.sigma_rad))
        put("sin_sigma", math.sin(self.sigma_rad))
        # +1 if the yaw-pitch axis is Rx(sigma) z, -1 if it is -Rx(sigma) z.
        put(
            "hyp_sign", 1.0 if float(np.dot(_rx(self.sigma_rad)[:, 2], self.hyp_axis)) > 0 else -1.0
        )


def _make_geometry(side: str) -> LegGeometry:
    b = {k: body_by_name(f"{side}_{k}") for k in ("hip1", "thigh", "shank", "ankle", "foot")}
    hip = np.array(b["hip1"].anchor)
    knee, ankle_p, ankle_r = (np.array(b[k].anchor) for k in ("shank", "ankle", "foot"))
    foot = b["foot"]
    sole = np.array(foot.centre) - ankle_r - np.array([0, 0, foot.size[2] / 2])
    axis = np.array(b["hip1"].axis)
    # axis = +-Rx(sigma) z with Rx(s) z = (0, -sin s, cos s); pick the sign giving |sigma| < 90.
    sigma = math.atan2(-axis[1], axis[2])
    if abs(sigma) > math.pi / 2:
        sigma = math.atan2(axis[1], -axis[2])
    idx = leg_joint_indices(side)
    return LegGeometry(
        side=1 if side == "left" else -1,
        hip=hip,
        hyp_axis=axis,
        thigh=knee - hip,
        shank=ankle_p - knee,
        ankle=ankle_r - ankle_p,
        sole=sole,
        sigma_rad=sigma,
        lower_rad=lower_limits_rad()[idx].copy(),
        upper_rad=upper_limits_rad()[idx].copy(),
    )


def leg_joint_indices(side: str) -> np.ndarray:
    """(6,) joint-table indices of one leg (``left`` or ``right``), chain order."""
    return np.array([joint_index(f"{side}_{j}") for j in LEG_JOINTS])


_GEOMETRY = {s: _make_geometry(s) for s in ("left", "right")}


def leg_geometry(side: str) -> LegGeometry:
    """Geometry of the ``left`` or ``right`` leg."""
    return _GEOMETRY[side]


def leg_fk(side: str, q_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Foot frame pose in the torso frame for the six leg angles (chain order) [rad].

    Returns:
        (position (3,) of the ankle-roll anchor [m], rotation (3, 3)).
    """
    g = _GEOMETRY[side]
    q = np.asarray(q_rad, dtype=float)
    r = _axis_angle(g.hyp_axis, q[0]) @ _rx(q[1]) @ _ry(-q[2])
    p = g.hip + r @ g.thigh
    r = r @ _ry(-q[3])
    p = p + r @ g.shank
    r = r @ _ry(-q[4])
    p = p + r @ g.ankle
    return p, r @ _rx(q[5])


def sole_to_ankle(side: str, sole_pos_m: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """(3,) ankle-roll anchor for a sole-centre position and foot rotation (torso frame)."""
    return np.asarray(sole_pos_m) - rot @ _GEOMETRY[side].sole


_TWO_PI = 2 * pi


def leg_ik(
    side: str,
    ankle_pos_m: np.ndarray,
    rot: np.ndarray | None = None,
    *,
    clip_to_limits: bool = True,
    passes: int = 3,
) -> np.ndarray:
    """Six leg angles [rad] (chain order) placing the foot frame at a pose.

    Args:
        side: ``left`` or ``right``.
        ankle_pos_m: (3,) ankle-roll anchor in the torso frame [m] (``sole_to_ankle`` converts
            a sole-centre target).
        rot: (3, 3) foot rotation in the torso frame (default: parallel to the torso).
        clip_to_limits: clip the result to the joint stops.
        passes: solves; each one refines the ankle-roll offset with the last roll angle.

    Out-of-reach targets are pulled back onto the reachable sphere around the hip (the foot
    keeps the requested direction), so the result is always finite.
    """
    g = _GEOMETRY[side]
    rot_l = _EYE if rot is None else np.asarray(rot, dtype=float).tolist()
    out = np.array(_solve_passes(g, [float(v) for v in ankle_pos_m], rot_l, passes))
    if clip_to_limits:
        np.clip(out, g.lower_rad, g.upper_rad, out=out)
    return out


def leg_ik_floats(side: str, ankle_xyz_m, rot_rows, passes: int = 3) -> list[float]:
    """``leg_ik`` (clipped to the joint stops) on plain floats, for a caller in a cycle's
    inner loop: the ankle-roll anchor as three floats [m], the foot rotation as three rows of
    three floats; the six angles [rad] come back as a list. Same arithmetic, same result."""
    g = _GEOMETRY[side]
    q1, q2, q3, q4, q5, q6 = _solve_passes(g, ankle_xyz_m, rot_rows, passes)
    (l1, l2, l3, l4, l5, l6), (u1, u2, u3, u4, u5, u6) = g.lower_f, g.upper_f
    # np.clip's numbers: ``clamp`` written out, angle by angle (a loop, let alone six calls,
    # costs more than the comparisons).
    q1 = l1 if l1 > q1 else q1
    q2 = l2 if l2 > q2 else q2
    q3 = l3 if l3 > q3 else q3
    q4 = l4 if l4 > q4 else q4
    q5 = l5 if l5 > q5 else q5
    q6 = l6 if l6 > q6 else q6
    return [
        u1 if u1 < q1 else q1,
        u2 if u2 < q2 else q2,
        u3 if u3 < q3 else q3,
        u4 if u4 < q4 else q4,
        u5 if u5 < q5 else q5,
        u6 if u6 < q6 else q6,
    ]


def _solve_passes(g: LegGeometry, ankle_xyz_m, rot_rows, passes: int) -> list[float]:
    """The unclipped angles after ``passes`` solves, each with the ankle-pitch anchor placed
    by the last pass's roll angle.

    Plain floats throughout (``rot_rows`` as nested lists or tuples): this runs for both legs
    every cycle. A pass before the last one only places the next pass's anchor, for which its
    roll angle is all that is needed: only the last pass solves the other five angles (the
    same numbers as solving each pass in full).
    """
    if passes < 1:
        return [0.0] * 6
    tx, ty, tz = ankle_xyz_m
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rot_rows
    hx, hy, hz = g.hip_f
    ax, az = g.ankle_f[0], g.ankle_f[2]  # ankle offset: (0, 0, -5 mm) at the zero pose
    q6 = 0.0
    for _ in range(passes):
        # Ankle-pitch anchor = ankle-roll anchor - rot Rx(-q6) (ankle offset), less the hip.
        c6, s6 = cos(q6), sin(q6)
        ox, oy, oz = ax, s6 * az, c6 * az
        vx = tx - (r00 * ox + r01 * oy + r02 * oz) - hx
        vy = ty - (r10 * ox + r11 * oy + r12 * oz) - hy
        vz = tz - (r20 * ox + r21 * oy + r22 * oz) - hz
        # The leg seen from the foot, r = rot^T v: its y/z ratio is the ankle roll, since
        # r = Rx(-q6) b with b in the foot's sagittal plane, pointing down (b_z < 0).
        ry = r01 * vx + r11 * vy + r21 * vz
        rz = r02 * vx + r12 * vy + r22 * vz
        q6 = atan2(-ry, -rz)
    rx = r00 * vx + r10 * vy + r20 * vz
    # Knee: |Ry(q4) thigh + shank|^2 = l1^2 + l2^2 + 2 l1 l2 cos(beta + q4 - gamma), the 5 mm
    # knee offset appearing as the constant angles beta, gamma; the knee bends with q4 < 0.
    # (``clamp`` and ``acos_domain`` written out, here and below: the same comparisons.)
    dist, shortest, longest = sqrt(vx * vx + vy * vy + vz * vz), g.reach_min_m, g.reach_max_m
    dist = shortest if shortest > dist else dist
    dist = longest if longest < dist else dist
    c = (g.l_squares - dist * dist) / g.l_twice_product
    c = c if c < 1.0 else 1.0
    c = c if c > -1.0 else -1.0
    q4 = (g.knee_offset_rad - (pi - acos(c)) + pi) % _TWO_PI - pi  # wrapped
    # In the foot's sagittal plane: p = Rx(q6) r = Ry(q5) m with m = Ry(q4) thigh + shank.
    c6, s6 = cos(q6), sin(q6)
    px, pz = rx, s6 * ry + c6 * rz
    tx, _, tz = g.thigh_f
    sx, _, sz = g.shank_f
    c4, s4 = cos(q4), sin(q4)
    mx = c4 * tx + s4 * tz + sx
    mz = -s4 * tx + c4 * tz + sz
    q5 = (atan2(px, pz) - atan2(mx, mz) + pi) % _TWO_PI - pi  # wrapped
    # Hip: M = Rx(-sigma) rot Rx(-q6) Ry(q4 + q5) = Rz(psi) Rx(phi) Ry(-q3).
    # Columns of B = Rx(-q6) Ry(a): needed rows of rot @ B, then Rx(-sigma).
    a = q4 + q5
    ca, sa = cos(a), sin(a)
    b0x, b0y, b0z = ca, -s6 * sa, -c6 * sa  # column 0 of Rx(-q6) Ry(a)
    b1x, b1y, b1z = 0.0, c6, -s6  # column 1
    b2x, b2y, b2z = sa, s6 * ca, c6 * ca  # column 2
    # Row i of rot dotted with column j of B (written out: this is the solver's inner loop).
    rot0_b1 = r00 * b1x + r01 * b1y + r02 * b1z
    rot1_b0 = r10 * b0x + r11 * b0y + r12 * b0z
    rot1_b1 = r10 * b1x + r11 * b1y + r12 * b1z
    rot1_b2 = r10 * b2x + r11 * b2y + r12 * b2z
    rot2_b0 = r20 * b0x + r21 * b0y + r22 * b0z
    rot2_b1 = r20 * b1x + r21 * b1y + r22 * b1z
    rot2_b2 = r20 * b2x + r21 * b2y + r22 * b2z
    cs, ss = g.cos_sigma, g.sin_sigma
    # Rows of Rx(-sigma): (1,0,0), (0, cs, ss), (0, -ss, cs).
    m01 = rot0_b1
    m11 = cs * rot1_b1 + ss * rot2_b1
    m20 = -ss * rot1_b0 + cs * rot2_b0
    m21 = -ss * rot1_b1 + cs * rot2_b1
    m22 = -ss * rot1_b2 + cs * rot2_b2
    m21 = m21 if m21 < 1.0 else 1.0
    m21 = m21 if m21 > -1.0 else -1.0
    phi = asin(m21)
    theta = atan2(-m20, m22)
    psi = atan2(-m01, m11)
    return [g.hyp_sign * psi, phi + g.sigma_rad, -theta, q4, q5, q6]


_EYE = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
