"""What ``mimic improve`` maximises: a score from trial episodes (the trials' own scenes, seeds
and statistics), for kicks and for walks.

* ``kick``: kick distance and accuracy: the mean over kicks of distance x success [m] (a kick
  succeeds when the ball travels more than the trial's ``success_distance_m``, the study's 2 m
  unless set; 0 scores plain distance), minus ``fall_penalty_m`` per
  fall per kick. The search plays kick-trial episodes (walk to the ball, line up, kick, until a
  goal) cut at ``search_limit_s`` of simulated time to spend the budget on kicks.
* ``walk``: walk speed over the walk trial's 15 m [m/s], minus ``fall_penalty_m_s`` times the
  share of runs that fell, minus ``drift_penalty_per_m`` per metre of sideways error beyond
  ``drift_tolerance_m`` (mean over runs).
* ``getup``: the share of get-up trial runs that stood up, less ``time_weight_per_s`` per
  second they took (mean over runs; a run that stays down counts the trial's whole
  ``timeout_s``, plus ``height_credit_per_m`` per metre its torso rose at its highest).

Validation plays the trials unchanged (``trial_config``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace

import numpy as np

from mimic.errors import MimicError
from mimic.trials.getup import GetupTrialConfig, run_getup_episode
from mimic.trials.kick import KickTrialConfig, run_kick_episode
from mimic.trials.parallel import EpisodeBatch
from mimic.trials.report import getup_summary, kick_summary, walk_summary
from mimic.trials.walk import WalkTrialConfig, run_walk_episode

__all__ = ["KickObjective", "WalkObjective", "GetupObjective", "make_objective", "OBJECTIVES"]


@dataclass(frozen=True)
class KickObjective:
    """Kick distance and accuracy (module docstring)."""

    # Trial episodes per candidate evaluation.
    episodes: int = 2
    # Simulated time of one search episode [s] (the trial's episodes run up to 240 s).
    search_limit_s: float = 60.0
    # Score lost per fall per kick [m].
    fall_penalty_m: float = 2.0
    # The kick trial's settings (validation runs them unchanged).
    trial_config: KickTrialConfig = KickTrialConfig()

    name = "kick"
    episode_fn = staticmethod(run_kick_episode)
    summarise = staticmethod(kick_summary)

    @property
    def search_config(self) -> KickTrialConfig:
        return replace(self.trial_config, episode_limit_s=self.search_limit_s)

    def score(self, batch: EpisodeBatch) -> float:
        """Mean distance x success [m] over the batch's kicks, minus the fall penalty."""
        falls = sum(e["falls"] for e in batch.episodes)
        kicks = len(batch.rows)
        if kicks == 0:
            return -self.fall_penalty_m * (1 + falls)
        success_m = self.trial_config.success_distance_m
        useful = np.mean([r["distance_m"] * (r["distance_m"] > success_m) for r in batch.rows])
        return float(useful - self.fall_penalty_m * falls / kicks)

    def describe(self) -> dict:
        return dict(
            name=self.name,
            episodes=self.episodes,
            search_limit_s=self.search_limit_s,
            fall_penalty_m=self.fall_penalty_m,
            success_distance_m=self.trial_config.success_distance_m,
            trial_config=asdict(self.trial_config),
        )


@dataclass(frozen=True)
class WalkObjective:
    """Walk speed with penalties for falls and drift (module docstring)."""

    # Walk-trial runs per candidate evaluation.
    episodes: int = 4
    # Score lost per share of runs that fell [m/s] (one fall in 4 runs: -0.25 m/s).
    fall_penalty_m_s: float = 1.0
    # Sideways error allowed without penalty [m], and the penalty beyond it [m/s per m].
    drift_tolerance_m: float = 0.3
    drift_penalty_per_m: float = 0.5
    # The walk trial's settings.
    trial_config: WalkTrialConfig = WalkTrialConfig()

    name = "walk"
    episode_fn = staticmethod(run_walk_episode)
    summarise = staticmethod(walk_summary)

    @property
    def search_config(self) -> WalkTrialConfig:
        return self.trial_config

    def score(self, batch: EpisodeBatch) -> float:
        """Mean speed [m/s] minus the fall and drift penalties."""
        runs = batch.rows
        speed = np.mean([r["speed_m_s"] for r in runs])
        fell = np.mean([r["fell"] for r in runs])
        drift = np.mean([max(0.0, r["y_error_m"] - self.drift_tolerance_m) for r in runs])
        return float(speed - self.fall_penalty_m_s * fell - self.drift_penalty_per_m * drift)

    def describe(self) -> dict:
        return dict(
            name=self.name,
            episodes=self.episodes,
            fall_penalty_m_s=self.fall_penalty_m_s,
            drift_tolerance_m=self.drift_tolerance_m,
            drift_penalty_per_m=self.drift_penalty_per_m,
            trial_config=asdict(self.trial_config),
        )


@dataclass(frozen=True)
class GetupObjective:
    """Get-up success, then speed (module docstring)."""

    # Get-up trial runs per candidate evaluation.
    episodes: int = 4
    # Score lost per second to stand [1/s] (a 6 s get-up that stands: 1 - 0.06 = 0.94).
    time_weight_per_s: float = 0.01
    # A run that stays down: credit per metre its torso rose at its highest [1/m] (a search
    # that starts where nothing stands up gets a slope to climb; a T1 kneeling 0.35 m up
    # earns 0.17, less than any run that stands).
    height_credit_per_m: float = 0.5
    # The get-up trial's settings.
    trial_config: GetupTrialConfig = GetupTrialConfig()

    name = "getup"
    episode_fn = staticmethod(run_getup_episode)
    summarise = staticmethod(getup_summary)

    @property
    def search_config(self) -> GetupTrialConfig:
        return self.trial_config

    def score(self, batch: EpisodeBatch) -> float:
        """Share of runs that stood, less the time weight per second they took; a run that
        stayed down: the whole time, plus the height credit."""
        w, limit, credit = (
            self.time_weight_per_s,
            self.trial_config.timeout_s,
            self.height_credit_per_m,
        )
        return float(
            np.mean(
                [
                    (1.0 - w * r["time_to_stand_s"])
                    if r["stood"]
                    else -w * limit + credit * r.get("max_torso_height_m", 0.0)
                    for r in batch.rows
                ]
            )
        )

    def describe(self) -> dict:
        return dict(
            name=self.name,
            episodes=self.episodes,
            time_weight_per_s=self.time_weight_per_s,
            height_credit_per_m=self.height_credit_per_m,
            trial_config=asdict(self.trial_config),
        )


OBJECTIVES = {"kick": KickObjective, "walk": WalkObjective, "getup": GetupObjective}


def make_objective(name: str, episodes: int | None = None, **settings):
    """The objective ``kick`` or ``walk`` with ``episodes`` per evaluation (default: its own).

    Raises:
        MimicError: unknown name, episodes < 1.
    """
    if name not in OBJECTIVES:
        raise MimicError(f"unknown objective {name!r}; objectives: {', '.join(OBJECTIVES)}")
    if episodes is not None:
        if episodes < 1:
            raise MimicError(f"--episodes must be >= 1, got {episodes}")
        settings["episodes"] = episodes
    return OBJECTIVES[name](**settings)
