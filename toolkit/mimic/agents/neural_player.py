"""Plays a learned motion: the network gives references each 20 ms cycle, tracked by the same
proportional controller as the keyframe player (so a learned copy meets the same attenuation)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.tracking import TrackingController
from mimic.learn.model import MotionModel
from mimic.robot.joints import NUM_JOINTS
from mimic.world.world import Observation

__all__ = ["NeuralPlayer"]


class NeuralPlayer(Agent):
    """A motion network as an agent.

    One-shot models: time since ``reset`` goes in; ``done`` is set when the ended flag
    exceeds 0.5 (or, as a guard, ``max_overrun_s`` after the trained duration).
    Cyclic models: the phase advances at ``speed_rate`` times the learned rate and loops;
    they never finish by themselves.
    """

    team = "mimic"

    def __init__(self, model: MotionModel, tracking: TrackingController = TrackingController(),
                 speed_rate: float = 1.0, max_overrun_s: float = 1.0) -> None:
        super().__init__()
        self.model, self.tracking = model, tracking
        self.speed_rate, self.max_overrun_s = speed_rate, max_overrun_s
        self.name = model.name
        self.period_s = model.period_s / speed_rate if model.cyclic else None
        self.ended_flag = 0.0
        self._start_s = 0.0

    @classmethod
    def from_file(cls, path: str | Path, **kwargs) -> "NeuralPlayer":
        """Load a ``.mimic`` model (raises ``ModelFileError`` for a bad file)."""
        from mimic.learn.model_file import load_model

        return cls(load_model(path), **kwargs)

    def reset(self, obs: Observation) -> None:
        self._start_s = obs.time_s
        self.done = False
        self.ended_flag = 0.0

    def reference_at(self, t_s: float) -> np.ndarray:
        """(23,) network output at ``t_s`` [s] of playing (phase-scaled for cyclic models)."""
        if self.model.cyclic:
            t_s = (t_s * self.speed_rate) % self.model.period_s
        return self.model.predict(t_s)

    def act(self, obs: Observation) -> np.ndarray:
        t = obs.time_s - self._start_s
        out = self.reference_at(t)
        self.reference_rad = out[:NUM_JOINTS]
        self.ended_flag = float(out[NUM_JOINTS])
        if not self.model.cyclic:
            self.done = (self.ended_flag > 0.5
                         or t >= self.model.duration_s + self.max_overrun_s - 1e-9)
        return self.tracking.speeds(self.reference_rad, obs.joint_angles_rad)
