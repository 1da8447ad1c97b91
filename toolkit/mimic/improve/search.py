"""CMA-ES over a target's search space, candidates scored by trial episodes; checkpointed.

Generation g asks the optimiser (``cmaes.CMA``, seeded) for a population of candidates and
plays every candidate in the same trial episodes: indices ``g * E .. g * E + E - 1`` with
seeds ``derive_seed(seed, index)`` (common random numbers within a generation, fresh episodes
every generation). Results come back in candidate order whatever the executor, so a pool and
Ray give the same search for the same seed.

The checkpoint (JSON) holds the settings and every generation's candidates and scores. A
resumed run replays the optimiser from the seed with the stored scores (no episode is played
again), checks that it asks for exactly the stored candidates, and continues.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mimic.errors import MimicError
from mimic.files import atomic_output
from mimic.tasks.base import EpisodeBatch
from mimic.trials.executors import Executor
from mimic.trials.parallel import derive_seed, run_job

__all__ = [
    "SearchConfig",
    "Generation",
    "SearchResult",
    "CheckpointError",
    "search",
    "evaluate",
    "default_population",
    "MAX_SEARCH_EPISODE",
    "CHECKPOINT_FORMAT",
]

CHECKPOINT_FORMAT = "mimic-improve-checkpoint"
#: Search episodes use indices below this; validation starts here (``improve.validation``).
MAX_SEARCH_EPISODE = 1 << 30
#: Fewest candidates per generation: CMA-ES needs two parents (mu = population // 2).
MIN_POPULATION = 4


class CheckpointError(MimicError):
    """A checkpoint that cannot be read or belongs to another search."""


@dataclass(frozen=True)
class SearchConfig:
    """Settings of one search."""

    # Candidate evaluations in all (each plays the objective's episodes).
    budget: int
    # Seeds the optimiser and the episodes.
    seed: int = 0
    # Initial step of the optimiser, in search units (1 = each parameter's scale).
    sigma: float = 1.0
    # Candidates per generation (default: CMA-ES's 4 + 3 ln d, at most the budget).
    population: int | None = None

    def __post_init__(self) -> None:
        if (
            isinstance(self.budget, bool)
            or not isinstance(self.budget, (int, np.integer))
            or self.budget < 1
        ):
            raise MimicError(
                f"--budget must be a whole number of evaluations >= 1, got {self.budget!r}"
            )
        if not (
            isinstance(self.sigma, (int, float)) and math.isfinite(self.sigma) and self.sigma > 0
        ):
            raise MimicError(f"--sigma must be a finite number > 0, got {self.sigma!r}")
        if self.population is not None and self.population < MIN_POPULATION:
            raise MimicError(f"--population must be >= {MIN_POPULATION}, got {self.population}")


def default_population(dim: int, budget: int) -> int:
    """CMA-ES's default population for ``dim`` parameters (4 + 3 ln d), at most ``budget``
    and at least ``MIN_POPULATION``."""
    return max(MIN_POPULATION, min(4 + int(3 * math.log(dim)), budget))


@dataclass
class Generation:
    """One generation: candidates (search units), their scores and summaries."""

    index: int
    z: np.ndarray  # (pop, d)
    scores: np.ndarray  # (pop,)
    first_episode: int
    summaries: list[dict] = field(default_factory=list)

    @property
    def best(self) -> int:
        return int(np.argmax(self.scores))

    def to_json(self) -> dict:
        return dict(
            index=self.index,
            first_episode=self.first_episode,
            z=self.z.tolist(),
            scores=self.scores.tolist(),
            summaries=self.summaries,
        )

    @classmethod
    def from_json(cls, data: dict) -> Generation:
        return cls(
            int(data["index"]),
            np.array(data["z"], dtype=float),
            np.array(data["scores"], dtype=float),
            int(data["first_episode"]),
            list(data.get("summaries", [])),
        )


@dataclass
class SearchResult:
    """Every generation so far, and the best candidate seen."""

    settings: dict
    generations: list[Generation]
    # Generations replayed from the checkpoint (not played in this run).
    resumed: int = 0
    # (d,) the optimiser's mean after the last generation: under noisy scores a steadier
    # choice than the best candidate seen, whose score is partly luck.
    mean_z: np.ndarray | None = None

    @property
    def evaluations(self) -> int:
        return sum(len(g.scores) for g in self.generations)

    @property
    def best(self) -> tuple[np.ndarray, float, int]:
        """(z, score, generation) of the highest-scoring candidate."""
        g = max(self.generations, key=lambda g: g.scores.max())
        return g.z[g.best], float(g.scores.max()), g.index

    def search_episodes(self, episodes: int) -> list[int]:
        """Every episode index the search played."""
        return [g.first_episode + i for g in self.generations for i in range(episodes)]


def evaluate(
    specs: list, objective, *, seed: int, first_episode: int, executor: Executor
) -> tuple[np.ndarray, list[dict]]:
    """Scores (n,) and summaries of candidates ``specs``, all in the same episodes
    ``first_episode ..`` (one job per candidate and episode; results in candidate order)."""
    e = objective.episodes
    config = objective.search_config
    jobs = [
        (
            objective.episode_fn,
            spec,
            derive_seed(seed, first_episode + i),
            config,
            first_episode + i,
        )
        for spec in specs
        for i in range(e)
    ]
    results = executor.map(run_job, jobs)
    scores, summaries = [], []
    for c, spec in enumerate(specs):
        batch = EpisodeBatch([], [])
        for rows, summary in results[c * e : (c + 1) * e]:
            batch.add(rows, summary)
        scores.append(objective.score(batch))
        summaries.append(
            {
                k: v
                for k, v in objective.summarise(spec.label, batch).items()
                if isinstance(v, (int, float)) and not isinstance(v, bool)
            }
        )
    return np.array(scores, dtype=float), summaries


def _settings(target, objective, config: SearchConfig, population: int) -> dict:
    return dict(
        target=target.text,
        target_kind=target.kind,
        parameters=list(target.space.names),
        objective=objective.describe(),
        seed=config.seed,
        sigma=config.sigma,
        population=population,
    )


def _read_checkpoint(path: Path, settings: dict) -> list[Generation]:
    try:
        doc = json.loads(path.read_text())
        if doc.get("format") != CHECKPOINT_FORMAT:
            raise ValueError("no format tag")
        generations = [Generation.from_json(g) for g in doc["generations"]]
        stored = doc["settings"]
    except (
        OSError,
        UnicodeDecodeError,
        json.JSONDecodeError,
        ValueError,
        KeyError,
        TypeError,
        AttributeError,
    ) as err:
        raise CheckpointError(
            f"checkpoint {path} is damaged or not a checkpoint ({err}); delete it to start afresh"
        ) from None
    # JSON turns tuples into lists: compare in JSON form.
    if json.loads(json.dumps(settings)) != stored:
        differ = sorted(
            k for k in settings if json.loads(json.dumps(settings.get(k))) != stored.get(k)
        )
        raise CheckpointError(
            f"checkpoint {path} belongs to another search (different "
            f"{', '.join(differ) or 'settings'}); give another --checkpoint or "
            "delete it"
        )
    return generations


def _write_checkpoint(path: Path, settings: dict, generations: list[Generation]) -> None:
    doc = dict(
        format=CHECKPOINT_FORMAT,
        format_version=1,
        settings=settings,
        generations=[g.to_json() for g in generations],
    )

    with atomic_output(path) as tmp:  # a checkpoint is replaced only by a whole new one
        tmp.write_text(json.dumps(doc))


def search(
    target,
    objective,
    config: SearchConfig,
    *,
    executor: Executor,
    checkpoint: Path | None = None,
    progress: Callable[[SearchResult], None] | None = None,
) -> SearchResult:
    """Run CMA-ES on ``target`` for ``config.budget`` evaluations (whole generations).

    ``checkpoint``: read first if it exists (resume), written after every generation.
    ``progress``: called after every generation (replayed ones included, once at the start).

    Raises:
        CheckpointError: damaged checkpoint, or one of a different search.
        MimicError: a budget smaller than one generation. (A budget the checkpoint already
            spent is fine: nothing more runs.)
    """
    try:
        import cmaes
    except ModuleNotFoundError:
        raise MimicError("mimic improve needs the cmaes package: pip install cmaes") from None

    space = target.space
    population = config.population or default_population(space.dim, config.budget)
    if population > config.budget:
        raise MimicError(
            f"--budget {config.budget} is less than one generation ({population} "
            "candidates); raise --budget or lower --population"
        )
    settings = _settings(target, objective, config, population)
    stored = _read_checkpoint(checkpoint, settings) if checkpoint and checkpoint.exists() else []
    optimizer = cmaes.CMA(
        mean=np.zeros(space.dim),
        sigma=config.sigma,
        bounds=space.bounds_z(),
        seed=config.seed,
        population_size=population,
    )
    result = SearchResult(settings, [], resumed=len(stored))
    for g in stored:  # replay: the optimiser must ask for exactly what was stored
        asked = np.array([optimizer.ask() for _ in range(population)])
        if asked.shape != g.z.shape or not np.array_equal(asked, g.z):
            raise CheckpointError(
                f"checkpoint {checkpoint} does not replay (generation "
                f"{g.index} differs; another cmaes version?); delete it"
            )
        optimizer.tell(list(zip(asked, -g.scores)))
        result.generations.append(g)
    if stored and progress:
        progress(result)
    while result.evaluations + population <= config.budget:
        index = len(result.generations)
        first = index * objective.episodes
        if first + objective.episodes > MAX_SEARCH_EPISODE:
            raise MimicError("the search ran out of episode indices; lower --budget")
        z = np.array([optimizer.ask() for _ in range(population)])
        scores, summaries = evaluate(
            [target.spec(x, label=f"g{index}c{c}") for c, x in enumerate(z)],
            objective,
            seed=config.seed,
            first_episode=first,
            executor=executor,
        )
        optimizer.tell(list(zip(z, -scores)))
        result.generations.append(Generation(index, z, scores, first, summaries))
        if checkpoint:
            _write_checkpoint(checkpoint, settings, result.generations)
        if progress:
            progress(result)
    result.mean_z = np.array(optimizer.mean, dtype=float)
    return result
