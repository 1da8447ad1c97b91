"""Trials as functions: run one or more variants under the same seeds and tabulate them."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import polars as pl

from mimic import options
from mimic.agents.registry import AgentSpec
from mimic.episode.disturbance import disturb_level
from mimic.errors import MimicError
from mimic.trials.executors import Executor, make_executor
from mimic.trials.getup import GetupTrialConfig, run_getup_episode
from mimic.trials.kick import KickTrialConfig, run_kick_episode
from mimic.trials.parallel import EpisodeBatch, run_episodes
from mimic.trials.report import (
    getup_summary,
    kick_summary,
    ratio_intervals,
    summary_files,
    walk_summary,
    with_ratios,
    write_rows,
    write_summary,
)
from mimic.trials.walk import WalkTrialConfig, run_walk_episode
from mimic.world.registry import MUJOCO, check_world, world_kind, world_owns_physics

__all__ = [
    "TrialResult",
    "kick_trial",
    "walk_trial",
    "getup_trial",
    "check_trial",
    "check_variants",
    "trial_files",
]


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


def trial_files(out: Path | None) -> list[Path]:
    """The files a trial with ``out`` writes: the parquet of every event and its summary."""
    return [] if out is None else [Path(out), *summary_files(Path(out))]


def check_variants(kind: str, specs: list[AgentSpec]) -> None:
    """Before any episode runs: every variant can be built for this trial (model files read
    and are made for this robot, motion files parse, a kick knows where its ball lies).

    Raises:
        MimicError: the first variant that cannot, named.
    """
    if not specs:
        raise MimicError("no variant to try; give a motion, a .mimic model or an agent name")
    for spec in specs:
        options.finite(spec.speed_rate, "--speed-rate", above=0)
        if spec.kind == "model":
            from mimic.model.model_file import load_model

            load_model(spec.ref)
        elif spec.kind == "motion":
            from mimic.motion.files import load_motion

            load_motion(spec.ref, spec.robot)
        if kind == "kick":
            spec.ball_offset_m()


def check_trial(
    kind: str,
    specs: list[AgentSpec],
    *,
    minutes: float | None = None,
    runs: int | None = None,
    seed: int = 0,
    workers: int | None = None,
    config: KickTrialConfig | WalkTrialConfig | GetupTrialConfig | None = None,
) -> None:
    """Everything a trial checks before its first episode: options in range (``--minutes``
    finite and > 0, ``--runs`` and ``--workers`` >= 1, a seed numpy accepts), the world
    (``config.world``: it plays every variant's robot; a kick's way to the ball suits the
    robot) and every variant (``check_variants``).

    Raises:
        MimicError: the first problem, in one line naming the option or the variant.
    """
    options.finite(minutes, "--minutes", above=0)
    options.count(runs, "--runs")
    options.seed(seed)
    options.workers(workers)
    world = world_kind(getattr(config, "world", MUJOCO))
    level = getattr(config, "disturb", "none")
    if disturb_level(level).physics and not world_owns_physics(world):
        raise MimicError(
            f"--disturb {level} pushes the robot and changes friction and masses, which the "
            f"{world} world cannot (its physics runs in another process); use --disturb none"
        )
    if kind == "kick" and config is not None:
        options.finite(config.success_distance_m, "--success-m", at_least=0)
    for spec in specs:
        check_world(world, spec.robot)
        if kind == "kick" and config is not None:
            from mimic.trials.kick import reach_method

            reach_method(config, spec.robot)
    check_variants(kind, specs)
    if kind == "getup" and config is not None:
        for spec in specs:  # each lies down on a side: its own, or the one given
            config.side_for(spec.build().start_posture)


def _run(
    kind: str,
    episode_fn: Callable,
    summarise: Callable,
    specs: list[AgentSpec],
    config,
    *,
    minutes: float | None,
    runs: int | None,
    seed: int,
    workers: int | None,
    executor: Executor | None,
    out: Path | None,
    progress: Callable[[str, EpisodeBatch], None] | None,
    trace: bool,
    overwrite: bool,
) -> TrialResult:
    check_trial(kind, specs, minutes=minutes, runs=runs, seed=seed, workers=workers, config=config)
    if out is not None and not overwrite:
        from mimic.files import check_outputs

        check_outputs(trial_files(out))
    if executor is None:  # one pool for every variant: workers start once
        with make_executor(workers) as own:
            return _run_variants(
                kind,
                episode_fn,
                summarise,
                specs,
                config,
                minutes=minutes,
                runs=runs,
                seed=seed,
                executor=own,
                out=out,
                progress=progress,
                trace=trace,
                overwrite=overwrite,
            )
    return _run_variants(
        kind,
        episode_fn,
        summarise,
        specs,
        config,
        minutes=minutes,
        runs=runs,
        seed=seed,
        executor=executor,
        out=out,
        progress=progress,
        trace=trace,
        overwrite=overwrite,
    )


def _run_variants(
    kind: str,
    episode_fn: Callable,
    summarise: Callable,
    specs: list[AgentSpec],
    config,
    *,
    minutes: float | None,
    runs: int | None,
    seed: int,
    executor: Executor,
    out: Path | None,
    progress: Callable[[str, EpisodeBatch], None] | None,
    trace: bool,
    overwrite: bool,
) -> TrialResult:
    frames, rows, traces = [], [], {}
    expected_s = None  # the previous variant's mean episode: how many to run at once
    first_rows = None  # the first variant's events: every ratio's base
    for spec in specs:
        if progress:  # the variant starts now (its clock too), before its first episode ends
            progress(spec.label, EpisodeBatch([], []))
        batch = run_episodes(
            episode_fn,
            spec,
            config,
            budget_s=None if minutes is None else minutes * 60,
            episodes=runs,
            seed=seed,
            executor=executor,
            progress=(lambda b, s=spec: progress(s.label, b)) if progress else None,
            trace_episodes=1 if trace else 0,
            expected_episode_s=expected_s,
        )
        expected_s = batch.simulated_s / len(batch.episodes) if batch.episodes else None
        if 0 in batch.traces:
            traces[spec.label] = batch.traces[0]
        if first_rows is None:  # the base of every ratio: its own is 1, without an interval
            first_rows = batch.rows
            rows.append(summarise(spec.label, batch))
        else:
            rows.append(
                {**summarise(spec.label, batch), **ratio_intervals(kind, first_rows, batch.rows)}
            )
        if batch.rows:
            frames.append(
                pl.DataFrame(batch.rows).with_columns(pl.lit(spec.label).alias("variant"))
            )
    summary = with_ratios(pl.DataFrame(rows))
    table = pl.concat(frames, how="diagonal_relaxed") if frames else pl.DataFrame()
    result = TrialResult(kind, table, summary, traces=traces)
    if out is not None:
        meta = dict(
            kind=kind,
            minutes=minutes,
            runs=runs,
            seed=seed,
            variants=[asdict(s) for s in specs],
            config=asdict(config),
        )
        write_rows(table, out, meta, summary=summary, overwrite=overwrite)
        result.files = [
            out,
            *write_summary(summary, out.with_name(out.stem + "_summary"), overwrite=overwrite),
        ]
    return result


def kick_trial(
    specs: list[AgentSpec],
    *,
    minutes: float = 30.0,
    seed: int = 0,
    workers: int | None = None,
    out: Path | None = None,
    config: KickTrialConfig = KickTrialConfig(),
    progress=None,
    trace: bool = False,
    executor: Executor | None = None,
    overwrite: bool = True,
    world: str | None = None,
) -> TrialResult:
    """Kick trial of each variant for ``minutes`` simulated minutes under the same seeds
    (whole episodes that end within the budget).

    ``world``: where the episodes play (``mujoco``, ``league``, ``league-server`` or
    ``league-like``; None: ``config.world``); on ``league-server`` every episode hosts its own
    server (``world.registry``).

    ``trace``: keep the first episode of each variant as a pose trace (``result.traces``).
    ``executor``: where episodes run (``trials.executors``: pool or Ray); default a pool of
    ``workers`` processes. ``overwrite``: replace existing output files (False: refuse before
    any episode runs).

    Raises:
        MimicError: an option out of range, a variant that cannot be built (checked for every
            variant before the first episode), an output that exists (``overwrite`` False).
    """
    if world is not None:
        config = replace(config, world=world_kind(world))
    return _run(
        "kick",
        run_kick_episode,
        kick_summary,
        specs,
        config,
        minutes=minutes,
        runs=None,
        seed=seed,
        workers=workers,
        executor=executor,
        out=out,
        progress=progress,
        trace=trace,
        overwrite=overwrite,
    )


def walk_trial(
    specs: list[AgentSpec],
    *,
    minutes: float | None = None,
    runs: int | None = None,
    seed: int = 0,
    workers: int | None = None,
    out: Path | None = None,
    config: WalkTrialConfig = WalkTrialConfig(),
    progress=None,
    trace: bool = False,
    executor: Executor | None = None,
    overwrite: bool = True,
    world: str | None = None,
) -> TrialResult:
    """Walk trial (from a standing start, straight ahead: our world's own goal line to the
    centre line, 15 m; the league's 10 m course) of each variant, by minutes or run count.

    ``trace``: keep the first run of each variant as a pose trace (``result.traces``).
    ``executor``, ``overwrite``, ``world``, Raises: as ``kick_trial``.
    """
    if world is not None:
        config = replace(config, world=world_kind(world))
    if minutes is not None and runs is not None:
        raise MimicError("give --minutes or --runs, not both")
    if minutes is None and runs is None:
        runs = 10
    return _run(
        "walk",
        run_walk_episode,
        walk_summary,
        specs,
        config,
        minutes=minutes,
        runs=runs,
        seed=seed,
        workers=workers,
        executor=executor,
        out=out,
        progress=progress,
        trace=trace,
        overwrite=overwrite,
    )


def getup_trial(
    specs: list[AgentSpec],
    *,
    runs: int = 10,
    seed: int = 0,
    workers: int | None = None,
    out: Path | None = None,
    config: GetupTrialConfig = GetupTrialConfig(),
    progress=None,
    trace: bool = False,
    executor: Executor | None = None,
    overwrite: bool = True,
    world: str | None = None,
) -> TrialResult:
    """Get-up trial (``trials.getup``: knocked down on the side the get-up starts from, get
    up) of each variant, ``runs`` runs each on seeds drawn from ``seed``.

    ``trace``, ``executor``, ``overwrite``, ``world``, Raises: as ``kick_trial``.
    """
    if world is not None:
        config = replace(config, world=world_kind(world))
    return _run(
        "getup",
        run_getup_episode,
        getup_summary,
        specs,
        config,
        minutes=None,
        runs=runs,
        seed=seed,
        workers=workers,
        executor=executor,
        out=out,
        progress=progress,
        trace=trace,
        overwrite=overwrite,
    )
