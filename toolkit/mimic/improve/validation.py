"""Validation of an improved candidate on episodes the search never played.

The search plays episode indices below ``MAX_SEARCH_EPISODE``; validation plays indices from
there on, with the same seed, so the episode seeds (``derive_seed(seed, index)``) are those
of other episodes by construction; ``held_out_episodes`` also checks that no seed repeats.
Validation plays the trial's own settings (``objective.trial_config``), the target as it was
and the improved candidate side by side (after any reference variants, e.g. the original
keyframe kick, which then heads the table and its ratios).
"""

from __future__ import annotations

from collections.abc import Callable

import polars as pl

from mimic.errors import MimicError
from mimic.improve.search import MAX_SEARCH_EPISODE
from mimic.tasks.registry import get_task
from mimic.trials.api import TrialResult
from mimic.trials.executors import Executor
from mimic.trials.parallel import derive_seed, run_episodes
from mimic.trials.report import with_ratios

__all__ = ["validate", "held_out_episodes", "VALIDATION_FIRST_EPISODE"]

#: First episode index of a validation run.
VALIDATION_FIRST_EPISODE = MAX_SEARCH_EPISODE


def held_out_episodes(seed: int, episodes: int, search_episodes: list[int]) -> range:
    """Indices of ``episodes`` validation episodes, checked to share no seed with the search.

    Raises:
        MimicError: a seed of the search would repeat (never seen; the indices differ).
    """
    indices = range(VALIDATION_FIRST_EPISODE, VALIDATION_FIRST_EPISODE + episodes)
    if any(i >= VALIDATION_FIRST_EPISODE for i in search_episodes):
        raise MimicError("search episodes overlap the validation range")
    seen = {derive_seed(seed, i) for i in search_episodes}
    repeated = [i for i in indices if derive_seed(seed, i) in seen]
    if repeated:
        raise MimicError(
            f"validation episode seeds repeat search seeds ({len(repeated)}); use another --seed"
        )
    return indices


def validate(
    specs: list,
    objective,
    *,
    seed: int,
    episodes: int,
    executor: Executor,
    search_episodes: list[int],
    trace_label: str | None = None,
    progress: Callable | None = None,
) -> TrialResult:
    """Play ``episodes`` held-out trial episodes of every spec (the first heads the ratios).

    ``trace_label``: keep that variant's first episode as a pose trace (the 3D replay).
    """
    indices = held_out_episodes(seed, episodes, search_episodes)
    frames, rows, traces = [], [], {}
    for spec in specs:
        batch = run_episodes(
            objective.episode_fn,
            spec,
            objective.trial_config,
            episodes=episodes,
            seed=seed,
            executor=executor,
            first_episode=indices.start,
            trace_episodes=1 if spec.label == trace_label else 0,
            progress=(lambda b, s=spec: progress(s.label, b)) if progress else None,
            task=objective.name,
        )
        if batch.traces:
            traces[spec.label] = next(iter(batch.traces.values()))
        # The objective's score on the held-out episodes: what says whether the improved
        # candidate beat the starting point.
        rows.append({**objective.summarise(spec.label, batch), "score": objective.score(batch)})
        if batch.rows:
            frames.append(
                pl.DataFrame(batch.rows).with_columns(pl.lit(spec.label).alias("variant"))
            )
    table = pl.concat(frames, how="diagonal_relaxed") if frames else pl.DataFrame()
    ratio_columns = get_task(objective.name).ratio_columns
    return TrialResult(
        objective.name, table, with_ratios(pl.DataFrame(rows), ratio_columns), traces=traces
    )
