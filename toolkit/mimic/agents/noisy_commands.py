"""An agent whose speed commands carry seeded Gaussian noise (servo and timing jitter)."""

from __future__ import annotations

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.world.base import Observation

__all__ = ["NoisyCommands"]


class NoisyCommands(Agent):
    """Wraps an agent and adds seeded Gaussian noise [rad/s] to its speed commands.

    A reference command is first turned into the speeds the robot's servos would send
    (``servos``: the robot's actuator model, needed only then). With zero noise the inner
    agent's commands pass through unchanged and nothing is drawn from ``rng``.
    """

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

    def resume(self, obs: Observation) -> None:
        self.inner.resume(obs)
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
