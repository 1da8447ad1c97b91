"""A monitor on a league server: the scene stream in, referee commands out.

A monitor connects to the server's monitor port and receives an RSMP frame every second cycle
(25 Hz): full frames now and then, diff frames in between (``mimic.league.rsmp``). It may send
commands: place a robot (its joints then start at zero) or the ball, give a kick-off.
``MonitorClient`` keeps the scene as of the last frame it read (``state``).
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import numpy as np

from mimic.league.protocol import Connection, connect
from mimic.league.rsmp import SceneState

__all__ = ["MonitorClient", "place_player_command", "place_ball_command"]


def _num(v: float) -> str:
    return f"{float(v):.6f}".rstrip("0").rstrip(".") or "0"


def place_player_command(team: str, player: int, pos_m, quat_wxyz=None) -> bytes:
    """``(agent (unum N)(team T)(pos X Y Z))``, with ``move3d`` when an orientation is given."""
    where = (
        f"(pos {' '.join(map(_num, pos_m))})"
        if quat_wxyz is None
        else f"(move3d {' '.join(map(_num, (*pos_m, *quat_wxyz)))})"
    )
    return f"(agent (unum {player})(team {team}){where})".encode()


def place_ball_command(pos_m, vel_m_s=(0.0, 0.0, 0.0)) -> bytes:
    """``(ball (pos X Y Z)(vel VX VY VZ))``."""
    return (
        f"(ball (pos {' '.join(map(_num, pos_m))})(vel {' '.join(map(_num, vel_m_s))}))"
    ).encode()


class MonitorClient:
    """A monitor connection and the scene it has seen (a context manager).

    Args:
        host, port: the server's monitor port.
    """

    def __init__(self, host: str, port: int) -> None:
        self._conn: Connection = connect(host, port, "monitor port")
        self.state = SceneState()

    @property
    def where(self) -> str:
        return self._conn.where

    def read(self, timeout_s: float | None = None) -> bool:
        """Read and apply one frame; False if none came within ``timeout_s`` [s].

        Raises:
            LeagueConnectionError: the server closed the connection.
        """
        message = self._conn.receive(timeout_s=timeout_s)
        if message is None:
            return False
        self.state.apply(message)
        return True

    def drain(self) -> int:
        """Apply every frame that has arrived, without waiting; how many there were."""
        messages = self._conn.receive_available()
        for message in messages:
            self.state.apply(message)
        return len(messages)

    def frames(self, timeout_s: float | None = None) -> Iterator[SceneState]:
        """The scene after each frame, as frames arrive (the same ``SceneState``, updated);
        ends when none arrives within ``timeout_s`` [s]."""
        while self.read(timeout_s):
            yield self.state

    def wait_until(self, time_s: float, timeout_s: float = 10.0) -> None:
        """Read frames until one at or after server time ``time_s`` [s], for at most
        ``timeout_s`` [s] in all."""
        deadline = time.monotonic() + timeout_s
        while not (self.state.time_s >= time_s - 1e-6):
            left = deadline - time.monotonic()
            if left <= 0 or not self.read(left):
                return

    # --- commands ---------------------------------------------------------------------------
    def send(self, command: bytes) -> None:
        """Send one or more commands, e.g. ``b"(kickOff Left)"``."""
        self._conn.send(command)

    def place_player(self, team: str, player: int, pos_m, quat_wxyz=None) -> None:
        self.send(place_player_command(team, player, pos_m, quat_wxyz))

    def place_ball(self, pos_m, vel_m_s=(0.0, 0.0, 0.0)) -> None:
        self.send(place_ball_command(pos_m, vel_m_s))

    def ball_pos_m(self) -> np.ndarray | None:
        return self.state.ball_pos_m()

    def close(self) -> None:
        self._conn.close()

    def __enter__(self) -> MonitorClient:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
