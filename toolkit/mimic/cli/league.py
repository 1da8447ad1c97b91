"""The league parts of `mimic record` and `mimic import`: a player from a server's monitor
stream (``--server``) and players from game logs. Called by ``cli/record.py``."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.progress import Progress, TextColumn

from mimic.cli.common import console, err_console, fail
from mimic.errors import MimicError

__all__ = ["record_server", "import_log"]


def _plain(console_, text: str) -> None:
    """Print a line that holds names from outside as plain text (never as Rich markup; the
    names already went through ``printable``)."""
    console_.print(text, markup=False, highlight=False, soft_wrap=True)


def _report(result) -> None:
    """One line per recording; a recording that ended early exits non-zero."""
    from mimic.recording.blackbox import who

    what = (
        f"{who(result.team, result.player)} ({result.robot.upper()}): {result.samples} "
        f"samples, {result.duration_s:.2f} s -> {result.path}"
    )
    if result.frames_skipped:
        what += f" ({result.frames_skipped} frames skipped: malformed or not decodable)"
    if not result.interrupted:
        ended = "" if result.reason in ("done", "end of log") else f" ({result.reason})"
        _plain(console, what + ended)
        return
    if result.reason.startswith("interrupted"):
        _plain(err_console, f"interrupted: saved {what}")
        raise typer.Exit(130)
    fail(f"{result.reason}: saved {what} (the file is complete up to there)", 1)


def record_server(
    server: str | None,
    out: Path | None,
    team: str | None,
    player: int | None,
    seconds: float | None,
    robot: str | None,
    list_only: bool,
    wait_s: float,
    agent: str | None,
) -> None:
    """``mimic record --server HOST:MONITOR_PORT ...``."""
    from mimic.recording.blackbox import describe_players, list_players, record_player, who

    if server is None:
        raise MimicError("--list needs --server HOST:MONITOR_PORT")
    if list_only:
        players = list_players(server)
        _plain(console, f"on the field of {server}: {describe_players(players)}")
        return
    if agent is not None:
        raise MimicError(
            f"--server records a player seen on a league server; leave out the "
            f"agent {agent!r} (play one with 'mimic play {agent}')"
        )
    if team is None or player is None:
        raise MimicError("--server needs --team NAME and --player N (see them with --list)")
    if out is None:
        raise MimicError("give the output file with -o FILE.mcap")
    with Progress(
        TextColumn("recording {task.fields[who]}", markup=False),
        TextColumn("{task.completed:.2f} s"),
        console=err_console,
        transient=True,
        disable=not err_console.is_terminal,  # no bar, and no blank line, in a pipe
    ) as bar:
        task = bar.add_task("record", total=None, who=who(team, player))

        def progress(t_s: float, total_s: float | None) -> None:
            bar.update(task, completed=t_s, total=total_s)

        def on_wait(message: str) -> None:
            _plain(bar.console, message)

        result = record_player(
            server,
            out,
            team,
            player,
            seconds=seconds,
            robot=robot,
            wait_s=wait_s,
            on_wait=on_wait,
            progress=progress,
        )
    _report(result)


def import_log(
    log: Path,
    out: Path,
    team: str | None,
    player: int | None,
    every: bool,
    robot: str | None,
    force: bool = False,
) -> None:
    """``mimic import GAME.log --team NAME --player N -o out.mcap`` (or ``--all -o DIR``)."""
    from mimic.recording.game_log import import_game_log, import_game_log_all

    if every:
        if team is not None or player is not None:
            raise MimicError("give --all or --team/--player, not both")
        for result in import_game_log_all(log, out, robot=robot, force=force):
            _report(result)
        return
    if team is None or player is None:
        raise MimicError(f"{log} is a game log: give --team NAME --player N (or --all -o DIR)")
    _report(import_game_log(log, out, team, player, robot=robot))
