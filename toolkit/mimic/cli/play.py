"""`mimic play`: any mimic agent as a team process on a league server."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, Progress, TextColumn

from mimic.cli.common import FORCE, console, err_console, fail, reports_errors, warn

__all__ = ["register"]


def register(app: typer.Typer) -> None:
    @app.command()
    @reports_errors
    def play(
        agent: Annotated[
            str,
            typer.Argument(
                help="A shipped motion of the robot, a behaviour, or a model FILE.mimic "
                "(FILE.mimic+balance: inside the balance layer)."
            ),
        ],
        server: Annotated[
            str | None,
            typer.Option(help="The server's agent port HOST:PORT (default: mimic hosts a server)."),
        ] = None,
        team: Annotated[str, typer.Option(help="Team name.")] = "mimic",
        player: Annotated[int, typer.Option(help="Shirt number (1-99).")] = 1,
        seconds: Annotated[
            float | None,
            typer.Option(
                "--duration",
                "--seconds",
                help="Seconds to play, > 0 (default: until the agent is done, at most 60).",
            ),
        ] = None,
        robot: Annotated[str, typer.Option(help="The player's robot (mimic robots).")] = "t1",
        settle: Annotated[
            float,
            typer.Option(
                help="Seconds the robot holds its stand pose before the agent starts (it "
                "joins with straight joints), >= 0."
            ),
        ] = 1.0,
        out: Annotated[
            Path | None,
            typer.Option(
                "-o",
                "--out",
                help="Record references, perceived angles and the torso and ball (/tf) to "
                "this .mcap.",
            ),
        ] = None,
        vx: Annotated[
            float | None,
            typer.Option(
                "--vx",
                help="Forward speed command \\[m/s] of a walk that takes one (a learned walk, "
                "the other team's walks); default: its own.",
                show_default=False,
            ),
        ] = None,
        force: Annotated[bool, FORCE] = False,
    ) -> None:
        """Play an agent on a league server (RCSSServerMJ) as an ordinary team process."""
        from contextlib import nullcontext

        from mimic import options
        from mimic.files import check_output, claim_output, spec_files
        from mimic.team.play import play as play_agent

        if not (settle >= 0 and settle < float("inf")):
            fail(f"--settle must be a finite number of seconds >= 0, got {settle}")
        options.finite(seconds, "--duration", above=0)
        if out is not None:  # before a server starts; held until the file is written
            check_output(out, force=force, inputs=spec_files(agent))
        if vx is not None or server is not None:
            from mimic.agents.registry import agent_spec
            from mimic.robot.registry import get_robot
            from mimic.team.play import settle_note

            if vx is not None:
                options.finite(vx, "--vx", above=0)
            built = agent_spec(agent, robot=robot, speed_m_s=vx).build()
            built.check_robot(get_robot(robot))
            agent = built
            note = settle_note(built, server is None, settle)
            if note:
                warn(note)

        with (
            claim_output(out) if out is not None else nullcontext(),
            Progress(
                TextColumn(f"{team} #{player} playing"),
                BarColumn(),
                TextColumn("{task.completed:.2f} s"),
                console=err_console,
                transient=True,
                disable=not err_console.is_terminal,
            ) as bar,
        ):
            task = bar.add_task("play", total=None)

            def progress(t_s: float, total_s: float | None) -> None:
                bar.update(task, completed=t_s, total=total_s)

            result = play_agent(
                agent,
                robot=robot,
                agent_address=server,
                team=team,
                player=player,
                seconds=seconds,
                out_path=out,
                progress=progress,
                settle_s=settle,
            )
        saved = f"; saved {result.duration_s:.2f} s to {result.path}" if result.path else ""
        if result.end == "interrupted":
            err_console.print(f"interrupted after {result.cycles} cycles{saved}", highlight=False)
            raise typer.Exit(130)
        if result.interrupted:
            fail(
                f"{result.end} after {result.cycles} cycles{saved} (the file is complete up "
                "to there)"
                if result.path
                else f"{result.end} after {result.cycles} cycles",
                1,
            )
        how = "the agent finished" if result.end == "done" else "time is up"
        ball = "" if result.ball_moved_m is None else f"; the ball went {result.ball_moved_m:.2f} m"
        console.print(
            f"{team} #{player}: {how} after {result.cycles} cycles{_moved(result)}{ball}{saved}",
            highlight=False,
            soft_wrap=True,  # one line, however long the path
        )


def _moved(result) -> str:
    """``; walked 3.21 m at 0.32 m/s, 0 falls`` (what the robot did while the agent played)."""
    if result.distance_m is None:
        return ""
    falls = f"{result.falls} fall" + ("" if result.falls == 1 else "s")
    return f"; walked {result.distance_m:.2f} m at {result.speed_m_s:.2f} m/s, {falls}"
