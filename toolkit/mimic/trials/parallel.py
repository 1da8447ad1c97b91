"""Runs episodes on an executor until a simulated-time budget is spent, reproducibly.

Episode i always gets seed ``derive_seed(seed, i)``. Episodes are counted in index order. One
that ends within the budget counts whole; the first that would end past it ends the trial. It
counts to the budget's end, as of its last checkpoint within the budget, if it gives
checkpoints (``tasks.budget.CHECKPOINTS``: a kick episode's kicks that ended by then, its
falls and pushes by then), else not at all (but the first episode, which counts whole if
nothing of it is within). So a trial counts exactly its budget (less what an episode without
checkpoints leaves), and the same seed gives the same table whatever the executor (one
process, a pool of any size, Ray).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import os
import shutil
import tempfile
from collections import deque
from collections.abc import Callable
from pathlib import Path

import numpy as np

from mimic.tasks.base import EpisodeBatch
from mimic.tasks.budget import CHECKPOINTS, episode_cap
from mimic.trials.executors import Executor, available_cores, make_executor
from mimic.world.base import CYCLE_S

__all__ = ["run_episodes", "derive_seed", "default_workers", "run_job"]


def derive_seed(seed: int, episode: int) -> int:
    """A per-episode seed, independent of how episodes are spread over workers."""
    return int(np.random.SeedSequence([seed, episode]).generate_state(1)[0])


def default_workers() -> int:
    return available_cores()


#: In the process running ``run_episodes``: learns of episodes that ended meanwhile and
#: rewrites the live caps (``_CapFile`` calls it before it reads, so an episode this process
#: plays itself sees the others end). None elsewhere.
_refresh: Callable[[], None] | None = None

#: The suffix of the file beside an episode's cap in which it says how far it has played.
_PLAYED = ".played"


class _CapFile:
    """An episode's live cap (``tasks.budget``): a file the trial rewrites as the episodes
    before it play and end; beside it (``_PLAYED``) the episode writes how far it has played,
    which the trial reads as a bound on its duration when it lowers the later episodes'
    caps. Picklable (a path), for the worker that plays the episode. A file never read
    (another machine's worker) means no cap; one removed after it was read, that the trial
    is over (0)."""

    def __init__(self, path: str) -> None:
        self.path, self._seen, self._played_s = path, False, None

    def __call__(self, played_s: float | None = None) -> float:
        # An episode reads its cap several times at one decision: write what it played once.
        if played_s is not None and played_s != self._played_s:
            _write_cap(Path(self.path + _PLAYED), played_s)
            self._played_s = played_s
        if _refresh is not None:
            _refresh()
        try:
            cap_s = float(Path(self.path).read_text())
        except (OSError, ValueError):
            return 0.0 if self._seen else math.inf
        self._seen = True
        return cap_s


def _write_cap(path: Path, cap_s: float) -> None:
    """Replace the file at once (a reader sees the old value or the new, never a part)."""
    part = path.with_name(path.name + ".part")
    part.write_text(repr(cap_s))
    os.replace(part, path)


def _played_s(path: Path) -> float:
    """How far the episode whose cap is at ``path`` has said it played [s] (0: not yet)."""
    try:
        return float(path.with_name(path.name + _PLAYED).read_text())
    except (OSError, ValueError):
        return 0.0


def run_job(job: tuple) -> tuple[list[dict], dict]:
    """One episode: ``(func, spec, seed, config, episode[, cap])`` -> (rows, summary), each
    tagged with the episode index (module level: worker processes and Ray pickle it by
    name). ``cap``: the episode's live cap (``_CapFile``), if its trial has one."""
    func, spec, seed, config, episode, *cap = job
    with episode_cap(cap[0] if cap else None):
        rows, summary = func(spec, seed, config)
    # The episode as it ended and as of each of its checkpoints: each may be what counts.
    as_of = [(rows, summary), *((r, s) for _, r, s in summary.get(CHECKPOINTS, ()))]
    for some_rows, some_summary in as_of:
        for r in some_rows:
            r["episode"] = episode
        some_summary["episode"] = episode
    return rows, summary


def _cut(checkpoint: tuple, summary: dict, duration_s: float) -> tuple[list[dict], dict]:
    """An episode's rows and summary as of ``checkpoint`` (``tasks.budget.Checkpoint``),
    counted for ``duration_s`` [s]; the pose trace, if it kept one, is the whole episode's
    (what a replay shows of it)."""
    _, rows, cut = checkpoint
    trace = {"trace": summary["trace"]} if "trace" in summary else {}
    return rows, cut | {"duration_s": duration_s} | trace


def _capped(config, budget_s: float | None, counted_s: float):
    """``config`` with its ``episode_limit_s`` cut to just past what the budget has left once
    ``counted_s`` is spent: nothing an episode does past that could count, so it stops there
    instead of playing on (each limit bounds its episode's time only; an episode plays
    exactly as without the cap until it). Configs without the field, and trials counted in
    episodes, are returned as they are."""
    limit_s = getattr(config, "episode_limit_s", None)
    if budget_s is None or limit_s is None:
        return config
    # One cycle past what is left: a capped episode's duration is then over the budget, and
    # a checkpoint at exactly what is left was reached before it stopped.
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
    end past ``budget_s`` of simulated time (summary['duration_s']; that one counted to the
    budget's end if it gives checkpoints, as the module says), or exactly ``episodes``.

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
    nothing of it past that could count, so it stops instead of playing on. With several
    workers that bound shrinks while the episode plays (``tasks.budget``), as the episodes
    before it play on and end, to zero once it cannot count. What counts does not depend on
    any of this.
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
    # Live caps: only where an episode may start before the ones before it have ended.
    caps = (
        Path(tempfile.mkdtemp(prefix="mimic-caps-")) if budget_s and executor.workers > 1 else None
    )
    cap_s: dict[int, float] = {}  # episode index -> its cap as last written
    ended: dict[int, tuple] = {}  # episode index -> (rows, summary), ended but not yet counted

    def jobs():
        for i in range(episodes) if episodes is not None else itertools.count():
            traced = dataclasses.replace(config, trace=True) if i < trace_episodes else config
            index = first_episode + i
            job = (func, spec, derive_seed(seed, index))
            if i > 0:
                traced = _capped(traced, budget_s, batch.simulated_s)
            limit_s = getattr(traced, "episode_limit_s", None)
            if caps is None or limit_s is None:
                yield (*job, traced, index)
                continue
            if i > 0:  # the first one's cap stays its limit: it says how far it played only
                cap_s[index] = limit_s
            _write_cap(caps / str(index), limit_s)
            yield (*job, traced, index, _CapFile(str(caps / str(index))))

    job_iter = jobs()
    pending: deque = deque()  # (index, handle), in index order

    def refresh() -> None:
        """Take the results of episodes that have ended, and lower the caps of those still
        playing: the budget less every earlier episode, ended (its duration) or playing (how
        far it has played, which it will at least take), plus a cycle (0 once that is
        nothing)."""
        for index, handle in pending:
            if index not in ended and executor.done(handle):
                try:
                    ended[index] = executor.result(handle)
                except Exception:  # raised again where it is counted, in index order
                    pass
        spent_s = batch.simulated_s
        for index, _ in pending:
            if index in cap_s:
                left_s = budget_s - spent_s
                cap = left_s + CYCLE_S if left_s > 0 else 0.0
                if cap < cap_s[index]:
                    cap_s[index] = cap
                    _write_cap(caps / str(index), cap)
            if index in ended:
                spent_s += ended[index][1]["duration_s"]
            else:
                spent_s += _played_s(caps / str(index))

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
            pending.append((job[4], executor.submit(run_job, job)))

    global _refresh
    outer, _refresh = _refresh, (refresh if caps is not None else None)
    try:
        top_up()
        while pending:
            if _refresh is not None:
                _refresh()  # the episodes counted so far lower the caps of those playing
            index, handle = pending[0]
            if index not in ended:
                ended[index] = executor.result(handle, waiting=_refresh)
            pending.popleft()
            rows, summary = ended.pop(index)
            checkpoints = summary.pop(CHECKPOINTS, None)
            if budget_s is not None and batch.simulated_s + summary["duration_s"] > budget_s:
                # Would end past the budget: it ends the trial, counted to the budget's end as
                # of its last checkpoint within it; without one, not at all (the first episode
                # whole: a trial counts something).
                within = [c for c in checkpoints or () if batch.simulated_s + c[0] <= budget_s]
                if within:
                    batch.add(*_cut(within[-1], summary, budget_s - batch.simulated_s))
                    if progress:
                        progress(batch)
                    break
                if batch.episodes:
                    break
            batch.add(rows, summary)
            if progress:
                progress(batch)
            if budget_s is not None and batch.simulated_s >= budget_s:
                break
            top_up()
    finally:
        _refresh = outer
        if caps is not None:  # the episodes still playing cannot count: stop them
            for index, _ in pending:
                if index in cap_s:
                    _write_cap(caps / str(index), 0.0)
            shutil.rmtree(caps, ignore_errors=True)
    executor.discard([handle for _, handle in pending])
    return batch
