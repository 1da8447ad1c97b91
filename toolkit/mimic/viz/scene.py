"""The robot, field, goals and ball in Rerun's 3D view."""

from __future__ import annotations

import numpy as np
import rerun as rr

from mimic.robot.description import BODIES
from mimic.viz.paths import BALL, ROBOT, WORLD, time_column
from mimic.world import field as F

__all__ = ["log_field", "log_robot_geometry", "log_body_poses", "log_ball_shape",
           "log_ball_poses"]

_ROBOT_COLOUR = (210, 210, 225)
_JOINT_COLOUR = (70, 70, 80)


def log_field(rec: rr.RecordingStream) -> None:
    """Static field lines and goals in the ``world`` frame (x to the opponent goal, z up)."""
    rec.log(WORLD, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    hl, hw = F.FIELD_LENGTH_M / 2, F.FIELD_WIDTH_M / 2
    strips = [[[-hl, -hw, 0], [hl, -hw, 0], [hl, hw, 0], [-hl, hw, 0], [-hl, -hw, 0]],
              [[0, -hw, 0], [0, hw, 0]]]
    angles = np.linspace(0, 2 * np.pi, 49)
    strips.append(np.c_[F.CENTRE_CIRCLE_RADIUS_M * np.cos(angles),
                        F.CENTRE_CIRCLE_RADIUS_M * np.sin(angles), np.zeros_like(angles)])
    for sx in (1, -1):
        x_in, pw = sx * (hl - F.PENALTY_DEPTH_M), F.PENALTY_WIDTH_M / 2
        strips.append([[sx * hl, -pw, 0], [x_in, -pw, 0], [x_in, pw, 0], [sx * hl, pw, 0]])
    rec.log(f"{WORLD}/field/lines", rr.LineStrips3D(strips, colors=(255, 255, 255)), static=True)
    for name, sx in (("opponent_goal", 1), ("own_goal", -1)):
        centre = (sx * (hl + F.GOAL_DEPTH_M / 2), 0, F.GOAL_HEIGHT_M / 2)
        half = (F.GOAL_DEPTH_M / 2, F.GOAL_WIDTH_M / 2, F.GOAL_HEIGHT_M / 2)
        rec.log(f"{WORLD}/field/{name}",
                rr.Boxes3D(centers=[centre], half_sizes=[half], colors=(255, 230, 50)),
                static=True)
    log_ball_shape(rec)


def log_ball_shape(rec: rr.RecordingStream, path: str = BALL) -> None:
    """The ball's static sphere at ``path`` (its pose is logged on the same path)."""
    rec.log(f"{path}/shape", rr.Ellipsoids3D(half_sizes=[[F.BALL_RADIUS_M] * 3],
                                             colors=(255, 128, 0), fill_mode="solid"),
            static=True)


def log_robot_geometry(rec: rr.RecordingStream, root: str = ROBOT) -> None:
    """Static primitive shapes of every body, each in its own body frame (at the joint anchor)."""
    for body in BODIES:
        offset = np.subtract(body.centre, body.anchor)
        path = f"{root}/{body.name}/shape"
        if body.shape == "box":
            shape = rr.Boxes3D(centers=[offset], half_sizes=[np.divide(body.size, 2)],
                               colors=_ROBOT_COLOUR, fill_mode="solid")
        elif body.shape == "sphere":
            shape = rr.Ellipsoids3D(centers=[offset], half_sizes=[[body.size[0]] * 3],
                                    colors=_ROBOT_COLOUR if body.collides else _JOINT_COLOUR,
                                    fill_mode="solid")
        else:
            radius, length = body.size
            shape = rr.Capsules3D(lengths=[length], radii=[radius],
                                  translations=[offset - (0, 0, length / 2)],
                                  colors=_ROBOT_COLOUR)
        rec.log(path, shape, static=True)


def log_body_poses(rec: rr.RecordingStream, times_s: np.ndarray,
                   poses: dict[str, tuple[np.ndarray, np.ndarray]], root: str = ROBOT) -> None:
    """Body poses over time; ``poses[body] = (positions (N, 3) [m], quats_wxyz (N, 4))`` in the
    world frame, sampled at ``times_s`` (N,)."""
    for body in BODIES:
        if body.name not in poses:
            continue
        pos, quat_wxyz = poses[body.name]
        rec.send_columns(f"{root}/{body.name}", indexes=[time_column(times_s)],
                         columns=rr.Transform3D.columns(
                             translation=pos, quaternion=np.asarray(quat_wxyz)[:, [1, 2, 3, 0]]))


def log_ball_poses(rec: rr.RecordingStream, times_s: np.ndarray, positions_m: np.ndarray,
                   path: str = BALL) -> None:
    """Ball centre (N, 3) [m] over time."""
    rec.send_columns(path, indexes=[time_column(times_s)],
                     columns=rr.Transform3D.columns(translation=positions_m))
