"""The agent interface: an observation in, 22 joint speed commands out, every 20 ms cycle."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from mimic.world.world import Observation

__all__ = ["Agent"]


class Agent(ABC):
    """A controller for the robot.

    Subclasses set ``name`` (the motion or behaviour, e.g. ``kick_right``) and ``team``
    (``mimic`` for ours, ``other_team`` for controllers whose internals we do not see).
    """

    name: str = "agent"
    team: str = "mimic"
    #: Period [s] of a cyclic motion (a walk), or None for a one-shot motion.
    period_s: float | None = None
    #: How the robot must be set up before the agent starts: ``standing``, ``lying_front`` or
    #: ``lying_back`` (get-ups); see ``mimic.motion.keyframe.START_POSTURES``.
    start_posture: str = "standing"

    def __init__(self) -> None:
        self.done = False
        #: (22,) joint references [rad] sent this cycle, or None for agents that do not
        #: expose them (the other team): only our own agents fill it.
        self.reference_rad: np.ndarray | None = None

    @abstractmethod
    def reset(self, obs: Observation) -> None:
        """Start (or restart) the behaviour from the current observation."""

    @abstractmethod
    def act(self, obs: Observation) -> np.ndarray:
        """(22,) joint speed commands [rad/s] for this cycle; sets ``done`` when finished."""
