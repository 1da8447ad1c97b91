"""The agent interface: an observation in, a joint command out, every 20 ms cycle."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from mimic.errors import MimicError
from mimic.robot.actuators import JointCommand
from mimic.robot.model import RobotDescription
from mimic.world.base import Observation

__all__ = ["Agent", "JointCommand"]


class Agent(ABC):
    """A controller for one robot.

    Subclasses set ``name`` (the motion or behaviour, e.g. ``kick_right``) and ``team``
    (``mimic`` for ours, ``other_team`` for controllers whose internals we do not see). An agent
    answers with joint references (any robot: the robot's actuator model tracks them) or, for
    a controller written for the NAO's speed servos, joint speeds.
    """

    name: str = "agent"
    team: str = "mimic"
    #: Period [s] of a cyclic motion (a walk), or None for a one-shot motion.
    period_s: float | None = None
    #: How the robot must be set up before the agent starts: ``standing``, ``lying_front`` or
    #: ``lying_back`` (get-ups); see ``mimic.world.base.POSTURES``.
    start_posture: str = "standing"
    #: The robot this agent drives (its joint vectors are that robot's).
    robot: str = "nao"
    #: A controller written for one robot only (a walk engine with that robot's geometry)
    #: says so: it refuses any other robot.
    robot_only: bool = False

    def __init__(self) -> None:
        self.done = False
        #: (N,) joint references [rad] sent this cycle, or None for agents that do not
        #: expose them (the other team): only our own agents fill it.
        self.reference_rad: np.ndarray | None = None

    def check_robot(self, robot: RobotDescription) -> None:
        """Refuse, with one clear line, a robot this agent cannot drive."""
        if robot.name == self.robot:
            return
        if self.robot_only:
            raise MimicError(
                f"{self.name} is a {self.robot.upper()}-only controller; it cannot "
                f"drive the {robot.name.upper()}"
            )
        raise MimicError(
            f"{self.name} was made for the {self.robot.upper()} "
            f"({self.robot} joints); the world's robot is the {robot.name.upper()}"
        )

    @abstractmethod
    def reset(self, obs: Observation) -> None:
        """Start (or restart) the behaviour from the current observation."""

    def resume(self, obs: Observation) -> None:
        """Start again after an interruption within the same task (the robot fell and got
        up): what it aims for stays, the rest starts afresh from ``obs``. A walk along a
        course keeps the course (its start line and heading), so it turns back to it; an
        agent that keeps nothing (the default) simply restarts (``reset``)."""
        self.reset(obs)

    @abstractmethod
    def act(self, obs: Observation) -> JointCommand:
        """This cycle's joint command; sets ``done`` when finished."""
