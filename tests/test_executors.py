"""Where episodes run: budgets never overshot, one pool for every variant, workers capped at
the cores, and the same results in one process, a process pool and Ray."""

import dataclasses
import math
import multiprocessing
import os
import time

import numpy as np
import pytest

from mimic.agents.registry import AgentSpec
from mimic.errors import MimicError
from mimic.tasks.walk import WalkTrialConfig
from mimic.trials import api
from mimic.trials.executors import (
    InlineExecutor,
    PoolExecutor,
    available_cores,
    make_executor,
    resolve_workers,
)
from mimic.trials.parallel import run_episodes


def fake_episode(spec, seed, config):
    """An episode without a simulator: 10..59 s long, one row (module level: picklable)."""
    duration = 10.0 + seed % 50
    return [dict(seed=seed, value=seed % 7)], dict(duration_s=duration, seed=seed)


def _run(executor, budget_s=200.0):
    return run_episodes(fake_episode, None, None, budget_s=budget_s, seed=3, executor=executor)


def test_budget_is_never_overshot_and_the_cut_is_the_same_in_a_pool():
    inline = _run(InlineExecutor())
    assert inline.simulated_s <= 200.0
    # The next episode in index order would have ended past the budget.
    nxt = fake_episode(None, _seed(3, len(inline.episodes)), None)[1]["duration_s"]
    assert inline.simulated_s + nxt > 200.0
    with PoolExecutor(2) as pool:
        pooled = _run(pool)
        again = _run(pool)  # the same pool serves the next variant
    assert pooled.rows == inline.rows == again.rows
    assert [e["episode"] for e in pooled.episodes] == list(range(len(inline.episodes)))


def _seed(seed, i):
    from mimic.trials.parallel import derive_seed

    return derive_seed(seed, i)


@dataclasses.dataclass(frozen=True)
class _Limited:
    """A config with an episode time limit, as a kick trial's."""

    episode_limit_s: float = 60.0
    trace: bool = False


def limited_episode(spec, seed, config, given=[]):  # noqa: B006 (records every call)
    """``fake_episode`` cut at the config's limit; ``given`` collects the limits it got."""
    rows, summary = fake_episode(spec, seed, config)
    given.append((config.episode_limit_s, summary["duration_s"]))
    summary["duration_s"] = min(summary["duration_s"], config.episode_limit_s)
    return rows, summary


def test_an_episode_that_cannot_count_stops_where_the_budget_ends():
    given = limited_episode.__defaults__[0]
    given.clear()
    batch = run_episodes(
        limited_episode, None, _Limited(), budget_s=190.0, seed=3, executor=InlineExecutor()
    )
    # The same episodes count as without a cap (every fake episode is shorter than 60 s).
    assert batch.rows == _run(InlineExecutor(), budget_s=190.0).rows
    # The first runs to its own limit; each later one gets what the budget had left when it
    # started plus one cycle, so the one that would end past the budget stops there.
    durations = [d for _, d in given]
    assert given[0][0] == 60.0
    for i, (limit, _) in enumerate(given[1:], start=1):
        assert limit == pytest.approx(min(60.0, 190.0 - sum(durations[:i]) + 0.02))
    dropped_limit, dropped_natural_s = given[-1]
    assert len(given) == len(batch.episodes) + 1
    assert dropped_limit < dropped_natural_s


def test_the_first_episode_counts_even_past_a_tiny_budget():
    batch = _run(InlineExecutor(), budget_s=1.0)
    assert len(batch.episodes) == 1


def checkpointed_episode(spec, seed, config):
    """``fake_episode`` with a row every 7 s of it, each a checkpoint (as a kick episode's
    kicks): had it ended there, those rows and that duration. Plays to its config's limit
    only, as a kick episode does."""
    natural_s = 10.0 + seed % 50
    duration_s = min(natural_s, config.episode_limit_s)
    ends = [t for t in np.arange(7.0, natural_s + 1e-9, 7.0) if t <= duration_s]
    rows = [dict(seed=seed, at_s=float(t)) for t in ends]
    checkpoints = [
        (float(t), rows[: k + 1], dict(duration_s=float(t), seed=seed, cut=True))
        for k, t in enumerate(ends)
    ]
    summary = dict(duration_s=duration_s, seed=seed, cut=False, checkpoints=checkpoints)
    return rows, summary


def test_the_episode_that_reaches_the_budget_counts_to_its_end_as_of_its_last_checkpoint():
    """Whole episodes while they fit; the one that would end past the budget counts to the
    budget's end, with its rows and summary as of its last checkpoint within it, and ends
    the trial: the same in a pool (where it may play on past its cap before the ones before
    it end) as in one process."""

    def trial(executor, budget_s=190.0):
        return run_episodes(
            checkpointed_episode, None, _Limited(), budget_s=budget_s, seed=3, executor=executor
        )

    inline = trial(InlineExecutor())
    whole = [e for e in inline.episodes if not e["cut"]]
    (cut,) = [e for e in inline.episodes if e["cut"]]
    assert inline.episodes[-1] is cut and "checkpoints" not in cut
    # The cut episode: its own seed, its first rows, its last checkpoint within the budget.
    left_s = 190.0 - sum(e["duration_s"] for e in whole)
    natural_s = 10.0 + cut["seed"] % 50
    assert whole and 7.0 <= left_s < natural_s
    assert cut["duration_s"] == pytest.approx(left_s) and inline.simulated_s == pytest.approx(190.0)
    counted = [r for r in inline.rows if r["seed"] == cut["seed"]]
    assert [r["at_s"] for r in counted] == list(np.arange(7.0, left_s + 1e-9, 7.0))
    with PoolExecutor(2) as pool:
        pooled = trial(pool)
    assert pooled.rows == inline.rows and pooled.episodes == inline.episodes
    # Nothing of it within the budget: the first episode counts whole, a later one not.
    first = trial(InlineExecutor(), budget_s=3.0)
    assert [e["cut"] for e in first.episodes] == [False]


def test_workers_are_capped_at_the_cores_with_one_line():
    cores = available_cores()
    assert resolve_workers(None) == (cores, None)
    n, note = resolve_workers(cores + 14)
    assert n == cores and note == (
        f"using {cores} workers: {cores + 14} asked, {cores} cores available"
    )
    with pytest.raises(MimicError, match="--workers must be >= 1"):
        resolve_workers(0)
    with make_executor(cores + 14) as ex:
        assert ex.workers == min(cores, cores + 14)


def test_one_executor_serves_every_variant(monkeypatch):
    made = []
    real = api.make_executor

    def counting(workers=None, ray=None):
        made.append(workers)
        return real(workers, ray)

    monkeypatch.setattr(api, "make_executor", counting)
    walk = AgentSpec("behaviour", "walk")
    result = api.walk_trial([walk, walk], runs=1, workers=1, config=WalkTrialConfig(timeout_s=1.0))
    assert made == [1] and result.rows.height == 2


def test_map_returns_results_in_order():
    with InlineExecutor() as ex:
        assert ex.map(abs, [-3, 2, -1]) == [3, 2, 1]


@pytest.fixture(scope="module")
def local_ray():
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield ray
    ray.shutdown()


@pytest.mark.slow  # starting Ray takes 10-15 s on 2 cores
def test_ray_gives_the_results_of_the_process_pool(local_ray, tmp_path):
    from typer.testing import CliRunner

    from mimic.cli.main import app
    from mimic.improve import improve
    from mimic.tasks.walk import WalkObjective

    with make_executor(ray="local") as ray_ex, PoolExecutor(2) as pool:
        assert ray_ex.workers == 2
        walk, short = AgentSpec("behaviour", "walk"), WalkTrialConfig(timeout_s=2.0)
        trials = [
            api.walk_trial([walk], minutes=0.3, seed=5, config=short, executor=ex)
            for ex in (ray_ex, pool)
        ]
        assert trials[0].rows.equals(trials[1].rows) and trials[0].rows.height >= 5
        tiny = WalkObjective(episodes=1, trial_config=WalkTrialConfig(timeout_s=3.0))
        runs = [
            improve(
                "other-team-walk",
                objective=tiny,
                budget=8,
                population=4,
                out=tmp_path / f"{name}.json",
                executor=ex,
            )
            for name, ex in (("ray", ray_ex), ("pool", pool))
        ]
    (z_ray, s_ray, _), (z_pool, s_pool, _) = (r.search.best for r in runs)
    assert np.array_equal(z_ray, z_pool) and s_ray == s_pool
    assert (tmp_path / "ray.json").read_text() == (tmp_path / "pool.json").read_text()
    # The trial command on the Ray started above.
    result = CliRunner().invoke(app, ["trial", "walk", "--runs", "2", "--ray"])
    assert result.exit_code == 0, result.output


@dataclasses.dataclass(frozen=True)
class _Logged:
    """A kick-trial-like config whose episodes note the caps they read in ``log_dir``."""

    log_dir: str = ""
    episode_limit_s: float = 240.0
    trace: bool = False


#: Natural durations of the episodes of ``capped_episode`` by index [s].
_DURATIONS_S = (50.0, 60.0, 40.0, 60.0, 60.0)


def capped_episode(spec, seed, config):
    """An episode that plays its natural length unless its live cap falls below it first:
    it reads the cap as a kick trial's episode does at each decision (here every 10 ms of
    wall time, for at most 20 s), and stops at the cap if it falls short. On two workers
    episode 1 plays in the spawned process, 2 in this one and 3 after 1 in the spawned one;
    1 takes a second, and 2 ends only once 3 has read its cap (a file says so), so 3 starts
    before the ones before it have all ended, whatever the machine's speed. Its index comes
    from its seed (trial seed 3); what it read goes to ``config.log_dir``."""
    from pathlib import Path

    from mimic.tasks.budget import episode_cap_s

    index = next(i for i in range(len(_DURATIONS_S)) if _seed(3, i) == seed)
    natural_s = min(_DURATIONS_S[index], config.episode_limit_s)
    started = Path(config.log_dir, "3.started")
    if index == 1:
        time.sleep(1.0)
    first_s = cap_s = episode_cap_s()
    if index == 2 and math.isfinite(first_s):  # a live cap: another worker plays episode 3
        for _ in range(2000):
            if started.exists():
                break
            time.sleep(0.01)
    if index == 3:
        started.write_text("")
        for _ in range(2000):
            if cap_s < natural_s:
                break
            time.sleep(0.01)
            cap_s = episode_cap_s()
    Path(config.log_dir, str(index)).write_text(f"{first_s} {cap_s}")
    return [dict(index=index)], dict(duration_s=min(natural_s, cap_s))


def test_an_episode_started_early_stops_once_those_before_it_fill_the_budget(tmp_path):
    """Two workers: episode 3 starts while episode 2 still plays, with only an upper bound of
    what the budget leaves it (200 - 50 s). Once episodes 1 and 2 have ended (60 + 40 s) its
    cap falls to what is left plus a cycle, it stops there, past the budget, and does not
    count: the same episodes count as on one worker."""

    def trial(name, executor):
        (tmp_path / name).mkdir()
        config = _Logged(str(tmp_path / name))
        return run_episodes(capped_episode, None, config, budget_s=200.0, seed=3, executor=executor)

    with PoolExecutor(2) as pool:
        pooled = trial("pool", pool)
    first_s, last_s = map(float, (tmp_path / "pool" / "3").read_text().split())
    assert first_s == pytest.approx(200.0 - 50.0 + 0.02)
    assert last_s == pytest.approx(200.0 - 50.0 - 60.0 - 40.0 + 0.02)
    inline = trial("one", InlineExecutor())
    assert [r["index"] for r in pooled.rows] == [r["index"] for r in inline.rows] == [0, 1, 2]
    # On one worker every episode starts knowing what is left (its config's limit): no
    # live cap.
    assert (tmp_path / "one" / "3").read_text().split() == ["inf", "inf"]


def reporting_episode(spec, seed, config):
    """``capped_episode``'s order of play on two workers (1 and then 3 in the spawned process,
    2 in this one), with episode 2 saying at each read of its cap that it has played 30 s,
    until episode 3 has seen its own cap fall by that; episode 3 notes that cap."""
    from pathlib import Path

    from mimic.tasks.budget import episode_cap_s

    index = next(i for i in range(len(_DURATIONS_S)) if _seed(3, i) == seed)
    log = Path(config.log_dir)
    if index == 1:
        time.sleep(1.0)
    if index == 2:
        for _ in range(2000):
            episode_cap_s(30.0)  # this process lowers the caps as it reads its own
            if (log / "3").exists():
                break
            time.sleep(0.01)
    if index == 3:  # until its cap is below what episodes 0 and 1 alone leave (90 s)
        for _ in range(2000):
            cap_s = episode_cap_s()
            if cap_s < 200.0 - 50.0 - 60.0:
                break
            time.sleep(0.01)
        (log / "3").write_text(repr(cap_s))
    return [dict(index=index)], dict(duration_s=_DURATIONS_S[index])


def test_an_episode_s_cap_falls_by_how_far_those_before_it_have_played(tmp_path):
    """Two workers: episode 3 starts once 0 and 1 have ended (50 + 60 s), with 2 still
    playing; its cap falls by the 30 s episode 2 says it has played (2 will take at least
    that), before 2 ends."""
    with PoolExecutor(2) as pool:
        run_episodes(
            reporting_episode, None, _Logged(str(tmp_path)), budget_s=200.0, seed=3, executor=pool
        )
    assert float((tmp_path / "3").read_text()) == pytest.approx(200.0 - 50.0 - 60.0 - 30.0 + 0.02)


def dies(_):
    """A call whose worker process dies at once (killed, out of memory); in this process
    (a pool runs some calls here) it returns."""
    if multiprocessing.parent_process() is not None:
        os._exit(1)


def test_a_worker_that_dies_is_one_clear_error():
    with PoolExecutor(2) as pool:
        pool.submit(fake_episode, None)  # the first call runs in this process
        handle = pool.submit(dies, None)
        with pytest.raises(MimicError, match="a worker process stopped unexpectedly"):
            pool.result(handle)
    with PoolExecutor(2) as pool, pytest.raises(MimicError, match="--workers 1"):
        pool.map(dies, [None, None, None])
