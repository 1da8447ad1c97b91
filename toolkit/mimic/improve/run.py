"""One ``mimic improve`` run as a function: read the target, search, write, validate."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from mimic.agents.registry import agent_spec
from mimic.errors import MimicError
from mimic.improve.objectives import make_objective
from mimic.improve.search import SearchConfig, SearchResult, default_population, search
from mimic.improve.stand_window import AUTO, StandWindow, stand_window
from mimic.improve.targets import Target, load_target
from mimic.improve.validation import validate
from mimic.model.model_file import load_model
from mimic.tasks.registry import get_task
from mimic.trials.api import TrialResult
from mimic.trials.executors import Executor, make_executor
from mimic.trials.report import write_summary
from mimic.world.registry import check_world, default_robot, world_kind

__all__ = ["improve", "ImproveRun", "default_checkpoint", "PICKS"]

#: Which candidate is written: the best scored in the search, or the optimiser's final mean.
PICKS = ("best", "mean")


@dataclass
class ImproveRun:
    """What a run produced."""

    target: Target
    objective: object
    search: SearchResult
    # The improved candidate's file (motion, model or parameter file) and its search point.
    out: Path
    z: object = None
    # Held-out validation (None when skipped), and the files its table went to.
    validation: TrialResult | None = None
    files: list[Path] = field(default_factory=list)
    # Wall times [s].
    search_wall_s: float = 0.0
    validation_wall_s: float = 0.0
    # The objective's score on the held-out episodes: the starting point's and the improved
    # candidate's (None without validation); ``kept_start``: the candidate validated worse,
    # so ``out`` holds the starting point (unless ``keep_worse``).
    start_score: float | None = None
    improved_score: float | None = None
    kept_start: bool = False
    # ``--window auto``: the stand window placed (``improve.stand_window``).
    stand_window: StandWindow | None = None

    @property
    def validated_worse(self) -> bool:
        """The improved candidate scored below the starting point on held-out episodes."""
        return (
            self.start_score is not None
            and self.improved_score is not None
            and self.improved_score < self.start_score
        )


def default_checkpoint(out: Path) -> Path:
    """Where a run writing ``out`` keeps its checkpoint: ``OUT.ckpt.json`` beside it."""
    return out.with_name(out.name + ".ckpt.json")


def improve(
    target: str,
    *,
    objective,
    budget: int,
    out: Path,
    seed: int = 0,
    episodes: int | None = None,
    sigma: float = 1.0,
    population: int | None = None,
    joints: str = "legs",
    window_s: tuple[float, float] | str | None = None,
    pick: str = "best",
    validation_episodes: int = 0,
    references: tuple[str, ...] = (),
    checkpoint: Path | None = None,
    workers: int | None = None,
    ray: str | None = None,
    executor: Executor | None = None,
    on_generation: Callable[[SearchResult], None] | None = None,
    on_validation: Callable | None = None,
    before_search: Callable | None = None,
    world: str | None = None,
    robot: str | None = None,
    keep_worse: bool = False,
) -> ImproveRun:
    """Improve ``target`` (an agent spec: motion, ``.mimic`` model, engine or ``.json``
    parameter file) for ``objective`` (``kick``/``walk``, or an objective from
    ``improve.objectives`` with its own settings) with ``budget`` evaluations of
    ``episodes`` trial episodes each; write the best candidate to ``out``; then validate it
    against the target as it was (and ``references``) on ``validation_episodes`` held-out
    episodes.

    Episodes run on ``executor``, else on a pool of ``workers`` processes or on Ray (``ray``:
    ``local`` or an address). ``checkpoint`` (default ``OUT.ckpt.json``) resumes a stopped run.
    ``pick``: write the best candidate scored (``best``) or the optimiser's final mean
    (``mean``: never scored in the search, steadier when scores are noisy); validation tells
    which held up. A candidate that validates worse than the starting point (the objective's
    score on the held-out episodes) is not kept: ``out`` then holds the starting point
    (``run.kept_start``), unless ``keep_worse``.
    ``before_search(target, objective, population)`` is called once the inputs are checked.
    ``world`` (``mujoco``, ``league``, ``league-server`` or ``league-like``; default: the
    objective's trial settings, ours) is where every episode plays, search and validation
    alike; ``robot`` (default: the NAO in ours, the T1 in the league's; a model file says its
    own) is whose motion or engine a name means. ``window_s`` (a learned one-shot model):
    its offsets and gains act only within that window [s of the motion]; ``"auto"`` (a get-up
    objective): the stand window, from just before the copy (as it is) is first upright to
    its end (``improve.stand_window``, played on the search's first episodes before it
    starts; ``run.stand_window`` says where and why).

    Raises:
        MimicError: bad target, objective, budget, out suffix, checkpoint, Ray address, world,
            or a robot that the world or the target does not take.
    """

    out = Path(out)
    obj = make_objective(objective, episodes) if isinstance(objective, str) else objective
    if world is not None:
        obj = replace(obj, trial_config=replace(obj.trial_config, world=world_kind(world)))
    kind = obj.trial_config.world
    placed = None
    if isinstance(window_s, str):
        placed = _auto_window(target, window_s, obj, seed, robot or default_robot(kind))
        window_s = placed.window_s
    tgt = load_target(target, joints=joints, robot=robot or default_robot(kind), window_s=window_s)
    target_robot = tgt.baseline().robot
    if robot is not None and target_robot != robot:
        raise MimicError(
            f"{target} drives the {target_robot}, not the {robot}; pass --robot {target_robot} "
            "or leave --robot out"
        )
    check_world(kind, target_robot)
    if out.suffix != tgt.suffix:
        raise MimicError(
            f"-o {out}: a {tgt.kind} target is written as a {tgt.suffix} file; "
            f"give e.g. -o {out.with_suffix(tgt.suffix).name}"
        )
    if pick not in PICKS:
        raise MimicError(f"--pick must be one of {', '.join(PICKS)}, got {pick!r}")
    config = SearchConfig(budget=budget, seed=seed, sigma=sigma, population=population)
    if validation_episodes < 0:
        raise MimicError(f"--validate must be >= 0, got {validation_episodes}")
    refs = [agent_spec(r, robot=target_robot) for r in references]
    task = get_task(obj.name)
    for spec in (tgt.baseline(), *refs):  # e.g. a kick objective needs kicks: fail before searching
        task.check_variant(spec)
    checkpoint = checkpoint or default_checkpoint(out)
    pop = population or default_population(tgt.space.dim, budget)
    if pop > budget:
        raise MimicError(
            f"--budget {budget} is less than one generation ({pop} candidates); "
            "raise --budget or lower --population"
        )
    if executor is None:  # inputs are checked: start the workers
        with make_executor(workers, ray) as own:
            run = improve(
                target,
                objective=obj,
                budget=budget,
                out=out,
                seed=seed,
                episodes=episodes,
                sigma=sigma,
                population=population,
                joints=joints,
                window_s=window_s,
                pick=pick,
                validation_episodes=validation_episodes,
                references=references,
                checkpoint=checkpoint,
                executor=own,
                on_generation=on_generation,
                on_validation=on_validation,
                before_search=before_search,
                robot=robot,
                keep_worse=keep_worse,
            )
            run.stand_window = placed or run.stand_window
            return run
    if before_search:
        before_search(tgt, obj, pop)
    start = time.perf_counter()
    result = search(
        tgt, obj, config, executor=executor, checkpoint=checkpoint, progress=on_generation
    )
    search_wall_s = time.perf_counter() - start
    z, score, generation = result.best
    if pick == "mean":
        z = result.mean_z
    provenance = dict(
        target=target,
        objective=obj.name,
        objective_settings={k: v for k, v in obj.describe().items() if k != "trial_config"},
        world=kind,
        robot=target_robot,
        seed=seed,
        evaluations=result.evaluations,
        episodes_per_evaluation=obj.episodes,
        pick=pick,
        best_score=score,
        best_generation=generation,
        parameters=tgt.space.describe(z),
    )
    tgt.write(z, out, provenance)
    run = ImproveRun(tgt, obj, result, out, z=z, search_wall_s=search_wall_s, stand_window=placed)
    if validation_episodes:
        improved = tgt.spec(z, label=f"{tgt.label} (improved)")
        start = time.perf_counter()
        run.validation = validate(
            [*refs, tgt.baseline(), improved],
            obj,
            seed=seed,
            episodes=validation_episodes,
            executor=executor,
            search_episodes=result.search_episodes(obj.episodes),
            trace_label=improved.label,
            progress=on_validation,
        )
        run.validation_wall_s = time.perf_counter() - start
        run.files = write_summary(run.validation.summary, out.with_name(out.stem + "_validation"))
        scores = dict(
            zip(
                run.validation.summary["variant"].to_list(),
                run.validation.summary["score"].to_list(),
            )
        )
        run.start_score = scores.get(tgt.baseline().label)
        run.improved_score = scores.get(improved.label)
        if run.validated_worse and not keep_worse:
            start_z = np.zeros(tgt.space.dim)
            tgt.write(
                start_z,
                out,
                {
                    **provenance,
                    "kept_start": True,
                    "parameters": tgt.space.describe(start_z),
                    "validation_scores": {"start": run.start_score, "improved": run.improved_score},
                },
            )
            run.z, run.kept_start = start_z, True
    return run


def _auto_window(target: str, text: str, obj, seed: int, robot: str) -> StandWindow:
    """``--window auto``: the stand window of the get-up copy ``target`` (a learned one-shot
    model), played in ``obj``'s trial on the search's first episodes."""
    if text != AUTO:
        raise MimicError(f"--window takes START,END in seconds or auto; got {text!r}")
    if obj.name != "getup":
        raise MimicError(
            f"--window auto places a get-up's stand window; it needs --objective getup, "
            f"not {obj.name}"
        )
    spec = agent_spec(target, robot=robot)
    if spec.kind != "model" or spec.balance:
        raise MimicError(f"--window corrects a learned model (.mimic), not {target!r}")
    model = load_model(spec.ref)
    if model.cyclic:
        raise MimicError(f"--window auto: {target} is cyclic; a stand window is a get-up's")
    return stand_window(spec, model.duration_s, obj.trial_config, seed=seed, runs=obj.episodes)
