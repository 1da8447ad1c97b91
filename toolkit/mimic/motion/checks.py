"""Seeded physical outcome checks of our keyframe motions: kicks, get-ups, standing.

Each check builds a fresh world, places the robot (and ball) with small random perturbations
drawn from ``np.random.default_rng(seed)``, plays the motion with ``KeyframePlayer`` through
``run_agent`` and reports what happened. Tests and benchmarks share these functions, so a rate
printed by a benchmark is the rate the tests assert on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.tracking import TrackingController
from mimic.errors import MotionFileError
from mimic.motion.files import load_motion, stand_pose_rad
from mimic.motion.keyframe import Movement
from mimic.robot.joints import NUM_JOINTS, lower_limits_rad, upper_limits_rad
from mimic.runner import run_agent
from mimic.world.world import CYCLE_S, World

__all__ = ["Perturbation", "KickOutcome", "GetupOutcome", "stand_pose_rad", "run_kick",
           "run_getup", "run_stand"]


@dataclass(frozen=True)
class Perturbation:
    """Half-widths of the uniform noise added to a start pose (all zero: no noise)."""

    # Every joint angle [deg].
    joint_deg: float = 1.0
    # Robot x and y [m].
    position_m: float = 0.01
    # Robot heading [deg].
    yaw_deg: float = 2.0
    # Ball x and y [m].
    ball_m: float = 0.01


NO_PERTURBATION = Perturbation(0.0, 0.0, 0.0, 0.0)

#: Where the ball waits during checks that do not use it [m], far from the robot.
_BALL_OUT_OF_THE_WAY_M = (5.0, 5.0)


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


def _noisy_pose(rng: np.random.Generator, pose: np.ndarray, p: Perturbation) -> np.ndarray:
    noise = rng.uniform(-1.0, 1.0, NUM_JOINTS) * math.radians(p.joint_deg)
    return np.clip(pose + noise, lower_limits_rad(), upper_limits_rad())


def _hold(world: World, pose: np.ndarray, duration_s: float) -> None:
    """Track a fixed pose for ``duration_s`` [s] (lets a freshly beamed robot settle)."""
    control = TrackingController()
    for _ in range(int(round(duration_s / CYCLE_S))):
        world.step(control.speeds(pose, world.joint_angles_rad()))


def run_kick(movement: Movement, seed: int, perturb: bool = True, *,
             perturbation: Perturbation = Perturbation(),
             ball_start_m: tuple[float, float] = (-8.0, 0.0),
             settle_s: float = 0.2, after_s: float = 2.0, max_time_s: float = 12.0,
             rest_speed_m_s: float = 0.01) -> KickOutcome:
    """Stand the robot behind a ball at the motion's ``ball_offset_m``, kick, measure.

    The ball starts near ``ball_start_m`` (field frame [m]; far from the goals so it rolls
    freely toward +x); the robot faces +x. After the motion the robot keeps the last keyframe;
    the ball is followed until slower than ``rest_speed_m_s`` or ``max_time_s`` after the
    motion start [s].

    Raises:
        MotionFileError: the movement has no ball offset.
    """
    if movement.ball_offset_m is None:
        raise MotionFileError(f"motion {movement.name!r} has no 'ball_offset X_M Y_M' line; "
                              "a kick needs one to place the ball")
    rng = np.random.default_rng(seed)
    p = perturbation if perturb else NO_PERTURBATION
    pose = _noisy_pose(rng, stand_pose_rad(), p)
    dx, dy = rng.uniform(-1.0, 1.0, 2) * p.position_m
    yaw = math.radians(rng.uniform(-1.0, 1.0) * p.yaw_deg)
    bx, by = np.asarray(ball_start_m) + rng.uniform(-1.0, 1.0, 2) * p.ball_m
    off_x, off_y = movement.ball_offset_m

    world = World()
    world.beam(ball_start_m[0] - off_x + dx, ball_start_m[1] - off_y + dy, yaw, pose)
    world.place_ball(bx, by)
    _hold(world, pose, settle_s)
    heading = world.torso_yaw_rad()
    ball0 = world.ball_pos_m()[:2]

    player = KeyframePlayer(movement, hold_s=after_s)
    run_agent(world, player, max_duration_s=movement.duration_s + after_s + 1.0)
    standing = not world.fallen()

    last = movement.steps[-1].angles_rad
    control = TrackingController()
    remaining = max(0.0, max_time_s - movement.duration_s - after_s)
    for _ in range(int(round(remaining / CYCLE_S))):
        if world.ball_speed_m_s() < rest_speed_m_s:
            break
        world.step(control.speeds(last, world.joint_angles_rad()))

    moved = world.ball_pos_m()[:2] - ball0
    distance = float(np.hypot(*moved))
    forward = float(moved[0] * math.cos(heading) + moved[1] * math.sin(heading))
    lateral = float(-moved[0] * math.sin(heading) + moved[1] * math.cos(heading))
    direction = math.atan2(lateral, forward) if distance >= 0.05 else math.nan
    return KickOutcome(distance, forward, direction, standing)


def run_getup(movement: Movement, side: str, seed: int, perturb: bool = True, *,
              perturbation: Perturbation = Perturbation(),
              lying_pose_rad: np.ndarray | None = None,
              settle_s: float = 0.5, after_s: float = 1.0) -> GetupOutcome:
    """Lay the robot on its ``side`` (``"front"`` or ``"back"``), let it settle, get up.

    ``lying_pose_rad``: (22,) joint angles while lying (default: the stand pose), perturbed.
    Success is ``World.upright()`` at the motion's end + ``after_s`` [s].
    """
    if side not in ("front", "back"):
        raise ValueError(f"side must be 'front' or 'back', got {side!r}")
    rng = np.random.default_rng(seed)
    p = perturbation if perturb else NO_PERTURBATION
    base = stand_pose_rad() if lying_pose_rad is None else np.asarray(lying_pose_rad)
    pose = _noisy_pose(rng, base, p)
    dx, dy = rng.uniform(-1.0, 1.0, 2) * p.position_m
    yaw = math.radians(rng.uniform(-1.0, 1.0) * p.yaw_deg)

    world = World()
    world.beam(dx, dy, yaw, pose, lying=side)
    world.place_ball(*_BALL_OUT_OF_THE_WAY_M)  # the ball starts at the centre spot
    _hold(world, pose, settle_s)

    upright: list[bool] = []
    run_agent(world, KeyframePlayer(movement, hold_s=after_s),
              max_duration_s=movement.duration_s + after_s + 1.0,
              observers=(lambda w, obs, agent: upright.append(w.upright()),))
    if not world.upright():
        return GetupOutcome(False, None)
    # The last cycles seen by the observer precede the final state: count back the run of
    # upright cycles that reaches the end.
    k = len(upright)
    while k > 0 and upright[k - 1]:
        k -= 1
    return GetupOutcome(True, k * CYCLE_S)


def run_stand(duration_s: float, seed: int | None = None) -> bool:
    """Beam the robot in the stand pose (perturbed if ``seed`` is given) and play ``stand``
    held for ``duration_s`` [s]; True if it never fell."""
    pose = stand_pose_rad()
    if seed is not None:
        pose = _noisy_pose(np.random.default_rng(seed), pose, Perturbation())
    world = World()
    world.beam(0.0, 0.0, 0.0, pose)
    world.place_ball(*_BALL_OUT_OF_THE_WAY_M)
    fell: list[bool] = []
    stand = load_motion("stand")
    run_agent(world, KeyframePlayer(stand, hold_s=duration_s),
              max_duration_s=stand.duration_s + duration_s,
              observers=(lambda w, obs, agent: fell.append(w.fallen()),))
    return not any(fell) and not world.fallen()
