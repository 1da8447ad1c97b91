"""The scenarios by name: a config class (its defaults are the scenario's), the scene it sets
up and how one episode plays.

    from mimic.tasks.scenarios import get_scenario
    kick = get_scenario("kick-from-stand")
    outcome = kick.play(world, agent, 0, kick.config(settle_s=0.5))

Every caller plays a scenario through ``play(world, agent, seed, config)`` with a config of
its own; the differences between callers live in the config's fields, not in copies.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from mimic.errors import MimicError
from mimic.tasks import kick_from_stand, stand, straight_walk

__all__ = ["Scenario", "SCENARIOS", "get_scenario"]


@dataclass(frozen=True)
class Scenario:
    """One scenario.

    Attributes:
        name: its name in ``SCENARIOS``.
        config: the frozen config class; ``config()`` is the scenario's default.
        scene: the scene a config sets up (``scene(config, ...)``).
        play: ``play(world, agent, seed, config)`` -> the scenario's typed outcome.
    """

    name: str
    config: type
    scene: Callable[..., Any]
    play: Callable[..., Any]


SCENARIOS: dict[str, Scenario] = {
    s.name: s
    for s in (
        Scenario(
            "kick-from-stand",
            kick_from_stand.KickFromStandConfig,
            kick_from_stand.scene,
            kick_from_stand.play,
        ),
        Scenario("stand", stand.StandConfig, stand.scene, stand.play),
        Scenario(
            "straight-walk",
            straight_walk.StraightWalkConfig,
            straight_walk.scene,
            straight_walk.play,
        ),
    )
}


def get_scenario(name: str) -> Scenario:
    """The scenario called ``name``.

    Raises:
        MimicError: an unknown name, with the known ones.
    """
    try:
        return SCENARIOS[name]
    except KeyError:
        raise MimicError(f"unknown scenario {name!r}; scenarios: {', '.join(SCENARIOS)}") from None
