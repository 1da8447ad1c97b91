"""Black-box recording: another team's player, seen only through the server's monitor stream.

As in the study (which watched SimSpark's monitor), nothing of the team's code is read: the
monitor shows every body of every robot, ``league.decode`` turns one player's bodies back into its
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
from mimic.league.errors import (
    LeagueConnectionError,
    LeagueError,
    LeagueProtocolError,
    PlayerNotFoundError,
)
from mimic.league.monitor import MonitorClient
from mimic.league.protocol import parse_address
from mimic.league.rsmp import PlayerNode, SceneState
from mimic.league.untrusted import printable
from mimic.recording.player_writer import PlayerWriter
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.sigint import SigintFlag
from mimic.world.registry import LEAGUE, get_world

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
#: The longest single wait for a frame, so that Ctrl-C is answered within it [s].
_POLL_S = 0.25
#: A recording ends when no valid frame came for this long [s, wall clock].
STALL_S = 30.0

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
    """``A #1 (T1), A #2 (T1), B #1 (K1)``, or ``nobody`` (names as ``printable`` shows them:
    plain text, control characters escaped)."""
    return (
        ", ".join(f"{who(p.team, p.player)} ({printable(p.model) or '?'})" for p in players)
        or "nobody"
    )


def who(team: str, player: int) -> str:
    """``TEAM #N`` with the team name as ``printable`` shows it."""
    return f"{printable(team)} #{player}"


def robot_of(node: PlayerNode, robot: str | RobotDescription | None, who: str) -> RobotDescription:
    """The robot to decode a player as: the scene graph's model, checked against ``robot``
    (an option); ``DEFAULT_LEAGUE_ROBOT`` when neither says."""
    if robot is None:
        name = robot_for_model(node.model) if node.model else DEFAULT_LEAGUE_ROBOT
        league_robots = get_world(LEAGUE).robots
        if name not in league_robots:
            raise LeagueError(
                f"{who} is a {printable(node.model)} robot, which mimic does not know; "
                f"league robots: {', '.join(league_robots)}"
            )
        return get_robot(name)
    name = robot.name if isinstance(robot, RobotDescription) else robot.lower()
    check_model(name, node.model, who)  # before loading a robot we would not use
    return get_robot(robot)


def _first_scene(
    monitor: MonitorClient, timeout_s: float, sigint: SigintFlag | None = None
) -> SceneState:
    """Read until the scene is whole (a full frame), for at most ``timeout_s`` [s]; Ctrl-C
    (``sigint``) ends the wait within ``_POLL_S``.

    Raises:
        LeagueConnectionError: no whole scene in time (junk, or not a monitor port).
        KeyboardInterrupt: Ctrl-C.
    """
    deadline = time.monotonic() + timeout_s
    while not monitor.state.valid:
        if sigint is not None and sigint.raised:
            raise KeyboardInterrupt
        left = deadline - time.monotonic()
        if left <= 0:
            skipped = monitor.state.skipped
            bad = f" ({skipped} malformed frames)" if skipped else ""
            raise LeagueConnectionError(
                f"no scene from {monitor.where} within {timeout_s:g} s{bad}: is it the "
                "server's monitor port (rcssservermj --mport)?"
            )
        monitor.read(timeout_s=min(_POLL_S, left))
    return monitor.state


def list_players(monitor_address: str, timeout_s: float = 10.0) -> tuple[PlayerNode, ...]:
    """The robots on the field of the server whose monitor port is ``monitor_address``.

    Raises:
        LeagueConnectionError: nothing listens, or no whole scene within ``timeout_s`` [s].
        KeyboardInterrupt: Ctrl-C (answered within a second).
    """
    with (
        SigintFlag() as sigint,
        MonitorClient(*parse_address(monitor_address, "--server")) as monitor,
    ):
        return _first_scene(monitor, timeout_s, sigint).players


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

    Ctrl-C (or SIGTERM, which raises ``mimic.sigint.Terminated`` under the CLI) ends the
    recording with its file finished (marked interrupted) and the connection left cleanly;
    before the first sample it raises ``KeyboardInterrupt``.

    Raises:
        LeagueConnectionError: nothing listens at the address, or no whole scene came.
        PlayerNotFoundError: the player did not appear within ``wait_s`` (the message names
            the players that are on the field). No file is written then.
        KeyboardInterrupt: Ctrl-C before anything was recorded.
    """
    if seconds is not None and not seconds > 0:
        raise LeagueError(f"--seconds must be > 0, got {seconds}")
    if not wait_s >= 0 or wait_s == float("inf"):
        raise LeagueError(f"--wait must be a finite number of seconds >= 0, got {wait_s}")
    name = who(team, player)
    with (
        SigintFlag() as sigint,
        MonitorClient(*parse_address(monitor_address, "--server")) as monitor,
    ):
        state = _first_scene(monitor, max(wait_s, 10.0), sigint)
        node = _await_player(monitor, team, player, wait_s, on_wait, sigint)
        decoder = PlayerDecoder(robot_of(node, robot, name))
        skipped_before = state.skipped
        out: PlayerWriter | None = None
        reason, t_seen = "done", state.time_s
        last_frame = time.monotonic()
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
                    reason = f"{name} left the field"
                    break
                frames = state.frames
                try:
                    monitor.read(timeout_s=_POLL_S)  # None in time: look at Ctrl-C again
                except LeagueProtocolError as err:
                    reason = str(err)
                    break
                except LeagueConnectionError:
                    reason = "the server stopped"
                    break
                if state.frames != frames:
                    last_frame = time.monotonic()
                elif time.monotonic() - last_frame > STALL_S:
                    reason = f"no valid frame from {monitor.where} for {STALL_S:g} s"
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
                f"{reason} before {name} showed a whole "
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
    name = who(team, player)
    deadline = time.monotonic() + wait_s
    next_message = time.monotonic() + _FIRST_WAIT_MESSAGE_S  # a quick look says nothing
    while True:
        found = monitor.state.player(team, player)
        if found is not None:
            return found
        if sigint.raised:
            raise KeyboardInterrupt
        now = time.monotonic()
        if now >= deadline:
            raise PlayerNotFoundError(
                f"{name} is not on the field of {monitor.where}; on the "
                f"field: {describe_players(monitor.state.players)}"
            )
        if on_wait is not None and now >= next_message:
            on_wait(
                f"waiting for {name} to join (on the field: "
                f"{describe_players(monitor.state.players)})"
            )
            next_message = now + _WAIT_MESSAGE_EVERY_S
        monitor.read(timeout_s=min(_POLL_S, max(0.01, deadline - now)))
