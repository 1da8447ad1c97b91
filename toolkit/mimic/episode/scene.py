"""A scene: how an episode starts, drawn from an explicit random generator.

Where the robot stands (or lies), how its start pose is perturbed, where the ball goes and
how long the robot settles before the agent starts. ``Scene.setup(world, rng)`` does it; every
random number comes from ``rng`` (a ``numpy.random.Generator`` handed in), in a fixed order:
robot x and y, heading, joints, ball x and y.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.hold import HoldPose
from mimic.episode.run import run
from mimic.world.base import POSTURES, World

__all__ = ["Scene", "PoseNoise", "Placement", "BALL_ASIDE_M", "SETTLE_S"]

#: Where the ball waits when a scene does not use it: this far to the robot's left [m].
BALL_ASIDE_M = 3.0
#: How long a placed robot settles before the agent starts [s] (every scene's default).
SETTLE_S = 0.5


@dataclass(frozen=True)
class PoseNoise:
    """Random perturbation of a scene's start.

    With ``distribution="normal"`` the values are standard deviations, with ``"uniform"``
    half-widths of a uniform interval.

    Attributes:
        position_m: robot x and y [m].
        yaw_rad: robot heading [rad].
        joint_rad: every joint angle [rad] (the result is clipped to the joint stops).
        ball_m: ball x and y [m].
        distribution: ``normal`` or ``uniform``.
    """

    position_m: float = 0.0
    yaw_rad: float = 0.0
    joint_rad: float = 0.0
    ball_m: float = 0.0
    distribution: str = "normal"

    def __post_init__(self) -> None:
        if self.distribution not in ("normal", "uniform"):
            raise ValueError(
                f"noise distribution must be normal or uniform, got {self.distribution!r}"
            )
        for name in ("position_m", "yaw_rad", "joint_rad", "ball_m"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"noise {name} must be finite and >= 0, got {value}")

    def draw(self, rng: np.random.Generator, scale: float, size: int | None = None):
        """Noise of one kind (``scale``: its std or half-width)."""
        if self.distribution == "normal":
            return rng.normal(0.0, scale, size)
        return rng.uniform(-1.0, 1.0, size) * scale


@dataclass(frozen=True)
class Placement:
    """Where a scene actually put things (after noise and settling).

    Attributes:
        pose_rad: (N,) the start pose the robot was placed in [rad].
        robot_xy_m, robot_yaw_rad: the robot's placement [m], [rad].
        ball_xy_m: the ball's placement [m].
    """

    pose_rad: np.ndarray
    robot_xy_m: tuple[float, float]
    robot_yaw_rad: float
    ball_xy_m: tuple[float, float]


@dataclass(frozen=True)
class Scene:
    """How an episode starts.

    Attributes:
        robot_xy_m: robot position in the field frame [m].
        robot_yaw_rad: robot heading [rad].
        posture: ``standing``, ``lying_front`` or ``lying_back``.
        pose_rad: (N,) joint angles to start in; None: the robot's stand pose.
        noise: random perturbation of robot, pose and ball.
        ball_offset_m: ball relative to the torso in the robot frame (x forward, y left) [m];
            None: the ball at ``ball_xy_m``.
        ball_xy_m: ball in the field frame [m]; None (and no offset): ``BALL_ASIDE_M`` to the
            robot's left, out of the way.
        ball_after_settle: place the ball (at its offset) only after settling, relative to
            the settled torso (a kick's feet move a little while the robot settles).
        settle_s: time the robot settles before the agent starts [s].
        settle_into_stand: while settling, move into the robot's stand pose (undoing the
            joint noise, as a robot does before it starts to walk); False holds the start
            pose as placed.
    """

    robot_xy_m: tuple[float, float] = (0.0, 0.0)
    robot_yaw_rad: float = 0.0
    posture: str = "standing"
    pose_rad: tuple[float, ...] | None = None
    noise: PoseNoise = PoseNoise()
    ball_offset_m: tuple[float, float] | None = None
    ball_xy_m: tuple[float, float] | None = None
    ball_after_settle: bool = False
    settle_s: float = SETTLE_S
    settle_into_stand: bool = False

    def __post_init__(self) -> None:
        if self.posture not in POSTURES:
            raise ValueError(f"posture must be one of {', '.join(POSTURES)}, got {self.posture!r}")
        if not (math.isfinite(self.settle_s) and self.settle_s >= 0):
            raise ValueError(f"settle time must be finite and >= 0 s, got {self.settle_s}")

    def setup(self, world: World, rng: np.random.Generator, observers=()) -> Placement:
        """Reset ``world``, place robot and ball with noise from ``rng``, let the robot settle.

        ``observers`` watch the settling (a pose trace, a fall counter).
        """
        robot, n = world.robot, self.noise
        world.reset()
        dx, dy = n.draw(rng, n.position_m, 2)
        yaw = self.robot_yaw_rad + float(n.draw(rng, n.yaw_rad))
        base = (
            robot.stand_pose()
            if self.pose_rad is None
            else robot.check_vector(self.pose_rad, "scene pose")
        )
        pose = robot.clip(base + n.draw(rng, n.joint_rad, robot.num_joints))
        ball_noise = n.draw(rng, n.ball_m, 2)
        x, y = self.robot_xy_m[0] + dx, self.robot_xy_m[1] + dy
        world.place_robot(x, y, yaw, pose, posture=self.posture)
        if self.ball_offset_m is not None and not self.ball_after_settle:
            ball = _in_field(self.ball_offset_m, (x, y), yaw) + ball_noise
        elif self.ball_xy_m is not None and self.ball_offset_m is None:
            ball = np.asarray(self.ball_xy_m, dtype=float) + ball_noise
        else:  # aside while settling (or for good)
            ball = np.array([x, y + BALL_ASIDE_M])
        world.place_ball(*ball)
        if self.settle_s > 0:
            hold = robot.stand_pose() if self.settle_into_stand else pose
            run(
                world,
                HoldPose(hold, robot.name),
                max_s=self.settle_s,
                stop_when_done=False,
                observers=observers,
            )
        if self.ball_offset_m is not None and self.ball_after_settle:
            torso = world.torso_pos_m()
            ball = (
                _in_field(self.ball_offset_m, (torso[0], torso[1]), world.torso_yaw_rad())
                + ball_noise
            )
            world.place_ball(*ball)
        return Placement(pose, (float(x), float(y)), float(yaw), (float(ball[0]), float(ball[1])))


def _in_field(offset_m, xy_m, yaw_rad) -> np.ndarray:
    """A robot-frame offset (x forward, y left) from (x, y) heading ``yaw_rad``, in the field."""
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    return np.array(
        [xy_m[0] + c * offset_m[0] - s * offset_m[1], xy_m[1] + s * offset_m[0] + c * offset_m[1]]
    )
