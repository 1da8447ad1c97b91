"""The T1 team's walk as a learned policy walks: no two steps alike.

Most league teams walk with a policy learned in simulation. It follows a velocity command
(forward, sideways, turn) that the team's behaviour sets every moment from what it sees, and
it reacts to its sensors, so its steps never repeat exactly. This walk is a stand-in with
those traits, built on the team's pendulum walk (``walk.OtherTeamT1Walk``):

* **a velocity command toward a noisy target**: the target lies ``target_distance_m`` ahead of
  the start; the team sees it with a sideways error that wanders from step to step (an AR(1)
  draw per step), and turns and side-steps toward where it believes it is. The turn and
  sideways commands saturate and flip sign every few steps, as a real team's do when it
  steers at a noisy ball estimate;
* **a step time that adapts every step**: longer when the forward capture point runs ahead of
  the plan (at the commanded speed a longer step lands farther, under a torso falling ahead),
  read through a noisy estimate that wanders from step to step, within
  ``min_step_scale``..``max_step_scale`` of the team's step time and at most one cycle from
  the last step's (the pendulum's sway cannot change its rhythm at once);
* **optionally, a policy's action jitter** (``action_noise_rad``, off by default): every
  cycle each joint's reference gets an AR(1) noise of its own, as a learned policy's actions
  jitter from one 50 Hz cycle to the next; the PD motors pass part of it to the joints.

Its noise comes from a generator seeded by ``PolicyWalkParams.seed`` and the robot's first
observation, so every episode walks differently and a seeded episode replays exactly. The
action jitter has a stream of its own from the same seed and observation: turning it on leaves
the steering's and the step time's draws as they were.
``steps`` lists each step's (duration [s], forward [m/s], sideways [m/s], turn [rad/s])
command, for measurement.
"""

from __future__ import annotations

import math
import zlib

import numpy as np

from mimic.agents.base import JointCommand
from mimic.agents.other_team_t1.params import PolicyWalkParams, WalkParams
from mimic.agents.other_team_t1.walk import OtherTeamT1Walk
from mimic.world.base import CYCLE_S, Observation

__all__ = ["OtherTeamT1PolicyWalk"]

#: Mixed into the action jitter's seed: its stream apart from the steering's and timing's.
_ACTION_STREAM = 1


class OtherTeamT1PolicyWalk(OtherTeamT1Walk):
    """Walks toward a target ``command.target_distance_m`` ahead, steering at a noisy estimate
    of it, with a step time that adapts every step."""

    name = "other_team_policy_walk"

    def __init__(
        self, params: WalkParams = WalkParams(), command: PolicyWalkParams = PolicyWalkParams()
    ) -> None:
        self.command = command
        self.steps: list[tuple[float, float, float, float]] = []
        self._rng = np.random.default_rng(command.seed)
        self._target_xy_m = np.zeros(2)
        self._noise_m = self._timing_noise = 0.0
        self._cmd = (command.speed_m_s, 0.0, 0.0)
        self._action_rng = np.random.default_rng(command.seed)
        self._action_noise_rad: np.ndarray | None = None
        super().__init__(params)
        self._noise_share = self._jitter_shares()

    def reset(self, obs: Observation) -> None:
        c = self.command
        # The team's sensor noise: a fresh generator per episode, fixed by what it first sees.
        mix = zlib.crc32(np.asarray(obs.joint_angles_rad, dtype=np.float64).tobytes())
        self._rng = np.random.default_rng([c.seed, mix])
        self._action_rng = np.random.default_rng([c.seed, mix, _ACTION_STREAM])
        self._action_noise_rad = None
        yaw = obs.torso_yaw_rad
        ahead = np.array([math.cos(yaw), math.sin(yaw)])
        self._target_xy_m = np.asarray(obs.torso_pos_m[:2], float) + c.target_distance_m * ahead
        self._noise_m = float(self._rng.normal(0.0, c.target_noise_m))
        self._timing_noise = 0.0
        self._cmd = (c.speed_m_s, 0.0, 0.0)
        self.steps = []
        super().reset(obs)

    @property
    def velocity_command(self) -> tuple[float, float, float]:
        """The step under way's (forward [m/s], sideways [m/s], turn [rad/s]) command."""
        return self._cmd

    def _begin_step(self, obs: Observation) -> None:
        self._steer(obs)
        super()._begin_step(obs)
        self.steps.append((self._cur_step_s, *self._cmd))

    def _steer(self, obs: Observation) -> None:
        """A new command from the target as the team now sees it."""
        c = self.command
        keep = c.target_noise_keep
        self._noise_m = keep * self._noise_m + math.sqrt(1 - keep * keep) * float(
            self._rng.normal(0.0, c.target_noise_m)
        )
        heading = self._heading_rad  # the start heading: the error lies across it
        across = np.array([-math.sin(heading), math.cos(heading)])
        seen = self._target_xy_m + self._noise_m * across - np.asarray(obs.torso_pos_m[:2])
        bearing = math.remainder(math.atan2(seen[1], seen[0]) - obs.torso_yaw_rad, 2 * math.pi)
        turn = float(np.clip(c.turn_gain * bearing, -c.max_turn_rad_s, c.max_turn_rad_s))
        side = float(np.clip(c.side_gain * bearing, -c.max_side_m_s, c.max_side_m_s))
        self._cmd = (c.speed_m_s, side, turn)

    def _step_timing(self, obs: Observation) -> int:
        c, p = self.command, self.params
        ahead_m = 0.0
        if self._err_m is not None:  # the forward capture point against the plan, last step
            ahead_m = float(self._err_m[0] + self._err_rate[0] / self._w_per_s)
        keep = c.timing_noise_keep
        self._timing_noise = keep * self._timing_noise + math.sqrt(1 - keep * keep) * float(
            self._rng.normal(0.0, c.timing_noise)
        )
        scale = 1.0 + c.timing_capture_gain * ahead_m + self._timing_noise
        scale = float(np.clip(scale, c.min_step_scale, c.max_step_scale))
        # A step at most ``max_step_change_cycles`` longer or shorter than the last: the
        # pendulum's sway cannot change its rhythm at once.
        change = c.max_step_change_cycles
        wanted = int(round(p.step_cycles * scale))
        return max(2, int(np.clip(wanted, self._step_cycles - change, self._step_cycles + change)))

    def _sway_m(self) -> float:
        """The team's sway, scaled to the step's time as the pendulum's periodic sway between
        the feet scales (peak 1 - 1 / cosh(w T / 2) of the half-width)."""

        def reach(step_s: float) -> float:
            return 1.0 - 1.0 / math.cosh(0.5 * self._w_per_s * step_s)

        return self.params.sway_m * reach(self._cur_step_s) / reach(self.step_s)

    def _velocity_command(self, obs: Observation) -> tuple[float, float]:
        return self._cmd[0], self._cmd[1] * self._step_cycles * CYCLE_S

    def act(self, obs: Observation) -> JointCommand:
        return JointCommand.references(self._jitter(self._references(obs)))

    def _jitter_shares(self) -> np.ndarray:
        """Per joint: its share of ``action_noise_rad`` (legs and waist, arms, the rest)."""
        c, robot = self.command, self._body.robot
        share = np.ones(robot.num_joints)
        for i, name in enumerate(robot.joint_names):
            if "Shoulder" in name or "Elbow" in name:
                share[i] = c.action_noise_arm_share
        legs = [i for side in self._body.leg.values() for i in side.values()]
        share[legs + [robot.joint_index("Waist")]] = c.action_noise_leg_share
        return share

    def _jitter(self, q: np.ndarray) -> np.ndarray:
        """The references with this cycle's action jitter (once per cycle: ``_references``
        calls itself when the walk halts)."""
        c = self.command
        if c.action_noise_rad <= 0.0:  # no draw at all: the walk without jitter, bit for bit
            return q
        draw = self._action_rng.normal(0.0, c.action_noise_rad, q.shape) * self._noise_share
        if self._action_noise_rad is None:  # the first cycle: a draw from the stationary law
            self._action_noise_rad = draw
        else:
            keep = c.action_noise_keep
            self._action_noise_rad = (
                keep * self._action_noise_rad + math.sqrt(1 - keep * keep) * draw
            )
        return self._body.robot.clip(q + self._action_noise_rad)

    def _turn_rad(self, obs: Observation) -> float:
        turn = self._cmd[2] * self._step_cycles * CYCLE_S
        return float(np.clip(turn, -self.params.max_turn_rad, self.params.max_turn_rad))
