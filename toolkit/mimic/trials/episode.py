"""Pieces every trial episode shares: a seeded scene, running an agent with fall accounting,
standing still, and getting up after a fall."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.motion.files import load_motion, stand_pose_rad
from mimic.world.world import CYCLE_S, World

__all__ = ["EpisodeClock", "FallCounter", "stand_pose_rad", "run_until", "stand_still",
           "get_up", "lying_side"]


@dataclass
class EpisodeClock:
    """Simulated-time budget of one episode [s]."""

    limit_s: float

    def left_s(self, world: World) -> float:
        return self.limit_s - world.time_s


@dataclass
class FallCounter:
    """Counts falls (upright -> fallen transitions) and successful get-ups."""

    falls: int = 0
    getups: int = 0
    _was_fallen: bool = field(default=False, repr=False)

    def update(self, world: World) -> bool:
        fallen = world.fallen()
        if fallen and not self._was_fallen:
            self.falls += 1
        self._was_fallen = fallen
        return fallen


def run_until(world: World, agent: Agent, *, max_s: float, falls: FallCounter,
              stop=None, reset: bool = True, abort_on_fall: bool = True) -> str:
    """Run ``agent`` until it is done, ``stop(world)`` is true, it falls, or ``max_s`` passes.

    Returns:
        ``done``, ``stop``, ``fell`` or ``timeout``.
    """
    if reset:
        agent.reset(world.observe())
    for _ in range(max(0, int(round(max_s / CYCLE_S)))):
        obs = world.observe()
        speeds = agent.act(obs)
        if agent.done:
            return "done"
        if stop is not None and stop(world):
            return "stop"
        world.step(speeds)
        if falls.update(world) and abort_on_fall:
            return "fell"
    return "timeout"


def stand_still(world: World, *, max_s: float, falls: FallCounter, stop=None) -> str:
    """Hold the stand pose (tracked) until ``stop(world)`` or ``max_s``."""
    player = KeyframePlayer(load_motion("stand"), hold_s=math.inf)
    return run_until(world, player, max_s=max_s, falls=falls, stop=stop)


def lying_side(world: World) -> str:
    """``front`` if the torso faces the ground, else ``back``."""
    forward_z = world.data.xmat[world.torso_body_id][6]  # z of the torso x axis
    return "front" if forward_z < 0 else "back"


def get_up(world: World, falls: FallCounter, *, attempts: int = 3) -> bool:
    """Let the robot come to rest, then play the matching get-up; True once upright."""
    settle = KeyframePlayer(load_motion("stand"), hold_s=math.inf)
    for _ in range(attempts):
        run_until(world, settle, max_s=0.6, falls=falls, abort_on_fall=False)
        motion = load_motion(f"getup_{lying_side(world)}")
        run_until(world, KeyframePlayer(motion, hold_s=0.5), max_s=motion.duration_s + 1.5,
                  falls=falls, abort_on_fall=False)
        if world.upright() and not world.fallen():
            falls.getups += 1
            falls.update(world)
            return True
    return False
