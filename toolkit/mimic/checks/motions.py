"""Seeded physical outcome checks of our keyframe motions: kicks, get-ups, standing.

The kick, the get-up and standing are the ``kick-from-stand``, get-up (``tasks.getup``, the
get-up trial's episode) and ``stand`` tasks (``mimic.tasks``) with the configs of these
checks. Each check builds a fresh world for the motion's robot (our
MuJoCo world; for a league robot on the league's field and ball) or uses the one it is given
(``world=``: the league server's ``LeagueWorld``), sets up a scene with small random
perturbations drawn from ``np.random.default_rng(seed)``, plays the motion with
``KeyframePlayer`` through the episode layer's ``run`` and reports what happened. Tests and
benchmarks share these functions, so a rate printed by a benchmark is the rate the tests
assert on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.agents.keyframe_player import KeyframePlayer
from mimic.episode.scene import SETTLE_S
from mimic.errors import MotionFileError
from mimic.motion.keyframe import Movement
from mimic.tasks import kick_from_stand, stand
from mimic.tasks.getup import GetupTrialConfig, play_getup
from mimic.tasks.kick_from_stand import KickFromStandConfig, Standing
from mimic.tasks.perturbation import NO_PERTURBATION, Perturbation
from mimic.tasks.stand import StandConfig
from mimic.world.base import World
from mimic.world.mujoco_world import MujocoWorld

__all__ = [
    "Perturbation",
    "NO_PERTURBATION",
    "KickOutcome",
    "GetupOutcome",
    "run_kick",
    "run_getup",
    "run_stand",
]


@dataclass(frozen=True)
class KickOutcome:
    """What one kick did.

    Attributes:
        distance_m: ball displacement on the ground from its start to where it came to rest
            (or where it was at the time limit) [m].
        forward_m: that displacement along the robot's heading at the kick start [m].
        direction_error_rad: angle of the displacement from the heading, in (-pi, pi]
            (positive = to the robot's left); NaN if the ball moved less than 5 cm.
        standing_after: the robot has not fallen 2 s (``after_s``) after the motion ended.
    """

    distance_m: float
    forward_m: float
    direction_error_rad: float
    standing_after: bool


@dataclass(frozen=True)
class GetupOutcome:
    """What one get-up did.

    Attributes:
        upright: ``World.upright()`` at the motion's end + ``after_s``.
        time_to_upright_s: from the motion start to the first cycle after which the robot
            stayed upright to the end [s]; None if it was not upright at the end.
    """

    upright: bool
    time_to_upright_s: float | None


def run_kick(
    movement: Movement,
    seed: int,
    perturb: bool = True,
    *,
    perturbation: Perturbation = Perturbation(),
    ball_start_m: tuple[float, float] = (-8.0, 0.0),
    settle_s: float = 0.2,
    after_s: float = 2.0,
    max_time_s: float = 12.0,
    rest_speed_m_s: float = 0.01,
    world: World | None = None,
) -> KickOutcome:
    """Stand the robot behind a ball at the motion's ``ball_offset_m``, kick, measure: the
    ``kick-from-stand`` task (``tasks.kick_from_stand``) with the keyframe check's config.

    The ball starts near ``ball_start_m`` (field frame [m]; far from the goals so it rolls
    freely toward +x); the robot faces +x. The motion's player holds its last keyframe for
    ``after_s`` [s] itself (no after phase of the task), then "standing" is "not fallen";
    the robot keeps the last keyframe while the ball is followed until slower than
    ``rest_speed_m_s`` or ``max_time_s`` after the motion start [s]. ``world``: where to
    kick (default: a fresh ``MujocoWorld`` of the movement's robot).

    Raises:
        MotionFileError: the movement has no ball offset.
    """
    if movement.ball_offset_m is None:
        raise MotionFileError(
            f"motion {movement.name!r} has no 'ball_offset X_M Y_M' line; "
            "a kick needs one to place the ball"
        )
    p = perturbation if perturb else NO_PERTURBATION
    world = world if world is not None else MujocoWorld(movement.robot)
    config = KickFromStandConfig(
        ball_start_m=ball_start_m,
        ball_offset_m=movement.ball_offset_m,
        noise=p.noise(),
        settle_s=settle_s,
        kick_max_s=movement.duration_s + after_s + 1.0,
        after_s=0.0,
        standing=Standing.NOT_FALLEN,
        roll_max_s=max(0.0, max_time_s - movement.duration_s - after_s),
        rest_speed_m_s=rest_speed_m_s,
        hold_pose_rad=tuple(movement.steps[-1].angles_rad),
    )
    o = kick_from_stand.play(world, KeyframePlayer(movement, hold_s=after_s), seed, config)
    return KickOutcome(o.distance_m, o.forward_m, o.direction_error_rad, o.standing)


def run_getup(
    movement: Movement,
    side: str,
    seed: int,
    perturb: bool = True,
    *,
    perturbation: Perturbation = Perturbation(),
    lying_pose_rad: np.ndarray | None = None,
    settle_s: float = SETTLE_S,
    after_s: float = 1.0,
    world: World | None = None,
) -> GetupOutcome:
    """Lay the robot on its ``side`` (``"front"`` or ``"back"``), let it settle, get up.

    ``lying_pose_rad``: (N,) joint angles while lying (default: the stand pose), perturbed.
    Success is ``World.upright()`` at the motion's end + ``after_s`` [s]. ``world``: where
    (default: a fresh ``MujocoWorld`` of the movement's robot).
    """
    if side not in ("front", "back"):
        raise ValueError(f"side must be 'front' or 'back', got {side!r}")
    p = perturbation if perturb else NO_PERTURBATION
    world = world if world is not None else MujocoWorld(movement.robot)
    # The get-up task with the check's settings: the player holds its last keyframe
    # ``after_s`` itself, so nothing is held after it.
    config = GetupTrialConfig(
        side=side, settle_s=settle_s, timeout_s=movement.duration_s + after_s + 1.0, after_s=0.0
    )
    getup, _ = play_getup(
        world,
        KeyframePlayer(movement, hold_s=after_s),
        seed,
        config,
        noise=p.noise(),
        pose_rad=lying_pose_rad,
    )
    return GetupOutcome(getup.stood, getup.time_to_stand_s)


def run_stand(
    duration_s: float, seed: int | None = None, robot: str = "nao", *, world: World | None = None
) -> bool:
    """Place the robot in its stand pose (perturbed if ``seed`` is given) and play ``stand``
    held for ``duration_s`` [s]; True if it never fell (the ``stand`` task). ``world``:
    where (default: a fresh ``MujocoWorld`` of ``robot``)."""
    world = world if world is not None else MujocoWorld(robot)
    noise = (Perturbation() if seed is not None else NO_PERTURBATION).noise()
    config = StandConfig(duration_s=duration_s, noise=noise)
    return stand.play(world, None, seed or 0, config).stood
