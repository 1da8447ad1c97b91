"""Standing: the robot placed in its stand pose holds it; does it stay up?

The scene places the robot standing at the centre spot, its start pose perturbed, no
settling. The agent (by default the robot's own ``stand`` motion, held) plays for
``duration_s``; the robot stood if it never lay, before any cycle or at the end.

    outcome = play(world, None, seed=0, config=StandConfig(duration_s=10.0))
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.episode import PoseNoise, Scene, UprightLog, run
from mimic.errors import MimicError
from mimic.motion.files import load_motion
from mimic.tasks.perturbation import Perturbation
from mimic.world.base import CYCLE_S, World

__all__ = ["StandConfig", "StandOutcome", "scene", "play"]


@dataclass(frozen=True)
class StandConfig:
    """One stand."""

    # How long the robot holds its stand pose [s] (after the stand motion itself).
    duration_s: float = 10.0
    # Start-pose and placement noise, drawn from the seed.
    noise: PoseNoise = Perturbation().noise()
    # Time the placed robot holds its (perturbed) start pose before the agent starts [s].
    settle_s: float = 0.0

    def __post_init__(self) -> None:
        for name in ("duration_s", "settle_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise MimicError(f"stand: {name} must be finite and >= 0, got {value}")


@dataclass(frozen=True)
class StandOutcome:
    """What one stand did.

    Attributes:
        stood: the robot never lay, at any cycle or at the end.
        first_fallen_s: time from the agent's start to the first cycle it lay [s]; None if
            it never lay during the run.
    """

    stood: bool
    first_fallen_s: float | None


def scene(config: StandConfig) -> Scene:
    """The scene of a stand."""
    return Scene(noise=config.noise, settle_s=config.settle_s)


def play(
    world: World, agent: Agent | None, seed: int, config: StandConfig = StandConfig()
) -> StandOutcome:
    """Play one stand in ``world`` (module docstring); ``agent`` None: the robot's ``stand``
    motion, held for ``duration_s`` after it ends."""
    scene(config).setup(world, np.random.default_rng(seed))
    log = UprightLog()
    if agent is None:
        stand = load_motion("stand", world.robot.name)
        agent, max_s = KeyframePlayer(stand, hold_s=config.duration_s), stand.duration_s
    else:
        max_s = 0.0
    run(world, agent, max_s=max_s + config.duration_s, observers=(log,))
    first = next((k for k, fallen in enumerate(log.fallen) if fallen), None)
    return StandOutcome(
        first is None and not world.fallen(), None if first is None else first * CYCLE_S
    )
