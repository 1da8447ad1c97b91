"""Runs episodes in worker processes until a simulated-time budget is spent, reproducibly.

Episode i always gets seed ``derive_seed(seed, i)``, and whole episodes are counted in index
order until their simulated time reaches the budget, so the same seed gives the same table
whatever the number of workers.
"""

from __future__ import annotations

import dataclasses
import multiprocessing as mp
import os
from collections import deque
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field

import numpy as np

__all__ = ["EpisodeBatch", "run_episodes", "derive_seed", "default_workers"]


def derive_seed(seed: int, episode: int) -> int:
    """A per-episode seed, independent of how episodes are spread over workers."""
    return int(np.random.SeedSequence([seed, episode]).generate_state(1)[0])


def default_workers() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


@dataclass
class EpisodeBatch:
    """Rows of every counted episode, tagged with the episode index."""

    rows: list[dict]
    episodes: list[dict]
    # Pose traces of the traced episodes, by episode index (see ``episode.PoseTrace``).
    traces: dict = field(default_factory=dict)

    def add(self, rows: list[dict], summary: dict) -> None:
        trace = summary.pop("trace", None)
        if trace is not None:
            self.traces[summary["episode"]] = trace
        self.rows += rows
        self.episodes.append(summary)

    @property
    def simulated_s(self) -> float:
        return sum(e["duration_s"] for e in self.episodes)


def _call(job):
    func, spec, seed, config, episode = job
    rows, summary = func(spec, seed, config)
    for r in rows:
        r["episode"] = episode
    summary["episode"] = episode
    return rows, summary


def run_episodes(func: Callable, spec, config, *, budget_s: float | None = None,
                 episodes: int | None = None, seed: int = 0, workers: int | None = None,
                 progress: Callable[[EpisodeBatch], None] | None = None,
                 trace_episodes: int = 0) -> EpisodeBatch:
    """Run ``func(spec, seed, config) -> (rows, summary)`` episodes until ``budget_s`` of
    simulated time (summary['duration_s']) is reached, or exactly ``episodes`` episodes.

    The first ``trace_episodes`` episodes run with ``config.trace = True`` (the config must
    have that field); their ``summary['trace']`` goes to ``batch.traces``.
    """
    if (budget_s is None) == (episodes is None):
        raise ValueError("give exactly one of budget_s and episodes")
    workers = workers or default_workers()
    batch = EpisodeBatch([], [])

    def enough() -> bool:
        if episodes is not None:
            return len(batch.episodes) >= episodes
        return batch.simulated_s >= budget_s

    def jobs():
        i = 0
        while episodes is None or i < episodes:
            traced = dataclasses.replace(config, trace=True) if i < trace_episodes else config
            yield (func, spec, derive_seed(seed, i), traced, i)
            i += 1

    job_iter = jobs()
    if workers <= 1:
        for job in job_iter:
            batch.add(*_call(job))
            if progress:
                progress(batch)
            if enough():
                break
        return batch
    with ProcessPoolExecutor(workers, mp_context=mp.get_context("spawn")) as pool:
        pending: deque = deque()
        for _ in range(workers + 1):  # a few spare so no worker idles; few to discard
            job = next(job_iter, None)
            if job is not None:
                pending.append(pool.submit(_call, job))
        while pending and not enough():
            batch.add(*pending.popleft().result())
            if progress:
                progress(batch)
            if not enough():
                job = next(job_iter, None)
                if job is not None:
                    pending.append(pool.submit(_call, job))
        for future in pending:
            future.cancel()
    return batch
