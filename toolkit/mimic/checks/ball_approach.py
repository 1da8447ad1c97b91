"""Physical check of the kick trial's walk to the ball: go-to-pose behind the ball, in our world.

Used by ``tests/test_walk.py``, ``benchmarks/goto_ball.py`` and ``benchmarks/walk_speed.py``.
A walk is chaotic: a change in the last digit of the arithmetic (another CPU, another libm)
changes which step lands where, so the check runs from several starts and reports each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.walk.engine import WalkEngine
from mimic.agents.walk.goto import GoToPose, pose_behind_ball
from mimic.episode import run
from mimic.world.base import World

__all__ = ["BALL_OFFSET_M", "ApproachResult", "approach_starts", "go_to_pose", "walk_behind_ball"]

#: A kick's ball offset (forward, left) in the robot frame [m]: our ``kick_right``'s.
BALL_OFFSET_M = (0.160, -0.069)
#: Where the robot should face from the ball: the opponent goal's centre (field frame) [m].
GOAL_XY_M = (15.0, 0.0)
#: The ball counts as left in place below this displacement [m].
BALL_MOVED_LIMIT_M = 0.03
#: Lined up: the ball within this distance of ``BALL_OFFSET_M`` in the robot frame [m].
OFFSET_ERROR_LIMIT_M = 0.05


@dataclass(frozen=True)
class ApproachResult:
    """One walk behind the ball."""

    arrived: bool
    fell: bool
    # How far the ball moved [m] and how far it lies from the wanted offset (robot frame) [m].
    ball_moved_m: float
    offset_error_m: float
    time_s: float

    @property
    def ok(self) -> bool:
        """Arrived standing, the ball left in place and where the kick wants it."""
        return (
            self.arrived
            and not self.fell
            and self.ball_moved_m < BALL_MOVED_LIMIT_M
            and self.offset_error_m < OFFSET_ERROR_LIMIT_M
        )


def approach_starts(
    rng: np.random.Generator, near: int, around: int
) -> list[tuple[tuple[float, float], tuple[float, float, float]]]:
    """(ball xy [m], robot start (x [m], y [m], yaw [rad])) pairs, field frame.

    ``near``: 0.5 m ahead of a ball at (-3, -1), facing away from the goal (the walk turns round
    and passes the ball), moved by Gaussian noise of 2 cm and 0.05 rad. ``around``: 0.4 to 1.0 m
    from a ball at (2, 1) in any direction, facing anywhere."""
    out = []
    for _ in range(near):
        start = (-2.5 + rng.normal(0, 0.02), -1.0 + rng.normal(0, 0.02), 0.5 + rng.normal(0, 0.05))
        out.append(((-3.0, -1.0), start))
    for _ in range(around):
        a, r = rng.uniform(-math.pi, math.pi), rng.uniform(0.4, 1.0)
        start = (2.0 + r * math.cos(a), 1.0 + r * math.sin(a), rng.uniform(-math.pi, math.pi))
        out.append(((2.0, 1.0), start))
    return out


def go_to_pose(world: World, goto: GoToPose, target, limit_s: float = 40.0) -> bool:
    """Walk ``goto`` to ``target`` (x [m], y [m], heading [rad], field frame) until it has
    arrived, fallen or ``limit_s`` [s] passed; returns whether the robot fell."""
    goto.set_target(*target)
    return run(world, goto, max_s=limit_s, abort_on_fall=True).end == "fell"


def walk_behind_ball(
    world: World, ball_xy, start, ball_offset_m=BALL_OFFSET_M, limit_s: float = 40.0
) -> ApproachResult:
    """Place the robot at ``start`` and the ball at ``ball_xy``; walk (our walk engine) until
    standing behind the ball facing the goal with the ball at ``ball_offset_m``."""
    robot = world.robot
    world.reset()
    world.place_robot(*start, robot.stand_pose())
    world.place_ball(*ball_xy)
    goto = GoToPose(WalkEngine())
    fell = go_to_pose(world, goto, pose_behind_ball(ball_xy, GOAL_XY_M, ball_offset_m), limit_s)
    return ApproachResult(
        arrived=goto.arrived,
        fell=fell,
        ball_moved_m=float(np.hypot(*(world.ball_pos_m()[:2] - np.asarray(ball_xy)))),
        offset_error_m=float(
            np.hypot(*(world.ball_in_robot_frame_m() - np.asarray(ball_offset_m)))
        ),
        time_s=world.time_s,
    )
