"""The get-up trial: the robot knocked down, lying on its front or back, gets up; repeated.

Every run lays the robot on the side its get-up starts from (``Agent.start_posture``: a
keyframe get-up's ``start`` line, a learned one's ``start_posture``, read from the torso at
its recording's start) or on ``config.side``, in its stand pose with the usual start-pose
noise, lets it settle ``settle_s`` and plays the get-up until it says it is done (at most
``timeout_s``); then the robot holds the last reference ``after_s``. A run succeeds when the
robot is upright (``World.upright``) at its end; its time to stand is from the get-up's
start to the first cycle after which it stayed upright to the end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.hold import HoldPose
from mimic.agents.registry import AgentSpec
from mimic.episode import Episode, PoseNoise, PoseTrace, Scene, run
from mimic.episode.disturbance import EpisodeDisturbances
from mimic.episode.observers import Observer, UprightLog
from mimic.episode.scene import SETTLE_S
from mimic.errors import MimicError
from mimic.world.base import CYCLE_S
from mimic.world.registry import open_world, world_kind

__all__ = ["GetupTrialConfig", "run_getup_episode", "getup_scene", "SIDES"]

#: Sides a get-up trial lays the robot on.
SIDES = ("front", "back")


@dataclass(frozen=True)
class GetupTrialConfig:
    """Settings of one get-up run."""

    # Side the robot lies on: ``front``, ``back``, or None: the side its get-up starts from.
    side: str | None = None
    # Time the robot lies still before the get-up starts [s].
    settle_s: float = SETTLE_S
    # Longest the get-up may take before it counts as failed [s].
    timeout_s: float = 20.0
    # Time the robot holds the get-up's last reference after it is done [s].
    after_s: float = 2.0
    # Start-pose noise, uniform half-widths: position [m], heading [rad], joint angles [rad]
    # (the checks' ``Perturbation``).
    start_noise_pos_m: float = 0.01
    start_noise_yaw_rad: float = math.radians(2)
    start_noise_joint_rad: float = math.radians(1)
    # Keep a pose trace of the episode for the Rerun replay.
    trace: bool = False
    # Where episodes play (``world.registry``): ``mujoco`` (ours), ``league`` (RCSSServerMJ's
    # simulation in this process), ``league-server`` (a hosted server) or ``league-like``.
    world: str = "mujoco"
    # ``league-server`` only: the command that starts the server (None: ``python -m rcsssmj``).
    server_command: tuple[str, ...] | None = None
    # Disturbance level (``episode.disturbance.DISTURB_LEVELS``): none, game or hard. The
    # library's default is none (the undisturbed trial); ``mimic trial`` defaults to game.
    disturb: str = "none"

    def __post_init__(self) -> None:
        if self.side is not None and self.side not in SIDES:
            raise MimicError(f"--side must be front or back, got {self.side!r}")
        for name in ("settle_s", "timeout_s", "after_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise MimicError(f"get-up trial: {name} must be finite and >= 0, got {value}")

    def side_for(self, start_posture: str) -> str:
        """The side to lie on for a get-up that starts in ``start_posture``."""
        if self.side is not None:
            return self.side
        side = start_posture.removeprefix("lying_")
        if side not in SIDES:
            raise MimicError(
                f"the get-up trial lays the robot down, but this agent starts {start_posture}; "
                "give --side front or --side back"
            )
        return side


def getup_scene(config: GetupTrialConfig, side: str) -> Scene:
    """Lying on ``side`` at the field's centre facing +x, in the stand pose with noise."""
    return Scene(
        posture=f"lying_{side}",
        settle_s=config.settle_s,
        noise=PoseNoise(
            position_m=config.start_noise_pos_m,
            yaw_rad=config.start_noise_yaw_rad,
            joint_rad=config.start_noise_joint_rad,
            distribution="uniform",
        ),
    )


class _Highest(Observer):
    """The highest the torso got [m]."""

    def __init__(self) -> None:
        self.height_m = 0.0

    def after_step(self, world) -> None:
        self.height_m = max(self.height_m, float(world.torso_pos_m()[2]))


def run_getup_episode(
    getup: AgentSpec, seed: int, config: GetupTrialConfig = GetupTrialConfig()
) -> tuple[list[dict], dict]:
    """One get-up in ``config.world``; returns ([the run's row], the same row as summary)
    for the shared runner."""
    with open_world(config.world, getup.robot, server_command=config.server_command) as world:
        return _play_getup_episode(world, getup, seed, config)


def _play_getup_episode(
    world, getup: AgentSpec, seed: int, config: GetupTrialConfig
) -> tuple[list[dict], dict]:
    disturb = EpisodeDisturbances(config.disturb, seed, world)
    disturb.apply_physics(world)
    agent = getup.build()
    side = config.side_for(agent.start_posture)
    trace = PoseTrace() if config.trace else None
    episode = Episode(world, observers=(trace, disturb.pusher) if trace else (disturb.pusher,))
    getup_scene(config, side).setup(world, np.random.default_rng(seed), observers=episode.watchers)
    disturb.start_delay(episode, lying=True)
    log = UprightLog()
    highest = _Highest()
    t0 = world.time_s
    disturb.pusher.arm(world)
    agent = disturb.agent(agent)
    outcome = run(world, agent, max_s=config.timeout_s, observers=(*episode.watchers, log, highest))
    motion_s = world.time_s - t0
    last = agent.reference_rad
    if last is not None and config.after_s > 0:
        run(
            world,
            HoldPose(np.asarray(last, float), world.robot.name),
            max_s=config.after_s,
            observers=(*episode.watchers, log, highest),
        )
    upright = bool(world.upright())
    # The run of upright cycles that reaches the end, counted back.
    k = len(log.upright)
    while upright and k > 0 and log.upright[k - 1]:
        k -= 1
    row = dict(
        seed=seed,
        side=side,
        stood=upright,
        time_to_stand_s=k * CYCLE_S if upright else None,
        motion_s=motion_s,
        end={"done": "done", "timeout": "timeout", "stop": "stop", "fell": "fell"}[outcome.end],
        torso_height_m=float(world.torso_pos_m()[2]),
        max_torso_height_m=highest.height_m,
        duration_s=world.time_s,
        falls=0 if upright else 1,
        world=world_kind(config.world),
        **disturb.columns(),
    )
    summary = dict(row, trace=disturb.traced(trace.trace())) if trace is not None else row
    return [row], summary
