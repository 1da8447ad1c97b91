"""`mimic demo` and `mimic paper`: the whole flow, record -> train -> trial -> tables."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import polars as pl
import typer
from rich.table import Table

from mimic.cli.common import console, reports_errors
from mimic.cli.trial import _print, _progress_bar
from mimic.errors import MimicError


def _table(frame: pl.DataFrame, title: str) -> None:
    table = Table(title=title)
    for c in frame.columns:
        table.add_column(c.replace("_", " "), justify="left" if frame[c].dtype == pl.String
                         else "right")
    for row in frame.iter_rows():
        table.add_row(*["" if v is None else f"{v:.3g}" if isinstance(v, float) else str(v)
                        for v in row])
    console.print(table)


@reports_errors
def demo(
    out: Annotated[Path, typer.Option("--out", "-o", help="Folder for the files it writes.")] = Path("out/demo"),
    minutes: Annotated[float, typer.Option(help="Simulated minutes of kick trial per variant.")] = 2.0,
    seed: Annotated[int, typer.Option(help="Seed of recording, training and trial.")] = 0,
    workers: Annotated[int | None, typer.Option(help="Worker processes (default: all cores).")] = None,
) -> None:
    """Record our kick, learn it, and try the original and the learned kick side by side."""
    from mimic.pipeline import demo as run_demo
    if minutes <= 0:
        raise MimicError(f"--minutes must be > 0, got {minutes}")
    progress, update = _progress_bar(minutes, None)
    result = run_demo(out, minutes=minutes, seed=seed, workers=workers,
                      say=lambda s: console.print(f"[bold]>[/] {s}", highlight=False),
                      progress=_started(progress, update))
    progress.stop()
    _print(result, f"demo: kick trial, {minutes:g} simulated min per variant")


def _started(progress, update):
    def call(label, batch):
        if not progress.live.is_started:
            progress.start()
        update(label, batch)
    return call


@reports_errors
def paper(
    out: Annotated[Path, typer.Option("--out", "-o", help="Folder for the files it writes.")] = Path("out/paper"),
    minutes: Annotated[float, typer.Option(help="Simulated minutes per trial and variant.")] = 30.0,
    seed: Annotated[int, typer.Option(help="Seed of recording, training and trials.")] = 0,
    workers: Annotated[int | None, typer.Option(help="Worker processes (default: all cores).")] = None,
) -> None:
    """Reproduce the study: record, learn and try our kick and the other team's walk."""
    from mimic.pipeline import reproduce_paper
    if minutes <= 0:
        raise MimicError(f"--minutes must be > 0, got {minutes}")
    progress, update = _progress_bar(minutes, None)
    result = reproduce_paper(out, minutes=minutes, seed=seed, workers=workers,
                             say=lambda s: console.print(f"[bold]>[/] {s}", highlight=False),
                             progress=_started(progress, update))
    progress.stop()
    _table(result.network, "Table 1: network fit")
    _table(result.kick, "Table 2: kick trial (study vs ours)")
    _table(result.walk, "Table 3: walk trial (study vs ours)")
    for f in result.files:
        console.print(f"wrote {f}")


def register(app: typer.Typer) -> None:
    app.command("demo")(demo)
    app.command("paper")(paper)
