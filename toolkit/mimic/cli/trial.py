"""`mimic trial kick|walk`: the study's statistical trials, variants side by side."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated

import typer
from rich import box
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from mimic.cli.common import console, reports_errors
from mimic.cli.executor_options import RAY, RAY_ADDRESS, WORKERS, open_executor
from mimic.errors import MimicError

trial_app = typer.Typer(help="Run the kick and walk trials (original and learned side by side).",
                        no_args_is_help=True)

_VARIANTS = typer.Argument(help="Variants to try side by side (motion names, .mimic models, "
                           "agent names; M.mimic+balance: that model inside the balance layer); "
                           "the first is the baseline for ratios.", show_default=False)
_COMPARE = typer.Option("--compare", "-c", help="Compare the variants given (the study's table "
                        "with ratios); reads as: --compare kick_right models/kick_right.mimic.")
_MOTION = typer.Option("--motion", help="One keyframe motion or agent name to try.")
_MODEL = typer.Option("--model", help="One learned model (.mimic) to try.")
_SAVE_RRD = typer.Option(help="Save a Rerun dashboard (.rrd): curves, histogram, episode "
                         "markers, the first episode of each variant in 3D.")
_RERUN = typer.Option("--rerun", help="Open the same dashboard in a Rerun viewer.")


def _specs(variants, compare, motion, model, balance, speed_rate, default):
    from mimic.agents.registry import agent_spec
    names = list(variants or []) + [n for n in (motion, model) if n]
    if compare and len(names) < 2:
        raise MimicError("--compare needs at least two variants, e.g. "
                         "--compare kick_right models/kick_right.mimic")
    if not names:
        names = [default]
    specs = [agent_spec(n, speed_rate=speed_rate) for n in names]
    # --balance wraps every learned motion; keyframe motions and agents stay as they are.
    specs = [replace(s, balance=True) if balance and s.kind == "model" else s for s in specs]
    for spec in specs:  # every variant can run, before the first one does
        spec.check()
    return specs


def _progress_bar(total_min: float | None, total_runs: int | None):
    progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                        TextColumn("{task.fields[status]}"), TimeElapsedColumn(), console=console)
    tasks: dict[str, int] = {}

    def update(label: str, batch) -> None:
        if label not in tasks:
            tasks[label] = progress.add_task(label, total=total_min or total_runs, status="")
        eps = batch.episodes
        if total_min:
            done = batch.simulated_s / 60
            status = (f"{done:.1f}/{total_min:g} sim min, kicks {len(batch.rows)}, "
                      f"goals {sum(e.get('goals', 0) for e in eps)}, "
                      f"falls {sum(e.get('falls', 0) for e in eps)}")
        else:
            done = len(eps)
            status = f"{done}/{total_runs} runs, falls {sum(e.get('falls', 0) for e in eps)}"
        progress.update(tasks[label], completed=min(done, total_min or total_runs), status=status)

    return progress, update


#: Columns of the printed table (all columns go to the files), with short headers.
_SHOWN = {
    "kick": {"variant": "variant", "attempts": "kicks", "successful": "ok", "accuracy_pct": "acc %",
             "mean_distance_m": "dist m", "std_distance_m": "std m", "goals": "goals",
             "falls": "falls", "stuck": "stuck", "accuracy_pct_ratio": "acc ratio",
             "mean_distance_m_ratio": "dist ratio"},
    "walk": {"variant": "variant", "runs": "runs", "mean_speed_m_s": "speed m/s",
             "std_speed_m_s": "std", "mean_y_error_m": "Y err m", "std_y_error_m": "std",
             "falls": "falls", "mean_speed_m_s_ratio": "speed ratio"},
}


def _print(result, title: str) -> None:
    shown = {c: h for c, h in _SHOWN[result.kind].items() if c in result.summary.columns}
    rows = [[f"{row[c]:.3g}" if isinstance(row[c], float) else str(row[c]) for c in shown]
            for row in result.summary.iter_rows(named=True)]
    # Headers on two lines and no vertical rules: a whole kick table fits in 80 columns.
    table = Table(title=title, box=box.SIMPLE_HEAD, pad_edge=False, padding=(0, 1, 0, 0))
    for c, header in shown.items():
        table.add_column(header.replace(" ", "\n"), justify="left" if c == "variant" else "right")
    for r in rows:
        table.add_row(*r)
    console.print(table)
    for f in result.files:
        console.print(f"wrote {f}")


def _dashboard(result, save_rrd: Path | None, rerun: bool) -> None:
    from mimic.viz.trials import save_trial_dashboard, show_trial_dashboard
    if save_rrd:
        save_trial_dashboard(result, save_rrd)
        console.print(f"wrote {save_rrd}")
    if rerun:
        try:
            show_trial_dashboard(result)
        except Exception as exc:  # no viewer binary or no display: the tables stand anyway
            reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            raise MimicError(f"could not open a Rerun viewer ({reason}); use --save-rrd FILE and "
                             "open it with `rerun FILE` where a display is available") from exc


@trial_app.command("kick")
@reports_errors
def kick(
    variants: Annotated[list[str] | None, _VARIANTS] = None,
    compare: Annotated[bool, _COMPARE] = False,
    motion: Annotated[str | None, _MOTION] = None,
    model: Annotated[str | None, _MODEL] = None,
    minutes: Annotated[float, typer.Option(help="Simulated minutes per variant.")] = 30.0,
    seed: Annotated[int, typer.Option(help="Seed; the same seed gives the same table.")] = 0,
    workers: Annotated[int | None, WORKERS] = None,
    balance: Annotated[bool, typer.Option(help="Wrap learned motions in balance feedback.")] = False,
    out: Annotated[Path | None, typer.Option("--out", "-o", help="Parquet file of every kick.")] = None,
    save_rrd: Annotated[Path | None, _SAVE_RRD] = None,
    rerun: Annotated[bool, _RERUN] = False,
    ray: Annotated[bool, RAY] = False,
    ray_address: Annotated[str | None, RAY_ADDRESS] = None,
) -> None:
    """Kick trial: kick toward the goal, walk to the ball, kick again until a goal; repeat."""
    from mimic.trials.api import kick_trial
    if minutes <= 0:
        raise MimicError(f"--minutes must be > 0, got {minutes}")
    specs = _specs(variants, compare, motion, model, balance, 1.0, "kick_right")
    progress, update = _progress_bar(minutes, None)
    with open_executor(workers, ray, ray_address) as executor, progress:
        result = kick_trial(specs, minutes=minutes, seed=seed, executor=executor, out=out,
                            progress=update, trace=bool(save_rrd or rerun))
    _print(result, f"kick trial, {minutes:g} simulated min per variant, seed {seed}")
    _dashboard(result, save_rrd, rerun)


@trial_app.command("walk")
@reports_errors
def walk(
    variants: Annotated[list[str] | None, _VARIANTS] = None,
    compare: Annotated[bool, _COMPARE] = False,
    motion: Annotated[str | None, _MOTION] = None,
    model: Annotated[str | None, _MODEL] = None,
    minutes: Annotated[float | None, typer.Option(help="Simulated minutes per variant.")] = None,
    runs: Annotated[int | None, typer.Option(help="Runs per variant (instead of minutes).")] = None,
    seed: Annotated[int, typer.Option(help="Seed; the same seed gives the same table.")] = 0,
    workers: Annotated[int | None, WORKERS] = None,
    balance: Annotated[bool, typer.Option(help="Wrap learned motions in balance feedback.")] = False,
    speed_rate: Annotated[float, typer.Option(help="Phase-rate multiplier for learned cyclic motions.")] = 1.0,
    out: Annotated[Path | None, typer.Option("--out", "-o", help="Parquet file of every run.")] = None,
    save_rrd: Annotated[Path | None, _SAVE_RRD] = None,
    rerun: Annotated[bool, _RERUN] = False,
    ray: Annotated[bool, RAY] = False,
    ray_address: Annotated[str | None, RAY_ADDRESS] = None,
) -> None:
    """Walk trial: from the own goal line to the centre line (15 m), repeated."""
    from mimic.trials.api import walk_trial
    if minutes is not None and runs is not None:
        raise MimicError("give --minutes or --runs, not both")
    if (minutes is not None and minutes <= 0) or (runs is not None and runs <= 0):
        raise MimicError("--minutes and --runs must be > 0")
    specs = _specs(variants, compare, motion, model, balance, speed_rate, "walk")
    if minutes is None and runs is None:
        runs = 10
    progress, update = _progress_bar(minutes, runs)
    with open_executor(workers, ray, ray_address) as executor, progress:
        result = walk_trial(specs, minutes=minutes, runs=runs, seed=seed, executor=executor,
                            out=out, progress=update, trace=bool(save_rrd or rerun))
    _print(result, f"walk trial (15 m), seed {seed}")
    _dashboard(result, save_rrd, rerun)


def register(app: typer.Typer) -> None:
    app.add_typer(trial_app, name="trial")
