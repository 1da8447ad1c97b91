"""`mimic train`, `mimic export` and `mimic bench train`: learn motions, export them, time it."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from mimic.cli.common import (
    FORCE,
    SAVE,
    SAVE_OLD,
    OneLineUsageErrors,
    console,
    err_console,
    reports_errors,
    save_path,
    warn,
)

__all__ = ["register", "bench_app"]

bench_app = typer.Typer(
    cls=OneLineUsageErrors,
    help="Speed benchmarks (printed ratios vs a baseline run in-process).",
    no_args_is_help=True,
)


def _metrics_table(models) -> Table:
    table = Table(title="fit (absolute error, rad)", title_justify="left")
    table.add_column("joint")
    for m in models:
        table.add_column(m.name, justify="right")
    table.add_row("[bold]robot", *(m.robot for m in models))
    # Each model's own joints (models of different robots share the table; "-": not its joint).
    joints = list(dict.fromkeys(j for m in models for j in m.joint_names))
    for j in joints:
        errors = (m.metrics["mae_rad_per_joint"].get(j) for m in models)
        table.add_row(j, *("-" if e is None else f"{e:.4f}" for e in errors))
    rows = [
        ("mean abs error", "mae_rad", "{:.4f}"),
        ("max error", "max_error_rad", "{:.3f}"),
        ("ended-flag accuracy", "ended_accuracy", "{:.1%}"),
        ("epochs", "epochs", "{}"),
        ("wall time (s)", "wall_s", "{:.2f}"),
    ]
    for label, key, fmt in rows:
        table.add_row(f"[bold]{label}", *(fmt.format(m.metrics[key]) for m in models))
    return table


def _named(dataset, path: Path):
    """A league player's recording knows who moved, not what the motion was (its motion is
    ``TEAM_N``): its model is named after the model file instead (``seen_walk.mimic``:
    ``seen_walk``); the player stays in the metadata (``team``, ``recorded_as``)."""
    from dataclasses import replace

    if dataset.metadata.get("agent") != "league player":
        return dataset
    return replace(
        dataset,
        metadata={**dataset.metadata, "motion": path.stem, "recorded_as": dataset.name},
    )


def register(app: typer.Typer) -> None:
    app.add_typer(bench_app, name="bench")

    @app.command()
    @reports_errors
    def train(
        inputs: Annotated[
            list[Path],
            typer.Argument(
                help="Recordings (.mcap) or study tables (.txt); several train batched."
            ),
        ],
        out: Annotated[
            Path,
            typer.Option(
                "-o",
                "--out",
                help="Model file (.mimic), or a folder when several inputs are given.",
            ),
        ],
        preset: Annotated[str, typer.Option(help="paper (the study's setup) or fast.")] = "fast",
        epochs: Annotated[int | None, typer.Option(help="Total epochs (schedule scaled).")] = None,
        seed: Annotated[int, typer.Option(help="Seed of the initial weights (0 .. 2**32-1).")] = 0,
        topic: Annotated[
            str | None,
            typer.Option(
                help="/joint_references or /joint_states (default: references when present)."
            ),
        ] = None,
        target: Annotated[
            str | None,
            typer.Option(
                help="reached or compensated (default: compensated for /joint_states; PD "
                "robots need the torso pose on /tf)."
            ),
        ] = None,
        start: Annotated[
            float | None,
            typer.Option(help="Learn from this time on \\[s from the recording's first sample]."),
        ] = None,
        end: Annotated[
            float | None, typer.Option(help="Learn up to this time \\[s, as --start].")
        ] = None,
        period: Annotated[
            str | None,
            typer.Option(
                help="Learn one cyclic motion of this period \\[s], 'auto' to find it in the "
                "angles, or 'steps' to time each step on its own from the feet's touchdowns "
                "(a walk that never repeats exactly; default: as the recording says)."
            ),
        ] = None,
        symmetric: Annotated[
            bool,
            typer.Option(
                "--symmetric",
                help="Learn a cyclic motion left-right symmetric: each sample joined by its "
                "mirror image half a cycle later (a straight walk: cancels the recording's own "
                "turns and leans).",
            ),
        ] = False,
        merge: Annotated[
            bool,
            typer.Option(
                "--merge",
                help="Learn one motion from all inputs: recordings of it started on other "
                "cycles, aligned to the first and pooled (two 25 Hz monitor recordings give "
                "50 Hz); --start/--end are on the first one's clock.",
            ),
        ] = False,
        strict: Annotated[
            bool,
            typer.Option(
                "--strict",
                help="Refuse input that may hold only part of a motion (an interrupted "
                "or truncated recording, a motion that never ends).",
            ),
        ] = False,
        fit_in_sim: Annotated[
            int,
            typer.Option(
                "--fit-in-sim",
                metavar="ROUNDS",
                help="A walk: fit its references in a simulation of the copy (league robots: "
                "the league-like world) over this many rounds, until its joints follow the "
                "recording's, and train again on them (0: off; 6 is typical).",
            ),
        ] = 0,
        rerun: Annotated[
            bool, typer.Option("--rerun", help="Stream loss curves to Rerun.")
        ] = False,
        save: Annotated[Path | None, SAVE] = None,
        save_old: Annotated[Path | None, SAVE_OLD] = None,
        force: Annotated[bool, FORCE] = False,
    ) -> None:
        """Learn motions as neural networks (one model per input, or one from all with --merge)."""
        from mimic import options
        from mimic.errors import DatasetError, MimicError
        from mimic.files import check_outputs
        from mimic.learn.checks import fit_warnings, input_warnings
        from mimic.learn.dataset import NON_REPEATING_RAD
        from mimic.learn.presets import get_preset
        from mimic.learn.train import TrainConfig, training_dataset
        from mimic.model.model_file import SUFFIX, save_model

        save = save_path(save, save_old)
        options.count(fit_in_sim, "--fit-in-sim", at_least=0)
        if fit_in_sim and merge:
            raise MimicError("--fit-in-sim fits a walk; --merge pools one-shot motions")
        if rerun:
            from mimic.viz.display import require_viewer

            require_viewer("--save FILE.rrd")
        try:
            config = TrainConfig(get_preset(preset), seed=seed, epochs=epochs)
        except ValueError as err:
            raise MimicError(str(err)) from None
        several = len(inputs) > 1 and not merge
        if several and out.suffix == SUFFIX:
            raise MimicError(
                f"{len(inputs)} inputs: -o must be a folder (one model each), not {out}; "
                "or pass --merge to learn one motion from them all"
            )
        if merge:
            from mimic.learn.merge import merged_training_dataset

            if period is not None or symmetric:
                raise MimicError(
                    "--merge pools one-shot motions; train a cyclic one from one recording "
                    "with --period (and --symmetric)"
                )
            if out.suffix != SUFFIX:
                raise MimicError(f"--merge writes one model: -o must end in {SUFFIX}, not {out}")
            merged, alignments = merged_training_dataset(
                inputs, topic, target, start_s=start, end_s=end
            )
            datasets = [merged]
            for p, a in zip(inputs[1:], alignments[1:]):
                console.print(
                    f"aligned {p.name}: {a.shift_s:+.2f} s on {inputs[0].name}'s clock "
                    f"(angles {a.rms_rad:.4f} rad rms apart)",
                    highlight=False,
                )
            typical = [a.spread_rad for a in alignments if a.kept]
            for p, a in zip(inputs, alignments):
                if not a.kept:
                    warn(
                        f"left out {p}: its angles differ from the closest other "
                        f"recording's by {a.spread_rad:.3f} rad rms, the others' by "
                        f"{min(typical):.3f}-{max(typical):.3f} (a fall, or another motion?)"
                    )
        else:
            datasets = [
                training_dataset(
                    p, topic, target, start_s=start, end_s=end, period=period, symmetric=symmetric
                )
                for p in inputs
            ]
        for d in datasets:
            steps = d.metadata.get("steps")
            if steps:
                speed = d.metadata.get("walk_speed_m_s")
                console.print(
                    f"{d.name}: {steps['count']} steps from the feet, {steps['mean_s']:.3f} s "
                    f"mean, sd {steps['std_s']:.3f} s ({steps['min_s']:.2f}-"
                    f"{steps['max_s']:.2f} s, {_spread(steps)}); period {d.period_s:.3f} s"
                    + ("" if speed is None else f"; walked {speed:.3f} m/s"),
                    highlight=False,
                )
            elif d.period_s is not None and d.metadata.get("period_detected"):
                console.print(f"{d.name}: period {d.period_s:.3f} s", highlight=False)
            if d.metadata.get("non_repeating"):
                # A symmetric cycle holds every kept sample twice (itself and its mirror).
                kept = d.n_samples // (2 if d.metadata.get("symmetric") else 1)
                console.print(
                    f"{d.name}: left out {d.metadata['non_repeating']} of "
                    f"{kept + d.metadata['non_repeating']} samples that do not repeat the "
                    f"cycle (more than {NON_REPEATING_RAD} rad from its median at their phase)",
                    highlight=False,
                )
        if fit_in_sim:
            for p, d in zip(inputs, datasets):
                if d.period_s is None:
                    raise MimicError(
                        f"{p}: --fit-in-sim fits a walk, a cyclic motion: give --period "
                        "(steps, auto or seconds)"
                    )
        for warning in (w for d in datasets for w in input_warnings(d)):
            if strict:
                raise DatasetError(f"{warning} (--strict refuses such input)")
            warn(f"{warning}, or pass --strict to refuse such input")
        paths = [out / f"{p.stem}{SUFFIX}" for p in inputs] if several else [out]
        check_outputs([*paths, save], force=force, inputs=inputs)
        datasets = [_named(d, path) for d, path in zip(datasets, paths)]
        curves = None
        if rerun or save is not None:
            from mimic.viz.training import TrainingCurves

            curves = TrainingCurves(spawn=rerun, save_rrd=save, overwrite=force)
        try:
            models = _train_with_bar(datasets, config, curves)
            if fit_in_sim:
                from mimic.improve.sim_fit import SimFitConfig

                cut = dict(start_s=start, end_s=end, period=period, symmetric=symmetric)
                fit_config = SimFitConfig(rounds=fit_in_sim, seed=seed)
                fitted = [
                    _fitted(m, d, p, fit_config, cut) for m, d, p in zip(models, datasets, inputs)
                ]
                for d, fit in fitted:
                    console.print(f"{d.name}: {fit.describe()}", highlight=False)
                retrained = _train_with_bar([d for d, _ in fitted], config, curves)
                models = [
                    _checked(m, f, fit, fit_config)
                    for m, f, (_, fit) in zip(models, retrained, fitted)
                ]
        except BaseException:
            if curves is not None:
                curves.discard()
            raise
        if curves is not None:
            curves.close()
        for model, path in zip(models, paths):
            save_model(model, path, overwrite=force)
        console.print(_metrics_table(models))
        for path in paths:
            console.print(f"wrote {path}", highlight=False)
        if save is not None:
            console.print(f"wrote {save}", highlight=False)
        for model, dataset in zip(models, datasets):
            for warning in fit_warnings(model, dataset):
                warn(warning)

    @app.command()
    @reports_errors
    def export(
        model: Annotated[Path, typer.Argument(help="Model file (.mimic).")],
        onnx: Annotated[Path, typer.Option("--onnx", "-o", "--out", help="Output ONNX file.")],
        force: Annotated[bool, FORCE] = False,
    ) -> None:
        """Export a model as ONNX (input: time in seconds; output: the robot's joint angles +
        the ended flag)."""
        from mimic.files import check_output
        from mimic.learn.export import export_onnx
        from mimic.model.model_file import load_model

        loaded = load_model(model)
        check_output(onnx, force=force, inputs=[model])
        path = export_onnx(loaded, onnx, overwrite=force)
        console.print(f"wrote {path} ({path.stat().st_size} bytes)", highlight=False)

    @bench_app.command("train")
    @reports_errors
    def bench_train(
        baseline_epochs: Annotated[
            int, typer.Option(help="Epochs of the torch baseline (extrapolated to 50000).")
        ] = 2000,
        batch: Annotated[int, typer.Option(help="Motions trained batched vs in sequence.")] = 8,
    ) -> None:
        """Training speed: numpy trainer vs the straightforward torch loop; batched vs sequential."""
        from mimic import options
        from mimic.learn.bench import bench_train as run

        options.count(baseline_epochs, "--baseline-epochs")
        options.count(batch, "--batch")

        for line in run(baseline_epochs=baseline_epochs, batch_k=batch).lines():
            console.print(line, highlight=False)


def _train_with_bar(datasets, config, curves):
    """``train_models`` under a progress bar (and the loss curves, if any)."""
    from mimic.learn.train import train_models

    with Progress(
        TextColumn("training {task.description}"),
        BarColumn(),
        TextColumn("{task.completed}/{task.total} epochs"),
        TextColumn("loss {task.fields[loss]:.2e}  MAE {task.fields[mae]:.4f} rad"),
        TimeElapsedColumn(),
        console=err_console,
        transient=True,
        disable=not err_console.is_terminal,  # no bar, no blank line in a pipe
    ) as bar:
        task = bar.add_task(
            ", ".join(d.name for d in datasets),
            total=config.schedule().epochs,
            loss=float("nan"),
            mae=float("nan"),
        )

        def progress(p) -> None:
            bar.update(
                task,
                completed=p.epoch,
                description=", ".join(p.names),
                loss=float(p.loss.max()),
                mae=float(p.mae_rad.max()),
            )
            if curves is not None:
                curves(p)

        return train_models(datasets, config, progress)


@contextmanager
def _walks_bar(label: str, total: int):
    """(a progress bar counting simulated walks, its task); no bar in a pipe."""
    with Progress(
        TextColumn(label),
        BarColumn(),
        TextColumn("{task.completed}/{task.total} walks  {task.fields[said]}"),
        TimeElapsedColumn(),
        console=err_console,
        transient=True,
        disable=not err_console.is_terminal,
    ) as bar:
        yield bar, bar.add_task(label, total=total, said="")


def _checked(learned, fitted, fit, config):
    """The fitted model if its check walks (``improve.sim_fit.check_fit``) went no worse than
    the model's as learned, else that one; either carries the fit and the check in its
    metadata."""
    from dataclasses import replace

    from mimic.improve.sim_fit import check_fit
    from mimic.model.keys import SIM_FIT_KEY

    label = f"checking {fitted.name} against the copy as learned"
    with _walks_bar(label, 2 * config.check_walks) as (bar, task):
        check = check_fit(
            learned, fitted, fit.world, config, progress=lambda: bar.update(task, advance=1)
        )
    console.print(f"{fitted.name}: {check.describe()}", highlight=False)
    model = fitted if check.fitted_better else learned
    facts = {**fit.summary(), "check": check.summary()}
    return replace(model, metadata={**model.metadata, SIM_FIT_KEY: facts})


def _fitted(model, dataset, path: Path, config, cut: dict):
    """(the training dataset with the references fitted in simulation, the fit): the walk
    replayed ``config.rounds`` times (``improve.sim_fit``) against the recording's reached
    angles."""
    from mimic.improve.sim_fit import fit_in_simulation, fitted_dataset
    from mimic.learn.train import TARGET_REACHED, training_dataset
    from mimic.recording.layout import JOINT_STATES

    recorded = training_dataset(path, **{**cut, "topic": JOINT_STATES}, target=TARGET_REACHED)
    with _walks_bar(f"fitting {dataset.name} in simulation", config.rounds + 1) as (bar, task):

        def progress(r) -> None:
            said = f"{r.rms_rad:.3f} rad rms, {r.speed_m_s:.3f} m/s" + (" fell" if r.fell else "")
            bar.update(task, advance=1, said=said)

        fit = fit_in_simulation(model, recorded, config, progress=progress)
    return fitted_dataset(dataset, fit), fit


def _spread(steps: dict) -> str:
    """The shortest and the longest step against the mean: ``-22 %/+25 %``."""
    mean = steps["mean_s"]
    return f"{100 * (steps['min_s'] / mean - 1):+.0f} %/{100 * (steps['max_s'] / mean - 1):+.0f} %"
