"""Trials as functions: run one or more variants under the same seeds and tabulate them."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import polars as pl

from mimic.agents.registry import AgentSpec
from mimic.trials.executors import Executor, make_executor
from mimic.trials.kick import KickTrialConfig, run_kick_episode
from mimic.trials.parallel import EpisodeBatch, run_episodes
from mimic.trials.report import kick_summary, walk_summary, with_ratios, write_rows, write_summary
from mimic.trials.walk import WalkTrialConfig, run_walk_episode

__all__ = ["TrialResult", "kick_trial", "walk_trial"]


@dataclass
class TrialResult:
    """Per-event rows (every kick or walk run, all variants) and the summary table."""

    kind: str
    rows: pl.DataFrame
    summary: pl.DataFrame
    files: list[Path] = field(default_factory=list)
    # The first episode of each variant as a pose trace (``episode.EpisodeTrace``), when
    # the trial ran with ``trace=True``: the robot and ball replayed in the Rerun dashboard.
    traces: dict = field(default_factory=dict)


def _run(kind: str, episode_fn: Callable, summarise: Callable, specs: list[AgentSpec], config,
         *, minutes: float | None, runs: int | None, seed: int, workers: int | None,
         executor: Executor | None, out: Path | None,
         progress: Callable[[str, EpisodeBatch], None] | None, trace: bool) -> TrialResult:
    if executor is None:  # one pool for every variant: workers start once
        with make_executor(workers) as own:
            return _run(kind, episode_fn, summarise, specs, config, minutes=minutes, runs=runs,
                        seed=seed, workers=workers, executor=own, out=out, progress=progress,
                        trace=trace)
    frames, rows, traces = [], [], {}
    expected_s = None  # the previous variant's mean episode: how many to run at once
    for spec in specs:
        batch = run_episodes(episode_fn, spec, config,
                             budget_s=None if minutes is None else minutes * 60,
                             episodes=runs, seed=seed, executor=executor,
                             progress=(lambda b, s=spec: progress(s.label, b)) if progress
                             else None,
                             trace_episodes=1 if trace else 0, expected_episode_s=expected_s)
        expected_s = batch.simulated_s / len(batch.episodes) if batch.episodes else None
        if 0 in batch.traces:
            traces[spec.label] = batch.traces[0]
        rows.append(summarise(spec.label, batch))
        if batch.rows:
            frames.append(pl.DataFrame(batch.rows).with_columns(pl.lit(spec.label).alias("variant")))
    summary = with_ratios(pl.DataFrame(rows))
    table = pl.concat(frames, how="diagonal_relaxed") if frames else pl.DataFrame()
    result = TrialResult(kind, table, summary, traces=traces)
    if out is not None:
        meta = dict(kind=kind, minutes=minutes, runs=runs, seed=seed,
                    variants=[asdict(s) for s in specs], config=asdict(config))
        write_rows(table, out, meta)
        result.files = [out, *write_summary(summary, out.with_name(out.stem + "_summary"))]
    return result


def kick_trial(specs: list[AgentSpec], *, minutes: float = 30.0, seed: int = 0,
               workers: int | None = None, out: Path | None = None,
               config: KickTrialConfig = KickTrialConfig(), progress=None,
               trace: bool = False, executor: Executor | None = None) -> TrialResult:
    """Kick trial of each variant for ``minutes`` simulated minutes under the same seeds
    (whole episodes that end within the budget).

    ``trace``: keep the first episode of each variant as a pose trace (``result.traces``).
    ``executor``: where episodes run (``trials.executors``: pool or Ray); default a pool of
    ``workers`` processes.
    """
    return _run("kick", run_kick_episode, kick_summary, specs, config, minutes=minutes, runs=None,
                seed=seed, workers=workers, executor=executor, out=out, progress=progress,
                trace=trace)


def walk_trial(specs: list[AgentSpec], *, minutes: float | None = None, runs: int | None = None,
               seed: int = 0, workers: int | None = None, out: Path | None = None,
               config: WalkTrialConfig = WalkTrialConfig(), progress=None,
               trace: bool = False, executor: Executor | None = None) -> TrialResult:
    """Walk trial (own goal line to centre line) of each variant, by minutes or run count.

    ``trace``: keep the first run of each variant as a pose trace (``result.traces``).
    ``executor``: as for ``kick_trial``.
    """
    if minutes is None and runs is None:
        runs = 10
    return _run("walk", run_walk_episode, walk_summary, specs, config, minutes=minutes, runs=runs,
                seed=seed, workers=workers, executor=executor, out=out, progress=progress,
                trace=trace)
