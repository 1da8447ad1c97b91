"""Runs an agent in the world, cycle by cycle, handing each cycle to optional observers."""

from __future__ import annotations

from typing import Callable

import numpy as np

from mimic.agents.base import Agent
from mimic.world.world import CYCLE_S, Observation, World

__all__ = ["run_agent", "CycleObserver"]

#: Called once per cycle with the world, the observation and the agent, before stepping.
CycleObserver = Callable[[World, Observation, Agent], None]


def run_agent(world: World, agent: Agent, *, max_duration_s: float,
              stop_when_done: bool = True,
              observers: tuple[CycleObserver, ...] = ()) -> int:
    """Reset ``agent`` and run it until done (if asked) or ``max_duration_s`` [s] has passed.

    Returns:
        The number of cycles run.
    """
    agent.reset(world.observe())
    cycles = int(round(max_duration_s / CYCLE_S))
    for k in range(cycles):
        obs = world.observe()
        speeds = agent.act(obs)
        for observer in observers:
            observer(world, obs, agent)
        if stop_when_done and agent.done:
            return k
        world.step(np.asarray(speeds))
    return cycles
