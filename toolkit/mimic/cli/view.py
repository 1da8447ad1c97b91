"""`mimic view`: a recording (and optionally a learned model) in the Rerun viewer."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from mimic.cli.common import console, reports_errors


@reports_errors
def view(
    recording: Annotated[Path, typer.Argument(help="An MCAP recording.")],
    model: Annotated[Path | None, typer.Option(help="A learned model to overlay.")] = None,
    save: Annotated[Path | None, typer.Option(help="Save to this .rrd instead of opening "
                                                     "the viewer.")] = None,
) -> None:
    """Show a recording in Rerun: robot in 3D, joint curves grouped, references overlaid."""
    from mimic.viz.recording import view_recording
    logged = view_recording(recording, model=model, save=save)
    if save:
        console.print(f"wrote {save} ({logged['robot']}: {', '.join(logged['series'])})")


def register(app: typer.Typer) -> None:
    app.command("view")(view)
