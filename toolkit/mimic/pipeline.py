"""The whole flow as functions: record -> train -> trial -> tables.

``demo`` is the built-in default job; ``reproduce_paper`` is the study end to end (our kick and
the other team's walk, recorded, learned, and tried side by side with the study's numbers).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import polars as pl

from mimic.agents.registry import AgentSpec
from mimic.learn.train import TARGET_REACHED, TrainConfig, train_model, training_dataset
from mimic.model.model_file import save_model
from mimic.recording.layout import JOINT_STATES
from mimic.recording.recorder import record
from mimic.trials.api import TrialResult, kick_trial, trial_files, walk_trial
from mimic.trials.report import STUDY_KICK, STUDY_WALK

__all__ = [
    "PaperResult",
    "record_and_train",
    "train_and_save",
    "demo",
    "reproduce_paper",
    "network_summary",
    "demo_outputs",
    "paper_outputs",
]

Say = Callable[[str], None]


def _quiet(_: str) -> None:
    pass


def record_and_train(
    agent: str,
    out_dir: Path,
    *,
    observe_only: bool = False,
    target: str | None = None,
    seed: int = 0,
    say: Say = _quiet,
    warmup_s: float | None = None,
) -> tuple[Path, Path, dict]:
    """Record ``agent`` into ``out_dir/<agent>.mcap`` and train a model on it.

    Returns:
        (recording path, model path, the model's training metrics).
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    slug = agent.replace("-", "_")
    mcap = out_dir / f"{slug}.mcap"
    say(f"recording {agent} -> {mcap}")
    record(agent, mcap, seed=seed, observe_only=observe_only, warmup_s=warmup_s)
    path, metrics = train_and_save(
        mcap, out_dir / f"{slug}.mimic", target=target, seed=seed, say=say
    )
    return mcap, path, metrics


def train_and_save(
    mcap: Path,
    model_path: Path,
    *,
    topic: str | None = None,
    target: str | None = None,
    seed: int = 0,
    say: Say = _quiet,
) -> tuple[Path, dict]:
    """Train a model on one topic of a recording and save it.

    Returns:
        (model path, the model's training metrics).
    """
    say(f"training on {mcap}" + (f" {topic} ({target} angles)" if topic else ""))
    model = train_model(training_dataset(mcap, topic, target), TrainConfig(seed=seed))
    return save_model(model, model_path), model.metrics


def demo_outputs(out_dir: Path) -> list[Path]:
    """The files ``demo`` writes into ``out_dir``."""

    return [
        out_dir / "kick_right.mcap",
        out_dir / "kick_right.mimic",
        *trial_files(out_dir / "kick_trial.parquet"),
    ]


def paper_outputs(out_dir: Path) -> list[Path]:
    """The files ``reproduce_paper`` writes into ``out_dir``."""

    return [
        out_dir / "kick_right.mcap",
        out_dir / "kick_right.mimic",
        out_dir / "kick_right_observed.mimic",
        out_dir / "other_team_walk.mcap",
        out_dir / "other_team_walk.mimic",
        *trial_files(out_dir / "kick_trial.parquet"),
        *trial_files(out_dir / "walk_trial.parquet"),
    ]


def demo(
    out_dir: Path = Path("out/demo"),
    *,
    minutes: float = 2.0,
    seed: int = 0,
    workers: int | None = None,
    say: Say = _quiet,
    progress=None,
) -> TrialResult:
    """Record our kick, learn it, and run the kick trial of both side by side."""
    _, model, metrics = record_and_train("kick_right", out_dir, seed=seed, say=say)
    say(f"learned kick: mean absolute error {metrics['mae_rad']:.4f} rad")
    say(f"kick trial, {minutes:g} simulated minutes per variant")
    return kick_trial(
        [AgentSpec("motion", "kick_right"), AgentSpec("model", str(model))],
        minutes=minutes,
        seed=seed,
        workers=workers,
        out=out_dir / "kick_trial.parquet",
        progress=progress,
    )


@dataclass
class PaperResult:
    """The study's three tables, ours beside theirs."""

    network: pl.DataFrame
    kick: pl.DataFrame
    walk: pl.DataFrame
    files: list[Path] = field(default_factory=list)


def network_summary(metrics: dict[str, dict]) -> pl.DataFrame:
    """Table 1: the network and its fit, per learned motion, beside the study's kick fit."""
    rows = [
        dict(
            motion="study: ITAndroids kick",
            parameters=5123,
            epochs=50000,
            mae_rad=0.0178,
            max_error_rad=1.37,
        )
    ]
    for motion, m in metrics.items():
        rows.append(
            dict(
                motion=motion,
                parameters=int(m.get("parameters", 5123)),
                epochs=int(m.get("epochs", 0)),
                mae_rad=float(m["mae_rad"]),
                max_error_rad=float(m.get("max_error_rad", float("nan"))),
            )
        )
    return pl.DataFrame(rows)


def reproduce_paper(
    out_dir: Path = Path("out/paper"),
    *,
    minutes: float = 30.0,
    seed: int = 0,
    workers: int | None = None,
    say: Say = _quiet,
    progress=None,
) -> PaperResult:
    """Record our kick and the other team's walk, learn both, run both trials.

    Beyond the study, the kick is also learned from what an observer sees (``/joint_states``,
    reached angles) and tried inside the balance layer.
    """
    kick_mcap, kick_model, kick_metrics = record_and_train(
        "kick_right", out_dir, seed=seed, say=say
    )
    observed_model, observed_metrics = train_and_save(
        kick_mcap,
        out_dir / "kick_right_observed.mimic",
        topic=JOINT_STATES,
        target=TARGET_REACHED,
        seed=seed,
        say=say,
    )
    _, walk_model, walk_metrics = record_and_train(
        "other-team-walk", out_dir, seed=seed, say=say, observe_only=True
    )
    say(f"kick trial, {minutes:g} simulated minutes per variant")
    kick = kick_trial(
        [
            AgentSpec("motion", "kick_right"),
            AgentSpec("model", str(kick_model)),
            AgentSpec("model", str(observed_model), balance=True),
        ],
        minutes=minutes,
        seed=seed,
        workers=workers,
        out=out_dir / "kick_trial.parquet",
        progress=progress,
    )
    say(f"walk trial, {minutes:g} simulated minutes per variant")
    # The learned walk open-loop (as the study played it) and inside our balance layer.
    walk = walk_trial(
        [
            AgentSpec("behaviour", "other-team-walk"),
            AgentSpec("model", str(walk_model)),
            AgentSpec("model", str(walk_model), balance=True),
        ],
        minutes=minutes,
        seed=seed,
        workers=workers,
        out=out_dir / "walk_trial.parquet",
        progress=progress,
    )
    network = network_summary(
        {
            "kick_right": kick_metrics,
            "kick_right from /joint_states": observed_metrics,
            "other_team_walk": walk_metrics,
        }
    )
    kick_table = pl.concat(
        [STUDY_KICK, kick.summary.select(STUDY_KICK.columns)], how="vertical_relaxed"
    )
    walk_table = pl.concat(
        [STUDY_WALK, walk.summary.select(STUDY_WALK.columns)], how="vertical_relaxed"
    )
    return PaperResult(network, kick_table, walk_table, [*kick.files, *walk.files])
