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
from dataclasses import asdict, dataclass
from typing import ClassVar

import numpy as np
import polars as pl

from mimic.agents.base import Agent
from mimic.agents.hold import HoldPose
from mimic.agents.registry import AgentSpec
from mimic.episode import Episode, PoseNoise, PoseTrace, Scene, run
from mimic.episode.disturbance import EpisodeDisturbances
from mimic.episode.observers import EpisodeTrace, Observer, UprightLog
from mimic.episode.scene import SETTLE_S
from mimic.errors import MimicError
from mimic.stats import mean_interval, wilson_interval
from mimic.tasks.base import (
    Column,
    Dashboard,
    EpisodeBatch,
    TaskOption,
    TrialTask,
    as_row,
    ci_columns,
    first_value,
)
from mimic.world.base import CYCLE_S, World
from mimic.world.registry import open_world, world_kind

__all__ = [
    "GetupTask",
    "GetupObjective",
    "GetupRun",
    "getup_summary",
    "GetupTrialConfig",
    "run_getup_episode",
    "getup_scene",
    "play_getup",
    "SIDES",
]

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


def getup_scene(
    config: GetupTrialConfig,
    side: str,
    *,
    noise: PoseNoise | None = None,
    pose_rad: np.ndarray | None = None,
) -> Scene:
    """Lying on ``side`` at the field's centre facing +x, in the stand pose (or ``pose_rad``,
    (N,) [rad]) with the config's noise (or ``noise``)."""
    return Scene(
        posture=f"lying_{side}",
        settle_s=config.settle_s,
        noise=PoseNoise(
            position_m=config.start_noise_pos_m,
            yaw_rad=config.start_noise_yaw_rad,
            joint_rad=config.start_noise_joint_rad,
            distribution="uniform",
        )
        if noise is None
        else noise,
        pose_rad=None if pose_rad is None else tuple(pose_rad),
    )


class _TorsoExtremes(Observer):
    """The highest the torso got [m] and when (cycles counted from the observer's first), and
    the lowest its forward axis pointed (the z of the unit axis: -1 facing the ground)."""

    def __init__(self) -> None:
        self.height_m = 0.0
        self.forward_z = 1.0
        self.cycles = 0
        self.highest_cycle = 0

    def after_step(self, world) -> None:
        self.cycles += 1
        height = float(world.torso_pos_m()[2])
        if height > self.height_m:
            self.height_m, self.highest_cycle = height, self.cycles
        self.forward_z = min(self.forward_z, float(world.torso_forward_z()))


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
    run_row, trace = play_getup(world, getup.build(), seed, config)
    row = as_row(run_row)
    summary = dict(row, trace=trace) if trace is not None else row
    return [row], summary


def play_getup(
    world: World,
    agent: Agent,
    seed: int,
    config: GetupTrialConfig,
    *,
    noise: PoseNoise | None = None,
    pose_rad: np.ndarray | None = None,
    observers: tuple[Observer, ...] = (),
) -> tuple[GetupRun, EpisodeTrace | None]:
    """One get-up of ``agent`` in ``world`` (module docstring): the run's row and, with
    ``config.trace``, its pose trace. ``noise`` and ``pose_rad``: the lying robot's start
    noise and pose, in place of the config's noise and the stand pose (``getup_scene``);
    ``observers``: more observers of the get-up and the hold after it."""
    disturb = EpisodeDisturbances(config.disturb, seed, world)
    disturb.apply_physics(world)
    side = config.side_for(agent.start_posture)
    trace = PoseTrace() if config.trace else None
    episode = Episode(world, observers=(trace, disturb.pusher) if trace else (disturb.pusher,))
    scene = getup_scene(config, side, noise=noise, pose_rad=pose_rad)
    scene.setup(world, np.random.default_rng(seed), observers=episode.watchers)
    disturb.start_delay(episode, lying=True)
    log = UprightLog()
    extremes = _TorsoExtremes()
    t0 = world.time_s
    disturb.pusher.arm(world)
    agent = disturb.agent(agent)
    outcome = run(
        world,
        agent,
        max_s=config.timeout_s,
        observers=(*episode.watchers, log, extremes, *observers),
    )
    motion_s = world.time_s - t0
    last = agent.reference_rad
    if last is not None and config.after_s > 0:
        run(
            world,
            HoldPose(np.asarray(last, float), world.robot.name),
            max_s=config.after_s,
            observers=(*episode.watchers, log, extremes, *observers),
        )
    upright = bool(world.upright())
    # The run of upright cycles that reaches the end, counted back.
    k = len(log.upright)
    while upright and k > 0 and log.upright[k - 1]:
        k -= 1
    run_row = GetupRun(
        seed=seed,
        side=side,
        stood=upright,
        time_to_stand_s=k * CYCLE_S if upright else None,
        motion_s=motion_s,
        end={"done": "done", "timeout": "timeout", "stop": "stop", "fell": "fell"}[outcome.end],
        torso_height_m=float(world.torso_pos_m()[2]),
        max_torso_height_m=extremes.height_m,
        max_torso_height_s=extremes.highest_cycle * CYCLE_S,
        min_torso_forward_z=extremes.forward_z,
        upright_s=float(sum(log.upright)) * CYCLE_S,
        first_upright_s=log.upright.index(True) * CYCLE_S if any(log.upright) else None,
        duration_s=world.time_s,
        falls=0 if upright else 1,
        world=world_kind(config.world),
        disturbances=disturb.columns(),
    )
    return run_row, None if trace is None else disturb.traced(trace.trace())


@dataclass(frozen=True)
class GetupRun:
    """One get-up from lying on ``side``."""

    seed: int
    # front or back.
    side: str
    # Upright (``World.upright``) at the run's end.
    stood: bool
    # From the get-up's start to the first cycle after which it stayed upright [s]; None if
    # it did not stand.
    time_to_stand_s: float | None
    # How long the get-up itself played [s].
    motion_s: float
    # done, timeout, stop or fell.
    end: str
    # The torso's height at the end and the highest it got [m].
    torso_height_m: float
    max_torso_height_m: float
    # When the torso was highest, from the get-up's start [s].
    max_torso_height_s: float
    # The lowest the torso's forward axis pointed during the run (z of the unit axis: -1
    # facing the ground; a back get-up that rolls onto its front goes below 0).
    min_torso_forward_z: float
    # Time the robot was upright during the run, in all (``World.upright``) [s].
    upright_s: float
    # From the get-up's start to the first cycle it was upright [s] (None: never upright),
    # whether or not it stayed up (``time_to_stand_s``: from when it stayed).
    first_upright_s: float | None
    # Simulated time at the run's end, settling included [s].
    duration_s: float
    # 1 if it did not stand.
    falls: int
    world: str
    # The episode's disturbance draw (``EpisodeDisturbances.columns``).
    disturbances: dict


def getup_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the get-up table: how many runs stood up, and how fast."""
    runs = pl.DataFrame(batch.rows)
    stood = runs.filter(pl.col("stood"))
    times = stood["time_to_stand_s"].cast(pl.Float64).to_numpy()
    return dict(
        variant=label,
        runs=runs.height,
        stood=stood.height,
        success_pct=100.0 * stood.height / runs.height,
        **ci_columns("success_pct", wilson_interval(stood.height, runs.height), 100.0),
        mean_time_to_stand_s=float(times.mean()) if len(times) else None,
        **ci_columns("mean_time_to_stand_s", mean_interval(times)),
        std_time_to_stand_s=float(times.std(ddof=1)) if len(times) > 1 else 0.0,
        falls=runs.height - stood.height,
        simulated_min=batch.simulated_s / 60,
        world=first_value(batch.rows, "world"),
        side=first_value(batch.rows, "side"),
        disturb=first_value(batch.rows, "disturb"),
    )


def getup_rank(summary_row: dict) -> tuple[float, float]:
    """``--keep-best``: more runs stood up, then a shorter mean time to stand."""
    time_s = summary_row["mean_time_to_stand_s"]
    return summary_row["success_pct"], -(math.inf if time_s is None else time_s)


@dataclass(frozen=True)
class GetupObjective:
    """What ``mimic improve --objective getup`` maximises: the share of get-up trial runs
    that stood up, less ``time_weight_per_s`` per second they took (mean over runs). A run
    that stays down counts the trial's whole ``timeout_s``, plus ``height_credit_per_m`` per
    metre its torso rose at its highest, ``turn_credit`` times how far its torso turned to
    face the ground ((1 - the lowest z of its forward axis) / 2: 0 on its back, 1 face
    down) and ``upright_credit_per_s`` per second it was upright. So a search has stages to
    climb where nothing stands: sitting up, rolling from the back onto the front (the T1's
    back get-up), rising, standing a while before it topples; a run that stands scores
    above any that does not (docs/getups.md has the figures)."""

    # Get-up trial runs per candidate evaluation.
    episodes: int = 4
    # Score lost per second to stand [1/s] (a 6 s get-up that stands: 1 - 0.06 = 0.94).
    time_weight_per_s: float = 0.01
    # A run that stays down: credit per metre its torso rose at its highest [1/m] (a search
    # that starts where nothing stands up gets a slope to climb; a T1 kneeling 0.35 m up
    # earns 0.17, less than any run that stands).
    height_credit_per_m: float = 0.5
    # A run that stays down: credit for turning to face the ground (class docstring; a
    # back get-up that sits up and falls back earns about 0.05, one that rolls onto its
    # front 0.2; a front get-up's runs all earn 0.2, so it ranks them as before).
    turn_credit: float = 0.2
    # A run that stays down: credit per second it was upright on the way (at most
    # ``upright_credit_cap_s``), so a search whose candidates rise and topple can climb to
    # one that stays up (4 s upright earns 0.2; the credits in all stay below any run that
    # stands).
    upright_credit_per_s: float = 0.05
    upright_credit_cap_s: float = 4.0
    # The get-up trial's settings.
    trial_config: GetupTrialConfig = GetupTrialConfig()

    name: ClassVar[str] = "getup"
    #: A get-up scores success, not falls: ``--fall-penalty`` does not apply.
    fall_penalty_setting: ClassVar[str | None] = None
    episode_fn = staticmethod(run_getup_episode)
    summarise = staticmethod(getup_summary)

    @property
    def search_config(self) -> GetupTrialConfig:
        return self.trial_config

    def score(self, batch: EpisodeBatch) -> float:
        """Share of runs that stood, less the time weight per second they took; a run that
        stayed down: the whole time, plus the height, turn and upright credits."""
        w, limit, credit, turn, up, cap = (
            self.time_weight_per_s,
            self.trial_config.timeout_s,
            self.height_credit_per_m,
            self.turn_credit,
            self.upright_credit_per_s,
            self.upright_credit_cap_s,
        )
        return float(
            np.mean(
                [
                    (1.0 - w * r["time_to_stand_s"])
                    if r["stood"]
                    else -w * limit
                    + credit * r.get("max_torso_height_m", 0.0)
                    + turn * (1.0 - r.get("min_torso_forward_z", 1.0)) / 2
                    + up * min(r.get("upright_s", 0.0), cap)
                    for r in batch.rows
                ]
            )
        )

    def describe(self) -> dict:
        return dict(
            name=self.name,
            episodes=self.episodes,
            time_weight_per_s=self.time_weight_per_s,
            height_credit_per_m=self.height_credit_per_m,
            turn_credit=self.turn_credit,
            upright_credit_per_s=self.upright_credit_per_s,
            upright_credit_cap_s=self.upright_credit_cap_s,
            trial_config=asdict(self.trial_config),
        )


class GetupTask(TrialTask):
    """The get-up trial (module docstring)."""

    name = "getup"
    summary = (
        "Get-up trial: the robot knocked down on its front or back gets up; success rate "
        "and time to stand, repeated."
    )
    options = (
        TaskOption(
            "side",
            "--side",
            "Lay the robot on its front or back (default: the side each get-up starts from).",
            str,
        ),
    )
    Config = GetupTrialConfig
    Objective = GetupObjective
    validation_episodes = 20
    columns = (
        Column("variant", "variant"),
        Column("side", "side"),
        Column("runs", "runs"),
        Column("stood", "stood"),
        Column("success_pct", "stood %", "success_pct", "range"),
        Column("mean_time_to_stand_s", "time s", "mean_time_to_stand_s"),
        Column("std_time_to_stand_s", "std s"),
        Column("mean_time_to_stand_s_ratio", "time ratio"),
    )
    legend = (
        "stood: runs upright at their end; time: from the get-up's start until the robot "
        "stayed upright. 95% CI: of the share that stood (Wilson) and of the mean time (t, +- "
        "half width). Ratios: against the first variant."
    )
    ratio_columns = ("success_pct", "mean_time_to_stand_s")
    ratio_sources = {"mean_time_to_stand_s": "time_to_stand_s"}
    dashboard = Dashboard(
        curves=("time_to_stand_s", "max_torso_height_m"),
        histogram="time_to_stand_s",
        histogram_bins=(0.0, 20.5, 0.5),
    )
    run_episode = staticmethod(run_getup_episode)
    summarise = staticmethod(getup_summary)
    rank = staticmethod(getup_rank)
    rank_says = "more runs stood, then a shorter mean time to stand"

    @classmethod
    def default_variant(cls, robot: str, config: GetupTrialConfig) -> str:
        return f"getup_{config.side or 'front'}"

    @classmethod
    def title(cls, config: GetupTrialConfig) -> str:
        return "get-up trial"

    @classmethod
    def check(cls, config: GetupTrialConfig, specs: list[AgentSpec]) -> None:
        """Each variant lies down on a side: its own, or the one given."""
        for spec in specs:
            config.side_for(spec.build().start_posture)
