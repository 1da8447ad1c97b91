"""`mimic record`, `mimic info` and `mimic import`: make, inspect and import recordings."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, Progress, TextColumn
from rich.table import Table
from rich.text import Text

from mimic.cli.common import FORCE, console, err_console, reports_errors, warn
from mimic.league.untrusted import printable

__all__ = ["register", "print_recording_summary"]


def print_recording_summary(summary: dict) -> None:
    """Print ``describe_recording``'s dict as a table (also used by other info commands)."""
    table = Table(title=summary["path"], show_header=False, title_justify="left")
    cyclic = summary.get("cyclic")
    version, rate = summary.get("toolkit_version"), summary.get("rate_hz")
    rows = [
        ("motion", summary.get("motion")),
        ("robot", summary.get("robot")),
        ("world", summary.get("world")),
        ("agent", summary.get("agent")),
        ("team", summary.get("team")),
        ("source", summary.get("source")),
        (
            "cyclic",
            None
            if cyclic is None
            else f"yes, period {summary['period_s']:g} s"
            if cyclic
            else "no",
        ),
        ("duration", f"{summary['duration_s']:.2f} s"),
        ("rate", f"{rate:.1f} Hz" if rate else "- (no joint topic)"),
        ("seed", summary.get("seed")),
        ("written by", f"mimic {version}" if version else "- (no mimic metadata)"),
        ("started", summary.get("started_at")),
        ("state", "interrupted" if summary["interrupted"] else "complete"),
        ("recovery", summary["recovery"]),
    ]
    for key, value in rows:  # values may come from outside (a team name in a game log)
        table.add_row(key, Text("-" if value is None else printable(str(value))))
    for topic, t in summary["topics"].items():
        table.add_row(topic, f"{t['messages']} messages ({t['schema']})")
    console.print(table)
    for warning in summary.get("warnings", []):
        warn(warning)


def print_model_summary(summary: dict) -> None:
    """A model's description as a two-column table, per-joint errors as a second table."""
    table = Table(title=summary.get("path", "model"), show_header=False)
    table.add_column("field", style="bold")
    table.add_column("value")
    per_joint = {}
    for key, value in summary.items():
        if isinstance(value, dict):
            if key == "metrics":
                per_joint = value.get("mae_rad_per_joint", {})
                for k, v in value.items():
                    if not isinstance(v, dict):
                        table.add_row(
                            f"metrics.{k}", f"{v:.4g}" if isinstance(v, float) else str(v)
                        )
            continue
        table.add_row(key, json.dumps(value) if isinstance(value, (list, tuple)) else str(value))
    console.print(table)
    if per_joint:
        errors = Table(title="mean absolute error per joint [rad]")
        errors.add_column("joint")
        errors.add_column("MAE", justify="right")
        for name, v in per_joint.items():
            errors.add_row(name, f"{v:.4f}")
        console.print(errors)


def register(app: typer.Typer) -> None:
    @app.command()
    @reports_errors
    def record(
        name: Annotated[
            str | None,
            typer.Argument(
                help="Agent: a shipped motion (stand, kick_right, ...), walk, other-team-walk, "
                "other-team-kick, or a model FILE.mimic (FILE.mimic+balance: inside the "
                "balance layer)."
            ),
        ] = None,
        out: Annotated[Path, typer.Option("-o", "--out", help="Output .mcap file.")] = None,
        duration: Annotated[
            float | None,
            typer.Option(
                "--duration",
                "--seconds",
                help="Seconds to record, > 0 (default: until the motion ends; "
                "cyclic agents: 10 periods; --server: server time, until Ctrl-C, the player "
                "leaves or the server stops).",
            ),
        ] = None,
        seed: Annotated[int, typer.Option(help="Simulation seed (0 .. 2**32-1).")] = 0,
        observe_only: Annotated[
            bool,
            typer.Option("--observe-only", help="Record only reached joint angles, no references."),
        ] = False,
        warmup: Annotated[
            float | None,
            typer.Option(
                help="Cyclic agents: seconds run before recording, >= 0 (default 4: past the "
                "start-up).",
                show_default=False,
            ),
        ] = None,
        model: Annotated[
            Path | None,
            typer.Option(help="Record a learned motion from a .mimic model file instead of NAME."),
        ] = None,
        robot: Annotated[
            str | None,
            typer.Option(
                help="Robot of shipped motions (mimic robots; default nao). --server: the "
                "player's robot (default: as the server shows it, else t1)."
            ),
        ] = None,
        force: Annotated[bool, FORCE] = False,
        world: Annotated[
            str,
            typer.Option(
                help="Where to record: mujoco (ours; also 'nao'), league (the league server's "
                "own simulation, in this process), league-server (a league server mimic hosts "
                "for the recording) or league-like (ours with the league's solver and command "
                "delay)."
            ),
        ] = "mujoco",
        server: Annotated[
            str | None,
            typer.Option(
                help="Black-box: record a player of a league server (RCSSServerMJ) from its "
                "monitor port HOST:PORT.",
                rich_help_panel="League",
            ),
        ] = None,
        team: Annotated[
            str | None, typer.Option(help="--server: the player's team.", rich_help_panel="League")
        ] = None,
        player: Annotated[
            int | None,
            typer.Option(help="--server: the player's number.", rich_help_panel="League"),
        ] = None,
        list_players: Annotated[
            bool,
            typer.Option(
                "--list",
                help="--server: print the teams and players on the field.",
                rich_help_panel="League",
            ),
        ] = False,
        wait: Annotated[
            float,
            typer.Option(
                help="--server: seconds to wait for the player to join.", rich_help_panel="League"
            ),
        ] = 30.0,
    ) -> None:
        """Run an agent in the simulator and record it as MCAP (Ctrl-C keeps what was made),
        in any world (--world).

        With --server: record a league player from the server's monitor stream instead."""
        from mimic import options
        from mimic.errors import MimicError
        from mimic.files import check_output, spec_files
        from mimic.recording.reader import describe_recording
        from mimic.recording.recorder import record as record_agent

        if server is not None or list_players:
            from contextlib import nullcontext

            from mimic.cli.league import record_server
            from mimic.files import claim_output

            options.finite(duration, "--duration", above=0)
            options.finite(wait, "--wait", at_least=0)
            claim = nullcontext()
            if out is not None and not list_players:
                check_output(out, force=force)
                # Held from now: a second recorder of the same file is refused at once.
                claim = claim_output(out)
            with claim:
                return record_server(
                    server,
                    out,
                    team,
                    player,
                    duration,
                    robot,
                    list_players,
                    wait,
                    name if model is None else str(model),
                )
        if out is None:
            raise MimicError("give the output file with -o FILE.mcap")
        if (name is None) == (model is None):
            raise MimicError("give an agent NAME or --model FILE.mimic (one of them)")
        options.finite(duration, "--duration", above=0)
        options.finite(warmup, "--warmup", at_least=0)
        options.seed(seed)
        from mimic.agents.registry import make_agent
        from mimic.world.registry import get_world

        spec = get_world(world)
        agent = make_agent(
            str(model) if model is not None else name, robot=robot or spec.default_robot
        )
        check_output(out, force=force, inputs=spec_files(model, name))
        with Progress(
            TextColumn("recording"),
            BarColumn(),
            TextColumn("{task.completed:.2f} s sim"),
            console=err_console,
            transient=True,
            disable=not err_console.is_terminal,  # no bar, and no blank line, in a pipe
        ) as bar:
            task = bar.add_task("record", total=None)

            def progress(t_s: float, total_s: float | None) -> None:
                bar.update(task, completed=t_s, total=total_s)

            result = record_agent(
                agent,
                out,
                duration_s=duration,
                seed=seed,
                observe_only=observe_only,
                warmup_s=warmup,
                progress=progress,
                world=spec.name,
            )
        if result.interrupted:
            err_console.print(
                f"interrupted: saved {result.duration_s:.2f} s "
                f"({result.samples} samples) to {result.path}",
                highlight=False,
            )
            raise typer.Exit(130)
        print_recording_summary(describe_recording(result.path))

    @app.command()
    @reports_errors
    def info(
        file: Annotated[Path, typer.Argument(help="A recording (.mcap) or a model (.mimic).")],
        as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    ) -> None:
        """Describe a recording (topics, duration, rate, completeness) or a learned model."""
        from mimic.model.model_file import describe_model, looks_like_model_file
        from mimic.recording.reader import describe_recording

        if looks_like_model_file(file):
            summary = describe_model(file)
            if as_json:
                console.print_json(json.dumps(summary))
            else:
                print_model_summary(summary)
            return
        summary = describe_recording(file)
        if as_json:
            console.print_json(json.dumps(summary))
        else:
            print_recording_summary(summary)

    @app.command("import")
    @reports_errors
    def import_(
        paper_file: Annotated[
            Path,
            typer.Argument(
                help="A study '::' text file, or a league game log (rcssservermj --logfile)."
            ),
        ],
        out: Annotated[
            Path, typer.Option("-o", "--out", help="Output .mcap file (--all: a folder).")
        ],
        topic: Annotated[
            str | None,
            typer.Option(help="/joint_references or /joint_states (default: by file name)."),
        ] = None,
        distance: Annotated[
            float | None, typer.Option(help="Kick family: which distance \\[m] to import.")
        ] = None,
        team: Annotated[
            str | None, typer.Option(help="Game log: the player's team.", rich_help_panel="League")
        ] = None,
        player: Annotated[
            int | None,
            typer.Option(help="Game log: the player's number.", rich_help_panel="League"),
        ] = None,
        all_players: Annotated[
            bool,
            typer.Option(
                "--all",
                help="Game log: one recording per player, TEAM_N.mcap in the -o folder.",
                rich_help_panel="League",
            ),
        ] = False,
        robot: Annotated[
            str | None,
            typer.Option(
                help="Game log: the player's robot (default: as the log shows it).",
                rich_help_panel="League",
            ),
        ] = None,
        force: Annotated[bool, FORCE] = False,
    ) -> None:
        """Convert one of the study's joint tables, or players of a league game log, into
        recordings in our layout."""
        from mimic import options
        from mimic.files import check_output, input_file
        from mimic.recording.game_log import is_game_log
        from mimic.recording.paper_import import import_paper_file
        from mimic.recording.reader import describe_recording

        if is_game_log(paper_file) or team is not None or player is not None or all_players:
            from mimic.cli.league import import_log

            input_file(paper_file, "game log", "write one with 'rcssservermj --logfile FILE'")
            if not all_players:
                check_output(out, force=force, inputs=[paper_file])
            return import_log(paper_file, out, team, player, all_players, robot, force)
        options.finite(distance, "--distance", at_least=0)
        check_output(out, force=force, inputs=[paper_file])
        import_paper_file(paper_file, out, topic=topic, distance_m=distance, overwrite=force)
        print_recording_summary(describe_recording(out))
