"""Observers of a run: they see every cycle and keep what they need.

Falls and pose traces live here; the MCAP writer is ``recording.recorder.McapObserver`` and
live Rerun logging is ``viz.live.RerunObserver``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mimic.robot.actuators import JointCommand
from mimic.world.base import Observation, World

__all__ = ["Observer", "FallCounter", "PoseTrace", "EpisodeTrace", "UprightLog"]


class Observer:
    """Sees a run; override what you need (every hook does nothing by default)."""

    def start(self, world: World, agent) -> None:
        """Called once when a run starts."""

    def before_step(self, world: World, obs: Observation, agent, command: JointCommand) -> None:
        """What the agent saw and answered this cycle, before the world steps."""

    def after_step(self, world: World) -> None:
        """The world after this cycle's step."""


@dataclass
class FallCounter(Observer):
    """Counts falls (upright -> fallen transitions) and successful get-ups."""

    falls: int = 0
    getups: int = 0
    _was_fallen: bool = field(default=False, repr=False)

    def after_step(self, world: World) -> None:
        self.update(world)

    def update(self, world: World) -> bool:
        """Look at the robot now; True while it lies."""
        fallen = world.fallen()
        if fallen and not self._was_fallen:
            self.falls += 1
        self._was_fallen = fallen
        return fallen


@dataclass
class UprightLog(Observer):
    """Whether the robot stood upright and whether it lay, at every cycle before the step."""

    upright: list = field(default_factory=list)
    fallen: list = field(default_factory=list)

    def before_step(self, world, obs, agent, command) -> None:
        self.upright.append(world.upright())
        self.fallen.append(world.fallen())


@dataclass
class EpisodeTrace:
    """Poses of one episode in the field frame.

    times_s: (T,) simulated time [s]; body_pos_m: (T, B, 3); body_quat_wxyz: (T, B, 4), bodies
    in ``body_names`` order; ball_pos_m: (T, 3); pushes: (start time [s], force (3,) [N] in
    the field frame, duration [s]) of every push on the torso (``episode.disturbance``).
    """

    times_s: np.ndarray
    body_names: tuple[str, ...]
    body_pos_m: np.ndarray
    body_quat_wxyz: np.ndarray
    ball_pos_m: np.ndarray
    pushes: tuple[tuple[float, np.ndarray, float], ...] = ()

    def poses(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """``{body: (positions (T, 3), quats (T, 4))}``, the form ``viz.scene`` logs."""
        return {
            name: (self.body_pos_m[:, i], self.body_quat_wxyz[:, i])
            for i, name in enumerate(self.body_names)
        }


class PoseTrace(Observer):
    """Samples every link's pose and the ball every ``every_cycles`` steps, for a replay.

    One trace may watch several runs (an episode is a chain of runs: settle, kick, walk...).
    """

    def __init__(self, every_cycles: int = 2) -> None:
        self.every_cycles = every_cycles
        self._cycle = 0
        self._names: tuple[str, ...] = ()
        self._samples: list[tuple[float, np.ndarray, np.ndarray, np.ndarray]] = []

    def after_step(self, world: World) -> None:
        self._cycle += 1
        if self._cycle % self.every_cycles == 0:
            poses = world.body_poses()
            self._names = poses.names
            self._samples.append((world.time_s, poses.pos_m, poses.quat_wxyz, world.ball_pos_m()))

    def trace(self) -> EpisodeTrace:
        """Everything sampled so far."""
        if not self._samples:
            b = len(self._names)
            return EpisodeTrace(
                np.zeros(0), self._names, np.zeros((0, b, 3)), np.zeros((0, b, 4)), np.zeros((0, 3))
            )
        t, pos, quat, ball = zip(*self._samples)
        return EpisodeTrace(np.array(t), self._names, np.stack(pos), np.stack(quat), np.stack(ball))
