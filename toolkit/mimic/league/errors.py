"""Errors of the league layer: each says what went wrong and what to do, in one line."""

from __future__ import annotations

from mimic.errors import MimicError

__all__ = [
    "LeagueError",
    "LeagueConnectionError",
    "LeagueProtocolError",
    "ServerStartError",
    "PlayerNotFoundError",
    "GameLogError",
]


class LeagueError(MimicError):
    """Something about the league server, its stream or its logs."""


class LeagueConnectionError(LeagueError):
    """Nothing listens on a port, or the server went away."""


class LeagueProtocolError(LeagueConnectionError):
    """A peer whose bytes are not the league's stream (a message too long to be one)."""


class ServerStartError(LeagueError):
    """A hosted server did not come up."""


class PlayerNotFoundError(LeagueError):
    """A team or player that is not on the field."""


class GameLogError(LeagueError):
    """A file that is not an RCSSServerMJ game log."""
