"""The kick trial: ball at the centre spot, kick toward the goal, reach the ball, kick
again, until a goal; then reset and repeat. One episode is one call of ``run_kick_episode``.

The episode plays in the world ``config.world`` names (``world.registry``: ours or the league's
server). The ball starts ``start_goal_distance_m`` before the opponent goal line of that world's
field (15 m: the centre spot of the study's 30 m field). The robot reaches the ball
(``config.reach``) by walking there with our walk engine (the NAO) or by being placed behind it
facing the goal, with the same small noise as the start (``place``, as a beam: any robot, any
world; after a fall it is placed standing again). In the league the referee ends a kick when it
acts: a goal, or a ball over a line that it puts back for a throw-in or a goal kick.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from typing import ClassVar

import numpy as np
import polars as pl

from mimic import options
from mimic.agents.hold import HoldPose
from mimic.agents.registry import AgentSpec
from mimic.agents.walk import make_walk_agent
from mimic.agents.walk.goto import GoToPose, pose_behind_ball
from mimic.episode import Episode, Observer, PoseNoise, PoseTrace, Scene
from mimic.episode.disturbance import EpisodeDisturbances
from mimic.episode.scene import BALL_ASIDE_M, SETTLE_S
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
from mimic.tasks.budget import CHECKPOINTS, Checkpoint, episode_cap_s
from mimic.world.base import World
from mimic.world.registry import MUJOCO, get_world, open_world, world_kind

__all__ = [
    "KickTask",
    "KickObjective",
    "KickRow",
    "KickEpisode",
    "kick_summary",
    "KickTrialConfig",
    "run_kick_episode",
    "kick_scene",
    "SUCCESS_DISTANCE_M",
    "REACH_METHODS",
    "reach_method",
]

#: A kick counts as successful when the ball travels farther than this (the study's rule) [m].
SUCCESS_DISTANCE_M = 2.0
#: How the robot gets back to the ball: walking (our walk engine) or placed behind it.
REACH_METHODS = ("walk", "place")
#: Each way to reach the ball, as a trial's title says it.
_REACH_TEXT = {
    "place": "robot placed behind the ball after each kick",
    "walk": "robot walks to the ball",
}


@dataclass(frozen=True)
class KickTrialConfig:
    """Settings of one kick-trial episode."""

    # Longest simulated time one episode may take [s].
    episode_limit_s: float = 240.0
    # Longest walk to the ball before the episode is declared stuck [s].
    walk_timeout_s: float = 90.0
    # The walk aims this much farther behind the ball than the kick's offset [m]: its last
    # steps carry it a few cm on, and a swing foot that reaches the ball nudges it away.
    approach_back_off_m: float = 0.02
    # Lined up: the ball lies within this distance of the kick's ball offset, forward and
    # sideways [m]; otherwise (the walk nudged the ball, or stopped off target) walk again, at
    # most ``lineup_attempts`` times.
    lineup_tolerance_x_m: float = 0.05
    lineup_tolerance_y_m: float = 0.03
    lineup_attempts: int = 6
    # Ball counts as stopped below this speed [m/s].
    ball_rest_speed_m_s: float = 0.02
    # Longest wait for the ball to stop after a kick [s].
    ball_wait_s: float = 15.0
    # Start-pose noise: position [m], heading [rad], joint angles [rad].
    start_noise_pos_m: float = 0.01
    start_noise_yaw_rad: float = math.radians(2)
    start_noise_joint_rad: float = math.radians(1)
    # Keep a pose trace of the episode (robot bodies and ball) for the Rerun replay.
    trace: bool = False
    # Where episodes play (``world.registry``): ``mujoco`` (ours), ``league`` (RCSSServerMJ's
    # simulation in this process), ``league-server`` (a hosted server) or ``league-like``.
    world: str = MUJOCO
    # How the robot reaches the ball (``REACH_METHODS``); ``auto``: walk for the NAO in our
    # world, place otherwise (the walk engine is the NAO's).
    reach: str = "auto"
    # The ball's first spot lies this far before the opponent goal line, on the field's axis
    # [m] (15 m: the study's centre spot).
    start_goal_distance_m: float = 15.0
    # ``league-server`` only: the command that starts the server (None: ``python -m rcsssmj``).
    server_command: tuple[str, ...] | None = None
    # A kick succeeds when the ball travels farther than this [m] (the study's 2 m; a shorter
    # kick, such as the T1 other team's 1 m kick inside its walk, needs its own rule).
    success_distance_m: float = SUCCESS_DISTANCE_M
    # Disturbance level (``episode.disturbance.DISTURB_LEVELS``): none, game or hard. The
    # library's default is none (the undisturbed trial); ``mimic trial`` defaults to game.
    disturb: str = "none"


def _walk_engine_world(world: str) -> bool:
    """Our walk engine can walk to the ball in this world: it steps the physics itself and
    a command acts at once (the engine's timing was tuned so), on our field."""
    spec = get_world(world)
    return spec.owns_physics and spec.command_delay_cycles == 0 and not spec.league_field


def reach_method(config: KickTrialConfig, robot: str) -> str:
    """How this trial reaches the ball with this robot (``config.reach`` resolved).

    Raises:
        MimicError: ``walk`` for a robot our walk engine cannot drive, or an unknown method.
    """
    walkable = _walk_engine_world(config.world)
    if config.reach == "auto":
        return "walk" if robot == "nao" and walkable else "place"
    if config.reach not in REACH_METHODS:
        raise MimicError(
            f"unknown way to reach the ball {config.reach!r}; one of: auto, "
            f"{', '.join(REACH_METHODS)}"
        )
    if config.reach == "walk" and robot != "nao":
        raise MimicError(
            f"our walk engine drives the NAO only, not the {robot}; reach the ball with 'place'"
        )
    if config.reach == "walk" and not walkable:
        raise MimicError(
            "walking to the ball needs our MuJoCo world (the NAO); in the league "
            "the robot is placed behind the ball"
        )
    return config.reach


def _direction_error_rad(start_xy: np.ndarray, end_xy: np.ndarray, goal_x_m: float) -> float:
    """Angle between the ball's travel and the line from its start to the goal centre."""
    travel = end_xy - start_xy
    to_goal = np.array([goal_x_m, 0.0]) - start_xy
    if np.linalg.norm(travel) < 1e-6:
        return math.pi
    cos = travel @ to_goal / (np.linalg.norm(travel) * np.linalg.norm(to_goal))
    return float(math.acos(max(-1.0, min(1.0, cos))))


def kick_scene(offset_m, config: KickTrialConfig, goal_x_m: float) -> Scene:
    """Robot behind the start spot facing the opponent goal (line at ``goal_x_m``), settled in
    its stand; then the ball at the kick's offset from the settled torso (the feet move a
    little while settling)."""
    start_x = goal_x_m - config.start_goal_distance_m
    return Scene(
        robot_xy_m=(start_x - offset_m[0], -offset_m[1]),
        ball_offset_m=tuple(offset_m),
        ball_after_settle=True,
        settle_s=SETTLE_S,
        settle_into_stand=True,
        noise=PoseNoise(
            position_m=config.start_noise_pos_m,
            yaw_rad=config.start_noise_yaw_rad,
            joint_rad=config.start_noise_joint_rad,
        ),
    )


def _walk_to_ball(
    episode: Episode,
    offset_m,
    config: KickTrialConfig,
    limit_s: Callable[[], float],
    goal_x_m: float,
) -> str:
    """Walk behind the ball facing the goal until lined up: ``arrived``, ``fell``, ``timeout``
    (the walk took too long, or reached the episode's limit ``limit_s()``) or ``not lined
    up`` (every attempt ended off the ball)."""

    world = episode.world
    start_s = world.time_s
    for _ in range(config.lineup_attempts):
        deadline_s = start_s + min(config.walk_timeout_s, limit_s() - start_s)
        goto = GoToPose(make_walk_agent())
        ball = world.ball_pos_m()[:2]
        aim = (offset_m[0] + config.approach_back_off_m, offset_m[1])
        goto.set_target(*pose_behind_ball(ball, np.array([goal_x_m, 0.0]), aim))
        outcome = episode.run(
            goto, max_s=deadline_s - world.time_s, stop=lambda w, goto=goto: goto.arrived
        )
        if outcome not in ("stop", "done"):
            return outcome  # fell or timeout
        if episode.stand_still(max_s=0.4) == "fell":
            return "fell"
        error = world.ball_in_robot_frame_m() - np.asarray(offset_m)
        if (
            abs(error[0]) <= config.lineup_tolerance_x_m
            and abs(error[1]) <= config.lineup_tolerance_y_m
        ) or world.goal_scored():
            return "arrived"
    return "not lined up"


def _place_behind_ball(
    episode: Episode, offset_m, config: KickTrialConfig, rng: np.random.Generator, goal_x_m: float
) -> str:
    """Put the robot behind the ball facing the goal, with the start's noise drawn from
    ``rng`` (x, y, heading, joints), and let it settle into its stand: ``arrived`` or
    ``fell``."""

    world, robot = episode.world, episode.world.robot
    ball = world.ball_pos_m()[:2].copy()
    x, y, yaw = pose_behind_ball(ball, np.array([goal_x_m, 0.0]), offset_m)
    noise = rng.normal(0.0, config.start_noise_pos_m, 2)
    yaw += float(rng.normal(0.0, config.start_noise_yaw_rad))
    pose = robot.clip(
        robot.stand_pose() + rng.normal(0.0, config.start_noise_joint_rad, robot.num_joints)
    )
    # The ball waits aside (toward the field's long axis, so inside the lines) while the robot
    # appears and settles: the league's server puts a robot down with straight joints, and its
    # feet swing through the ball's spot on the way into the stand. Then the ball goes back
    # to where it lay, at rest.
    world.place_ball(ball[0], ball[1] - math.copysign(BALL_ASIDE_M, ball[1]))
    world.place_robot(x + noise[0], y + noise[1], yaw, pose)
    episode.falls.update(world)  # a robot lying before is standing now
    outcome = episode.run(
        HoldPose(robot.stand_pose(), robot.name), max_s=SETTLE_S, stop_when_done=False
    )
    world.place_ball(*ball)
    return "fell" if outcome == "fell" else "arrived"


@dataclass(frozen=True)
class KickRow:
    """One kick: from where the ball lay to where it stopped (or left play) [m, field frame]."""

    # The kick's number in its episode, from 0.
    kick: int
    # Simulated time the kick started [s].
    time_s: float
    # Straight distance the ball travelled [m].
    distance_m: float
    # Farther than the trial's ``success_distance_m``.
    success: bool
    # Angle between the ball's travel and the line from its start to the goal centre [deg].
    direction_error_deg: float
    goal: bool
    # The ball left the field (our world) or the league's referee called it out.
    ball_out: bool
    # The robot fell during the kick or the wait after it.
    fell: bool
    ball_start_x_m: float
    ball_start_y_m: float
    ball_end_x_m: float
    ball_end_y_m: float
    # Where the ball lay in the robot's frame before the kick, less the kick's ball offset [m].
    lineup_error_x_m: float
    lineup_error_y_m: float
    # Pushes begun during the kick and the wait after it.
    pushes_during_kick: int


#: The episode's disturbance draw repeated beside every kick (``EpisodeDisturbances.columns``).
_DRAW_PER_KICK = ("disturb", "friction_scale", "mass_scale", "start_delay_s")


@dataclass(frozen=True)
class KickEpisode:
    """One kick-trial episode: kicks until a goal, the ball out, or the time limit."""

    seed: int
    # Simulated time the episode took [s] (cut by its trial's budget: to the budget's end).
    duration_s: float
    kicks: int
    # 1 if the episode ended in a goal from a kick.
    goals: int
    # 1 if the ball went in while the robot walked to it (no kick's credit).
    goals_while_walking: int
    falls: int
    getups: int
    # Why it ended: goal, ball out, time limit, could not get up, could not stand, stuck: ...,
    # or budget (its trial's budget ended in it: what it counted by then).
    end: str
    stuck: bool
    world: str
    # How the robot reached the ball: walk or place.
    reach: str
    # The episode's disturbance draw (``EpisodeDisturbances.columns``).
    disturbances: dict


class _Checkpoints(Observer):
    """Where a trial whose budget ends in this kick episode may cut it (``tasks.budget``):
    the episode's rows and summary as of now, taken at its start, after each kick, and
    after each cycle in which something its summary counts changed (a fall, a get-up, a
    push, a start delay). Between two checkpoints nothing the trial counts changes, so it
    can count the episode to any time (the last checkpoint before, with that duration)."""

    def __init__(self, counts: Callable[[], tuple], ended: Callable[[], tuple]) -> None:
        self.points: list[Checkpoint] = []
        self._counts, self._ended = counts, ended
        self._seen: tuple | None = None

    def add(self, world: World) -> None:
        self._seen = self._counts()
        self.points.append((world.time_s, *self._ended()))

    def after_step(self, world: World) -> None:
        if self._counts() != self._seen:
            self.add(world)


class _BallWatch:
    """Stop condition of the wait after a kick: the ball has come to rest and ``waited(world)``
    holds, or the league's referee has acted. Remembers where the ball was last seen in play:
    when the referee calls it out it puts the ball back on a line at once, so that is where the
    kick took it."""

    def __init__(
        self, config: KickTrialConfig, waited: Callable[[World], bool], referee: bool
    ) -> None:
        self.rest_m_s, self.waited, self.referee = config.ball_rest_speed_m_s, waited, referee
        self.in_play_xy: np.ndarray | None = None

    def __call__(self, world: World) -> bool:
        if _referee(world, self.referee) is not None:
            return True
        self.in_play_xy = world.ball_pos_m()[:2]
        return world.ball_speed_m_s() < self.rest_m_s and self.waited(world)


def _referee(world: World, referee: bool) -> str | None:
    """What the league's referee made of the ball: ``goal``, ``out`` (a throw-in, corner or
    goal kick: it has put the ball back) or None (nothing yet, or no referee: ``referee``
    False, our world)."""
    if not referee:
        return None
    mode = world.play_mode()
    if mode == "BeforeKickOff":
        return None
    return "goal" if mode.startswith("Goal_") else "out"


def run_kick_episode(
    kick: AgentSpec, seed: int, config: KickTrialConfig = KickTrialConfig()
) -> tuple[list[dict], dict]:
    """Play one episode in ``config.world``; returns (one row per kick, the episode's summary
    row)."""
    with open_world(config.world, kick.robot, server_command=config.server_command) as world:
        return _play_kick_episode(world, kick, seed, config)


def _play_kick_episode(
    world: World, kick: AgentSpec, seed: int, config: KickTrialConfig
) -> tuple[list[dict], dict]:
    rng = np.random.default_rng(seed)
    disturb = EpisodeDisturbances(config.disturb, seed, world)
    disturb.apply_physics(world)
    reach = reach_method(config, kick.robot)
    referee = get_world(config.world).league_referee
    goal_x = world.field.opponent_goal_x_m
    trace = PoseTrace() if config.trace else None
    rows: list[KickRow] = []
    marks = _Checkpoints(
        lambda: (
            falls.falls,
            falls.getups,
            len(disturb.pusher.pushed),
            len(disturb.start_delays_s),
        ),
        lambda: ended("budget"),
    )
    episode = Episode(world, observers=(*((trace,) if trace else ()), disturb.pusher, marks))
    falls = episode.falls

    def ended(end: str) -> tuple[list[dict], dict]:
        """The episode's kick rows and summary row had it ended now, for ``end``."""
        draw = disturb.columns()
        summary = KickEpisode(
            seed=seed,
            duration_s=world.time_s,
            kicks=len(rows),
            goals=int(any(r.goal for r in rows)),
            goals_while_walking=int(end == "goal while walking"),
            falls=falls.falls,
            getups=falls.getups,
            end=end,
            stuck=end.startswith("stuck"),
            world=world_kind(config.world),
            reach=reach,
            disturbances=draw,
        )
        # The episode's draw beside every kick.
        kicks = [as_row(r) | {k: draw[k] for k in _DRAW_PER_KICK} for r in rows]
        return kicks, as_row(summary)

    def limit_s() -> float:  # the config's limit, or less as the trial's budget runs out
        return min(config.episode_limit_s, episode_cap_s(world.time_s))

    def left_s() -> float:
        return limit_s() - world.time_s

    offset = kick.ball_offset_m()
    kick_scene(offset, config, goal_x).setup(world, rng, observers=episode.watchers)
    disturb.start_delay(episode)
    disturb.pusher.arm(world)
    marks.add(world)  # the episode set up: a budget may end before its first kick
    end = "time limit"
    while left_s() > 0:
        start_xy = world.ball_pos_m()[:2]
        start_t = world.time_s
        lineup = world.ball_in_robot_frame_m()
        falls_before = falls.falls
        pushes_before = len(disturb.pusher.pushed)
        outcome = episode.run(disturb.agent(kick.build()), max_s=min(10.0, left_s()))
        pushed = len(disturb.pusher.pushed) - pushes_before
        if outcome != "fell":
            watch = _BallWatch(config, lambda w: w.time_s - start_t > 1.0, referee)  # noqa: B023 (used in this iteration)
            episode.stand_still(max_s=min(config.ball_wait_s, left_s()), stop=watch)
        else:  # the ball still rolls while the robot lies (placed anew next: a falling
            # robot may still push the ball, so wait until it has lain a second)
            fell_t = world.time_s
            watch = _BallWatch(
                config,
                (lambda w: w.time_s - fell_t > 1.0)  # noqa: B023
                if reach == "place"
                else (lambda w: True),
                referee,
            )
            episode.wait_limp(max_s=min(config.ball_wait_s, left_s()), stop=watch)
        called = _referee(world, referee)
        end_xy = world.ball_pos_m()[:2]
        if called == "out" and watch.in_play_xy is not None:
            end_xy = watch.in_play_xy
        distance = float(np.linalg.norm(end_xy - start_xy))
        rows.append(
            KickRow(
                kick=len(rows),
                time_s=start_t,
                distance_m=distance,
                success=distance > config.success_distance_m,
                direction_error_deg=math.degrees(_direction_error_rad(start_xy, end_xy, goal_x)),
                goal=bool(world.goal_scored()) or called == "goal",
                ball_out=bool(world.ball_out()) or called == "out",
                fell=falls.falls > falls_before,
                ball_start_x_m=float(start_xy[0]),
                ball_start_y_m=float(start_xy[1]),
                ball_end_x_m=float(end_xy[0]),
                ball_end_y_m=float(end_xy[1]),
                lineup_error_x_m=float(lineup[0] - offset[0]),
                lineup_error_y_m=float(lineup[1] - offset[1]),
                pushes_during_kick=pushed,
            )
        )
        marks.add(world)
        if rows[-1].goal:
            end = "goal"
            break
        if rows[-1].ball_out:
            end = "ball out"
            break
        if reach == "place":
            walk = _place_behind_ball(episode, offset, config, rng, goal_x)
            if walk == "fell" or disturb.start_delay(episode) == "fell":
                end = "could not stand"  # even placed anew it does not stand: give up
                break
            continue
        if world.fallen() and not episode.get_up():
            end = "could not get up"
            break
        walk = _walk_to_ball(episode, offset, config, limit_s, goal_x)
        while walk == "fell" and left_s() > 0:
            if not episode.get_up():
                break
            walk = _walk_to_ball(episode, offset, config, limit_s, goal_x)
        if world.goal_scored():  # pushed in while walking: a goal, but no kick's credit
            end = "goal while walking"
            break
        if walk != "arrived":
            end = "could not get up" if walk == "fell" else f"stuck: {walk}"
            break
    kicks, episode_row = ended(end)
    episode_row[CHECKPOINTS] = marks.points
    if trace is not None:
        episode_row["trace"] = disturb.traced(trace.trace())
    return kicks, episode_row


def kick_summary(label: str, batch: EpisodeBatch) -> dict:
    """One row of the kick table."""
    kicks = (
        pl.DataFrame(batch.rows)
        if batch.rows
        else pl.DataFrame(
            {"distance_m": [], "success": [], "direction_error_deg": []},
            schema={
                "distance_m": pl.Float64,
                "success": pl.Boolean,
                "direction_error_deg": pl.Float64,
            },
        )
    )
    eps = pl.DataFrame(batch.episodes)
    n = kicks.height
    ok = int(kicks["success"].sum()) if n else 0
    return dict(
        variant=label,
        attempts=n,
        successful=ok,
        accuracy_pct=100.0 * kicks["success"].mean() if n else 0.0,
        **ci_columns("accuracy_pct", wilson_interval(ok, n), 100.0),
        mean_distance_m=kicks["distance_m"].mean() if n else 0.0,
        **ci_columns("mean_distance_m", mean_interval(kicks["distance_m"].to_numpy())),
        std_distance_m=kicks["distance_m"].std() if n > 1 else 0.0,
        mean_direction_error_deg=kicks["direction_error_deg"].mean() if n else 0.0,
        goals=int(eps["goals"].sum()),
        goals_while_walking=int(eps["goals_while_walking"].sum()) if n else 0,
        falls=int(eps["falls"].sum()),
        getups=int(eps["getups"].sum()),
        stuck=int(eps["stuck"].sum()),
        episodes=eps.height,
        simulated_min=batch.simulated_s / 60,
        world=first_value(batch.episodes, "world"),
        reach=first_value(batch.episodes, "reach"),
        disturb=first_value(batch.episodes, "disturb"),
    )


@dataclass(frozen=True)
class KickObjective:
    """What ``mimic improve --objective kick`` maximises: kick distance and accuracy, the
    mean over kicks of distance x success [m] (a kick succeeds when the ball travels more
    than the trial's ``success_distance_m``, the study's 2 m unless set; 0 scores plain
    distance), minus ``fall_penalty_m`` per fall per kick. The search plays kick-trial
    episodes (reach the ball, line up, kick, until a goal) cut at ``search_limit_s`` of
    simulated time to spend the budget on kicks; validation plays the trial unchanged."""

    # Trial episodes per candidate evaluation.
    episodes: int = 2
    # Simulated time of one search episode [s] (the trial's episodes run up to 240 s).
    search_limit_s: float = 60.0
    # Score lost per fall per kick [m].
    fall_penalty_m: float = 2.0
    # The kick trial's settings (validation runs them unchanged).
    trial_config: KickTrialConfig = KickTrialConfig()

    name: ClassVar[str] = "kick"
    #: The setting ``mimic improve --fall-penalty`` sets.
    fall_penalty_setting: ClassVar[str | None] = "fall_penalty_m"
    episode_fn = staticmethod(run_kick_episode)
    summarise = staticmethod(kick_summary)

    @property
    def search_config(self) -> KickTrialConfig:
        return replace(self.trial_config, episode_limit_s=self.search_limit_s)

    def score(self, batch: EpisodeBatch) -> float:
        """Mean distance x success [m] over the batch's kicks, minus the fall penalty."""
        falls = sum(e["falls"] for e in batch.episodes)
        kicks = len(batch.rows)
        if kicks == 0:
            return -self.fall_penalty_m * (1 + falls)
        success_m = self.trial_config.success_distance_m
        useful = np.mean([r["distance_m"] * (r["distance_m"] > success_m) for r in batch.rows])
        return float(useful - self.fall_penalty_m * falls / kicks)

    def describe(self) -> dict:
        return dict(
            name=self.name,
            episodes=self.episodes,
            search_limit_s=self.search_limit_s,
            fall_penalty_m=self.fall_penalty_m,
            success_distance_m=self.trial_config.success_distance_m,
            trial_config=asdict(self.trial_config),
        )


class KickTask(TrialTask):
    """The kick trial (module docstring)."""

    name = "kick"
    summary = (
        "Kick trial: kick toward the goal, reach the ball (walk there, or be placed behind "
        "it), kick again until a goal; repeat."
    )
    minutes = 30.0
    runs = None
    by_minutes = True
    options = (
        TaskOption(
            "success_distance_m",
            "--success-m",
            "A kick succeeds when the ball travels farther than this \\[m]; default: the "
            "study's 2 m. Give a shorter kick its own (e.g. 0.5 for a 1 m kick).",
        ),
    )
    Config = KickTrialConfig
    Objective = KickObjective
    event = "kick"
    # About 60 kicks.
    validation_episodes = 12
    columns = (
        Column("variant", "variant"),
        Column("attempts", "kicks"),
        Column("successful", "ok"),
        Column("accuracy_pct", "acc %", "accuracy_pct", "range"),
        Column("mean_distance_m", "dist m", "mean_distance_m"),
        Column("std_distance_m", "std m"),
        Column("goals", "goals"),
        Column("falls", "falls"),
        Column("stuck", "stuck"),
        Column("accuracy_pct_ratio", "acc ratio", "accuracy_pct_ratio"),
        Column("mean_distance_m_ratio", "dist ratio", "mean_distance_m_ratio"),
    )
    legend = (
        "95% CI: 95 % confidence interval of the accuracy (Wilson) and of the mean distance "
        "(t, +- half width). ok: kicks farther than {success_distance_m:g} m. stuck: episodes that ended "
        "because the robot could not reach the ball in time or could not line up with it. "
        "Ratios: against the first variant, with their 95 % interval (delta method)."
    )
    ratio_columns = ("accuracy_pct", "mean_distance_m", "std_distance_m", "goals")
    ratio_sources = {"mean_distance_m": "distance_m", "accuracy_pct": "success"}
    dashboard = Dashboard(
        curves=("distance_m",),
        running_rate=("success", "running_accuracy_pct"),
        histogram="distance_m",
        histogram_bins=(0.0, 21.0, 1.0),
        ball_ends=True,
        episode_markers=True,
    )
    run_episode = staticmethod(run_kick_episode)
    summarise = staticmethod(kick_summary)

    @classmethod
    def check(cls, config: KickTrialConfig, specs: list[AgentSpec]) -> None:
        """The success distance is a distance; every robot can reach the ball this way."""
        options.finite(config.success_distance_m, "--success-m", at_least=0)
        for spec in specs:
            reach_method(config, spec.robot)

    @classmethod
    def default_variant(cls, robot: str, config: KickTrialConfig) -> str:
        return "kick_right"

    @classmethod
    def played(cls, summary_row: dict) -> str | None:
        """How the robot reached the ball."""
        return _REACH_TEXT.get(summary_row.get("reach"))

    @classmethod
    def check_variant(cls, spec: AgentSpec) -> None:
        """A kick knows where its ball lies."""
        spec.ball_offset_m()

    @classmethod
    def counts(cls, batch: EpisodeBatch, minutes: float | None) -> str:
        goals = sum(e.get("goals", 0) for e in batch.episodes)
        return f"{len(batch.rows)} kicks {goals} goals"
