"""Agents by name: our keyframe motions plus lazily imported behaviours and neural players.

Nothing beyond this module is imported until an agent is asked for, so listing names is cheap
and a missing optional module only matters when its agent is used.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Callable

from mimic.agents.base import Agent
from mimic.errors import MimicError

__all__ = ["make_agent", "agent_names", "agent_from_model", "LAZY_AGENTS"]

#: Agent name -> "module:factory" (a callable with no arguments returning an Agent).
LAZY_AGENTS: dict[str, str] = {
    "walk": "mimic.agents.walk:make_walk_agent",
    "other-team-walk": "mimic.agents.other_team:make_walk",
    "other-team-kick": "mimic.agents.other_team:make_kick",
}


def _load(target: str, what: str) -> Callable:
    module_name, attr = target.split(":")
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as err:
        if err.name and module_name.startswith(err.name):
            raise MimicError(f"{what} is not available: module {module_name} is missing "
                             "from this installation") from None
        raise
    try:
        return getattr(module, attr)
    except AttributeError:
        raise MimicError(f"{what} is not available: {module_name} has no {attr}") from None


def agent_names() -> list[str]:
    """Every name ``make_agent`` accepts: shipped motions, then the lazy agents."""
    from mimic.motion.files import list_motions

    return list_motions() + [n for n in LAZY_AGENTS if n not in list_motions()]


def make_agent(name: str) -> Agent:
    """A fresh agent: a shipped motion name gives a ``KeyframePlayer`` of that motion."""
    from mimic.motion.files import list_motions, load_motion

    if name in LAZY_AGENTS:
        return _load(LAZY_AGENTS[name], f"agent {name!r}")()
    if name in list_motions():
        from mimic.agents.keyframe_player import KeyframePlayer

        return KeyframePlayer(load_motion(name))
    raise MimicError(f"unknown agent {name!r}; known: {', '.join(agent_names())} "
                     "(or --model FILE.mimic for a learned motion)")


def agent_from_model(path: str | Path) -> Agent:
    """A neural player of a trained model file."""
    player = _load("mimic.agents.neural_player:NeuralPlayer", "the neural player")
    return player.from_file(path)
