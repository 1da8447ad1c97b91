"""The kick trial: ball at the centre spot, kick toward the goal, walk to the ball, kick
again, until a goal; then reset and repeat. One episode is one call of ``run_kick_episode``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.trials.episode import EpisodeClock, FallCounter, get_up, run_until, stand_pose_rad, \
    stand_still
from mimic.trials.specs import AgentSpec
from mimic.trials.trace import TracingWorld
from mimic.world import field as F
from mimic.world.world import World

__all__ = ["KickTrialConfig", "run_kick_episode", "SUCCESS_DISTANCE_M"]

#: A kick counts as successful when the ball travels farther than this (the study's rule) [m].
SUCCESS_DISTANCE_M = 2.0


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


def _direction_error_rad(start_xy: np.ndarray, end_xy: np.ndarray) -> float:
    """Angle between the ball's travel and the line from its start to the goal centre."""
    travel = end_xy - start_xy
    to_goal = np.array([F.OPPONENT_GOAL_X_M, 0.0]) - start_xy
    if np.linalg.norm(travel) < 1e-6:
        return math.pi
    cos = travel @ to_goal / (np.linalg.norm(travel) * np.linalg.norm(to_goal))
    return float(math.acos(max(-1.0, min(1.0, cos))))


def _place_for_kick(world: World, offset_m, rng, config: KickTrialConfig,
                    falls: FallCounter) -> None:
    """Robot at the centre spot facing the opponent goal, settled in its stand; then the ball
    at the kick's offset from the settled torso (the feet move a little while settling)."""
    yaw = rng.normal(0, config.start_noise_yaw_rad)
    dx, dy = offset_m
    x = -(dx * math.cos(yaw) - dy * math.sin(yaw)) + rng.normal(0, config.start_noise_pos_m)
    y = -(dx * math.sin(yaw) + dy * math.cos(yaw)) + rng.normal(0, config.start_noise_pos_m)
    pose = stand_pose_rad() + rng.normal(0, config.start_noise_joint_rad, size=22)
    world.beam(x, y, yaw, pose)
    world.place_ball(0.0, F.FIELD_WIDTH_M / 2 - 1.0)  # out of the way while settling
    stand_still(world, max_s=0.5, falls=falls)
    torso, yaw = world.torso_pos_m(), world.torso_yaw_rad()
    world.place_ball(torso[0] + dx * math.cos(yaw) - dy * math.sin(yaw),
                     torso[1] + dx * math.sin(yaw) + dy * math.cos(yaw))


def _ball_in_robot_frame(world: World) -> np.ndarray:
    """Ball centre relative to the torso, robot frame (x forward, y left) [m]."""
    d = world.ball_pos_m()[:2] - world.torso_pos_m()[:2]
    c, s = math.cos(world.torso_yaw_rad()), math.sin(world.torso_yaw_rad())
    return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]])


def _walk_to_ball(world: World, offset_m, falls: FallCounter, config: KickTrialConfig,
                  clock: EpisodeClock) -> str:
    """Walk behind the ball facing the goal until lined up: ``arrived``, ``fell``, ``timeout``
    (the walk took too long) or ``not lined up`` (every attempt ended off the ball)."""
    from mimic.agents.walk import make_walk_agent
    from mimic.agents.walk.goto import GoToPose, pose_behind_ball
    deadline_s = world.time_s + min(config.walk_timeout_s, clock.left_s(world))
    for _ in range(config.lineup_attempts):
        goto = GoToPose(make_walk_agent())
        ball = world.ball_pos_m()[:2]
        aim = (offset_m[0] + config.approach_back_off_m, offset_m[1])
        goto.set_target(*pose_behind_ball(ball, np.array([F.OPPONENT_GOAL_X_M, 0.0]), aim))
        outcome = run_until(world, goto, max_s=deadline_s - world.time_s, falls=falls,
                            stop=lambda w: goto.arrived)
        if outcome not in ("stop", "done"):
            return outcome  # fell or timeout
        if stand_still(world, max_s=0.4, falls=falls) == "fell":
            return "fell"
        error = _ball_in_robot_frame(world) - np.asarray(offset_m)
        if (abs(error[0]) <= config.lineup_tolerance_x_m
                and abs(error[1]) <= config.lineup_tolerance_y_m) or world.goal_scored():
            return "arrived"
    return "not lined up"


def run_kick_episode(kick: AgentSpec, seed: int, config: KickTrialConfig = KickTrialConfig()
                     ) -> tuple[list[dict], dict]:
    """Play one episode; returns (one row per kick, the episode's summary row)."""
    rng = np.random.default_rng(seed)
    world = TracingWorld() if config.trace else World()
    world.reset()
    offset = kick.ball_offset_m()
    falls, clock = FallCounter(), EpisodeClock(config.episode_limit_s)
    _place_for_kick(world, offset, rng, config, falls)
    rows: list[dict] = []
    end = "time limit"
    while clock.left_s(world) > 0:
        start_xy = world.ball_pos_m()[:2]
        start_t = world.time_s
        lineup = _ball_in_robot_frame(world)
        falls_before = falls.falls
        outcome = run_until(world, kick.build(), max_s=min(10.0, clock.left_s(world)),
                            falls=falls)
        if outcome != "fell":
            stand_still(world, max_s=min(config.ball_wait_s, clock.left_s(world)), falls=falls,
                        stop=lambda w: w.ball_speed_m_s() < config.ball_rest_speed_m_s
                        and w.time_s - start_t > 1.0)
        else:  # the ball still rolls while the robot lies
            run_until(world, _Limp(), max_s=min(config.ball_wait_s, clock.left_s(world)),
                      falls=falls, stop=lambda w: w.ball_speed_m_s() < config.ball_rest_speed_m_s,
                      abort_on_fall=False)
        end_xy = world.ball_pos_m()[:2]
        distance = float(np.linalg.norm(end_xy - start_xy))
        rows.append(dict(
            kick=len(rows), time_s=start_t, distance_m=distance,
            success=distance > SUCCESS_DISTANCE_M,
            direction_error_deg=math.degrees(_direction_error_rad(start_xy, end_xy)),
            goal=bool(world.goal_scored()), ball_out=bool(world.ball_out()),
            fell=falls.falls > falls_before,
            ball_start_x_m=float(start_xy[0]), ball_start_y_m=float(start_xy[1]),
            ball_end_x_m=float(end_xy[0]), ball_end_y_m=float(end_xy[1]),
            lineup_error_x_m=float(lineup[0] - offset[0]),
            lineup_error_y_m=float(lineup[1] - offset[1]),
        ))
        if world.goal_scored():
            end = "goal"
            break
        if world.ball_out():
            end = "ball out"
            break
        if world.fallen() and not get_up(world, falls):
            end = "could not get up"
            break
        walk = _walk_to_ball(world, offset, falls, config, clock)
        while walk == "fell" and clock.left_s(world) > 0:
            if not get_up(world, falls):
                break
            walk = _walk_to_ball(world, offset, falls, config, clock)
        if world.goal_scored():  # pushed in while walking: a goal, but no kick's credit
            end = "goal while walking"
            break
        if walk != "arrived":
            end = "could not get up" if walk == "fell" else f"stuck: {walk}"
            break
    summary = dict(seed=seed, duration_s=world.time_s, kicks=len(rows),
                   goals=int(any(r["goal"] for r in rows)),
                   goals_while_walking=int(end == "goal while walking"), falls=falls.falls,
                   getups=falls.getups, end=end, stuck=end.startswith("stuck"))
    if config.trace:
        summary["trace"] = world.trace()
    return rows, summary


class _Limp:
    """Zero joint speeds: used while waiting on a fallen robot."""

    done = False

    def reset(self, obs) -> None:
        pass

    def act(self, obs) -> np.ndarray:
        return np.zeros(22)
