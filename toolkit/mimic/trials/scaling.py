"""How episodes scale over workers: episodes per second for 1 and 2 local workers, the process
pool against Ray, measured in the same process run on the same episodes.

Each measurement first starts its workers (a process pool spawns, Ray starts once) and plays
one episode per worker untimed, so the timed part is steady-state episodes; the start-up is
reported beside it. The timed episodes of every measurement must give the same rows (the same
seeds), which ``same_rows`` reports.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from mimic.agents.registry import AgentSpec
from mimic.tasks.walk import WalkTrialConfig, run_walk_episode
from mimic.trials.executors import InlineExecutor, PoolExecutor, RayExecutor
from mimic.trials.parallel import run_episodes

__all__ = ["ScalingRow", "bench_scaling", "format_scaling"]


@dataclass(frozen=True)
class ScalingRow:
    """One measurement."""

    executor: str
    workers: int
    episodes: int
    # Start-up: workers started and one warm-up episode per worker [s].
    startup_s: float
    # Timed episodes [s] and their rate [1/s].
    wall_s: float
    episodes_per_s: float
    # The timed episodes gave the same rows as the first measurement.
    same_rows: bool


def _measure(name, executor, workers, episodes, spec, config, reference, started):
    run_episodes(run_walk_episode, spec, config, episodes=workers, seed=1, executor=executor)
    startup_s = time.perf_counter() - started
    start = time.perf_counter()
    batch = run_episodes(
        run_walk_episode, spec, config, episodes=episodes, seed=0, executor=executor
    )
    wall_s = time.perf_counter() - start
    rows = batch.rows
    return ScalingRow(
        name,
        workers,
        episodes,
        startup_s,
        wall_s,
        episodes / wall_s,
        reference is None or rows == reference,
    ), rows


def bench_scaling(
    episodes: int = 8,
    *,
    ray: bool = True,
    workers: tuple[int, ...] = (1, 2),
    timeout_s: float = 8.0,
) -> list[ScalingRow]:
    """Measure ``episodes`` walk-trial episodes (our walk, cut at ``timeout_s`` of simulated
    walking) per executor and worker count. Ray (``ray=True``) starts once, locally, with
    as many CPUs as the most workers asked, and is shut down at the end.

    Raises:
        MimicError: Ray asked for but not installed.
    """

    spec = AgentSpec("behaviour", "walk")
    config = WalkTrialConfig(timeout_s=timeout_s)
    rows, reference = [], None
    for k in workers:
        started = time.perf_counter()
        with InlineExecutor() if k == 1 else PoolExecutor(k) as ex:
            row, got = _measure(
                "pool" if k > 1 else "in process", ex, k, episodes, spec, config, reference, started
            )
        reference = got if reference is None else reference
        rows.append(row)
    if ray:
        started = time.perf_counter()
        owner = RayExecutor("local", max(workers))
        try:
            for i, k in enumerate(workers):
                if i:
                    started = time.perf_counter()
                ex = RayExecutor("local", k)  # joins the Ray started above
                row, _ = _measure("ray", ex, k, episodes, spec, config, reference, started)
                rows.append(row)
        finally:
            owner.close()
    return rows


def format_scaling(rows: list[ScalingRow]) -> str:
    """The measurements as a Markdown table, with speed-ups against one worker."""
    base = {r.executor: r.episodes_per_s for r in rows if r.workers == 1}
    lines = [
        "| executor | workers | episodes | start-up s | wall s | episodes/s | speed-up | "
        "same rows |",
        "|---|---|---|---|---|---|---|---|",
    ]
    one = rows[0].episodes_per_s
    for r in rows:
        lines.append(
            f"| {r.executor} | {r.workers} | {r.episodes} | {r.startup_s:.1f} | "
            f"{r.wall_s:.1f} | {r.episodes_per_s:.2f} | "
            f"{r.episodes_per_s / base.get(r.executor, one):.2f}x | "
            f"{'yes' if r.same_rows else 'NO'} |"
        )
    return "\n".join(lines) + "\n"
