"""Runs episodes on an executor until a simulated-time budget is spent, reproducibly.

Episode i always gets seed ``derive_seed(seed, i)``. Episodes are counted in index order, and
an episode counts only if it ends within the budget (the first one always counts), so a
trial never runs past its budget and the same seed gives the same table whatever the
executor (one process, a pool of any size, Ray).
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque
from collections.abc import Callable

import numpy as np

from mimic.tasks.base import EpisodeBatch
from mimic.trials.executors import Executor, available_cores, make_executor
from mimic.world.base import CYCLE_S

__all__ = ["run_episodes", "derive_seed", "default_workers", "run_job"]


def derive_seed(seed: int, episode: int) -> int:
    """A per-episode seed, independent of how episodes are spread over workers."""
    return int(np.random.SeedSequence([seed, episode]).generate_state(1)[0])


def default_workers() -> int:
    return available_cores()


def run_job(job: tuple) -> tuple[list[dict], dict]:
    """One episode: ``(func, spec, seed, config, episode)`` -> (rows, summary), each tagged
    with the episode index (module level: worker processes and Ray pickle it by name)."""
    func, spec, seed, config, episode = job
    rows, summary = func(spec, seed, config)
    for r in rows:
        r["episode"] = episode
    summary["episode"] = episode
    return rows, summary


def _capped(config, budget_s: float | None, counted_s: float):
    """``config`` with its ``episode_limit_s`` cut to just past what the budget has left once
    ``counted_s`` is spent: an episode that runs that long would end past the budget and not
    count, so it stops there instead of playing on (each limit bounds its episode's time
    only; an episode that ends within the budget plays exactly as without the cap). Configs
    without the field, and trials counted in episodes, are returned as they are."""
    limit_s = getattr(config, "episode_limit_s", None)
    if budget_s is None or limit_s is None:
        return config
    # One cycle past what is left: a capped episode's duration is then over the budget.
    cap_s = max(0.0, budget_s - counted_s) + CYCLE_S
    return dataclasses.replace(config, episode_limit_s=cap_s) if cap_s < limit_s else config


def run_episodes(
    func: Callable,
    spec,
    config,
    *,
    budget_s: float | None = None,
    episodes: int | None = None,
    seed: int = 0,
    workers: int | None = None,
    executor: Executor | None = None,
    progress: Callable[[EpisodeBatch], None] | None = None,
    trace_episodes: int = 0,
    first_episode: int = 0,
    expected_episode_s: float | None = None,
    task: str | None = None,
) -> EpisodeBatch:
    """Run ``func(spec, seed, config) -> (rows, summary)`` episodes until the next one would
    end past ``budget_s`` of simulated time (summary['duration_s']), or exactly ``episodes``.

    ``executor`` runs them (kept open for the caller's next batch); without one, a pool of
    ``workers`` processes (default: every core) is made and closed here. Episode indices start
    at ``first_episode`` (validation runs use indices a search never reaches). The first
    ``trace_episodes`` episodes run with ``config.trace = True`` (the config must have that
    field); their ``summary['trace']`` goes to ``batch.traces``.

    With a budget, only as many episodes run at once as the budget still looks like it needs
    (from the mean duration so far, or ``expected_episode_s`` before the first one ends, e.g.
    the previous variant's; with neither, as many as the budget needs at least, from
    ``config.episode_limit_s``, else one): a short trial does not pay for episodes it will
    throw away. With several workers one more episode waits queued, so a worker that finishes
    first starts the next at once. An episode after the first is given, as its config's
    ``episode_limit_s``, at most what the budget had left when it started (plus a cycle):
    past that it could not count, so it stops instead of playing on. Which episodes count
    does not depend on any of this.
    """
    if (budget_s is None) == (episodes is None):
        raise ValueError("give exactly one of budget_s and episodes")
    if executor is None:
        with make_executor(workers) as own:
            return run_episodes(
                func,
                spec,
                config,
                budget_s=budget_s,
                episodes=episodes,
                seed=seed,
                executor=own,
                progress=progress,
                trace_episodes=trace_episodes,
                first_episode=first_episode,
                expected_episode_s=expected_episode_s,
                task=task,
            )
    batch = EpisodeBatch([], [], task=task)

    def jobs():
        i = 0
        while episodes is None or i < episodes:
            traced = dataclasses.replace(config, trace=True) if i < trace_episodes else config
            if i > 0:
                traced = _capped(traced, budget_s, batch.simulated_s)
            index = first_episode + i
            yield (func, spec, derive_seed(seed, index), traced, index)
            i += 1

    job_iter = jobs()
    pending: deque = deque()

    # One episode more than workers when there are several: results are collected in order, so
    # a worker that finishes first would otherwise wait for the others before it gets the next.
    slots = executor.workers + (1 if executor.workers > 1 else 0)

    def wanted() -> int:  # episodes worth having in flight
        if budget_s is None:
            return slots
        mean_s = batch.simulated_s / len(batch.episodes) if batch.episodes else expected_episode_s
        if not mean_s:  # the longest an episode may run: the budget needs at least this many
            longest_s = getattr(config, "episode_limit_s", None)
            return max(1, min(slots, math.ceil(budget_s / longest_s))) if longest_s else 1
        left = math.ceil(max(0.0, budget_s - batch.simulated_s) / mean_s)
        return max(1, min(slots, left))

    def top_up() -> None:  # at most one episode per worker in flight, and one queued
        while len(pending) < wanted():
            job = next(job_iter, None)
            if job is None:
                return
            pending.append(executor.submit(run_job, job))

    top_up()
    while pending:
        rows, summary = executor.result(pending.popleft())
        if (
            budget_s is not None
            and batch.episodes
            and batch.simulated_s + summary["duration_s"] > budget_s
        ):
            break  # would end past the budget: it and every later episode do not count
        batch.add(rows, summary)
        if progress:
            progress(batch)
        if budget_s is not None and batch.simulated_s >= budget_s:
            break
        top_up()
    executor.discard(pending)
    return batch
