"""Joint angles from the scene graph: a robot's pose read back through its kinematic tree.

The monitor stream shows every body of a robot as its transform relative to its parent body.
For a hinge joining a parent link and a child link, that relative rotation is
``R(q0) Rot(axis, angle)`` (``q0``: the child's orientation in its parent at the zero pose,
``axis`` in the child frame; both from the robot's description), so the joint angle is the
rotation left after undoing ``R(q0)``, measured about the axis. The torso's transform is its
pose in the field.

When: the server computes body poses before the last physics step of a cycle integrates the
joints, so a frame stamped t shows the robot as it was one physics step earlier (t - 5 ms;
the step is the league world's ``timestep``). ``PlayerSample.time_s`` is that instant, so each
sample's angles are the joints' state at its own time.

Which node is which body: a body node lists its shapes first, then its child bodies in the
MJCF's body order, so a link with k child links finds them in its node's last k children.
Every child body's offset from its parent is fixed by the robot's description (hinges do not
translate), which checks the match on every frame: a frame where the offsets disagree (the
one right after a robot was moved by the referee or a monitor command, whose other bodies
are still at their old place) is refused, not decoded wrongly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from mimic.league.errors import LeagueError
from mimic.league.field import league_air
from mimic.league.rsmp import SceneNode, SceneState, slt_matrix
from mimic.league.untrusted import printable
from mimic.robot.model import RobotDescription

__all__ = ["PlayerDecoder", "PlayerSample", "robot_for_model", "check_model", "OFFSET_TOLERANCE_M"]

#: How far a child body's decoded offset from its parent may be from the description's [m]
#: (the stream rounds to 0.1 mm).
OFFSET_TOLERANCE_M = 0.002


@dataclass(frozen=True)
class PlayerSample:
    """One robot's pose in one monitor frame (N joints, B links in the robot's order).

    Attributes:
        time_s: server time of the pose [s] (the frame's time stamp minus one physics step).
        joint_angles_rad: (N,) joint angles [rad].
        link_pos_m: (B, 3) each link's origin in its parent link (the root: in the field) [m].
        link_quat_wxyz: (B, 4) each link's orientation in its parent (the root: in the field).
    """

    time_s: float
    joint_angles_rad: np.ndarray
    link_pos_m: np.ndarray
    link_quat_wxyz: np.ndarray

    @property
    def torso_pos_m(self) -> np.ndarray:
        """(3,) root link origin in the field frame [m]."""
        return self.link_pos_m[0]

    @property
    def torso_quat_wxyz(self) -> np.ndarray:
        """(4,) root link orientation in the field frame."""
        return self.link_quat_wxyz[0]


def robot_for_model(model: str) -> str:
    """The registry name of a league robot model as the scene graph names it (``T1`` -> ``t1``)."""
    return model.lower()


def _quat(rot: np.ndarray) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(rot, dtype=float).ravel())
    return q


def _mat(q_wxyz) -> np.ndarray:
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, np.asarray(q_wxyz, dtype=float))
    return m.reshape(3, 3)


class PlayerDecoder:
    """Decodes one robot model's poses from scene-graph nodes.

    Args:
        robot: the robot's description (links in body order, joints with axes).
        pose_lag_s: how long before a frame's time stamp its poses were taken [s] (default:
            one physics step of the league world).
    """

    def __init__(self, robot: RobotDescription, pose_lag_s: float | None = None) -> None:
        self.robot = robot
        self.pose_lag_s = league_air().timestep_s if pose_lag_s is None else pose_lag_s
        links = robot.links
        index = {link.name: i for i, link in enumerate(links)}
        #: child link indices of each link, in body order
        self._children = [
            [j for j, c in enumerate(links) if c.parent == link.name] for link in links
        ]
        self._offsets = np.array([link.pos_m for link in links])
        #: per joint: child link index, R(q0)^T, axis, limits
        self._joint_link = np.array([index[j.child_link] for j in robot.joints])
        self._rest_inv = np.array(
            [_mat(links[index[j.child_link]].quat_wxyz).T for j in robot.joints]
        )
        self._axes = np.array([j.axis for j in robot.joints], dtype=float)

    def decode(self, dsc: SceneNode, time_s: float) -> PlayerSample | None:
        """The pose under an agent's DSC node in a frame stamped ``time_s`` [s]; None if the
        nodes do not fit the robot (the frame after a teleport)."""
        if len(dsc.children) != 1:
            return None
        nodes: list[SceneNode | None] = [None] * len(self.robot.links)
        nodes[0] = dsc.children[0]
        for i, kids in enumerate(self._children):
            node = nodes[i]
            if node is None or len(node.children) < len(kids):
                return None
            for child, sub in zip(kids, node.children[len(node.children) - len(kids) :]):
                nodes[child] = sub
        if any(n is None or n.slt is None for n in nodes):
            return None
        mats = np.array([slt_matrix(n.slt) for n in nodes])  # (B, 4, 4)
        if np.abs(mats[1:, :3, 3] - self._offsets[1:]).max(initial=0.0) > OFFSET_TOLERANCE_M:
            return None
        rots = mats[:, :3, :3]
        angles = self._angles(rots)
        quats = np.array([_quat(r) for r in rots])
        return PlayerSample(time_s - self.pose_lag_s, angles, mats[:, :3, 3].copy(), quats)

    def _angles(self, rots: np.ndarray) -> np.ndarray:
        r = np.einsum("nij,njk->nik", self._rest_inv, rots[self._joint_link])  # (N, 3, 3)
        a = self._axes
        vee = np.stack(
            [r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]], axis=1
        )
        sin = 0.5 * np.einsum("ni,ni->n", vee, a)
        cos = 0.5 * (np.trace(r, axis1=1, axis2=2) - np.einsum("ni,nij,nj->n", a, r, a))
        angles = np.arctan2(sin, cos)
        # Joints whose range reaches past +-pi (the T1's shoulder pitch, down to -3.31 rad):
        # the turn of 2 pi that lands nearer the range.
        lo, hi = self.robot.lower_limits_rad, self.robot.upper_limits_rad
        for shift in (-2 * math.pi, 2 * math.pi):
            moved = angles + shift
            better = _outside(moved, lo, hi) < _outside(angles, lo, hi)
            angles = np.where(better, moved, angles)
        return angles

    def sample(self, state: SceneState, team: str, player: int) -> PlayerSample | None:
        """The pose of ``team`` #``player`` in the current scene, or None (not on the field,
        or this frame does not decode)."""
        found = state.player(team, player)
        if found is None or not state.valid:
            return None
        return self.decode(state.node(found.path), state.time_s)


def _outside(angles, lo, hi) -> np.ndarray:
    return np.maximum(lo - angles, 0.0) + np.maximum(angles - hi, 0.0)


def check_model(robot: str, model: str, who: str) -> None:
    """Refuse, in one line, decoding a ``model`` robot (as the scene graph names it) as the
    registry's ``robot``."""
    if model and robot_for_model(model) != robot:
        shown = printable(model)
        raise LeagueError(
            f"{who} is a {shown} robot, not a {robot.upper()}; leave out "
            f"--robot (or pass --robot {robot_for_model(shown)})"
        )
