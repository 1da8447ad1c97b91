"""The T1 team's leg kinematics: each leg's chain read from the robot description, a forward
model and a damped Newton inverse.

The T1's hip is not spherical (pitch, then roll 2 cm lower, then yaw 8 cm lower; the knee
sits 1.4 cm behind the yaw axis), so the team solves its legs numerically: a few Newton steps
on the foot's position and orientation error with the chain's geometric Jacobian, warm-started
from the last solution (one or two steps suffice at 50 Hz).

Frames: the torso (root link) frame, x forward, y left, z up, metres. A foot pose is its foot
link's origin (the ankle-roll joint) and orientation. Every offset, axis and joint comes from
the ``RobotDescription`` (links, parents, joint axes); joints sit at their link's origin, as
MJCF puts them by default.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.errors import MimicError
from mimic.geometry import rot_x, rot_y, rot_z
from mimic.robot.model import RobotDescription

__all__ = ["LegChain", "leg_chains", "rot_x", "rot_y", "rot_z", "rotation_log", "SIDES"]

#: The legs: +1 is the left (y > 0), -1 the right.
SIDES = {1.0: "left", -1.0: "right"}


def _axis_rot(axis: np.ndarray, a: float) -> np.ndarray:
    x, y, z = axis
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)


def _quat_matrix(q) -> np.ndarray:
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rotation_log(r: np.ndarray) -> np.ndarray:
    """(3,) rotation vector [rad] of a (3, 3) rotation matrix (angle below pi)."""
    cos = max(-1.0, min(1.0, (np.trace(r) - 1) / 2))
    angle = math.acos(cos)
    v = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if angle < 1e-9:
        return v / 2
    return v * (angle / (2 * math.sin(angle)))


@dataclass(frozen=True)
class _Link:
    """One link of a chain: offset and rotation in its parent at the zero pose, and the
    index (in the robot's joint order) and axis of the hinge that moves it, if any."""

    pos_m: np.ndarray
    rot: np.ndarray
    joint: int | None
    axis: np.ndarray | None


class LegChain:
    """One leg from the torso to its foot link: forward kinematics and a Newton inverse.

    Args:
        robot: the robot description.
        side: +1 left leg, -1 right leg.

    Attributes:
        joints: (6,) indices of the leg's hinges in the robot's joint order, hip to ankle.
        fixed: indices of hinges on the chain that the IK holds at their given angles (the
            T1's waist).
    """

    def __init__(self, robot: RobotDescription, side: float) -> None:
        self.side = side
        foot = robot.foot_links[0 if side > 0 else 1]
        by_name = {link.name: link for link in robot.links}
        by_child = {j.child_link: (i, j) for i, j in enumerate(robot.joints)}
        names, link = [], by_name[foot]
        while link.parent is not None:
            names.append(link.name)
            link = by_name[link.parent]
        links = []
        for name in reversed(names):
            spec = by_name[name]
            i, joint = by_child.get(name, (None, None))
            links.append(
                _Link(
                    np.array(spec.pos_m),
                    _quat_matrix(spec.quat_wxyz),
                    i,
                    None if joint is None else np.array(joint.axis),
                )
            )
        self._links = tuple(links)
        group = f"{SIDES[side]}_leg"
        self.joints = np.array(
            [
                lk.joint
                for lk in links
                if lk.joint is not None and robot.joints[lk.joint].group == group
            ]
        )
        self.fixed = np.array(
            [
                lk.joint
                for lk in links
                if lk.joint is not None and robot.joints[lk.joint].group != group
            ],
            dtype=np.int64,
        )
        if len(self.joints) != 6:
            raise MimicError(
                f"{robot.name}: the {SIDES[side]} leg has {len(self.joints)} "
                "hinges from torso to foot; the T1 team's IK needs 6"
            )
        self.lower_rad = robot.lower_limits_rad[self.joints]
        self.upper_rad = robot.upper_limits_rad[self.joints]

    def frames(self, q_rad: np.ndarray, fixed_rad: np.ndarray | None = None):
        """Foot pose and every hinge's (point, world axis) in the torso frame.

        Args:
            q_rad: (6,) leg angles [rad].
            fixed_rad: angles of the ``fixed`` hinges (default: zero).

        Returns:
            ((3,) foot position [m], (3, 3) foot rotation, (6, 3) hinge points [m],
            (6, 3) hinge axes).
        """
        p, r = np.zeros(3), np.eye(3)
        points, axes = [], []
        k_leg = k_fixed = 0
        for link in self._links:
            p = p + r @ link.pos_m
            r = r @ link.rot
            if link.joint is None:
                continue
            if k_leg < 6 and link.joint == self.joints[k_leg]:
                a, k_leg = q_rad[k_leg], k_leg + 1
                axis = r @ link.axis
                points.append(p)
                axes.append(axis)
            else:
                a = 0.0 if fixed_rad is None else fixed_rad[k_fixed]
                k_fixed += 1
            r = r @ _axis_rot(link.axis, a)
        return p, r, np.array(points), np.array(axes)

    def fk(self, q_rad: np.ndarray, fixed_rad: np.ndarray | None = None):
        """(3,) foot position [m] and (3, 3) foot rotation in the torso frame."""
        p, r, _, _ = self.frames(q_rad, fixed_rad)
        return p, r

    def ik(
        self,
        pos_m: np.ndarray,
        rot: np.ndarray,
        q0_rad: np.ndarray,
        *,
        fixed_rad: np.ndarray | None = None,
        iterations: int = 8,
        tolerance_m: float = 1e-5,
        damping: float = 1e-4,
    ) -> np.ndarray:
        """(6,) leg angles [rad] putting the foot at ``pos_m`` (3,) with rotation ``rot``.

        Damped Newton steps from ``q0_rad`` (the last solution), clipped to the joint stops;
        an unreachable target gives the closest pose found.
        """
        q = np.asarray(q0_rad, dtype=float).copy()
        for _ in range(iterations):
            p, r, points, axes = self.frames(q, fixed_rad)
            err = np.concatenate([pos_m - p, rotation_log(rot @ r.T)])
            if np.abs(err).max() < tolerance_m:
                break
            jac = np.vstack([np.cross(axes, p - points).T, axes.T])  # (6, 6)
            step = np.linalg.solve(jac.T @ jac + damping * np.eye(6), jac.T @ err)
            q = np.clip(q + step, self.lower_rad, self.upper_rad)
        return q


def leg_chains(robot: RobotDescription) -> dict[float, LegChain]:
    """Both legs' chains, keyed by side (+1 left, -1 right)."""
    return {side: LegChain(robot, side) for side in SIDES}
