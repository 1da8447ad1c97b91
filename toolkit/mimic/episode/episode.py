"""An episode: one world watched by the same observers through a chain of runs.

A trial episode is settle, kick, wait, walk, get up, kick again...: every step is a ``run``
with the same fall counter and pose trace. ``Episode`` keeps them together, and holds the
behaviours every episode shares: standing still, waiting limp, getting up after a fall.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from mimic.agents.base import Agent
from mimic.agents.hold import Limp
from mimic.agents.keyframe_player import KeyframePlayer
from mimic.episode.observers import FallCounter, Observer
from mimic.episode.run import run
from mimic.motion.files import load_motion
from mimic.world.base import World

__all__ = ["Episode"]


@dataclass
class Episode:
    """A world, its fall counter and the observers that watch every run of the episode."""

    world: World
    observers: tuple[Observer, ...] = ()
    falls: FallCounter = field(default_factory=FallCounter)

    @property
    def watchers(self) -> tuple[Observer, ...]:
        return (self.falls, *self.observers)

    def run(
        self,
        agent: Agent,
        *,
        max_s: float,
        stop: Callable[[World], bool] | None = None,
        reset: bool = True,
        abort_on_fall: bool = True,
        stop_when_done: bool = True,
    ) -> str:
        """``run`` the agent with the episode's observers; returns how it ended."""
        return run(
            self.world,
            agent,
            max_s=max_s,
            stop=stop,
            observers=self.watchers,
            reset=reset,
            abort_on_fall=abort_on_fall,
            stop_when_done=stop_when_done,
        ).end

    def stand_still(self, *, max_s: float, stop: Callable[[World], bool] | None = None) -> str:
        """Move into the stand pose and hold it until ``stop(world)`` or ``max_s`` [s]."""
        player = KeyframePlayer(load_motion("stand", self.world.robot.name), hold_s=math.inf)
        return self.run(player, max_s=max_s, stop=stop)

    def wait_limp(self, *, max_s: float, stop: Callable[[World], bool] | None = None) -> str:
        """Keep the joints where they are (a fallen robot) until ``stop`` or ``max_s`` [s]."""
        return self.run(Limp(self.world.robot.name), max_s=max_s, stop=stop, abort_on_fall=False)

    def get_up(self, *, attempts: int = 3) -> bool:
        """Let the robot come to rest, then play the matching get-up; True once upright."""
        robot = self.world.robot.name
        settle = KeyframePlayer(load_motion("stand", robot), hold_s=math.inf)
        for _ in range(attempts):
            self.run(settle, max_s=0.6, abort_on_fall=False)
            motion = load_motion(f"getup_{self.world.lying_side()}", robot)
            self.run(
                KeyframePlayer(motion, hold_s=0.5),
                max_s=motion.duration_s + 1.5,
                abort_on_fall=False,
            )
            if self.world.upright() and not self.world.fallen():
                self.falls.getups += 1
                self.falls.update(self.world)
                return True
        return False
