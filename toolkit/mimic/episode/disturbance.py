"""Disturbances: what makes one trial run differ from the next, beyond the start pose.

A game is not a lab: the robot starts moving on whatever cycle it is told, other robots bump
into it, the grass and the robot's own parts are not the nominal ones, and its sensors are
noisy. ``Disturbances`` says how much of each an episode gets; ``EpisodeDisturbances`` draws
them for one episode from the episode's seed and applies them:

* **start delay**: the agent starts after the robot has stood a further ``U(0,
  start_delay_s)`` seconds, so a motion begins on a different cycle of the settling robot;
* **pushes**: at times of a Poisson process (mean gap ``push_interval_s``, none in the first
  ``push_after_s`` of the agent's run), a horizontal force on the torso for
  ``push_duration_s`` in a uniformly drawn direction, sized to change the whole robot's
  momentum by its mass times ``push_scale`` times a game's push: the one the trial's original
  (its first variant) survives most of the time (``ORIGINAL_PUSH_SPEED_M_S``, else its
  robot's ``GAME_PUSH_SPEED_M_S``), the same for every variant;
* **physics**: every contact's sliding friction times ``U(1 - friction_spread, 1 +
  friction_spread)``, every link's mass and inertia times one ``U(1 - mass_spread, 1 +
  mass_spread)`` (a heavier or lighter robot of the same build: each link drawn on its own
  shifts the centre of mass, and at +-10 % that alone topples the T1 other team's walk in
  about one run in five, where no league game has robots of different builds);
* **sensor noise**: what the agent perceives (not what the trial measures) gets normal noise on
  the joint angles [rad], the gyro [rad/s] and the torso's tilt (a rotation about a random
  horizontal axis [rad]), drawn anew every cycle;
* **a fall is not the end** (``get_up_after_fall``): as in a game, a walk run that falls gets
  up and walks on (``Agent.resume``: the walk turns back to its course), so a fall costs the
  run the time it costs a player, not the rest of the run.

Every draw comes from its own generator, seeded from the episode seed and a fixed stream tag,
so the scene's draws are the same with and without disturbances and ``none`` plays exactly as
an undisturbed trial. Pushes and physics need a world that owns its physics
(``World.can_disturb_physics``): our MuJoCo worlds and the league's world in-process, not a
league server in another process.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.hold import HoldPose
from mimic.episode.observers import Observer
from mimic.errors import MimicError
from mimic.geometry import quat_mul
from mimic.robot.actuators import JointCommand
from mimic.world.base import CYCLE_S, Observation, World

__all__ = [
    "Disturbances",
    "EpisodeDisturbances",
    "DISTURB_LEVELS",
    "DEFAULT_DISTURB",
    "GAME_PUSH_SPEED_M_S",
    "ORIGINAL_PUSH_SPEED_M_S",
    "game_push_speed_m_s",
    "disturb_level",
]

#: Tag of the disturbances' random stream (the scene draws from the episode seed alone).
_STREAM = 0xD157


@dataclass(frozen=True)
class Disturbances:
    """How much an episode is disturbed (every value 0: not at all). Units in the names."""

    # The agent starts after a further U(0, this) seconds standing [s].
    start_delay_s: float = 0.0
    # Mean gap between pushes [s] (0: no pushes) and the quiet start of a run [s].
    push_interval_s: float = 0.0
    push_after_s: float = 1.0
    # A push's size in the robot's game pushes (``GAME_PUSH_SPEED_M_S``) and its length [s]
    # (half a second: a robot leaning into another, gentler than a blow of the same size).
    push_scale: float = 0.0
    push_duration_s: float = 0.1
    # Half widths of the uniform scales of sliding friction and of each link's mass.
    friction_spread: float = 0.0
    mass_spread: float = 0.0
    # Standard deviations of the sensor noise: joint angles [rad], gyro [rad/s], tilt [rad].
    joint_noise_rad: float = 0.0
    gyro_noise_rad_s: float = 0.0
    tilt_noise_rad: float = 0.0
    # A walk run that falls gets up and walks on to the finish (False: the fall ends it).
    get_up_after_fall: bool = False

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool):
                continue
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"disturbance {f.name} must be finite and >= 0, got {value}")
        for name in ("friction_spread", "mass_spread"):
            if getattr(self, name) >= 1:
                raise ValueError(f"disturbance {name} must be below 1, got {getattr(self, name)}")
        if self.push_duration_s < CYCLE_S:
            raise ValueError(f"a push lasts at least one cycle ({CYCLE_S} s)")

    @property
    def pushes(self) -> bool:
        return self.push_interval_s > 0 and self.push_scale > 0

    @property
    def physics(self) -> bool:
        """It changes the world's physics (pushes, friction, masses)."""
        return self.pushes or self.friction_spread > 0 or self.mass_spread > 0

    @property
    def sensors(self) -> bool:
        return self.joint_noise_rad > 0 or self.gyro_noise_rad_s > 0 or self.tilt_noise_rad > 0


#: The push [m/s of the whole robot's speed, given over ``push_duration_s``] a robot's
#: original walks survive most of the time (the NAO other team's walk in our world, the T1
#: other team's walks in the league's physics): a walk run falls in about one in four to
#: three. ``docs/disturbances.md`` says how they were found.
GAME_PUSH_SPEED_M_S = {"nao": 0.3, "t1": 0.05, "k1": 0.05}
#: (robot, behaviour) -> the same for an original that takes a harder push than its robot's
#: others: our NAO walk engine falls at the NAO's push in about one run in ten, so its runs
#: would differ mostly by their start.
ORIGINAL_PUSH_SPEED_M_S = {("nao", "walk"): 0.4}


def game_push_speed_m_s(robot: str, behaviour: str | None = None) -> float:
    """The game push [m/s] of a trial whose original is ``behaviour`` (an agent name; None or
    a motion or model: the robot's) on ``robot``."""
    return ORIGINAL_PUSH_SPEED_M_S.get((robot, behaviour or ""), GAME_PUSH_SPEED_M_S[robot])


#: The levels ``--disturb`` names. ``game`` is what a game in the league has: robots start on
#: any cycle, get pushed, and the grass and the robots are not the nominal ones; neither
#: simulator adds sensor noise (rcsssmj 0.2.1 sends exact values, truncated), so ``game`` adds
#: none. ``hard`` doubles the spreads and adds sensor noise; its pushes are game's (half as
#: much again and every walk falls in nearly every run). ``docs/disturbances.md``: how the
#: levels were chosen and what the originals do under them.
DISTURB_LEVELS: dict[str, Disturbances] = {
    "none": Disturbances(),
    "game": Disturbances(
        start_delay_s=0.5,
        push_interval_s=3.0,
        push_scale=1.0,
        push_duration_s=0.5,
        friction_spread=0.1,
        mass_spread=0.1,
        get_up_after_fall=True,
    ),
}
DISTURB_LEVELS["hard"] = replace(
    DISTURB_LEVELS["game"],
    friction_spread=0.2,
    mass_spread=0.2,
    joint_noise_rad=0.001,
    gyro_noise_rad_s=0.01,
    tilt_noise_rad=0.002,
)
#: The level a trial plays unless told.
DEFAULT_DISTURB = "game"


def disturb_level(name: str) -> Disturbances:
    """The disturbances of level ``name`` (``DISTURB_LEVELS``).

    Raises:
        MimicError: an unknown level, with the known ones.
    """
    try:
        return DISTURB_LEVELS[name]
    except KeyError:
        raise MimicError(
            f"unknown disturbance level {name!r}; levels: {', '.join(DISTURB_LEVELS)}"
        ) from None


def check_world_disturbable(level: str, world: World) -> None:
    """Refuse, in one line, a level that changes physics in a world that cannot."""
    if disturb_level(level).physics and not world.can_disturb_physics:
        raise MimicError(
            f"--disturb {level} pushes the robot and changes friction and masses; the "
            f"{world.describe()} cannot: use --disturb none there"
        )


class EpisodeDisturbances:
    """One episode's disturbances, drawn from ``seed`` for ``world`` (see the module);
    ``push_speed_m_s``: a push of ``push_scale`` 1 [m/s] (None: the robot's game push)."""

    def __init__(
        self, level: str, seed: int, world: World, push_speed_m_s: float | None = None
    ) -> None:
        self.level = level
        self.spec = disturb_level(level)
        check_world_disturbable(level, world)
        rng = np.random.default_rng([seed, _STREAM])
        s = self.spec
        self.friction_scale = float(rng.uniform(1 - s.friction_spread, 1 + s.friction_spread))
        self.mass_scale = float(rng.uniform(1 - s.mass_spread, 1 + s.mass_spread))
        self.link_mass_scales = np.full(len(world.robot.links), self.mass_scale)
        self._rng = rng  # start delays, push times and sensor noise, in the order asked
        self.start_delays_s: list[float] = []
        if push_speed_m_s is None:
            push_speed_m_s = game_push_speed_m_s(world.robot.name)
        self.push_speed_m_s = s.push_scale * push_speed_m_s
        self.pusher = Pusher(self)

    def apply_physics(self, world: World) -> None:
        """Scale friction and masses (before the scene places anything); nothing at ``none``."""
        if self.spec.friction_spread > 0 or self.spec.mass_spread > 0:
            world.scale_physics(self.friction_scale, self.link_mass_scales)

    def start_delay(self, episode, *, lying: bool = False) -> str:
        """Hold the stand (``lying``: the joints where they are) a further drawn delay before
        the agent starts (``episode.run``'s outcome, ``timeout`` when the robot kept its
        posture throughout)."""
        if self.spec.start_delay_s <= 0:
            return "timeout"
        delay = float(self._rng.uniform(0.0, self.spec.start_delay_s))
        self.start_delays_s.append(delay)
        world = episode.world
        pose = world.joint_angles_rad() if lying else world.robot.stand_pose()
        return episode.run(
            HoldPose(pose, world.robot.name),
            max_s=delay,
            stop_when_done=False,
            abort_on_fall=not lying,
        )

    def traced(self, trace):
        """An ``EpisodeTrace`` with this episode's pushes in it (for the replay)."""
        duration = self.spec.push_duration_s
        return replace(trace, pushes=tuple((t, f, duration) for t, f in self.pusher.pushed))

    def agent(self, agent: Agent) -> Agent:
        """``agent`` with noisy sensors (itself when there is no sensor noise)."""
        return NoisySensors(agent, self.spec, self._rng) if self.spec.sensors else agent

    def columns(self) -> dict:
        """What this episode got, for its rows (the parquet of every run or kick)."""
        return dict(
            disturb=self.level,
            start_delay_s=float(sum(self.start_delays_s)),
            friction_scale=self.friction_scale if self.spec.friction_spread > 0 else 1.0,
            mass_scale=self.mass_scale if self.spec.mass_spread > 0 else 1.0,
            pushes=len(self.pusher.pushed),
            push_speed_m_s=self.push_speed_m_s if self.spec.pushes else 0.0,
            push_times_s=[t for t, _ in self.pusher.pushed],
            push_directions_deg=[
                math.degrees(math.atan2(f[1], f[0])) for _, f in self.pusher.pushed
            ],
        )


class Pusher(Observer):
    """Pushes the torso at the episode's push times once ``arm``-ed (an observer of the runs
    it should disturb). ``pushed``: (start time [s], force (3,) [N], field frame) of every
    push begun; each lasts ``push_duration_s``."""

    def __init__(self, disturbances: EpisodeDisturbances) -> None:
        self._d = disturbances
        self.pushed: list[tuple[float, float]] = []
        self._next_s = math.inf
        self._until_s = -math.inf
        self._force = np.zeros(3)
        self._pushing = False  # a non-zero force is on

    def arm(self, world: World) -> None:
        """Pushes start ``push_after_s`` after now, at Poisson times."""
        if self._d.spec.pushes:
            self._next_s = world.time_s + self._d.spec.push_after_s + self._gap()

    def _gap(self) -> float:
        return float(self._d._rng.exponential(self._d.spec.push_interval_s))

    def before_step(self, world: World, obs, agent, command) -> None:
        t = world.time_s
        if self._pushing and t >= self._until_s:
            self._force = np.zeros(3)
            self._pushing = False
            world.push_torso(self._force)
        if t + 1e-9 >= self._next_s:
            s = self._d.spec
            angle = float(self._d._rng.uniform(-math.pi, math.pi))
            size_n = world.robot_mass_kg() * self._d.push_speed_m_s / s.push_duration_s
            self._force = size_n * np.array([math.cos(angle), math.sin(angle), 0.0])
            self._pushing = bool(self._force.any())
            world.push_torso(self._force)
            self.pushed.append((t, self._force.copy()))
            self._until_s = t + s.push_duration_s - 1e-9
            self._next_s = t + s.push_duration_s + self._gap()


class NoisySensors(Agent):
    """An agent that perceives through noisy sensors (the world's true state is unchanged)."""

    def __init__(self, inner: Agent, spec: Disturbances, rng: np.random.Generator) -> None:
        self.inner, self.spec, self._rng = inner, spec, rng
        for name in ("name", "team", "period_s", "start_posture", "robot", "robot_only"):
            setattr(self, name, getattr(inner, name))

    @property
    def done(self) -> bool:
        return self.inner.done

    @property
    def reference_rad(self):
        return self.inner.reference_rad

    def check_robot(self, robot) -> None:
        self.inner.check_robot(robot)

    def _noisy(self, obs: Observation) -> Observation:
        s, rng = self.spec, self._rng
        n = len(obs.joint_angles_rad)
        axis = rng.uniform(-math.pi, math.pi)
        half = 0.5 * rng.normal(0.0, s.tilt_noise_rad)
        tilt = np.array(
            [math.cos(half), math.sin(half) * math.cos(axis), math.sin(half) * math.sin(axis), 0]
        )
        return replace(
            obs,
            joint_angles_rad=obs.joint_angles_rad + rng.normal(0.0, s.joint_noise_rad, n),
            gyro_rad_s=obs.gyro_rad_s + rng.normal(0.0, s.gyro_noise_rad_s, 3),
            torso_quat_wxyz=quat_mul(tilt[None], obs.torso_quat_wxyz[None])[0],
        )

    def reset(self, obs: Observation) -> None:
        self.inner.reset(self._noisy(obs))

    def resume(self, obs: Observation) -> None:
        self.inner.resume(self._noisy(obs))

    def act(self, obs: Observation) -> JointCommand:
        return self.inner.act(self._noisy(obs))
