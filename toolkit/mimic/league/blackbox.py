"""Black-box recording: another team's player, seen only through the server's monitor stream.

As in the study (which watched SimSpark's monitor), nothing of the team's code is read: the
monitor shows every body of every robot, ``decode`` turns one player's bodies back into its
joint angles, and ``PlayerWriter`` writes them in our layout. Works on a server running a match
in real time or in sync mode; waits for the player to appear. The player leaving ends a recording
normally; Ctrl-C or the server stopping end it early, the file finished and saying so; a crash
of mimic loses at most ``FLUSH_PERIOD_S``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from mimic.league.decode import PlayerDecoder, check_model, robot_for_model
from mimic.league.errors import LeagueConnectionError, LeagueError, PlayerNotFoundError
from mimic.league.monitor import MonitorClient
from mimic.league.player_writer import PlayerWriter
from mimic.league.protocol import parse_address
from mimic.league.rsmp import PlayerNode, SceneState
from mimic.robot.league import LEAGUE_ROBOTS
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.sigint import SigintFlag

__all__ = [
    "record_player",
    "list_players",
    "BlackBoxResult",
    "describe_players",
    "robot_of",
    "DEFAULT_LEAGUE_ROBOT",
]

#: The robot a player is taken to be when the scene graph does not say.
DEFAULT_LEAGUE_ROBOT = "t1"
#: A player missing from the stream this long has left the field [s of server time].
_GONE_S = 1.0
#: When the wait message first shows, and how often it repeats [s].
_FIRST_WAIT_MESSAGE_S = 1.0
_WAIT_MESSAGE_EVERY_S = 5.0

#: Called with (recorded seconds, planned seconds or None).
Progress = Callable[[float, float | None], None]


@dataclass(frozen=True)
class BlackBoxResult:
    """What a black-box recording or import wrote.

    Attributes:
        path: the file; robot: the robot's registry name; samples: poses written;
        duration_s: recorded time [s]; interrupted: it stopped early (Ctrl-C, the server
        gone; the file is complete up to there); reason: why it ended (``done``, ``TEAM #N
        left the field``, ``the server stopped``, ...);
        frames_skipped: frames that did not decode (teleports, frames before the first full).
    """

    path: Path
    robot: str
    team: str
    player: int
    samples: int
    duration_s: float
    interrupted: bool
    reason: str
    frames_skipped: int


def describe_players(players: tuple[PlayerNode, ...]) -> str:
    """``A #1 (T1), A #2 (T1), B #1 (K1)``, or ``nobody``."""
    return ", ".join(f"{p.team} #{p.player} ({p.model or '?'})" for p in players) or "nobody"


def robot_of(node: PlayerNode, robot: str | RobotDescription | None, who: str) -> RobotDescription:
    """The robot to decode a player as: the scene graph's model, checked against ``robot``
    (an option); ``DEFAULT_LEAGUE_ROBOT`` when neither says."""
    if robot is None:
        name = robot_for_model(node.model) if node.model else DEFAULT_LEAGUE_ROBOT
        if name not in LEAGUE_ROBOTS:
            raise LeagueError(
                f"{who} is a {node.model} robot, which mimic does not know; "
                f"league robots: {', '.join(LEAGUE_ROBOTS)}"
            )
        return get_robot(name)
    name = robot.name if isinstance(robot, RobotDescription) else robot.lower()
    check_model(name, node.model, who)  # before loading a robot we would not use
    return get_robot(robot)


def _first_scene(monitor: MonitorClient, timeout_s: float) -> SceneState:
    deadline = time.monotonic() + timeout_s
    while not monitor.state.valid:
        left = deadline - time.monotonic()
        if left <= 0 or not monitor.read(timeout_s=left):
            raise LeagueConnectionError(
                f"no scene from {monitor.where} within "
                f"{timeout_s:g} s: is it the server's monitor port "
                "(rcssservermj --mport)?"
            )
    return monitor.state


def list_players(monitor_address: str, timeout_s: float = 10.0) -> tuple[PlayerNode, ...]:
    """The robots on the field of the server whose monitor port is ``monitor_address``."""
    with MonitorClient(*parse_address(monitor_address, "--server")) as monitor:
        return _first_scene(monitor, timeout_s).players


def record_player(
    monitor_address: str,
    out_path: str | Path,
    team: str,
    player: int,
    *,
    seconds: float | None = None,
    robot: str | None = None,
    wait_s: float = 30.0,
    on_wait: Callable[[str], None] | None = None,
    progress: Progress | None = None,
) -> BlackBoxResult:
    """Record ``team`` #``player`` from a server's monitor stream into ``out_path``.

    Args:
        monitor_address: ``HOST:PORT`` of the server's monitor port.
        seconds: server time to record [s] (None: until Ctrl-C, the player leaves or the
            server stops).
        robot: the robot the player is (None: as the scene graph says, else t1).
        wait_s: how long to wait for the player to appear [s, wall clock].
        on_wait: called with a message while waiting for the player.

    Raises:
        LeagueConnectionError: nothing listens at the address.
        PlayerNotFoundError: the player did not appear within ``wait_s`` (the message names
            the players that are on the field). No file is written then.
    """
    if seconds is not None and not seconds > 0:
        raise LeagueError(f"--seconds must be > 0, got {seconds}")
    who = f"{team} #{player}"
    with (
        SigintFlag() as sigint,
        MonitorClient(*parse_address(monitor_address, "--server")) as monitor,
    ):
        state = _first_scene(monitor, max(wait_s, 10.0))
        node = _await_player(monitor, team, player, wait_s, on_wait, sigint)
        decoder = PlayerDecoder(robot_of(node, robot, who))
        skipped_before = state.skipped
        out: PlayerWriter | None = None
        reason, t_seen = "done", state.time_s
        try:
            while not sigint.raised:
                sample = decoder.sample(state, team, player)
                if sample is not None:
                    t_seen = sample.time_s
                    if out is None:
                        out = PlayerWriter(
                            out_path,
                            decoder.robot,
                            team,
                            player,
                            "monitor",
                            monitor_address,
                            sample.time_s,
                        )
                    if seconds is not None and out.elapsed_s(sample) > seconds + 1e-6:
                        break
                    if out.write(sample, state.ball_pos_m()) and progress is not None:
                        progress(out.duration_s, seconds)
                elif (
                    state.player(team, player) is None
                    and state.valid
                    and state.time_s - t_seen > _GONE_S
                ):
                    reason = f"{who} left the field"
                    break
                try:
                    monitor.read(timeout_s=0.5)  # None in time: look at Ctrl-C again
                except LeagueConnectionError:
                    reason = "the server stopped"
                    break
            else:
                reason = "interrupted (Ctrl-C)"
        except KeyboardInterrupt:  # Ctrl-C outside the flag's reach, or SIGTERM: kept
            reason = "interrupted"
            raise
        except BaseException:  # a failed recording leaves the target as it was
            if out is not None:
                out.abandon()
                out = None
            raise
        finally:
            if out is not None:
                out.finish(interrupted=not _normal_end(reason), reason=reason)
        if out is None:  # nothing written, no file
            if reason.startswith("interrupted"):
                raise KeyboardInterrupt
            raise LeagueError(
                f"{reason} before {who} showed a whole "
                f"{decoder.robot.name.upper()} pose: nothing recorded"
            )
        return BlackBoxResult(
            out.path,
            decoder.robot.name,
            team,
            player,
            out.samples,
            out.duration_s,
            not _normal_end(reason),
            reason,
            state.skipped - skipped_before,
        )


def _normal_end(reason: str) -> bool:
    """The recording ran its course: its time was up, or the player left (a game's end)."""
    return reason == "done" or reason.endswith("left the field")


def _await_player(
    monitor: MonitorClient,
    team: str,
    player: int,
    wait_s: float,
    on_wait: Callable[[str], None] | None,
    sigint: SigintFlag,
) -> PlayerNode:
    who = f"{team} #{player}"
    deadline = time.monotonic() + wait_s
    next_message = time.monotonic() + _FIRST_WAIT_MESSAGE_S  # a quick look says nothing
    while True:
        found = monitor.state.player(team, player)
        if found is not None:
            return found
        now = time.monotonic()
        if now >= deadline or sigint.raised:
            raise PlayerNotFoundError(
                f"{who} is not on the field of {monitor.where}; on the "
                f"field: {describe_players(monitor.state.players)}"
            )
        if on_wait is not None and now >= next_message:
            on_wait(
                f"waiting for {who} to join (on the field: "
                f"{describe_players(monitor.state.players)})"
            )
            next_message = now + _WAIT_MESSAGE_EVERY_S
        monitor.read(timeout_s=min(0.5, max(0.01, deadline - now)))
