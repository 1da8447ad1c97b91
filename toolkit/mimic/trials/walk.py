"""The walk trial: straight ahead from a standing start, repeated.

In our world the course is the study's, from the own goal line to the centre line (15 m); in
the league's (``config.world``, ``world.registry``) it is 10 m through the centre spot, from
x = -5 m to x = 5 m of the league's field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.registry import AgentSpec
from mimic.episode import Episode, PoseNoise, PoseTrace, Scene
from mimic.episode.disturbance import EpisodeDisturbances
from mimic.episode.scene import SETTLE_S
from mimic.world import field as F
from mimic.world.registry import LEAGUE_WORLDS, MUJOCO, open_world, world_kind

__all__ = ["WalkTrialConfig", "run_walk_episode", "walk_scene", "LEAGUE_COURSE_M"]

#: The league walk's start and finish x on the league's field [m]: 10 m through the centre.
LEAGUE_COURSE_M = (-5.0, 5.0)


@dataclass(frozen=True)
class WalkTrialConfig:
    """Settings of one walk run."""

    # Start x [m] and finish x [m]; None: the world's course (ours: the own goal line and the
    # centre line; the league's: ``LEAGUE_COURSE_M``).
    start_x_m: float | None = None
    finish_x_m: float | None = None
    # Longest run before it counts as too slow [s].
    timeout_s: float = 120.0
    # Start-pose noise: position [m], heading [rad], joint angles [rad].
    start_noise_pos_m: float = 0.01
    start_noise_yaw_rad: float = math.radians(1)
    start_noise_joint_rad: float = math.radians(0.5)
    # Keep a pose trace of the episode (robot bodies and ball) for the Rerun replay.
    trace: bool = False
    # Where episodes play (``world.registry``): ``mujoco`` (ours), ``league`` (RCSSServerMJ's
    # simulation in this process), ``league-server`` (a hosted server) or ``league-like``.
    world: str = MUJOCO
    # ``league-server`` only: the command that starts the server (None: ``python -m rcsssmj``).
    server_command: tuple[str, ...] | None = None
    # Disturbance level (``episode.disturbance.DISTURB_LEVELS``): none, game or hard. The
    # library's default is none (the undisturbed trial); ``mimic trial`` defaults to game.
    disturb: str = "none"

    def course_m(self) -> tuple[float, float]:
        """(start x, finish x) [m] in this trial's world."""
        own = LEAGUE_COURSE_M if world_kind(self.world) in LEAGUE_WORLDS else (F.OWN_GOAL_X_M, 0.0)
        return (
            own[0] if self.start_x_m is None else self.start_x_m,
            own[1] if self.finish_x_m is None else self.finish_x_m,
        )


def walk_scene(config: WalkTrialConfig) -> Scene:
    """Standing on the start line facing the opponent goal, the ball out of the way."""
    return Scene(
        robot_xy_m=(config.course_m()[0], 0.0),
        settle_s=SETTLE_S,
        settle_into_stand=True,
        noise=PoseNoise(
            position_m=config.start_noise_pos_m,
            yaw_rad=config.start_noise_yaw_rad,
            joint_rad=config.start_noise_joint_rad,
        ),
    )


def run_walk_episode(
    walk: AgentSpec, seed: int, config: WalkTrialConfig = WalkTrialConfig()
) -> tuple[list[dict], dict]:
    """One run in ``config.world``; returns ([the run's row], the same row as summary) for
    the shared runner."""
    with open_world(config.world, walk.robot, server_command=config.server_command) as world:
        return _play_walk_episode(world, walk, seed, config)


def _play_walk_episode(
    world, walk: AgentSpec, seed: int, config: WalkTrialConfig
) -> tuple[list[dict], dict]:
    rng = np.random.default_rng(seed)
    disturb = EpisodeDisturbances(config.disturb, seed, world)
    disturb.apply_physics(world)
    finish_x = config.course_m()[1]
    trace = PoseTrace() if config.trace else None
    episode = Episode(world, observers=(trace, disturb.pusher) if trace else (disturb.pusher,))
    walk_scene(config).setup(world, rng, observers=episode.watchers)
    disturb.start_delay(episode)
    falls = episode.falls
    start = world.torso_pos_m()
    t0 = world.time_s
    disturb.pusher.arm(world)
    outcome = episode.run(
        disturb.agent(walk.build()),
        max_s=config.timeout_s,
        stop=lambda w: w.torso_pos_m()[0] >= finish_x,
    )
    end = world.torso_pos_m()
    elapsed = world.time_s - t0
    distance = float(end[0] - start[0])
    row = dict(
        seed=seed,
        duration_s=world.time_s,
        walk_time_s=elapsed,
        distance_m=distance,
        speed_m_s=distance / elapsed if elapsed > 0 else 0.0,
        y_error_m=float(abs(end[1] - start[1])),
        y_end_m=float(end[1]),
        heading_error_deg=math.degrees(abs(world.torso_yaw_rad())),
        finished=outcome == "stop",
        fell=outcome == "fell",
        falls=falls.falls,
        world=world_kind(config.world),
        end={"stop": "finished", "fell": "fell", "timeout": "timeout", "done": "agent stopped"}[
            outcome
        ],
        **disturb.columns(),
    )
    summary = dict(row, trace=disturb.traced(trace.trace())) if trace is not None else row
    return [row], summary
