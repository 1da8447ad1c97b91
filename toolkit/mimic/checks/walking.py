"""Physical checks of any walk or kick agent, through the ``Agent`` interface only.

Used by the tests and the benchmarks; they see the agents exactly as the recorder does
(reset / act / done / period_s / ball_offset_m): the other team's walk and kick among them.
A straight walk is the ``straight-walk`` task, a kick from a stand the ``kick-from-stand``
task (``mimic.tasks``), each with this check's config.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from mimic.agents.base import Agent
from mimic.agents.noisy_commands import NoisyCommands
from mimic.episode import PoseNoise
from mimic.tasks import kick_from_stand as kick_task
from mimic.tasks import straight_walk as walk_task
from mimic.tasks.kick_from_stand import After, KickFromStandConfig, Standing
from mimic.tasks.straight_walk import StraightWalkConfig
from mimic.tasks.straight_walk import StraightWalkOutcome as WalkResult
from mimic.world.base import World
from mimic.world.mujoco_world import MujocoWorld

__all__ = ["WalkResult", "KickResult", "straight_walk", "kick_from_stand", "NoisyCommands"]


@dataclass(frozen=True)
class KickResult:
    """Outcome of one kick from a stand."""

    # Ball travel along the field's x axis (the robot faces +x) [m].
    distance_m: float
    # Ball travel along the field's y axis [m].
    lateral_m: float
    # Robot upright 2 s after the kick finished (and the ball still on the field).
    standing: bool


def straight_walk(
    make_agent: Callable[[], Agent],
    distance_m: float = 15.0,
    *,
    seed: int = 0,
    speed_noise_rad_s: float = 0.0,
    start_after_m: float = 1.0,
    max_time_s: float = 60.0,
    world: World | None = None,
    pose_noise_rad: float = 0.0,
) -> WalkResult:
    """Place the robot standing on its own goal line facing +x and let the agent walk.

    The speed is measured from the moment the torso has advanced ``start_after_m`` [m]
    (past the start-up) until it has covered ``distance_m`` [m]. ``speed_noise_rad_s``
    adds Gaussian noise [rad/s] to every speed command and ``pose_noise_rad`` to every
    joint of the start pose [rad] (seeded perturbations).
    """
    config = StraightWalkConfig(
        distance_m=distance_m,
        start_after_m=start_after_m,
        max_time_s=max_time_s,
        pose_noise_rad=pose_noise_rad,
        speed_noise_rad_s=speed_noise_rad_s,
    )
    return walk_task.play(world or MujocoWorld(), make_agent(), seed, config)


def kick_from_stand(
    make_agent: Callable[[], Agent],
    *,
    seed: int = 0,
    pose_noise_rad: float = 0.0,
    ball_noise_m: float = 0.0,
    speed_noise_rad_s: float = 0.0,
    world: World | None = None,
) -> KickResult:
    """Stand the robot at the centre spot, put the ball where the kick wants it, kick.

    After the agent reports done, the joints hold their last pose for 2 s and the ball is
    left to roll to rest: the last joint references the agent sent, or the angles reached
    for an agent that sent speeds (``After.HOLD``). Seeded noise perturbs the start pose
    [rad], the ball position [m] and the speed commands [rad/s].
    """
    config = KickFromStandConfig(
        robot_xy_m=(0.0, 0.0),
        noise=PoseNoise(joint_rad=pose_noise_rad, ball_m=ball_noise_m, distribution="uniform"),
        settle_s=0.2,
        speed_noise_rad_s=speed_noise_rad_s,
        kick_max_s=10.0,
        after=After.HOLD,
        after_s=2.0,
        standing=Standing.UPRIGHT,
        roll_max_s=20.0,
        rest_speed_m_s=0.01,
    )
    o = kick_task.play(world or MujocoWorld(), make_agent(), seed, config)
    forward, lateral = o.moved_xy_m
    return KickResult(
        float(forward), float(lateral), bool(o.standing and not math.isnan(o.ball_end_m[0]))
    )
