"""Physical checks of any walk or kick agent, through the ``Agent`` interface only.

Used by the tests and the benchmarks; they see the agents exactly as the recorder does
(reset / act / done / period_s / ball_offset_m): the other team's walk and kick among them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.hold import HoldPose
from mimic.episode import PoseNoise, Scene, run
from mimic.episode.observers import Observer
from mimic.world import field as F
from mimic.world.base import Observation, World
from mimic.world.mujoco_world import MujocoWorld

__all__ = ["WalkResult", "KickResult", "straight_walk", "kick_from_stand", "NoisyCommands"]


class NoisyCommands(Agent):
    """Wraps an agent and adds seeded Gaussian noise [rad/s] to its speed commands (a
    reference command is first turned into the speeds the robot's servos would get)."""

    def __init__(
        self, inner: Agent, rng: np.random.Generator, speed_noise_rad_s: float, servos=None
    ) -> None:
        super().__init__()
        self.inner, self.rng, self.noise = inner, rng, speed_noise_rad_s
        self.servos = servos
        self.name, self.team, self.period_s = inner.name, inner.team, inner.period_s
        self.robot, self.robot_only = inner.robot, inner.robot_only

    def reset(self, obs: Observation) -> None:
        self.inner.reset(obs)
        self.done = False

    def act(self, obs: Observation) -> JointCommand:
        command = self.inner.act(obs)
        self.done, self.reference_rad = self.inner.done, self.inner.reference_rad
        if not self.noise:
            return command
        speeds = (
            command.speed_rad_s
            if command.speed_rad_s is not None
            else self.servos.track(command.reference_rad, obs.joint_angles_rad)
        )
        return JointCommand.speeds(speeds + self.rng.normal(0.0, self.noise, speeds.shape))


class _LastCommand(Observer):
    """The last command an agent sent."""

    def __init__(self) -> None:
        self.command: JointCommand | None = None

    def before_step(self, world, obs, agent, command) -> None:
        self.command = command


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


@dataclass(frozen=True)
class WalkResult:
    """Outcome of one straight walk."""

    # Whether the robot fell before covering the distance.
    fell: bool
    # Distance covered along x [m].
    distance_m: float
    # Mean forward speed from the first crossing of ``start_after_m`` to the end [m/s].
    speed_m_s: float
    # Largest |y| reached [m].
    max_drift_m: float
    # Simulated time used [s].
    time_s: float
    # (cycles, N) observed joint angles [rad], one row per 20 ms cycle.
    angles_rad: np.ndarray


@dataclass(frozen=True)
class KickResult:
    """Outcome of one kick from a stand."""

    # Ball travel along the robot's forward axis [m].
    distance_m: float
    # Ball sideways travel [m].
    lateral_m: float
    # Robot upright 2 s after the kick finished.
    standing: bool


def straight_walk(
    make_agent: Callable[[], Agent],
    distance_m: float = 15.0,
    *,
    seed: int = 0,
    speed_noise_rad_s: float = 0.0,
    start_after_m: float = 1.0,
    max_time_s: float = 60.0,
    world: World | None = None,
    pose_noise_rad: float = 0.0,
) -> WalkResult:
    """Place the robot standing on its own goal line facing +x and let the agent walk.

    The speed is measured from the moment the torso has advanced ``start_after_m`` [m]
    (past the start-up) until it has covered ``distance_m`` [m]. ``speed_noise_rad_s``
    adds Gaussian noise [rad/s] to every speed command and ``pose_noise_rad`` to every
    joint of the start pose [rad] (seeded perturbations).
    """
    w = world or MujocoWorld()
    rng = np.random.default_rng(seed)
    x0 = F.OWN_GOAL_X_M
    Scene(
        robot_xy_m=(x0, 0.0),
        settle_s=0.0,
        ball_xy_m=(0.0, 0.0),
        noise=PoseNoise(joint_rad=pose_noise_rad),
    ).setup(w, rng)
    agent = NoisyCommands(make_agent(), rng, speed_noise_rad_s, w.robot.actuator)
    log = _WalkLog(x0, start_after_m)
    run(
        w,
        agent,
        max_s=max_time_s,
        stop_when_done=False,
        abort_on_fall=True,
        observers=(log,),
        stop=lambda w: w.torso_pos_m()[0] - x0 >= distance_m,
    )
    x = w.torso_pos_m()[0]
    t_start = log.t_start_s
    speed = (
        (x - x0 - start_after_m) / (w.time_s - t_start)
        if t_start is not None and w.time_s > t_start
        else 0.0
    )
    return WalkResult(
        w.fallen(), float(x - x0), float(speed), float(log.drift_m), w.time_s, np.array(log.angles)
    )


def kick_from_stand(
    make_agent: Callable[[], Agent],
    *,
    seed: int = 0,
    pose_noise_rad: float = 0.0,
    ball_noise_m: float = 0.0,
    speed_noise_rad_s: float = 0.0,
    world: World | None = None,
) -> KickResult:
    """Stand the robot at the centre spot, put the ball where the kick wants it, kick.

    After the agent reports done, the joints hold their last pose for 2 s and the ball is
    left to roll to rest: the last joint references the agent sent (PD motors track those;
    holding the sagged angles instead would let the robot sag again), or the angles reached
    for an agent that sent speeds. Seeded noise perturbs the start pose [rad], the ball
    position [m] and the speed commands [rad/s].
    """
    w = world or MujocoWorld()
    rng = np.random.default_rng(seed)
    agent = make_agent()
    Scene(
        ball_offset_m=agent.ball_offset_m,
        settle_s=0.2,
        noise=PoseNoise(joint_rad=pose_noise_rad, ball_m=ball_noise_m, distribution="uniform"),
    ).setup(w, rng)
    ball0 = w.ball_pos_m()[:2]
    noisy = NoisyCommands(agent, rng, speed_noise_rad_s, w.robot.actuator)
    last = _LastCommand()
    run(w, noisy, max_s=10.0, observers=(last,))
    references = None if last.command is None else last.command.reference_rad
    hold = HoldPose(w.joint_angles_rad() if references is None else references, w.robot.name)
    run(w, hold, max_s=2.0)
    standing = w.upright()
    run(w, hold, max_s=20.0, stop=lambda w: w.ball_speed_m_s() < 0.01)
    b = w.ball_pos_m()
    return KickResult(
        float(b[0] - ball0[0]), float(b[1] - ball0[1]), bool(standing and not math.isnan(b[0]))
    )
