"""`mimic train`, `mimic export` and `mimic bench train`: learn motions, export them, time it."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from mimic.cli.common import console, err_console, reports_errors

__all__ = ["register", "bench_app"]

bench_app = typer.Typer(help="Speed benchmarks (printed ratios vs a baseline run in-process).",
                        no_args_is_help=True)


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
    rows = [("mean abs error", "mae_rad", "{:.4f}"), ("max error", "max_error_rad", "{:.3f}"),
            ("ended-flag accuracy", "ended_accuracy", "{:.1%}"), ("epochs", "epochs", "{}"),
            ("wall time (s)", "wall_s", "{:.2f}")]
    for label, key, fmt in rows:
        table.add_row(f"[bold]{label}", *(fmt.format(m.metrics[key]) for m in models))
    return table


def register(app: typer.Typer) -> None:
    app.add_typer(bench_app, name="bench")

    @app.command()
    @reports_errors
    def train(
        inputs: Annotated[list[Path], typer.Argument(
            help="Recordings (.mcap) or study tables (.txt); several train batched.")],
        out: Annotated[Path, typer.Option("-o", "--out", help="Model file (.mimic), or a "
                                          "folder when several inputs are given.")],
        preset: Annotated[str, typer.Option(help="paper (the study's setup) or fast.")] = "fast",
        epochs: Annotated[int | None, typer.Option(help="Total epochs (schedule scaled).")] = None,
        seed: Annotated[int, typer.Option(help="Seed of the initial weights.")] = 0,
        topic: Annotated[str | None, typer.Option(
            help="/joint_references or /joint_states (default: references when present).")] = None,
        target: Annotated[str | None, typer.Option(
            help="reached or compensated (default: compensated for /joint_states).")] = None,
        rerun: Annotated[bool, typer.Option("--rerun", help="Stream loss curves to Rerun.")] = False,
        save_rrd: Annotated[Path | None, typer.Option(
            "--save-rrd", help="Write the loss curves to this .rrd file.")] = None,
    ) -> None:
        """Learn motions as neural networks (one model per input)."""
        from mimic.errors import MimicError
        from mimic.learn.model_file import SUFFIX, save_model
        from mimic.learn.presets import get_preset
        from mimic.learn.train import TrainConfig, train_models, training_dataset

        try:
            config = TrainConfig(get_preset(preset), seed=seed, epochs=epochs)
        except ValueError as err:
            raise MimicError(str(err)) from None
        if epochs is not None and epochs < 1:
            raise MimicError(f"--epochs must be at least 1, got {epochs}")
        several = len(inputs) > 1
        if several and out.suffix == SUFFIX:
            raise MimicError(f"{len(inputs)} inputs: -o must be a folder (one model each), "
                             f"not {out}")
        datasets = [training_dataset(p, topic, target) for p in inputs]
        paths = [out / f"{p.stem}{SUFFIX}" for p in inputs] if several else [out]
        curves = None
        if rerun or save_rrd is not None:
            from mimic.viz.training import TrainingCurves

            curves = TrainingCurves(spawn=rerun, save_rrd=save_rrd)
        total = config.schedule().epochs
        with Progress(TextColumn("training {task.description}"), BarColumn(),
                      TextColumn("{task.completed}/{task.total} epochs"),
                      TextColumn("loss {task.fields[loss]:.2e}  MAE {task.fields[mae]:.4f} rad"),
                      TimeElapsedColumn(), console=err_console, transient=True) as bar:
            task = bar.add_task(", ".join(d.name for d in datasets), total=total,
                                loss=float("nan"), mae=float("nan"))

            def progress(p) -> None:
                bar.update(task, completed=p.epoch, description=", ".join(p.names),
                           loss=float(p.loss.max()), mae=float(p.mae_rad.max()))
                if curves is not None:
                    curves(p)

            models = train_models(datasets, config, progress)
        if curves is not None:
            curves.close()
        for model, path in zip(models, paths):
            save_model(model, path)
        console.print(_metrics_table(models))
        for path in paths:
            console.print(f"wrote {path}", highlight=False)

    @app.command()
    @reports_errors
    def export(
        model: Annotated[Path, typer.Argument(help="Model file (.mimic).")],
        onnx: Annotated[Path, typer.Option("--onnx", help="Output ONNX file.")],
    ) -> None:
        """Export a model as ONNX (input: time in seconds; output: the robot's joint angles +
        the ended flag)."""
        from mimic.learn.export import export_onnx
        from mimic.learn.model_file import load_model

        path = export_onnx(load_model(model), onnx)
        console.print(f"wrote {path} ({path.stat().st_size} bytes)", highlight=False)

    @bench_app.command("train")
    def bench_train(
        baseline_epochs: Annotated[int, typer.Option(
            help="Epochs of the torch baseline (extrapolated to 50000).")] = 2000,
        batch: Annotated[int, typer.Option(help="Motions trained batched vs in sequence.")] = 8,
    ) -> None:
        """Training speed: numpy trainer vs the straightforward torch loop; batched vs sequential."""
        from mimic.learn.bench import bench_train as run

        for line in run(baseline_epochs=baseline_epochs, batch_k=batch).lines():
            console.print(line, highlight=False)
