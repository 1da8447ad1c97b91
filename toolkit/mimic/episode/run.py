"""The one control loop: an agent in a world, cycle by cycle, watched by observers."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from mimic.agents.base import Agent
from mimic.episode.observers import Observer
from mimic.world.base import CYCLE_S, World

__all__ = ["run", "RunOutcome", "END_REASONS"]

#: Why a run ended: the agent said done, ``stop`` held, the robot fell (with
#: ``abort_on_fall``), or the time ran out.
END_REASONS = ("done", "stop", "fell", "timeout")


@dataclass(frozen=True)
class RunOutcome:
    """How a run ended (``END_REASONS``) and how many cycles it stepped."""

    end: str
    cycles: int


def run(
    world: World,
    agent: Agent,
    *,
    max_s: float,
    stop: Callable[[World], bool] | None = None,
    observers: Sequence[Observer] = (),
    reset: bool = True,
    stop_when_done: bool = True,
    abort_on_fall: bool = False,
) -> RunOutcome:
    """Run ``agent`` in ``world`` for at most ``max_s`` [s] of simulated time.

    Each cycle: observe, ask the agent, show both to every observer (``before_step``), end
    if the agent is done (``stop_when_done``) or ``stop(world)`` holds, step the world, show
    the result to every observer (``after_step``), end if ``abort_on_fall`` and the robot
    lies. ``reset``: start the agent afresh (and check it can drive the world's robot);
    False continues an agent that already ran.
    """
    if reset:
        agent.check_robot(world.robot)
        agent.reset(world.observe())
    for observer in observers:
        observer.start(world, agent)
    cycles = max(0, int(round(max_s / CYCLE_S)))
    for k in range(cycles):
        obs = world.observe()
        command = agent.act(obs)
        for observer in observers:
            observer.before_step(world, obs, agent, command)
        if stop_when_done and agent.done:
            return RunOutcome("done", k)
        if stop is not None and stop(world):
            return RunOutcome("stop", k)
        world.step(command)
        for observer in observers:
            observer.after_step(world)
        if abort_on_fall and world.fallen():
            return RunOutcome("fell", k + 1)
    return RunOutcome("timeout", cycles)
