"""The walk trial: straight ahead from a standing start, repeated.

In our world the course is the study's, from the own goal line to the centre line (15 m); in
the league's (``config.world``, ``world.registry``) it is 10 m through the centre spot, from
x = -5 m to x = 5 m of the league's field. A fall ends the run, unless the trial's disturbance
level says a game goes on (``Disturbances.get_up_after_fall``: ``game`` and ``hard``): then the
robot gets up and walks on (``Agent.resume``: back to its course), and the run's speed counts
the time its get-ups took.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import ClassVar

import numpy as np
import polars as pl

from mimic.agents.registry import AgentSpec
from mimic.episode import Episode, PoseNoise, PoseTrace, Scene
from mimic.episode.disturbance import EpisodeDisturbances, disturb_level, game_push_speed_m_s
from mimic.episode.scene import SETTLE_S
from mimic.stats import mean_interval, wilson_interval
from mimic.tasks.base import (
    Column,
    Dashboard,
    EpisodeBatch,
    TrialTask,
    as_row,
    ci_columns,
    first_value,
)
from mimic.world import field as F
from mimic.world.base import CYCLE_S
from mimic.world.registry import MUJOCO, get_world, open_world, world_kind

__all__ = [
    "WalkTask",
    "WalkObjective",
    "WalkRun",
    "walk_summary",
    "WalkTrialConfig",
    "run_walk_episode",
    "walk_scene",
    "LEAGUE_COURSE_M",
]

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
    # The push [m/s] of a game (``push_scale`` 1; ``episode.disturbance``); None: the robot's.
    # ``mimic trial`` sets the one its first variant, the original, survives most of the time.
    push_speed_m_s: float | None = None

    def course_m(self) -> tuple[float, float]:
        """(start x, finish x) [m] in this trial's world."""
        own = LEAGUE_COURSE_M if get_world(self.world).league_field else (F.OWN_GOAL_X_M, 0.0)
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
    disturb = EpisodeDisturbances(config.disturb, seed, world, config.push_speed_m_s)
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
    agent = disturb.agent(walk.build())

    def finished(w) -> bool:
        return w.torso_pos_m()[0] >= finish_x

    outcome = episode.run(agent, max_s=config.timeout_s, stop=finished)
    getups = 0
    # A game's fall costs the time to get up, then the walk goes on toward the finish.
    while outcome == "fell" and disturb.spec.get_up_after_fall:
        if not episode.get_up():
            break  # still lying: the run ends here
        getups += 1
        left_s = t0 + config.timeout_s - world.time_s
        if left_s < CYCLE_S:
            outcome = "timeout"
            break
        agent.resume(world.observe())
        outcome = episode.run(agent, max_s=left_s, stop=finished, reset=False)
    end = world.torso_pos_m()
    elapsed = world.time_s - t0
    distance = float(end[0] - start[0])
    run = WalkRun(
        seed=seed,
        duration_s=world.time_s,
        walk_time_s=elapsed,
        distance_m=distance,
        speed_m_s=distance / elapsed if elapsed > 0 else 0.0,
        y_error_m=float(abs(end[1] - start[1])),
        y_end_m=float(end[1]),
        heading_error_deg=math.degrees(abs(world.torso_yaw_rad())),
        finished=outcome == "stop",
        fell=outcome == "fell" or getups > 0,
        falls=falls.falls,
        getups=getups,
        world=world_kind(config.world),
        end={"stop": "finished", "fell": "fell", "timeout": "timeout", "done": "agent stopped"}[
            outcome
        ],
        disturbances=disturb.columns(),
    )
    row = as_row(run)
    summary = dict(row, trace=disturb.traced(trace.trace())) if trace is not None else row
    return [row], summary


@dataclass(frozen=True)
class WalkRun:
    """One walk from the start line toward the finish line (x along the course) [field frame]."""

    seed: int
    # Simulated time at the run's end, settling included [s].
    duration_s: float
    # From the walk's start to its end [s].
    walk_time_s: float
    # Forward progress along x [m].
    distance_m: float
    # distance_m / walk_time_s [m/s] (the time of any get-up included).
    speed_m_s: float
    # Sideways distance from the start [m], and the torso's y at the end [m].
    y_error_m: float
    y_end_m: float
    # The torso's heading away from +x at the end [deg].
    heading_error_deg: float
    # Crossed the finish line.
    finished: bool
    # Fell at least once (the run ended there, or the robot got up and walked on).
    fell: bool
    falls: int
    # Times it got up and walked on (``Disturbances.get_up_after_fall``).
    getups: int
    world: str
    # finished, fell (lying at the end), timeout or agent stopped.
    end: str
    # The episode's disturbance draw (``EpisodeDisturbances.columns``).
    disturbances: dict


def walk_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the walk table."""
    runs = pl.DataFrame(batch.rows)
    finished = runs.filter(pl.col("finished"))
    fell = int(runs["fell"].sum())
    return dict(
        variant=label,
        runs=runs.height,
        finished=finished.height,
        mean_speed_m_s=runs["speed_m_s"].mean(),
        **ci_columns("mean_speed_m_s", mean_interval(runs["speed_m_s"].to_numpy())),
        std_speed_m_s=runs["speed_m_s"].std() if runs.height > 1 else 0.0,
        mean_y_error_m=runs["y_error_m"].mean(),
        **ci_columns("mean_y_error_m", mean_interval(runs["y_error_m"].to_numpy())),
        std_y_error_m=runs["y_error_m"].std() if runs.height > 1 else 0.0,
        runs_fell=fell,
        falls=int(runs["falls"].sum()),
        fall_rate_pct=100.0 * fell / runs.height,
        **ci_columns("fall_rate_pct", wilson_interval(fell, runs.height), 100.0),
        simulated_min=batch.simulated_s / 60,
        world=first_value(batch.rows, "world"),
        disturb=first_value(batch.rows, "disturb"),
    )


@dataclass(frozen=True)
class WalkObjective:
    """What ``mimic improve --objective walk`` maximises: walk speed over the walk trial's
    course [m/s], minus ``fall_penalty_m_s`` times the share of runs that fell, minus
    ``drift_penalty_per_m`` per metre of sideways error beyond ``drift_tolerance_m`` (mean
    over runs)."""

    # Walk-trial runs per candidate evaluation.
    episodes: int = 4
    # Score lost per share of runs that fell [m/s] (one fall in 4 runs: -0.25 m/s).
    fall_penalty_m_s: float = 1.0
    # Sideways error allowed without penalty [m], and the penalty beyond it [m/s per m].
    drift_tolerance_m: float = 0.3
    drift_penalty_per_m: float = 0.5
    # The walk trial's settings.
    trial_config: WalkTrialConfig = WalkTrialConfig()

    name: ClassVar[str] = "walk"
    #: The setting ``mimic improve --fall-penalty`` sets.
    fall_penalty_setting: ClassVar[str | None] = "fall_penalty_m_s"
    episode_fn = staticmethod(run_walk_episode)
    summarise = staticmethod(walk_summary)

    @property
    def search_config(self) -> WalkTrialConfig:
        return self.trial_config

    def score(self, batch: EpisodeBatch) -> float:
        """Mean speed [m/s] minus the fall and drift penalties."""
        runs = batch.rows
        speed = np.mean([r["speed_m_s"] for r in runs])
        fell = np.mean([r["fell"] for r in runs])
        drift = np.mean([max(0.0, r["y_error_m"] - self.drift_tolerance_m) for r in runs])
        return float(speed - self.fall_penalty_m_s * fell - self.drift_penalty_per_m * drift)

    def describe(self) -> dict:
        return dict(
            name=self.name,
            episodes=self.episodes,
            fall_penalty_m_s=self.fall_penalty_m_s,
            drift_tolerance_m=self.drift_tolerance_m,
            drift_penalty_per_m=self.drift_penalty_per_m,
            trial_config=asdict(self.trial_config),
        )


class WalkTask(TrialTask):
    """The walk trial (module docstring)."""

    name = "walk"
    summary = (
        "Walk trial from a standing start, straight ahead (our world: own goal line to centre "
        "line, 15 m; the league: 10 m through the centre spot), repeated."
    )
    by_minutes = True
    speed_command = True
    Config = WalkTrialConfig
    Objective = WalkObjective
    validation_episodes = 40
    columns = (
        Column("variant", "variant"),
        Column("runs", "runs"),
        Column("mean_speed_m_s", "speed m/s", "mean_speed_m_s"),
        Column("std_speed_m_s", "std"),
        Column("mean_y_error_m", "Y err m", "mean_y_error_m"),
        Column("std_y_error_m", "std"),
        Column("runs_fell", "runs fell", "fall_rate_pct", "range %"),
        Column("mean_speed_m_s_ratio", "speed ratio", "mean_speed_m_s_ratio"),
    )
    legend = (
        "95% CI: 95 % confidence interval of the means (t, +- half width) and of the share "
        "of runs that fell (Wilson). Ratios: against the first variant, with their 95 % "
        "interval (delta method, runs paired by seed). A run that falls ends there "
        "(--disturb none) or gets up and walks on (game, hard; the summary's falls count "
        "every fall, failed get-ups too)."
    )
    ratio_columns = ("mean_speed_m_s", "std_speed_m_s", "mean_y_error_m", "std_y_error_m")
    ratio_sources = {"mean_speed_m_s": "speed_m_s"}
    paired = True
    dashboard = Dashboard(
        curves=("speed_m_s", "y_error_m"),
        histogram="speed_m_s",
        histogram_bins=(0.0, 1.5, 0.05),
    )
    run_episode = staticmethod(run_walk_episode)
    summarise = staticmethod(walk_summary)

    @classmethod
    def for_original(cls, config: WalkTrialConfig, original: AgentSpec) -> WalkTrialConfig:
        """Pushes (if the level has them) the size the original survives most of the time."""
        if config.push_speed_m_s is not None or not disturb_level(config.disturb).pushes:
            return config
        behaviour = original.ref if original.kind == "behaviour" else None
        return replace(config, push_speed_m_s=game_push_speed_m_s(original.robot, behaviour))

    @classmethod
    def default_variant(cls, robot: str, config: WalkTrialConfig) -> str:
        """Our walk engine on the NAO, the other team's walk on a league robot."""
        return "walk" if robot == "nao" else "other-team-walk"

    @classmethod
    def title(cls, config: WalkTrialConfig) -> str:
        start_x, finish_x = config.course_m()
        return f"walk trial ({finish_x - start_x:g} m from a standing start)"
