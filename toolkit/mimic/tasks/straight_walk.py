"""A straight walk: the robot starts on its own goal line facing +x and walks; how fast, how
straight, did it fall?

The scene places the robot standing at ``(start_x_m, 0)`` (field frame), no settling, the
ball out of the way at ``ball_xy_m``; the start pose's joints get Gaussian noise. The agent
walks until the torso has covered ``distance_m`` along x, the robot falls, or ``max_time_s``
has passed. The speed is measured from the moment the torso has advanced ``start_after_m``
(past the start-up) to the end.

    outcome = play(world, agent, seed=0, config=StraightWalkConfig(distance_m=4.0))
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.noisy_commands import NoisyCommands
from mimic.episode import Observer, PoseNoise, Scene, run
from mimic.errors import MimicError
from mimic.world import field as F
from mimic.world.base import World

__all__ = ["StraightWalkConfig", "StraightWalkOutcome", "scene", "play"]


@dataclass(frozen=True)
class StraightWalkConfig:
    """One straight walk."""

    # How far the torso walks along x before the walk ends [m].
    distance_m: float = 15.0
    # Where the robot starts, field x [m] (y = 0, facing +x): its own goal line.
    start_x_m: float = F.OWN_GOAL_X_M
    # Where the ball waits, field frame [m] (the centre spot: out of a 15 m walk's way).
    ball_xy_m: tuple[float, float] = (0.0, 0.0)
    # The speed is measured once the torso has advanced this far [m] (past the start-up).
    start_after_m: float = 1.0
    # Longest the walk lasts [s].
    max_time_s: float = 60.0
    # Gaussian noise on every start-pose joint [rad] (std).
    pose_noise_rad: float = 0.0
    # Gaussian noise on every speed command [rad/s] (std; 0: none).
    speed_noise_rad_s: float = 0.0

    def __post_init__(self) -> None:
        for name in ("distance_m", "start_after_m", "max_time_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise MimicError(f"straight walk: {name} must be finite and > 0, got {value}")
        for name in ("pose_noise_rad", "speed_noise_rad_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise MimicError(f"straight walk: {name} must be finite and >= 0, got {value}")


@dataclass(frozen=True)
class StraightWalkOutcome:
    """What one straight walk did."""

    # Whether the robot lay at the end (a fall ends the walk).
    fell: bool
    # Distance covered along x [m].
    distance_m: float
    # Mean forward speed from the first crossing of ``start_after_m`` to the end [m/s]
    # (0 if it never crossed it).
    speed_m_s: float
    # Largest |y| of the torso reached, field frame [m].
    max_drift_m: float
    # Simulated time used [s].
    time_s: float
    # (cycles, N) observed joint angles [rad], one row per 20 ms cycle.
    angles_rad: np.ndarray


def scene(config: StraightWalkConfig) -> Scene:
    """The scene of a straight walk."""
    return Scene(
        robot_xy_m=(config.start_x_m, 0.0),
        settle_s=0.0,
        ball_xy_m=config.ball_xy_m,
        noise=PoseNoise(joint_rad=config.pose_noise_rad),
    )


class _WalkLog(Observer):
    """Joint angles seen, largest sideways drift, and when the walk passed ``start_after_m``."""

    def __init__(self, x0_m: float, start_after_m: float) -> None:
        self.x0_m, self.start_after_m = x0_m, start_after_m
        self.angles: list[np.ndarray] = []
        self.drift_m, self.t_start_s = 0.0, None

    def before_step(self, world, obs, agent, command) -> None:
        self.angles.append(obs.joint_angles_rad)

    def after_step(self, world: World) -> None:
        x, y, _ = world.torso_pos_m()
        self.drift_m = max(self.drift_m, abs(y))
        if self.t_start_s is None and x - self.x0_m >= self.start_after_m:
            self.t_start_s = world.time_s


def play(
    world: World, agent: Agent, seed: int, config: StraightWalkConfig = StraightWalkConfig()
) -> StraightWalkOutcome:
    """Play one straight walk of ``agent`` in ``world`` (module docstring)."""
    rng = np.random.default_rng(seed)
    x0 = config.start_x_m
    scene(config).setup(world, rng)
    if config.speed_noise_rad_s:
        agent = NoisyCommands(agent, rng, config.speed_noise_rad_s, world.robot.actuator)
    log = _WalkLog(x0, config.start_after_m)
    run(
        world,
        agent,
        max_s=config.max_time_s,
        stop_when_done=False,
        abort_on_fall=True,
        observers=(log,),
        stop=lambda w: w.torso_pos_m()[0] - x0 >= config.distance_m,
    )
    x = world.torso_pos_m()[0]
    t_start = log.t_start_s
    speed = (
        (x - x0 - config.start_after_m) / (world.time_s - t_start)
        if t_start is not None and world.time_s > t_start
        else 0.0
    )
    return StraightWalkOutcome(
        world.fallen(),
        float(x - x0),
        float(speed),
        float(log.drift_m),
        world.time_s,
        np.array(log.angles),
    )
