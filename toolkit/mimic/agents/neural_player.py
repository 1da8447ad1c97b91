"""Plays a learned motion: the network gives references each 20 ms cycle, tracked by the robot's
actuator model like the keyframe player's (so a learned copy meets the same attenuation).

Cyclic motions (a walk) are learned from whole gait cycles at steady speed; jumping from the
stand pose straight into mid-gait at full rate throws the robot over within seconds. So a
cyclic model starts phase-locked, the way walk engines start: first the pose bends from the
angles at ``reset`` into the cycle's mean pose (``stance_s``), then the phase runs at its full
rate while the swing around that mean pose grows from zero to the learned amplitude
(``start_ramp_s``), like a step length ramped up from marching on the spot. Both set to 0
give the old behaviour (the learned cycle from the first cycle on).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.model.foot_track import FootTrack
from mimic.model.keys import BALANCE_GAINS_KEY, FOOT_TRACK_KEY, WALK_SPEED_KEY
from mimic.model.model_file import load_model
from mimic.model.motion_model import MotionModel
from mimic.world.base import Observation

__all__ = ["NeuralPlayer", "DEFAULT_STANCE_S", "DEFAULT_START_RAMP_S", "WALK_SPEED_KEY"]

#: Cyclic models: time to bend from the start pose into the cycle's mean pose [s].
DEFAULT_STANCE_S = 0.4
#: Cyclic models: time over which the swing grows to the learned amplitude [s].
DEFAULT_START_RAMP_S = 3.0
#: Robots whose walks ramp up over another time [s]: the T1's, searched with its balance gains
#: (``agents.balance``).
_START_RAMP_S = {"t1": 3.84}
#: The step length [m] of the copies the robot's ramp above was searched on (the T1 other
#: team's walk: 0.639 m/s at 0.42 s a step). A walk whose model knows its step length (learned
#: step by step: ``WALK_SPEED_KEY`` and its period) ramps in proportion, as a walk engine ramps
#: its step length by a fixed amount per step: a shorter step is reached sooner. (The T1 copy
#: of a 0.27 m step fell in every run with a 2.5 s ramp; the copy of a 0.17 m step walked.)
_RAMP_STEP_M = {"t1": 0.268}

# Phases sampled to find a cyclic model's mean pose.
_MEAN_SAMPLES = 64
#: Commanded speed: the phase rate changes by this share of the relative speed error per gait
#: cycle, within ``RATE_RANGE`` of the learned rate (T1 copies fell at 1.15-1.2).
RATE_GAIN = 0.5
RATE_RANGE = (0.8, 1.1)
#: ... changing by at most this much per gait cycle (a sudden step up in rate upsets the gait).
RATE_STEP = 0.02


def _smooth_step(x: float) -> float:
    """0 -> 1 cosine blend for x in [0, 1] (clamped outside), zero slope at both ends."""
    x = min(1.0, max(0.0, x))
    return 0.5 - 0.5 * math.cos(math.pi * x)


def _default_start_ramp_s(model: MotionModel) -> float:
    """A cyclic model's start ramp [s]: its robot's, in proportion to its step length where
    the model knows it and the robot's ramp has a step length (``_RAMP_STEP_M``)."""
    ramp_s = _START_RAMP_S.get(model.robot, DEFAULT_START_RAMP_S)
    speed = model.metadata.get(WALK_SPEED_KEY) if model.cyclic else None
    if speed is None or model.robot not in _RAMP_STEP_M:
        return ramp_s
    step_m = float(speed) * model.period_s / 2
    return ramp_s * step_m / _RAMP_STEP_M[model.robot]


class NeuralPlayer(Agent):
    """A motion network as an agent.

    One-shot models: time since ``reset`` goes in; ``done`` is set when the ended flag
    exceeds 0.5 (or, as a guard, ``max_overrun_s`` after the trained duration). Played past
    its end (``mimic play --seconds``, a run that does not stop when done), a one-shot model
    holds the last pose it learned: the time going in stops at the trained duration.
    Cyclic models: the phase advances at ``speed_rate`` times the learned rate and loops;
    they never finish by themselves. They start phase-locked (module docstring): the pose
    blends from the start angles into the cycle's mean pose over ``stance_s`` [s], then the
    phase starts at 0 and the swing around the mean pose ramps from 0 to 1 over
    ``start_ramp_s`` [s] (default: the robot's; both ignored by one-shot models). A cyclic
    walk with a commanded forward speed ``speed_m_s`` [m/s] (default: the speed its recording
    walked, for models learned step by step) holds it by its phase rate: once per gait cycle
    after the start-up, the rate moves by ``RATE_GAIN`` of the relative speed error (at most
    ``RATE_STEP``), within ``RATE_RANGE`` (the torso's travel from ``Observation.torso_pos_m``).
    """

    team = "mimic"

    def __init__(
        self,
        model: MotionModel,
        speed_rate: float = 1.0,
        max_overrun_s: float = 1.0,
        stance_s: float = DEFAULT_STANCE_S,
        start_ramp_s: float | None = None,
        speed_m_s: float | None = None,
    ) -> None:
        super().__init__()
        self.model = model
        self.robot = model.robot
        self.speed_rate, self.max_overrun_s = speed_rate, max_overrun_s
        if start_ramp_s is None:
            start_ramp_s = _default_start_ramp_s(model)
        self.stance_s, self.start_ramp_s = float(stance_s), float(start_ramp_s)
        self.name = model.name
        # A learned get-up starts lying, as its recording did.
        self.start_posture = str(model.metadata.get("start_posture", "standing"))
        # A learned kick wants the ball where its recording had it (robot frame [m]).
        offset = model.metadata.get("ball_offset_m")
        self.ball_offset_m = None if offset is None else (float(offset[0]), float(offset[1]))
        # Gains the balance layer uses around this model (``agents.balance``), if it has its own.
        self.balance_gains = dict(model.metadata.get(BALANCE_GAINS_KEY) or {})
        # Where the recording had its feet under the torso by phase (cyclic models learned
        # from a recording with body poses; ``model.foot_track``), for the balance layer.
        track = model.metadata.get(FOOT_TRACK_KEY) if model.cyclic else None
        self.foot_track = (
            None if track is None else FootTrack.from_metadata(track, f"{model.name}'s foot track")
        )
        # Cyclic models: the phase played this cycle [cycles, 0..1) and the swing's start-up
        # weight (0..1); None before the first ``act`` and for one-shot models.
        self.cycle_phase: float | None = None
        self.swing_weight = 0.0
        # A cyclic walk's commanded forward speed [m/s]: the phase rate follows it once the
        # start-up is done (``_hold_speed``). Default: the speed its recording walked, for a
        # model that says it (learned step by step); None plays at ``speed_rate``.
        if speed_m_s is None and model.cyclic:
            speed_m_s = model.metadata.get(WALK_SPEED_KEY)
        self.speed_m_s = None if speed_m_s is None else float(speed_m_s)
        self._rate_anchor = (0.0, 0.0)
        self._cycle_start: tuple[int, float, np.ndarray] | None = None
        self.ended_flag = 0.0
        self._start_s = 0.0
        self._start_rad: np.ndarray | None = None
        self._mean_rad: np.ndarray | None = None

    @property
    def period_s(self) -> float | None:
        """Gait period at the current ``speed_rate`` [s] (cyclic models), else None."""
        return self.model.period_s / self.speed_rate if self.model.cyclic else None

    @classmethod
    def from_file(cls, path: str | Path, **kwargs) -> NeuralPlayer:
        """Load a ``.mimic`` model (raises ``ModelFileError`` for a bad file)."""

        return cls(load_model(path), **kwargs)

    def reset(self, obs: Observation) -> None:
        self._start_s = obs.time_s
        self._start_rad = np.asarray(obs.joint_angles_rad, dtype=float).copy()
        self.done = False
        self.ended_flag = 0.0
        self.cycle_phase, self.swing_weight = None, 0.0
        # The phase clock: (walking time [s], cycle time played by then [s]) when the rate
        # last changed; the torso's place and the cycle count at the last cycle's start.
        self._rate_anchor = (0.0, 0.0)
        self._cycle_start: tuple[int, float, np.ndarray] | None = None

    def played_s(self, walk_s: float) -> float:
        """Cycle time played [s] after ``walk_s`` [s] of walking (past the stance blend)."""
        at_s, played_s = self._rate_anchor
        return played_s + (walk_s - at_s) * self.speed_rate

    def retime(self, speed_rate: float, walk_s: float) -> None:
        """Play on at ``speed_rate`` from ``walk_s`` [s] of walking, the phase continuous."""
        self._rate_anchor = (walk_s, self.played_s(walk_s))
        self.speed_rate = float(speed_rate)

    def reference_at(self, t_s: float) -> np.ndarray:
        """(N + 1,) network output at ``t_s`` [s] of playing (phase-scaled for cyclic models; no
        start-up blending)."""
        if self.model.cyclic:
            t_s = self.played_s(t_s) % self.model.period_s
        return self.model.predict(t_s)

    def mean_pose_rad(self) -> np.ndarray:
        """(N,) mean joint reference over one cycle of a cyclic model [rad]."""
        if self._mean_rad is None:
            t = np.arange(_MEAN_SAMPLES) * (self.model.period_s / _MEAN_SAMPLES)
            self._mean_rad = self.model.predict(t)[:, : self.model.num_joints].mean(axis=0)
        return self._mean_rad

    def start_weights(self, t_s: float) -> tuple[float, float]:
        """(stance blend, swing amplitude), each 0..1, at ``t_s`` [s] since ``reset``."""
        stance = 1.0 if self.stance_s <= 0 else _smooth_step(t_s / self.stance_s)
        walk_s = t_s - self.stance_s
        if walk_s < 0:
            return stance, 0.0
        return stance, 1.0 if self.start_ramp_s <= 0 else _smooth_step(walk_s / self.start_ramp_s)

    def cyclic_reference(self, t_s: float) -> np.ndarray:
        """(N + 1,) output of a cyclic model at ``t_s`` [s] since ``reset``, start-up included."""
        stance, swing = self.start_weights(t_s)
        out = self.reference_at(max(0.0, t_s - self.stance_s))
        if stance >= 1.0 and swing >= 1.0:
            return out
        mean = self.mean_pose_rad()
        n = self.model.num_joints
        q = mean + swing * (out[:n] - mean)
        if self._start_rad is not None:
            q = (1.0 - stance) * self._start_rad + stance * q
        out = out.copy()
        out[:n] = q
        return out

    def _hold_speed(self, obs: Observation, walk_s: float, played_s: float) -> None:
        """Once per gait cycle after the start-up: the torso's speed over the last cycle
        against the commanded one; the phase rate moves toward it."""
        cycle = int(played_s // self.model.period_s)
        if self._cycle_start is not None and cycle == self._cycle_start[0]:
            return
        xy = np.asarray(obs.torso_pos_m[:2], float)
        if self._cycle_start is not None and self.swing_weight >= 1.0:
            _, since_s, xy0 = self._cycle_start
            speed = float(np.hypot(*(xy - xy0))) / max(walk_s - since_s, 1e-9)
            change = RATE_GAIN * (self.speed_m_s - speed) / self.speed_m_s * self.speed_rate
            rate = self.speed_rate + float(np.clip(change, -RATE_STEP, RATE_STEP))
            self.retime(float(np.clip(rate, *RATE_RANGE)), walk_s)
        self._cycle_start = (cycle, walk_s, xy)

    def act(self, obs: Observation) -> JointCommand:
        t = obs.time_s - self._start_s
        if self.model.cyclic:
            _, self.swing_weight = self.start_weights(t)
            walk_s = max(0.0, t - self.stance_s)
            played_s = self.played_s(walk_s)
            if self.speed_m_s is not None and walk_s > 0:
                self._hold_speed(obs, walk_s, played_s)
                played_s = self.played_s(walk_s)
            self.cycle_phase = (played_s % self.model.period_s) / self.model.period_s
        # A one-shot network knows nothing past its end (played on, its references ran off
        # to 175 deg): it holds the last pose it learned.
        out = (
            self.cyclic_reference(t)
            if self.model.cyclic
            else self.reference_at(min(t, self.model.duration_s))
        )
        n = self.model.num_joints
        self.reference_rad = out[:n]
        self.ended_flag = float(out[n])
        if not self.model.cyclic:
            self.done = (
                self.ended_flag > 0.5 or t >= self.model.duration_s + self.max_overrun_s - 1e-9
            )
        return JointCommand.references(self.reference_rad)
