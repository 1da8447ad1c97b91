"""Kick from a stand: the robot stands behind a ball, kicks, stands on; how far did the ball go?

One episode has up to four phases, each a ``run`` of the episode layer:

1. the scene: the robot placed (field frame, facing +x) with the ball at the kick's ball
   offset (robot frame: x forward, y left [m]), perturbed from ``rng = default_rng(seed)``,
   then settling for ``settle_s``;
2. the kick: the agent plays until it is done, for at most ``kick_max_s``;
3. after the kick, for ``after_s``: the robot holds its last references (``After.HOLD``),
   moves into its stand pose (``After.STAND``) or, if it lies, waits limp
   (``After.STAND_OR_LIMP``); then whether it stands is read (``Standing``);
4. the roll-out (``roll_max_s`` not None): the robot holds its pose while the ball rolls on,
   until slower than ``rest_speed_m_s`` or ``roll_max_s`` has passed.

The ball is measured from where it was after the scene to where it is at the end, so a
config without a roll-out measures the ball still rolling.

    outcome = play(world, agent, seed=0, config=KickFromStandConfig())
    outcome.distance_m, outcome.standing
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.hold import HoldPose
from mimic.agents.noisy_commands import NoisyCommands
from mimic.agents.registry import kick_ball_offset_m
from mimic.episode import Episode, Observer, PoseNoise, Scene, run
from mimic.errors import MimicError
from mimic.tasks.perturbation import Perturbation
from mimic.world.base import World

__all__ = [
    "After",
    "Standing",
    "KickFromStandConfig",
    "KickFromStandOutcome",
    "scene",
    "play",
    "MIN_DIRECTION_M",
]

#: Below this ball travel [m] a kick has no direction (``direction_error_rad`` is NaN).
MIN_DIRECTION_M = 0.05


class After(str, Enum):
    """What the robot does between the kick and the standing check."""

    # Hold the last joint references the agent sent (PD motors track those; holding the
    # sagged angles instead would let the robot sag again), or, for an agent that sent
    # speeds, the angles reached.
    HOLD = "hold"
    # Move into the robot's stand pose and hold it (the run ends early on a fall).
    STAND = "stand"
    # Stand as above, but a robot that already lies waits limp instead.
    STAND_OR_LIMP = "stand-or-limp"


class Standing(str, Enum):
    """What "the robot stands after the kick" means, read at the end of the after phase."""

    # Not lying: torso not too low and not tilted too far (``World.fallen``).
    NOT_FALLEN = "not-fallen"
    # Upright: torso high and nearly vertical (``World.upright``, stricter than not fallen).
    UPRIGHT = "upright"
    # No fall counted from the kick's start and not lying at the end.
    NEVER_FELL = "never-fell"


@dataclass(frozen=True)
class KickFromStandConfig:
    """One kick from a stand. The defaults: ball far from the goals, 0.2 s of settling,
    small uniform start noise, 2 s holding the last references, then "upright", and the ball
    followed to rest."""

    # Where the ball starts, field frame [m] (far from the goals: it rolls freely toward
    # +x); the robot stands behind it at the kick's ball offset. Ignored with robot_xy_m.
    ball_start_m: tuple[float, float] = (-8.0, 0.0)
    # Where the robot stands instead, field frame [m]; None: behind ball_start_m.
    robot_xy_m: tuple[float, float] | None = None
    # Where the ball goes relative to the torso, robot frame (x forward, y left) [m];
    # None: where the agent's kick wants it (``agents.registry.kick_ball_offset_m``).
    ball_offset_m: tuple[float, float] | None = None
    # Start-pose, placement and ball noise, drawn from the seed.
    noise: PoseNoise = Perturbation().noise()
    # Time the placed robot settles before the kick [s].
    settle_s: float = 0.2
    # Place the ball only after settling, at the offset from the settled torso.
    ball_after_settle: bool = False
    # While settling, move into the stand pose (undoing the joint noise).
    settle_into_stand: bool = False
    # Gaussian noise on every speed command during the kick [rad/s] (0: none).
    speed_noise_rad_s: float = 0.0
    # Longest the kick plays [s] (it ends earlier when the agent is done).
    kick_max_s: float = 10.0
    # End the kick at the first fall.
    abort_on_fall: bool = False
    # What the robot does after the kick, for after_s [s] (0: nothing).
    after: After = After.HOLD
    after_s: float = 2.0
    # What standing means at the end of the after phase.
    standing: Standing = Standing.UPRIGHT
    # The roll-out: at most this long [s] (None: no roll-out), until the ball is slower
    # than rest_speed_m_s [m/s].
    roll_max_s: float | None = 20.0
    rest_speed_m_s: float = 0.01
    # (N,) the pose held after the kick and in the roll-out [rad]; None: the agent's last
    # references (or the angles reached, for an agent that sent speeds).
    hold_pose_rad: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "after", After(self.after))
        object.__setattr__(self, "standing", Standing(self.standing))
        for name in ("settle_s", "kick_max_s", "after_s", "rest_speed_m_s", "speed_noise_rad_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise MimicError(f"kick from a stand: {name} must be finite and >= 0, got {value}")
        if self.roll_max_s is not None and not self.roll_max_s >= 0:
            raise MimicError(f"kick from a stand: roll_max_s must be >= 0, got {self.roll_max_s}")


@dataclass(frozen=True)
class KickFromStandOutcome:
    """What one kick from a stand did.

    Attributes:
        ball_start_m: (3,) the ball after the scene, field frame [m].
        ball_end_m: (3,) the ball at the end of the episode, field frame [m].
        heading_rad: the torso's heading when the kick started, field frame [rad].
        standing: the robot stood at the end of the after phase (``config.standing``).
        falls: falls counted in the kick and the after phase.
        kick_end: how the kick ended (``episode.run.END_REASONS``).
    """

    ball_start_m: tuple[float, float, float]
    ball_end_m: tuple[float, float, float]
    heading_rad: float
    standing: bool
    falls: int
    kick_end: str

    @property
    def moved_xy_m(self) -> np.ndarray:
        """(2,) the ball's displacement on the ground, field frame [m]."""
        return np.array(self.ball_end_m[:2]) - np.array(self.ball_start_m[:2])

    @property
    def distance_m(self) -> float:
        """How far the ball went on the ground [m]."""
        return float(np.hypot(*self.moved_xy_m))

    @property
    def forward_m(self) -> float:
        """The ball's displacement along the robot's heading at the kick start [m]."""
        moved = self.moved_xy_m
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return float(moved[0] * c + moved[1] * s)

    @property
    def lateral_m(self) -> float:
        """The ball's displacement to the robot's left of that heading [m]."""
        moved = self.moved_xy_m
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return float(-moved[0] * s + moved[1] * c)

    @property
    def direction_error_rad(self) -> float:
        """Angle of the displacement from the heading, in (-pi, pi] (positive: to the
        robot's left) [rad]; NaN if the ball moved less than ``MIN_DIRECTION_M``."""
        if self.distance_m < MIN_DIRECTION_M:
            return math.nan
        return math.atan2(self.lateral_m, self.forward_m)


def scene(config: KickFromStandConfig, ball_offset_m: tuple[float, float]) -> Scene:
    """The scene of a kick whose ball goes at ``ball_offset_m`` (robot frame [m])."""
    robot_xy_m = config.robot_xy_m
    if robot_xy_m is None:
        robot_xy_m = (
            config.ball_start_m[0] - ball_offset_m[0],
            config.ball_start_m[1] - ball_offset_m[1],
        )
    return Scene(
        robot_xy_m=robot_xy_m,
        ball_offset_m=ball_offset_m,
        noise=config.noise,
        settle_s=config.settle_s,
        ball_after_settle=config.ball_after_settle,
        settle_into_stand=config.settle_into_stand,
    )


class _LastCommand(Observer):
    """The last command an agent sent."""

    def __init__(self) -> None:
        self.command: JointCommand | None = None

    def before_step(self, world, obs, agent, command) -> None:
        self.command = command


def play(
    world: World,
    agent: Agent,
    seed: int,
    config: KickFromStandConfig = KickFromStandConfig(),
    *,
    observers: tuple[Observer, ...] = (),
) -> KickFromStandOutcome:
    """Play one kick from a stand of ``agent`` in ``world`` (module docstring).

    ``observers`` watch the kick and the after phase (not the scene, not the roll-out).

    Raises:
        MimicError: no ball offset in the config and none the agent's kick wants.
    """
    offset = config.ball_offset_m
    if offset is None:
        offset = kick_ball_offset_m(agent)
    if offset is None:
        raise MimicError(f"{agent.name} does not say where it wants the ball; not a kick")
    rng = np.random.default_rng(seed)
    scene(config, offset).setup(world, rng)
    heading = world.torso_yaw_rad()
    ball_start = world.ball_pos_m()
    if config.speed_noise_rad_s:
        agent = NoisyCommands(agent, rng, config.speed_noise_rad_s, world.robot.actuator)
    last = _LastCommand()
    episode = Episode(world, observers=(last, *observers))
    kick_end = episode.run(agent, max_s=config.kick_max_s, abort_on_fall=config.abort_on_fall)
    hold = HoldPose(_hold_pose(world, config, last), world.robot.name)
    if config.after_s > 0:
        if config.after is After.HOLD:
            episode.run(hold, max_s=config.after_s, abort_on_fall=False)
        elif config.after is After.STAND_OR_LIMP and world.fallen():
            episode.wait_limp(max_s=config.after_s)
        else:
            episode.stand_still(max_s=config.after_s)
    standing = _standing(world, config.standing, episode.falls.falls)
    if config.roll_max_s is not None:
        run(
            world,
            hold,
            max_s=config.roll_max_s,
            stop=lambda w: w.ball_speed_m_s() < config.rest_speed_m_s,
        )
    return KickFromStandOutcome(
        tuple(float(v) for v in ball_start),
        tuple(float(v) for v in world.ball_pos_m()),
        float(heading),
        bool(standing),
        episode.falls.falls,
        kick_end,
    )


def _hold_pose(world: World, config: KickFromStandConfig, last: _LastCommand) -> np.ndarray:
    if config.hold_pose_rad is not None:
        return np.asarray(config.hold_pose_rad, dtype=float)
    references = None if last.command is None else last.command.reference_rad
    return world.joint_angles_rad() if references is None else references


def _standing(world: World, rule: Standing, falls: int) -> bool:
    if rule is Standing.UPRIGHT:
        return world.upright()
    if rule is Standing.NEVER_FELL:
        return falls == 0 and not world.fallen()
    return not world.fallen()
