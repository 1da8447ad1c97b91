"""Learned copies of the other team's walk beside the original, over 15 m.

    python benchmarks/learned_walk.py [--runs 8] [--seed 0] [--out DIR] [--reuse]

Records the other team's walk as a black box (joint states only, whole gait periods at its
steady speed, after ``--warmup`` s), trains the study's copy (``reached`` angles) and ours
(``compensated`` targets) with the same preset and seed, and walks every variant from the
own goal line to the centre line under the same seeds (``mimic.trials.api.walk_trial``):

    original | reached | reached + balance | compensated | compensated + balance

Learned copies start phase-locked (``NeuralPlayer`` ``stance_s``/``start_ramp_s``); one more
row shows compensated + balance with the old start (straight into the cycle at full rate),
run in this process with the same episode seeds. Ratios are against the original's row.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from pathlib import Path

import polars as pl
from rich.console import Console
from rich.table import Table

from mimic.agents.registry import AgentSpec
from mimic.learn.train import TrainConfig, train_model, training_dataset
from mimic.model.model_file import save_model
from mimic.recording.recorder import record
from mimic.robot.registry import DEFAULT_ROBOT
from mimic.tasks.walk import WalkTask, run_walk_episode
from mimic.trials.api import walk_trial
from mimic.trials.parallel import derive_seed
from mimic.trials.report import with_ratios

# Other team's walk: step length ramps up for ~3.5 s after the start; record after that.
DEFAULT_WARMUP_S = 4.0
DEFAULT_PERIODS = 10


@dataclass(frozen=True)
class _OldStart:
    """A compensated copy + balance that jumps straight into the cycle (no start-up)."""

    ref: str
    label: str = "compensated + balance, old start"
    robot: str = DEFAULT_ROBOT  # the robot the episode builds its world for (as AgentSpec)

    def build(self):
        from mimic.agents.balance import BalancedAgent
        from mimic.agents.neural_player import NeuralPlayer

        return BalancedAgent(NeuralPlayer.from_file(self.ref, stance_s=0.0, start_ramp_s=0.0))


def _finished_y_error(rows: pl.DataFrame) -> pl.DataFrame:
    """Mean Y error [m] of the finished runs of each variant."""
    return (
        rows.filter(pl.col("finished"))
        .group_by("variant")
        .agg(pl.col("y_error_m").mean().alias("finished_y_error_m"))
    )


def _old_start_row(model: Path, runs: int, seed: int) -> tuple[dict, pl.DataFrame]:
    rows = [
        run_walk_episode(_OldStart(str(model)), derive_seed(seed, i))[0][0] for i in range(runs)
    ]
    df = pl.DataFrame(rows).with_columns(pl.lit(_OldStart("").label).alias("variant"))
    return dict(
        variant=_OldStart("").label,
        runs=df.height,
        finished=int(df["finished"].sum()),
        mean_speed_m_s=df["speed_m_s"].mean(),
        std_speed_m_s=df["speed_m_s"].std(),
        mean_y_error_m=df["y_error_m"].mean(),
        std_y_error_m=df["y_error_m"].std(),
        falls=int(df["falls"].sum()),
    ), df


def _record_and_train(args, mcap: Path, models: dict[str, Path], console: Console) -> None:
    rec = record(
        "other-team-walk",
        mcap,
        observe_only=True,
        warmup_s=args.warmup,
        duration_s=args.periods * 0.32,
        seed=args.seed,
    )
    console.print(
        f"recorded {rec.samples} samples ({rec.duration_s:.2f} s, period "
        f"{rec.info.period_s} s) after {args.warmup:g} s of warm-up"
    )
    for target, path in models.items():
        start = time.perf_counter()
        model = train_model(
            training_dataset(mcap, target=target), TrainConfig(seed=args.seed, epochs=args.epochs)
        )
        save_model(model, path)
        console.print(
            f"trained {target}: MAE {model.metrics['mae_rad']:.4f} rad, "
            f"{time.perf_counter() - start:.1f} s"
        )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=8, help="15 m runs per variant (>= 4)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--warmup", type=float, default=DEFAULT_WARMUP_S)
    ap.add_argument("--periods", type=int, default=DEFAULT_PERIODS)
    ap.add_argument("--epochs", type=int, default=None, help="training epochs (default: preset)")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--out", type=Path, default=Path("out/learned_walk"))
    ap.add_argument(
        "--reuse", action="store_true", help="reuse the recording and models already in --out"
    )
    args = ap.parse_args()
    console = Console(width=150)
    args.out.mkdir(parents=True, exist_ok=True)

    mcap = args.out / "other_team_walk.mcap"
    models = {t: args.out / f"{t}.mimic" for t in ("reached", "compensated")}
    if not (args.reuse and mcap.exists() and all(p.exists() for p in models.values())):
        _record_and_train(args, mcap, models, console)

    specs = [
        AgentSpec("behaviour", "other-team-walk"),
        AgentSpec("model", str(models["reached"])),
        AgentSpec("model", str(models["reached"]), balance=True),
        AgentSpec("model", str(models["compensated"])),
        AgentSpec("model", str(models["compensated"]), balance=True),
    ]
    start = time.perf_counter()
    result = walk_trial(
        specs,
        runs=args.runs,
        seed=args.seed,
        workers=args.workers,
        out=args.out / "walk_trial.parquet",
    )
    old, old_rows = _old_start_row(models["compensated"], args.runs, args.seed)
    summary = with_ratios(
        pl.concat(
            [
                result.summary.drop([c for c in result.summary.columns if c.endswith("_ratio")]),
                pl.DataFrame([old]),
            ],
            how="diagonal_relaxed",
        ),
        WalkTask.ratio_columns,
    )
    rows = pl.concat([result.rows, old_rows], how="diagonal_relaxed")
    summary = summary.join(_finished_y_error(rows), on="variant", how="left")
    console.print(f"trials: {time.perf_counter() - start:.1f} s wall")

    table = Table(
        title=f"other team's walk and its learned copies, 15 m, {args.runs} runs "
        f"each, seed {args.seed}"
    )
    for c in (
        "variant",
        "finished",
        "falls",
        "speed m/s",
        "speed ratio",
        "Y err m",
        "std",
        "Y err finished m",
    ):
        table.add_column(c, justify="left" if c == "variant" else "right", no_wrap=True)
    for row in summary.iter_rows(named=True):
        table.add_row(
            row["variant"].replace(str(args.out) + "/", ""),
            f"{row['finished']}/{row['runs']}",
            str(row["falls"]),
            f"{row['mean_speed_m_s']:.3f}",
            f"{row['mean_speed_m_s_ratio']:.2f}",
            f"{row['mean_y_error_m']:.2f}",
            f"{row['std_y_error_m']:.2f}",
            "-" if row["finished_y_error_m"] is None else f"{row['finished_y_error_m']:.2f}",
        )
    console.print(table)
    console.print(
        "Y error: |end y - start y| \\[m] of every run (a fall ends the run early) and "
        "of the finished runs only; speed: x distance / walk time of every run."
    )


if __name__ == "__main__":
    main()
