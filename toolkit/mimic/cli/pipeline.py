"""`mimic demo` and `mimic paper`: the whole flow, record -> train -> trial -> tables."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import polars as pl
import typer
from rich import box
from rich.table import Table

from mimic.cli.common import FORCE, console, reports_errors
from mimic.cli.trial import TrialProgress, _minutes_text, _print

#: Short headers of the paper's tables (two lines each where they have a space), so the three
#: tables fit in 80 columns with every name and number whole.
_HEADERS = {
    "variant": "variant",
    "motion": "motion",
    "parameters": "params",
    "epochs": "epochs",
    "mae_rad": "MAE rad",
    "max_error_rad": "max err rad",
    "attempts": "kicks",
    "successful": "ok",
    "accuracy_pct": "acc %",
    "mean_distance_m": "dist m",
    "std_distance_m": "std m",
    "goals": "goals",
    "falls": "falls",
    "runs": "runs",
    "mean_speed_m_s": "speed m/s",
    "std_speed_m_s": "std",
    "mean_y_error_m": "Y err m",
    "std_y_error_m": "std",
}


def _table(frame: pl.DataFrame, title: str) -> None:
    table = Table(
        title=title, box=box.SIMPLE_HEAD, pad_edge=False, padding=(0, 1, 0, 0), show_edge=False
    )
    for c in frame.columns:
        text = frame[c].dtype == pl.String
        table.add_column(
            _HEADERS.get(c, c.replace("_", " ")).replace(" ", "\n"),
            justify="left" if text else "right",
            overflow="fold" if text else "ellipsis",
            no_wrap=not text,
        )
    for row in frame.iter_rows():
        table.add_row(
            *["" if v is None else f"{v:.3g}" if isinstance(v, float) else str(v) for v in row]
        )
    console.print(table)


def _say(text: str) -> None:
    console.print(f"[bold]>[/] {text}", highlight=False)


def _check(out: Path, outputs, minutes: float, seed: int, workers: int | None, force: bool) -> None:
    from mimic import options
    from mimic.files import check_outputs

    options.finite(minutes, "--minutes", above=0)
    options.seed(seed)
    options.workers(workers)
    check_outputs(outputs(out), force=force)


@reports_errors
def demo(
    out: Annotated[
        Path, typer.Option("--out", "-o", help="Folder for the files it writes.")
    ] = Path("out/demo"),
    minutes: Annotated[
        float, typer.Option(help="Simulated minutes of kick trial per variant, > 0.")
    ] = 2.0,
    seed: Annotated[int, typer.Option(help="Seed of recording, training and trial.")] = 0,
    workers: Annotated[
        int | None,
        typer.Option(help="Worker processes, >= 1 (default: all cores).", show_default=False),
    ] = None,
    force: Annotated[bool, FORCE] = False,
) -> None:
    """Record our kick, learn it, and try the original and the learned kick side by side."""
    from mimic.pipeline import demo as run_demo
    from mimic.pipeline import demo_outputs

    _check(out, demo_outputs, minutes, seed, workers, force)
    with TrialProgress(minutes, None) as progress:
        result = run_demo(
            out, minutes=minutes, seed=seed, workers=workers, say=_say, progress=progress
        )
    _print(result, f"demo: kick trial, {_minutes_text(result, minutes)}")


@reports_errors
def paper(
    out: Annotated[
        Path, typer.Option("--out", "-o", help="Folder for the files it writes.")
    ] = Path("out/paper"),
    minutes: Annotated[
        float, typer.Option(help="Simulated minutes per trial and variant, > 0.")
    ] = 30.0,
    seed: Annotated[int, typer.Option(help="Seed of recording, training and trials.")] = 0,
    workers: Annotated[
        int | None,
        typer.Option(help="Worker processes, >= 1 (default: all cores).", show_default=False),
    ] = None,
    force: Annotated[bool, FORCE] = False,
) -> None:
    """Reproduce the study: record, learn and try our kick and the other team's walk."""
    from mimic.pipeline import paper_outputs, reproduce_paper

    _check(out, paper_outputs, minutes, seed, workers, force)
    with TrialProgress(minutes, None) as progress:
        result = reproduce_paper(
            out, minutes=minutes, seed=seed, workers=workers, say=_say, progress=progress
        )
    _table(result.network, "Table 1: network fit")
    _table(result.kick, "Table 2: kick trial (study vs ours)")
    _table(result.walk, "Table 3: walk trial (study vs ours)")
    for f in result.files:
        console.print(f"wrote {f}", highlight=False)


def register(app: typer.Typer) -> None:
    app.command("demo")(demo)
    app.command("paper")(paper)
