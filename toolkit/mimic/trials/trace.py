"""A world that keeps a light trace of itself (body poses, ball) for replay in Rerun.

Trials run thousands of cycles in worker processes; tracing them all would cost memory and time,
so only the episodes asked for run in a ``TracingWorld`` (the first one of each variant when a
dashboard is wanted), sampled every few cycles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.robot.description import BODIES
from mimic.world.world import World

__all__ = ["EpisodeTrace", "TracingWorld"]


@dataclass
class EpisodeTrace:
    """Poses of one episode in the field frame.

    times_s: (N,) simulated time [s]; body_pos_m: (N, B, 3); body_quat_wxyz: (N, B, 4), bodies
    in ``body_names`` order; ball_pos_m: (N, 3).
    """

    times_s: np.ndarray
    body_names: tuple[str, ...]
    body_pos_m: np.ndarray
    body_quat_wxyz: np.ndarray
    ball_pos_m: np.ndarray

    def poses(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """``{body: (positions (N, 3), quats (N, 4))}``, the form ``viz.scene`` logs."""
        return {name: (self.body_pos_m[:, i], self.body_quat_wxyz[:, i])
                for i, name in enumerate(self.body_names)}


class TracingWorld(World):
    """A ``World`` that samples body poses and the ball every ``every_cycles`` cycles."""

    def __init__(self, *args, every_cycles: int = 2, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.every_cycles = every_cycles
        self._names = tuple(b.name for b in BODIES)
        self._ids = np.array([self.model.body(n).id for n in self._names])
        self._samples: list[tuple[float, np.ndarray, np.ndarray, np.ndarray]] = []

    def step(self, joint_speeds_rad_s: np.ndarray) -> None:
        super().step(joint_speeds_rad_s)
        if self.cycle % self.every_cycles == 0:
            d = self.data
            self._samples.append((float(d.time), d.xpos[self._ids].copy(),
                                  d.xquat[self._ids].copy(), self.ball_pos_m()))

    def trace(self) -> EpisodeTrace:
        """Everything sampled so far."""
        if not self._samples:
            empty = np.zeros((0, len(self._names), 3))
            return EpisodeTrace(np.zeros(0), self._names, empty, np.zeros((0, len(self._names), 4)),
                                np.zeros((0, 3)))
        t, pos, quat, ball = zip(*self._samples)
        return EpisodeTrace(np.array(t), self._names, np.stack(pos), np.stack(quat), np.stack(ball))
