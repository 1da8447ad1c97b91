"""The robot (any robot: its link shapes from ``mimic.viz.bodies``), field, goals and ball in
Rerun's 3D view."""

from __future__ import annotations

import mujoco
import numpy as np
import rerun as rr

from mimic.robot.model import RobotDescription
from mimic.viz.bodies import Shape, link_bodies
from mimic.viz.paths import BALL, ROBOT, WORLD, time_column
from mimic.world import field as F

__all__ = ["log_field", "log_robot_geometry", "log_body_poses", "log_ball_shape", "log_ball_poses"]

_ROBOT_COLOUR = (210, 210, 225)
_JOINT_COLOUR = (70, 70, 80)


def log_field(rec: rr.RecordingStream) -> None:
    """Static field lines and goals in the ``world`` frame (x to the opponent goal, z up)."""
    rec.log(WORLD, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    hl, hw = F.FIELD_LENGTH_M / 2, F.FIELD_WIDTH_M / 2
    strips = [
        [[-hl, -hw, 0], [hl, -hw, 0], [hl, hw, 0], [-hl, hw, 0], [-hl, -hw, 0]],
        [[0, -hw, 0], [0, hw, 0]],
    ]
    angles = np.linspace(0, 2 * np.pi, 49)
    strips.append(
        np.c_[
            F.CENTRE_CIRCLE_RADIUS_M * np.cos(angles),
            F.CENTRE_CIRCLE_RADIUS_M * np.sin(angles),
            np.zeros_like(angles),
        ]
    )
    for sx in (1, -1):
        x_in, pw = sx * (hl - F.PENALTY_DEPTH_M), F.PENALTY_WIDTH_M / 2
        strips.append([[sx * hl, -pw, 0], [x_in, -pw, 0], [x_in, pw, 0], [sx * hl, pw, 0]])
    rec.log(f"{WORLD}/field/lines", rr.LineStrips3D(strips, colors=(255, 255, 255)), static=True)
    for name, sx in (("opponent_goal", 1), ("own_goal", -1)):
        centre = (sx * (hl + F.GOAL_DEPTH_M / 2), 0, F.GOAL_HEIGHT_M / 2)
        half = (F.GOAL_DEPTH_M / 2, F.GOAL_WIDTH_M / 2, F.GOAL_HEIGHT_M / 2)
        rec.log(
            f"{WORLD}/field/{name}",
            rr.Boxes3D(centers=[centre], half_sizes=[half], colors=(255, 230, 50)),
            static=True,
        )
    log_ball_shape(rec)


def log_ball_shape(rec: rr.RecordingStream, path: str = BALL) -> None:
    """The ball's static sphere at ``path`` (its pose is logged on the same path)."""
    rec.log(
        f"{path}/shape",
        rr.Ellipsoids3D(
            half_sizes=[[F.BALL_RADIUS_M] * 3], colors=(255, 128, 0), fill_mode="solid"
        ),
        static=True,
    )


def log_robot_geometry(
    rec: rr.RecordingStream, robot: str | RobotDescription, root: str = ROBOT
) -> None:
    """Static shapes of every link of ``robot``, each in its own link frame
    (``{root}/{link}/shape``, further shapes of one link ``shape_1``, ``shape_2``...)."""
    for body in link_bodies(robot):
        for k, shape in enumerate(body.shapes):
            rec.log(
                f"{root}/{body.name}/shape" + (f"_{k}" if k else ""), _archetype(shape), static=True
            )


def _archetype(shape: Shape):
    """The Rerun archetype drawing one link shape (in its link frame)."""
    colour = _ROBOT_COLOUR if shape.collides or shape.kind == "mesh" else _JOINT_COLOUR
    w, x, y, z = shape.quat_wxyz
    quat = [rr.Quaternion(xyzw=[x, y, z, w])]
    size = shape.size_m
    if shape.kind == "mesh":
        return rr.Mesh3D(
            vertex_positions=shape.vertices_m, triangle_indices=shape.faces, albedo_factor=colour
        )
    if shape.kind == "box":
        return rr.Boxes3D(
            centers=[shape.pos_m],
            half_sizes=[size],
            quaternions=quat,
            colors=colour,
            fill_mode="solid",
        )
    if shape.kind in ("sphere", "ellipsoid"):
        half = [size[0]] * 3 if shape.kind == "sphere" else size
        return rr.Ellipsoids3D(
            centers=[shape.pos_m],
            half_sizes=[half],
            quaternions=quat,
            colors=colour,
            fill_mode="solid",
        )
    radius, half_length = size[0], size[1]
    if shape.kind == "cylinder":
        return rr.Cylinders3D(
            lengths=[2 * half_length],
            radii=[radius],
            centers=[shape.pos_m],
            quaternions=quat,
            colors=colour,
            fill_mode="solid",
        )
    # A Rerun capsule starts at its translation and runs along its +z; MuJoCo's is centred.
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, shape.quat_wxyz)
    base = shape.pos_m - rot.reshape(3, 3)[:, 2] * half_length
    return rr.Capsules3D(
        lengths=[2 * half_length],
        radii=[radius],
        translations=[base],
        quaternions=quat,
        colors=colour,
    )


def log_body_poses(
    rec: rr.RecordingStream,
    times_s: np.ndarray,
    poses: dict[str, tuple[np.ndarray, np.ndarray]],
    root: str = ROBOT,
) -> None:
    """Link poses over time; ``poses[link] = (positions (T, 3) [m], quats_wxyz (T, 4))`` in the
    world frame, sampled at ``times_s`` (T,)."""
    for name, (pos, quat_wxyz) in poses.items():
        rec.send_columns(
            f"{root}/{name}",
            indexes=[time_column(times_s)],
            columns=rr.Transform3D.columns(
                translation=pos, quaternion=np.asarray(quat_wxyz)[:, [1, 2, 3, 0]]
            ),
        )


def log_ball_poses(
    rec: rr.RecordingStream, times_s: np.ndarray, positions_m: np.ndarray, path: str = BALL
) -> None:
    """Ball centre (N, 3) [m] over time."""
    rec.send_columns(
        path,
        indexes=[time_column(times_s)],
        columns=rr.Transform3D.columns(translation=positions_m),
    )
