"""A learned walk's references fitted in a simulation of the copy, until its joints follow the
recording (``mimic train --fit-in-sim ROUNDS``).

A copy of a PD-motor robot's walk learns references reconstructed from the angles it reached
(``learn.pd_compensate``). Those are biased: on the T1 other team's walk, where the true
references are known, they miss them by 0.035-0.04 rad rms, the hip pitch's swing 6 % too
small. The copy then walks short, and a speed hold buys the difference with cadence, up to the
cadence where the copy falls (``docs/real-team-walk.md``). What the copy *reaches* can be seen
where it plays, so the references are corrected there, as iterative learning control does:

1. The copy walks in a simulated world (the league-like one for league robots), inside the
   balance layer, holding the recording's speed by its phase rate, as copies are played.
   After its start-up every cycle's reached angles are logged by phase.
2. Binned over the cycle (``phase_bins``), the reached angles' median is compared with the
   recording's at the same phase; the error, made left-right symmetric for a symmetric copy
   and smoothed over the neighbouring bins, is the next step of the correction, times
   ``gain`` and divided by the joint's *sensitivity*.
3. The sensitivity is the share of a step that the joint's reached angle followed, seen from
   the last step (the error's change along the correction's change), within
   ``SENSITIVITY_RANGE``. Inside the balance layer it is far from 1 for some joints: its
   torso feedback turns the support hip against a change of the torso's pitch, and the hip
   pitch followed a quarter to a half of its correction. On the T1 stand-in its swing, 18 %
   short of the recording's, closed by a quarter in 4 rounds of the plain step, and wholly
   in 8 divided by the sensitivity.
4. A round whose walk fell (sooner than the kept one, if that fell too) is undone and the
   gain halved. A joint whose error the round made larger gets its correction back and half
   its gain (light joints that the walk swings, like the head, answer a correction late and
   would drift off). The samples of the last ``fall_margin_s`` before a fall are left out of
   every comparison.

After ``rounds`` rounds the correction of the round that came closest to the recording
without falling is kept (if every round fell, the one that walked farthest):
``SimFit.at_phase`` gives it at any phase, and ``fitted_dataset`` adds it to the training
targets, so the network is trained again on them and stays an ordinary model (ONNX export,
``mimic improve``). ``check_fit`` then walks that network and the copy as learned from starts
the fit never walked; the fitted copy is kept only if it fell no more often and walked no
slower (``mimic train --fit-in-sim`` writes the other one otherwise, and says so). On the
T1's regular walk a fitted copy that walked its fit's start fell from 5 of 6 others, where
the copy as learned walked all 6, and in 16 of 20 league runs.

It corrects the mean cycle only: what the recording's walk did differently from step to step
stays out of the copy, as it does in the step-phase copy itself.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields, replace

import numpy as np

from mimic.agents.balance import BalancedAgent
from mimic.agents.base import Agent, JointCommand
from mimic.agents.neural_player import NeuralPlayer
from mimic.errors import MimicError
from mimic.learn.dataset import Dataset
from mimic.model.keys import SIM_FIT_KEY
from mimic.model.motion_model import MotionModel
from mimic.robot.registry import get_robot
from mimic.tasks.walk import WalkTrialConfig, run_walk_episode
from mimic.world.base import Observation
from mimic.world.registry import get_world

__all__ = [
    "SimFitConfig",
    "SimFitRound",
    "SimFit",
    "FitCheck",
    "check_fit",
    "fit_in_simulation",
    "fitted_dataset",
    "sim_fit_world",
]

#: The shares of a correction a joint is taken to follow, at least and at most: a step is
#: at most four times the gain's.
SENSITIVITY_RANGE = (0.25, 1.0)
#: A correction step smaller than this (rms over the cycle) says nothing of a joint's
#: sensitivity [rad].
_TOLD_RMS_RAD = 1.4e-3


@dataclass(frozen=True)
class SimFitConfig:
    """How a walk's references are fitted in simulation (module docstring)."""

    # Rounds of correction (each one walk in the simulated world, and one more to check the
    # last).
    rounds: int = 6
    # Share of the reached angles' error added to the correction each round. 0.7 overshot
    # on the first round (the T1 stand-in fell); 0.3 converged in 4-6.
    gain: float = 0.3
    # Bins the cycle is cut into to compare reached and recorded angles (at 25 Hz a
    # 0.75 s cycle holds 19 samples a cycle, about 30 cycles a walk: 10 samples a bin).
    phase_bins: int = 50
    # Weights of the circular smoothing over neighbouring bins (centred, sum 1).
    smoothing: tuple[float, ...] = (0.1, 0.2, 0.4, 0.2, 0.1)
    # Samples this long before a fall are not compared [s] (the fall is not the walk).
    fall_margin_s: float = 1.0
    # The episode seed of every round (the start pose's noise): one start for all, so that
    # two rounds differ by their corrections alone (the simulated worlds are deterministic).
    seed: int = 0
    # Walk inside the balance layer (``agents.balance``), as copies are played in trials.
    balance: bool = True
    # Hold the recording's speed by the phase rate, as copies are played: fitted at the
    # learned rate, a copy walked there, then fell once the hold raised its rate.
    speed_hold: bool = True
    # Check walks (``check_fit``), from the starts of episode seeds ``seed + 1`` on: starts
    # the fit never walked. A copy at the edge of what it can walk may walk its fit's start
    # and fall from others, and the network trained on the fitted references is not the
    # table the fit played.
    check_walks: int = 3

    def __post_init__(self) -> None:
        if self.rounds < 1:
            raise MimicError(f"fitting in simulation needs 1 round at least, got {self.rounds}")
        if self.check_walks < 1:
            raise MimicError(f"a fit is checked by 1 walk at least, got {self.check_walks}")
        if not 0 < self.gain <= 1:
            raise MimicError(f"the fit's gain must lie in (0, 1], got {self.gain}")


@dataclass(frozen=True)
class SimFitRound:
    """One walk of the fit: the correction it played, what it reached.

    Attributes:
        index: 0 for the copy as learned, k after k corrections.
        rms_rad: the reached angles' rms error against the recording's, over the bins [rad];
            NaN for a walk that fell before its start-up ended.
        speed_m_s: the walk's forward speed [m/s].
        fell: the walk fell.
        distance_m: how far it walked (to where it fell, if it fell) [m].
    """

    index: int
    rms_rad: float
    speed_m_s: float
    fell: bool
    distance_m: float


@dataclass(frozen=True)
class SimFit:
    """The correction found, per phase bin, and how the rounds went.

    Attributes:
        correction_rad: (B, N) added to the references at the centres of B bins of the cycle
            [rad], the model's joint order.
        rounds: every round played, in order.
        kept: the round whose correction is ``correction_rad``: the one that came closest to
            the recording without falling.
        world: where the copy walked.
    """

    correction_rad: np.ndarray
    rounds: tuple[SimFitRound, ...]
    kept: int
    world: str

    def at_phase(self, phase: np.ndarray) -> np.ndarray:
        """(T, N) the correction at phases (T,) in cycles (any real; taken modulo 1) [rad],
        interpolated linearly around the cycle between bin centres."""
        return _periodic_interp(self.correction_rad, np.asarray(phase, float))

    @property
    def first(self) -> SimFitRound:
        return self.rounds[0]

    @property
    def best(self) -> SimFitRound:
        return self.rounds[self.kept]

    def summary(self) -> dict:
        """JSON-able facts for the model's metadata (``SIM_FIT_KEY``)."""
        return {
            "world": self.world,
            "rounds": len(self.rounds) - 1,
            "kept_round": self.kept,
            "rms_rad": [round(self.first.rms_rad, 4), round(self.best.rms_rad, 4)],
            "speed_m_s": [round(self.first.speed_m_s, 4), round(self.best.speed_m_s, 4)],
            "fell": [self.first.fell, self.best.fell],
            "largest_correction_rad": round(float(np.abs(self.correction_rad).max()), 4),
        }

    def describe(self) -> str:
        """One line: what the fit changed."""
        n = len(self.rounds) - 1
        return (
            f"fitted in the {self.world} world, {n} round{'s' if n != 1 else ''} (kept "
            f"{self.kept}): joints {self.first.rms_rad:.3f} -> {self.best.rms_rad:.3f} rad rms "
            f"from the recording; walked {self.first.speed_m_s:.3f} -> "
            f"{self.best.speed_m_s:.3f} m/s"
            + (
                f"; it still fell, after {self.first.distance_m:.1f} -> "
                f"{self.best.distance_m:.1f} m"
                if self.best.fell
                else ""
            )
        )


def sim_fit_world(recorded: Dataset) -> str:
    """The simulated world a recording's copy is fitted in: the twin of the world it was
    recorded in (``WorldSpec.twin``: the league-like one, ``world.league_like``, for a walk
    recorded in the league, ours for one recorded in ours). A recording that does not say
    where it was made goes by its robot's world."""
    where = recorded.metadata.get("recording_world")
    if where is None:
        where = get_robot(recorded.robot).world
    return get_world(where).twin


def fit_in_simulation(
    model: MotionModel,
    recorded: Dataset,
    config: SimFitConfig = SimFitConfig(),
    *,
    world: str | None = None,
    progress: Callable[[SimFitRound], None] | None = None,
) -> SimFit:
    """The correction that makes ``model``'s walk reach the angles of ``recorded``.

    Args:
        model: a cyclic model (a walk) learned from the recording.
        recorded: the recording's reached angles as a cyclic dataset of the model's period
            (``training_dataset(..., target="reached")`` with the model's ``--period``).
        world: where the copy walks (default: ``sim_fit_world``).
        progress: called after every round.

    Raises:
        MimicError: the model is not cyclic, or the recording's cycle is not the model's.
    """
    if not model.cyclic:
        raise MimicError(
            f"{model.name}: fitting in simulation corrects a walk (a cyclic model, --period); "
            "this one is a one-shot motion"
        )
    if recorded.period_s is None or not math.isclose(
        recorded.period_s, model.period_s, rel_tol=1e-6
    ):
        raise MimicError(
            f"{model.name}: the recording's cycle ({recorded.period_s} s) is not the model's "
            f"({model.period_s:.4f} s); learn both with the same --period"
        )
    if tuple(recorded.joint_names) != tuple(model.joint_names):
        raise MimicError(f"{model.name}: the recording's joints are not the model's")
    world = world or sim_fit_world(recorded)
    bins = config.phase_bins
    robot = get_robot(model.robot)
    symmetric = bool(recorded.metadata.get("symmetric"))
    target = _binned(_phase(recorded.time_s, model.period_s), recorded.angles_rad, bins)
    correction = np.zeros((bins, model.num_joints))
    gains = np.full(model.num_joints, config.gain)
    # How much of a change of its correction each joint's reached angle follows (module
    # docstring); 1 until a step has been seen.
    sensitivity = np.ones(model.num_joints)
    kept: _Kept | None = None
    step = np.zeros_like(correction)
    rounds: list[SimFitRound] = []
    played: list[np.ndarray] = []  # the correction each round walked
    for index in range(config.rounds + 1):
        played.append(correction)
        walked = _walk(model, correction, world, config, config.seed)
        seen = len(walked.phase) > 0  # the walk got past its start-up
        if not seen and index == 0:
            raise MimicError(
                f"{model.name} fell before its start-up ended in the {world} world: there is "
                "no walk to fit (try it with mimic play, or learn it without --fit-in-sim)"
            )
        fell = walked.fell or not seen
        error = target - _binned(walked.phase, walked.angles_rad, bins) if seen else None
        rms = float(np.sqrt(np.nanmean(error**2))) if seen else math.nan
        rounds.append(SimFitRound(index, rms, walked.speed_m_s, fell, walked.distance_m))
        sooner = fell and not (
            kept is not None and kept.fell and walked.distance_m > kept.distance_m
        )
        if kept is not None and (sooner or not seen):
            # The step made the copy fall (sooner than the kept correction did, if that fell
            # too): undone, and taken again smaller.
            gains *= 0.5
        else:
            joint_rms = np.sqrt(np.nanmean(error**2, axis=0))
            if kept is not None:
                sensitivity = _sensitivity(
                    correction - kept.correction, error - kept.error, sensitivity
                )
                if symmetric:  # a joint and its mirror image answer alike
                    sensitivity = 0.5 * (sensitivity + sensitivity[robot.mirror_permutation])
                # A joint the last step moved away from the recording (a light joint that
                # the walk's motion swings, like the head, answers late) takes it back, and
                # steps at half the gain from then on.
                worse = joint_rms > kept.joint_rms
                if symmetric:  # a joint and its mirror image go back together
                    worse |= worse[robot.mirror_permutation]
                correction = np.where(worse, kept.correction, correction)
                error[:, worse], joint_rms[worse] = kept.error[:, worse], kept.joint_rms[worse]
                gains[worse] *= 0.5
            kept = _Kept(correction, error, joint_rms, fell, walked.distance_m)
            step = np.nan_to_num(error)  # a bin the walk never reached gets no correction
            if symmetric:
                step = 0.5 * (step + robot.mirror_angles(np.roll(step, -(bins // 2), axis=0)))
            step = _smooth(step, config.smoothing)
        correction = kept.correction + gains / sensitivity * step
        if progress is not None:
            progress(rounds[-1])
    # The round that came closest to the recording without falling: a step that helped one
    # joint may have cost the walk more elsewhere. If every round fell, the one that walked
    # farthest.
    walking = [r for r in rounds if not r.fell]
    if walking:
        best = min(walking, key=lambda r: r.rms_rad)
    else:
        best = max(rounds, key=lambda r: r.distance_m)
    return SimFit(played[best.index], tuple(rounds), best.index, world)


@dataclass(frozen=True)
class FitCheck:
    """The copy as learned and the copy trained on fitted references, walked from the same
    starts (``SimFitConfig.check_walks``).

    Attributes:
        seeds: the episode seeds walked.
        falls: (as learned, fitted) walks that fell.
        speed_m_s: (as learned, fitted) mean forward speed over the walks [m/s].
    """

    seeds: tuple[int, ...]
    falls: tuple[int, int]
    speed_m_s: tuple[float, float]

    @property
    def fitted_better(self) -> bool:
        """The fitted copy fell no more often and walked no slower."""
        return self.falls[1] <= self.falls[0] and self.speed_m_s[1] >= self.speed_m_s[0]

    def summary(self) -> dict:
        return {
            "seeds": list(self.seeds),
            "falls": list(self.falls),
            "speed_m_s": [round(v, 4) for v in self.speed_m_s],
            "fitted_kept": self.fitted_better,
        }

    def describe(self) -> str:
        """One line: the two copies' walks, and which one is kept."""
        n = len(self.seeds)
        kept = "the fitted copy" if self.fitted_better else "the copy as learned"
        return (
            f"check walks from {n} other starts: as learned {self.speed_m_s[0]:.3f} m/s, "
            f"fell {self.falls[0]} of {n}; fitted {self.speed_m_s[1]:.3f} m/s, fell "
            f"{self.falls[1]} of {n}: kept {kept}"
        )


def check_fit(
    learned: MotionModel,
    fitted: MotionModel,
    world: str,
    config: SimFitConfig = SimFitConfig(),
    *,
    progress: Callable[[], None] | None = None,
) -> FitCheck:
    """Walk ``learned`` and ``fitted`` (trained on ``fitted_dataset``) from the config's check
    starts in ``world``, as the fit walked (balance layer, speed hold); ``progress`` is
    called after every walk."""
    seeds = tuple(range(config.seed + 1, config.seed + 1 + config.check_walks))
    falls, speeds = [], []
    for model in (learned, fitted):
        walks = []
        for seed in seeds:
            walks.append(_walk(model, None, world, config, seed))
            if progress is not None:
                progress()
        falls.append(sum(w.fell for w in walks))
        speeds.append(float(np.mean([w.speed_m_s for w in walks])))
    return FitCheck(seeds, (falls[0], falls[1]), (speeds[0], speeds[1]))


def fitted_dataset(dataset: Dataset, fit: SimFit) -> Dataset:
    """``dataset`` (cyclic: the model's training data) with the fit's correction added to
    every sample's references at its phase; ``metadata[SIM_FIT_KEY]`` says what the fit did."""
    phase = _phase(dataset.time_s, dataset.period_s)
    targets = dataset.targets.copy()
    targets[:, : dataset.num_joints] += fit.at_phase(phase)
    return replace(
        dataset, targets=targets, metadata={**dataset.metadata, SIM_FIT_KEY: fit.summary()}
    )


@dataclass(frozen=True)
class _Walked:
    phase: np.ndarray  # (T,) the played phase of each logged cycle [cycles]
    angles_rad: np.ndarray  # (T, N) the angles reached then
    speed_m_s: float
    fell: bool
    distance_m: float


@dataclass(frozen=True)
class _Kept:
    """The correction the fit stands on, and what its walk reached."""

    correction: np.ndarray  # (B, N) [rad]
    error: np.ndarray  # (B, N) the recording's binned angles less the walk's [rad]
    joint_rms: np.ndarray  # (N,) [rad]
    fell: bool
    distance_m: float


def _walk(
    model: MotionModel,
    correction: np.ndarray | None,
    world: str,
    config: SimFitConfig,
    seed: int,
) -> _Walked:
    """One walk of the course in ``world``: the model with ``correction`` (B, N) [rad] on
    its references (None: as it is), played as ``config`` says."""
    log: list[tuple[float, float, np.ndarray]] = []
    played = model if correction is None else _CorrectedModel.of(model, correction)
    player = _LoggedPlayer(played, log, config.speed_hold)
    agent = BalancedAgent(player) if config.balance else player
    row = run_walk_episode(_Built(model.robot, agent), seed, WalkTrialConfig(world=world))[0][0]
    if row["fell"] and log:
        last_s = log[-1][0]
        log = [entry for entry in log if entry[0] < last_s - config.fall_margin_s]
    return _Walked(
        np.array([e[1] for e in log]),
        np.array([e[2] for e in log]).reshape(len(log), model.num_joints),
        float(row["speed_m_s"]),
        bool(row["fell"]),
        float(row["distance_m"]),
    )


@dataclass
class _CorrectedModel(MotionModel):
    """A cyclic model whose references get a per-phase correction on top (no retraining)."""

    correction_rad: np.ndarray | None = None

    @classmethod
    def of(cls, model: MotionModel, correction_rad: np.ndarray) -> _CorrectedModel:
        values = {f.name: getattr(model, f.name) for f in fields(MotionModel)}
        return cls(**values, correction_rad=correction_rad)

    def predict(self, time_s) -> np.ndarray:
        out = super().predict(time_s)
        scalar = out.ndim == 1
        out = np.atleast_2d(out).copy()
        phase = _phase(np.atleast_1d(np.asarray(time_s, float)), self.period_s)
        out[:, : self.num_joints] += _periodic_interp(self.correction_rad, phase)
        return out[0] if scalar else out


class _LoggedPlayer(NeuralPlayer):
    """A walk that logs (time [s], phase [cycles], reached angles [rad]) every cycle once its
    start-up is over; ``speed_hold`` off, at its learned phase rate."""

    def __init__(self, model: MotionModel, log: list, speed_hold: bool) -> None:
        super().__init__(model)
        if not speed_hold:
            self.speed_m_s = None  # the rate stays the learned one
        self._log = log

    def act(self, obs: Observation) -> JointCommand:
        command = super().act(obs)
        if self.swing_weight >= 1.0:
            angles = np.asarray(obs.joint_angles_rad, float).copy()
            self._log.append((obs.time_s, self.cycle_phase, angles))
        return command


@dataclass(frozen=True)
class _Built:
    """An agent already built, in the shape ``run_walk_episode`` takes (``AgentSpec``'s)."""

    robot: str
    agent: Agent

    def build(self) -> Agent:
        return self.agent


def _phase(time_s: np.ndarray, period_s: float) -> np.ndarray:
    return (np.asarray(time_s, float) % period_s) / period_s


def _binned(phase: np.ndarray, values: np.ndarray, bins: int) -> np.ndarray:
    """(bins, N) the median of ``values`` (T, N) in each bin of ``phase`` (T,) [cycles]; NaN
    in a bin no sample fell in."""
    index = np.floor(np.asarray(phase) * bins).astype(int) % bins
    out = np.full((bins, values.shape[1]), np.nan)
    for b in range(bins):
        if (index == b).any():
            out[b] = np.median(values[index == b], axis=0)
    return out


def _sensitivity(
    correction_step: np.ndarray, error_change: np.ndarray, previous: np.ndarray
) -> np.ndarray:
    """(N,) the share of a correction step (B, N) [rad] that each joint's reached angle
    followed, from the error's change (B, N) [rad] along it: ``-<de, dc> / <dc, dc>``, clipped
    to ``SENSITIVITY_RANGE``. ``previous`` where the step was too small to tell."""
    change = np.nan_to_num(error_change)
    moved = (correction_step**2).sum(axis=0)
    told = np.sqrt(moved / len(correction_step)) > _TOLD_RMS_RAD
    seen = -(change * correction_step).sum(axis=0) / np.where(told, moved, 1.0)
    return np.where(told, np.clip(seen, *SENSITIVITY_RANGE), previous)


def _smooth(values: np.ndarray, weights: tuple[float, ...]) -> np.ndarray:
    """(B, N) ``values`` smoothed around the cycle by the centred ``weights``."""
    half = len(weights) // 2
    return sum(w * np.roll(values, k - half, axis=0) for k, w in enumerate(weights))


def _periodic_interp(table: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """(T, N) ``table`` (B, N, values at the B bin centres) at ``phase`` (T,) [cycles],
    linear between centres, around the cycle."""
    bins = len(table)
    x = (np.asarray(phase, float) % 1.0) * bins - 0.5  # in bin-centre units
    lo = np.floor(x).astype(int)
    w = (x - lo)[:, None]
    return (1 - w) * table[lo % bins] + w * table[(lo + 1) % bins]
