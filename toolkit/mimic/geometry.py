"""Rotation helpers: the one place that turns quaternions (w, x, y, z) into angles.

Frames: the field frame (x toward the opponent goal, y left, z up) and a body frame that
rotates with the torso. Signs, once for the whole toolkit: yaw is positive turning left
(counter-clockwise seen from above), pitch positive leaning forward, roll positive leaning
left.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "quat_mul",
    "rotate",
    "yaw_from_quat",
    "torso_pitch_roll",
    "forward_axis_z",
    "in_robot_frame",
    "one_hemisphere",
    "rot_x",
    "rot_y",
    "rot_z",
]


def _floats(q_wxyz):
    """A float64 array's numbers as Python floats (the same values and arithmetic, quicker
    one at a time than numpy's scalars); anything else as it is."""
    if isinstance(q_wxyz, np.ndarray) and q_wxyz.dtype == _FLOAT64:
        return q_wxyz.tolist()
    return q_wxyz


_FLOAT64 = np.dtype(np.float64)


def yaw_from_quat(q_wxyz) -> float:
    """Heading [rad] of the body x axis projected on the ground (0: along field x)."""
    w, x, y, z = _floats(q_wxyz)
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def forward_axis_z(q_wxyz):
    """z component [-1, 1] of the body's forward (x) axis in the field frame: negative when
    the torso faces the ground. One quaternion (4,): a float; (N, 4): (N,)."""
    q = np.asarray(q_wxyz, dtype=float)
    w, x, y, z = q.tolist() if q.ndim == 1 else np.moveaxis(q, -1, 0)
    return 2 * (x * z - w * y)


def torso_pitch_roll(q_wxyz, yaw_rad: float | None = None) -> tuple[float, float]:
    """Torso pitch (positive: leaning forward) and roll (positive: leaning left) [rad].

    Measured in the torso's heading frame, so they do not depend on where it faces.
    ``yaw_rad``: ``yaw_from_quat(q_wxyz)`` if the caller has it already.
    """
    q = _floats(q_wxyz)
    w, x, y, z = q
    # Torso z axis in the world (third column of the rotation matrix), then in the heading
    # frame.
    zx, zy, zz = 2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)
    yaw = yaw_from_quat(q) if yaw_rad is None else yaw_rad
    c, s = math.cos(yaw), math.sin(yaw)
    fwd, left = c * zx + s * zy, -s * zx + c * zy
    return math.atan2(fwd, zz), math.atan2(left, zz)


def in_robot_frame(xy_m, robot_xy_m, yaw_rad: float) -> np.ndarray:
    """(2,) field-frame point ``xy_m`` seen from a robot at ``robot_xy_m`` heading ``yaw_rad``:
    x forward, y left [m]."""
    dx, dy = np.asarray(xy_m, dtype=float)[:2] - np.asarray(robot_xy_m, dtype=float)[:2]
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    return np.array([c * dx + s * dy, -s * dx + c * dy])


def one_hemisphere(q_wxyz: np.ndarray) -> np.ndarray:
    """(N, 4) quaternions with each sign chosen to agree with the first (q and -q are one
    orientation), so a track of them can be interpolated or fitted component by component."""
    q = np.asarray(q_wxyz, dtype=float)
    return q * np.where(np.sum(q * q[:1], axis=1) < 0, -1.0, 1.0)[:, None]


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a * b of (N, 4) quaternions."""
    aw, ax, ay, az = a[:, 0], a[:, 1], a[:, 2], a[:, 3]
    bw, bx, by, bz = b[:, 0], b[:, 1], b[:, 2], b[:, 3]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[:, 0] = aw * bw - ax * bx - ay * by - az * bz
    out[:, 1] = aw * bx + ax * bw + ay * bz - az * by
    out[:, 2] = aw * by - ax * bz + ay * bw + az * bx
    out[:, 3] = aw * bz + ax * by - ay * bx + az * bw
    return out


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    out = np.empty(np.broadcast_shapes(u.shape, v.shape))
    out[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    out[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    out[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return out


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate (N, 3) vectors by (N, 4) unit quaternions."""
    w, u = q[:, :1], q[:, 1:]
    t = 2.0 * _cross(u, v)
    return v + w * t + _cross(u, t)


def rot_x(a: float) -> np.ndarray:
    """3x3 rotation by ``a`` [rad] about x (right-handed: y turns toward z)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    """3x3 rotation by ``a`` [rad] about y (right-handed: z turns toward x)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    """3x3 rotation by ``a`` [rad] about z (right-handed: x turns toward y)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
