"""`mimic view`: a recording (and optionally a learned model) in the Rerun viewer."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from mimic.cli.common import FORCE, SAVE, console, reports_errors


@reports_errors
def view(
    recording: Annotated[Path, typer.Argument(help="An MCAP recording.")],
    model: Annotated[Path | None, typer.Option(help="A learned model to overlay.")] = None,
    save: Annotated[Path | None, SAVE] = None,
    force: Annotated[bool, FORCE] = False,
) -> None:
    """Show a recording in Rerun: robot in 3D, joint curves, references, the ended flag."""
    from mimic.files import check_output
    from mimic.viz.recording import view_recording

    if save is not None:
        check_output(save, force=force, inputs=[recording, model])
    else:
        from mimic.files import input_file
        from mimic.viz.display import require_viewer

        input_file(recording, "recording")  # a missing file says so first
        require_viewer(f"--save {recording.with_suffix('.rrd').name}")
    logged = view_recording(recording, model=model, save=save, overwrite=force)
    if save:
        console.print(
            f"wrote {save} ({logged['robot']}: {', '.join(logged['series'])})", highlight=False
        )


def register(app: typer.Typer) -> None:
    app.command("view")(view)
