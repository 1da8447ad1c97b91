"""The walk trial: from the own goal line to the centre line (15 m), repeated."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.registry import AgentSpec
from mimic.episode import Episode, PoseNoise, PoseTrace, Scene
from mimic.world import field as F
from mimic.world.mujoco_world import MujocoWorld

__all__ = ["WalkTrialConfig", "run_walk_episode", "walk_scene"]


@dataclass(frozen=True)
class WalkTrialConfig:
    """Settings of one walk run."""

    # Start x [m] (the own goal line) and finish x [m] (the centre line).
    start_x_m: float = F.OWN_GOAL_X_M
    finish_x_m: float = 0.0
    # Longest run before it counts as too slow [s].
    timeout_s: float = 120.0
    # Start-pose noise: position [m], heading [rad], joint angles [rad].
    start_noise_pos_m: float = 0.01
    start_noise_yaw_rad: float = math.radians(1)
    start_noise_joint_rad: float = math.radians(0.5)
    # Keep a pose trace of the episode (robot bodies and ball) for the Rerun replay.
    trace: bool = False


def walk_scene(config: WalkTrialConfig) -> Scene:
    """Standing on the start line facing the opponent goal, the ball out of the way."""
    return Scene(robot_xy_m=(config.start_x_m, 0.0), settle_s=0.5, settle_into_stand=True,
                 noise=PoseNoise(position_m=config.start_noise_pos_m,
                                 yaw_rad=config.start_noise_yaw_rad,
                                 joint_rad=config.start_noise_joint_rad))


def run_walk_episode(walk: AgentSpec, seed: int, config: WalkTrialConfig = WalkTrialConfig()
                     ) -> tuple[list[dict], dict]:
    """One run; returns ([the run's row], the same row as summary) for the shared runner."""
    rng = np.random.default_rng(seed)
    world = MujocoWorld(walk.robot)
    trace = PoseTrace() if config.trace else None
    episode = Episode(world, observers=(trace,) if trace else ())
    walk_scene(config).setup(world, rng, observers=episode.watchers)
    falls = episode.falls
    start = world.torso_pos_m()
    t0 = world.time_s
    outcome = episode.run(walk.build(), max_s=config.timeout_s,
                          stop=lambda w: w.torso_pos_m()[0] >= config.finish_x_m)
    end = world.torso_pos_m()
    elapsed = world.time_s - t0
    distance = float(end[0] - start[0])
    row = dict(seed=seed, duration_s=world.time_s, walk_time_s=elapsed,
               distance_m=distance, speed_m_s=distance / elapsed if elapsed > 0 else 0.0,
               y_error_m=float(abs(end[1] - start[1])), y_end_m=float(end[1]),
               heading_error_deg=math.degrees(abs(world.torso_yaw_rad())),
               finished=outcome == "stop", fell=outcome == "fell", falls=falls.falls,
               end={"stop": "finished", "fell": "fell", "timeout": "timeout",
                    "done": "agent stopped"}[outcome])
    summary = dict(row, trace=trace.trace()) if trace is not None else row
    return [row], summary
