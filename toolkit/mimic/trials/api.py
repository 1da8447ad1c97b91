"""Trials as functions: run one or more variants of a task under the same seeds and
tabulate them. ``run_trial`` plays any task (``tasks.registry``); ``kick_trial``,
``walk_trial`` and ``getup_trial`` are its three trials with their usual budgets."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import polars as pl

from mimic import options
from mimic.agents.registry import AgentSpec
from mimic.episode.disturbance import disturb_level
from mimic.errors import MimicError
from mimic.files import atomic_output, check_outputs
from mimic.model.model_file import load_model
from mimic.motion.files import load_motion
from mimic.tasks.base import EpisodeBatch, TrialTask
from mimic.tasks.getup import GetupTrialConfig
from mimic.tasks.kick import KickTrialConfig
from mimic.tasks.registry import get_task
from mimic.tasks.walk import WalkTrialConfig
from mimic.trials.executors import Executor, make_executor
from mimic.trials.parallel import run_episodes
from mimic.trials.report import (
    ratio_intervals,
    summary_files,
    with_ratios,
    write_rows,
    write_summary,
)
from mimic.world.registry import MUJOCO, check_world, world_kind, world_owns_physics

__all__ = [
    "TrialResult",
    "run_trial",
    "kick_trial",
    "walk_trial",
    "getup_trial",
    "check_trial",
    "check_variants",
    "trial_files",
    "keep_candidates",
    "keep_best",
]


@dataclass
class TrialResult:
    """Per-event rows (every kick or walk run, all variants) and the summary table."""

    # The task's name (``tasks.registry``).
    kind: str
    rows: pl.DataFrame
    summary: pl.DataFrame
    files: list[Path] = field(default_factory=list)
    # The first episode of each variant as a pose trace (``episode.EpisodeTrace``), when
    # the trial ran with ``trace=True``: the robot and ball replayed in the Rerun dashboard.
    traces: dict = field(default_factory=dict)

    @property
    def task(self) -> type[TrialTask]:
        return get_task(self.kind)


def trial_files(out: Path | None) -> list[Path]:
    """The files a trial with ``out`` writes: the parquet of every event and its summary."""
    return [] if out is None else [Path(out), *summary_files(Path(out))]


def keep_candidates(task: str | type[TrialTask], specs: list[AgentSpec]) -> list[AgentSpec]:
    """The variants ``--keep-best`` chooses among: the learned models (``.mimic``).

    Raises:
        MimicError: the trial ranks no variants (``TrialTask.rank``), or none is a model.
    """
    task = _task(task)
    if task.rank is None:
        raise MimicError(f"the {task.name} trial keeps no best variant (--keep-best)")
    candidates = [s for s in specs if s.kind == "model"]
    if not candidates:
        raise MimicError("--keep-best keeps a learned model: give at least one .mimic variant")
    return candidates


def keep_best(
    result: TrialResult, specs: list[AgentSpec], path: Path, *, overwrite: bool = False
) -> tuple[AgentSpec, dict]:
    """The best learned model of the trial (``keep_candidates``, ranked by the task's
    ``rank`` on its summary row; equal ranks: the one given first), its file copied to
    ``path`` as it is (replaced only when the copy is whole). Returns (its spec, its row).

    Raises:
        MimicError: as ``keep_candidates``; OutputError: ``path`` exists and not ``overwrite``.
    """
    candidates = keep_candidates(result.kind, specs)
    # The summary has a row per variant in the order given (two variants may share a label).
    ranked = [
        (spec, row)
        for spec, row in zip(specs, result.summary.iter_rows(named=True), strict=True)
        if spec in candidates
    ]
    best, row = max(ranked, key=lambda pair: result.task.rank(pair[1]))
    with atomic_output(path, overwrite=overwrite) as tmp:
        Path(tmp).write_bytes(Path(best.ref).read_bytes())
    return best, row


def check_variants(task: str | type[TrialTask], specs: list[AgentSpec]) -> None:
    """Before any episode runs: every variant can be built for this trial (model files read
    and are made for this robot, motion files parse, and what the task asks of a variant,
    e.g. a kick knows where its ball lies).

    Raises:
        MimicError: the first variant that cannot, named.
    """
    task = _task(task)
    if not specs:
        raise MimicError("no variant to try; give a motion, a .mimic model or an agent name")
    for spec in specs:
        options.finite(spec.speed_rate, "--speed-rate", above=0)
        if spec.kind == "model":
            load_model(spec.ref)
        elif spec.kind == "motion":
            load_motion(spec.ref, spec.robot)
        task.check_variant(spec)


def _task(task: str | type[TrialTask]) -> type[TrialTask]:
    return get_task(task) if isinstance(task, str) else task


def check_trial(
    task: str | type[TrialTask],
    specs: list[AgentSpec],
    *,
    minutes: float | None = None,
    runs: int | None = None,
    seed: int = 0,
    workers: int | None = None,
    config=None,
) -> None:
    """Everything a trial checks before its first episode: options in range (``--minutes``
    finite and > 0, ``--runs`` and ``--workers`` >= 1, a seed numpy accepts), the world
    (``config.world``: it plays every variant's robot, and can disturb the physics if the
    level asks), the task's own settings (``TrialTask.check``) and every variant
    (``check_variants``).

    Raises:
        MimicError: the first problem, in one line naming the option or the variant.
    """
    task = _task(task)
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
    for spec in specs:
        check_world(world, spec.robot)
    check_variants(task, specs)
    if config is not None:
        task.check(config, specs)


def run_trial(
    task: str | type[TrialTask],
    specs: list[AgentSpec],
    *,
    minutes: float | None = None,
    runs: int | None = None,
    seed: int = 0,
    workers: int | None = None,
    out: Path | None = None,
    config=None,
    progress: Callable[[str, EpisodeBatch], None] | None = None,
    trace: bool = False,
    executor: Executor | None = None,
    overwrite: bool = True,
    world: str | None = None,
) -> TrialResult:
    """The trial of ``task`` (a ``TrialTask`` or its name) for each variant, under the same
    seeds: for ``minutes`` simulated minutes (the episodes that end within the budget, and
    the one it ends in up to the budget's end if it can be cut: ``trials.parallel``) or
    ``runs`` episodes each, one of the two.

    ``config``: the task's settings (None: its defaults); ``world`` (``mujoco``, ``league``,
    ``league-server`` or ``league-like``; None: ``config.world``): where the episodes play;
    on ``league-server`` every episode hosts its own server (``world.registry``).
    ``trace``: keep the first episode of each variant as a pose trace (``result.traces``).
    ``executor``: where episodes run (``trials.executors``: pool or Ray); default a pool of
    ``workers`` processes. ``overwrite``: replace existing output files (False: refuse before
    any episode runs).

    Raises:
        MimicError: an option out of range, a variant that cannot be built (checked for every
            variant before the first episode), an output that exists (``overwrite`` False).
    """
    task = _task(task)
    config = task.Config() if config is None else config
    if world is not None:
        config = replace(config, world=world_kind(world))
    if minutes is not None and runs is not None:
        raise MimicError("give --minutes or --runs, not both")
    if minutes is None and runs is None:
        raise MimicError("give --minutes or --runs")
    check_trial(task, specs, minutes=minutes, runs=runs, seed=seed, workers=workers, config=config)
    if specs:
        config = task.for_original(config, specs[0])
    if out is not None and not overwrite:
        check_outputs(trial_files(out))
    run = dict(minutes=minutes, runs=runs, seed=seed, out=out, progress=progress, trace=trace)
    if executor is None:  # one pool for every variant: workers start once
        with make_executor(workers) as own:
            return _run_variants(task, specs, config, executor=own, overwrite=overwrite, **run)
    return _run_variants(task, specs, config, executor=executor, overwrite=overwrite, **run)


def _run_variants(
    task: type[TrialTask],
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
            progress(spec.label, EpisodeBatch([], [], task=task.name))
        batch = run_episodes(
            task.run_episode,
            spec,
            config,
            budget_s=None if minutes is None else minutes * 60,
            episodes=runs,
            seed=seed,
            executor=executor,
            progress=(lambda b, s=spec: progress(s.label, b)) if progress else None,
            task=task.name,
            trace_episodes=1 if trace else 0,
            expected_episode_s=expected_s,
        )
        expected_s = batch.simulated_s / len(batch.episodes) if batch.episodes else None
        if 0 in batch.traces:
            traces[spec.label] = batch.traces[0]
        if first_rows is None:  # the base of every ratio: its own is 1, without an interval
            first_rows = batch.rows
            rows.append(task.summarise(spec.label, batch))
        else:
            rows.append(
                {
                    **task.summarise(spec.label, batch),
                    **ratio_intervals(task, first_rows, batch.rows),
                }
            )
        if batch.rows:
            frames.append(
                pl.DataFrame(batch.rows).with_columns(pl.lit(spec.label).alias("variant"))
            )
    summary = with_ratios(pl.DataFrame(rows), task.ratio_columns)
    table = pl.concat(frames, how="diagonal_relaxed") if frames else pl.DataFrame()
    result = TrialResult(task.name, table, summary, traces=traces)
    if out is not None:
        meta = dict(
            kind=task.name,
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
    config: KickTrialConfig = KickTrialConfig(),
    **settings,
) -> TrialResult:
    """Kick trial (``tasks.kick``) of each variant for ``minutes`` simulated minutes under
    the same seeds. Options and Raises: as ``run_trial``."""
    return run_trial("kick", specs, minutes=minutes, config=config, **settings)


def walk_trial(
    specs: list[AgentSpec],
    *,
    minutes: float | None = None,
    runs: int | None = None,
    config: WalkTrialConfig = WalkTrialConfig(),
    **settings,
) -> TrialResult:
    """Walk trial (``tasks.walk``: from a standing start, straight ahead: our world's own
    goal line to the centre line, 15 m; the league's 10 m course) of each variant, by
    minutes or run count (default 10 runs). Options and Raises: as ``run_trial``."""
    if minutes is None and runs is None:
        runs = 10
    return run_trial("walk", specs, minutes=minutes, runs=runs, config=config, **settings)


def getup_trial(
    specs: list[AgentSpec],
    *,
    runs: int = 10,
    config: GetupTrialConfig = GetupTrialConfig(),
    **settings,
) -> TrialResult:
    """Get-up trial (``tasks.getup``: knocked down on the side the get-up starts from, get
    up) of each variant, ``runs`` runs each on seeds drawn from ``seed``. Options and
    Raises: as ``run_trial``."""
    return run_trial("getup", specs, runs=runs, config=config, **settings)
