"""A get-up copy's references fitted in simulation until it follows its recording
(``mimic improve COPY.mimic --objective getup --follow REC.mcap``): iterative learning
control over the part of the motion after the copy first lies face down.

Why (issue 35): the T1's back get-up copies of most recordings roll onto their front, push
up into a kneel and then tip forward as their hips rise, where the original rises with its
torso upright. Their references in the kneel are off in ways one offset per joint cannot
mend (the compensated knee pressed 0.4 rad past its stop, the hips 0.3 rad deeper, left and
right unlike): played from 7 s on with the original's leg pitch references (shifted 0.12 s)
a copy rises; with those references smoothed over 0.25 s knots, or with any of 60 constant
offsets and gains, it still tips. What the copy *reaches* can be compared with what the
recording reached, sample by sample, and the references corrected until they agree:

1. The copy plays in the get-up trial (``config``, one run per seed) and on in its hold.
   Its correction window starts ``START_AFTER_FACE_DOWN_S`` after it first faced the ground
   (forward axis z below ``FACE_DOWN_Z``, in the first seed's run as it is): the roll before
   stays as learned (a correction there broke it). From the window's start the copy plays at
   the recording's own speed (a time warp undoing the whole-motion searches' one, which
   rushed one copy's kneel 26 % faster than recorded, into a tip).
2. Each run *follows* the recording until its torso parts from the recording's (``/tf``):
   forward-axis z off by more than ``fz_tolerance`` or height by more than
   ``height_tolerance_m`` from the recording's anywhere within ``time_tolerance_s``, for
   ``diverge_s`` in a row. A round's followed time is the median over the seeds (the
   shortest held one recording's copy at a push-up that one seed missed).
3. The joints' error (the recording's angle less the reached one, mean over the seeds) over
   the followed part, ``lead_s`` on (a reference acts a cycle late and the joint lags it),
   smoothed, times ``gain``, is added to the correction's track, but only in the
   ``front_s`` before the followed time: a correction reaches forward in time, so the front
   is mended first and what already follows is left alone. After its end the copy holds
   its last pose: the mean error of the hold goes to the last knots.
4. A round that followed more than ``tolerance_s`` less than the best so far is undone and
   the gain halved.
5. The copy's last pose starts as the compensated reference of the recording's last
   ``stand_s`` (it stands still there; ``learn.train.pd_compensated_targets``), blended in
   over the copy's last ``stand_blend_s``: the whole-motion searches had moved the copies'
   knees and ankles 0.1 rad from it, and they fell back from a stand they had reached.
6. The fit runs twice from the same start: on the joints' error alone, then with the
   torso's pitch error (the recording's less the copy's, ``asin`` of the forward axis z,
   clipped to ``torso_clip_rad``) times ``torso_gain`` added to the hip pitch joints' error
   (a hip pitch turns the torso up by its axis's y). The joints alone can agree to 0.05 rad
   while the torso tips over (recording R4's copy, at its kneel) or stands leaning 0.3 rad
   forward of the recording's (R1's); but in a kneel at its balance point the hips do not
   turn the torso as assumed (R3's tips forward with 0.15 rad more or less hip pitch). The
   fit that follows further is kept; a tie (within ``tolerance_s``) goes to the torso term's.
7. Two more fits (joints alone, then with the torso term) step a shorter front
   (``short_front_s``, 1 s) and let each run mend the front before its *own* followed time
   (a knot gets the mean step of the runs whose front holds it); one is kept only if it
   follows further than every fit before it by more than ``tolerance_s``, so a copy whose
   2 s fits already follow to their recording's end keeps them, the same to the bit; and
   they are not tried at all once a 2 s fit raises the torso to standing height (the robot's
   ``upright_above_m``, the mean over the best round's runs of each one's highest): R3's
   2 s fit rose (0.67 m) and its stand search held it (9-10 of 10 at four unseen league
   seeds), while its short fit, kept for following its recording further (13.24 against
   9.82 s), stood 7-10 of 10 at four. Why
   (2026-11-28, R9 and R10, whose S1b copies never rose): their 2 s fronts reached back
   from the push out of the kneel (7.3-7.9 s) into the sit-up before it (5.0-5.8 s), whose
   large, brief errors then stepped the sit-up into failing (rounds undone, the gain halved
   to nothing), and a run that fell in the sit-up while the median went on was never mended
   there (its front lay past the median's). With the short fronts both followed to
   12.6-12.8 s, were upright in 6 of 6 league-like development runs, and with their stands
   searched stood in 5 and 6 of 6 (docs/getups.md); the eight recordings whose copies rose
   already keep their 2 s fits.

The result is an ordinary windowed model (``model.windowed.WindowedModel`` with an offset
track, knots every ``knot_s``); a stand window (``--window auto``) can go on top.

Measured (docs/getups.md, "Following the recording"; T1 ``getup_back``, recordings R1, R2,
R3, on their S1b copies, 24 rounds of 3 runs): every copy followed its recording to where
its torso tipped (7.3-8.0 s) as it was; fitted, R2's and R3's rise upright in 6 of 6
league-like development runs and R1's in 3, where no S1b copy was ever upright; in the
league at trial seeds 7000 and 8000 R2's stood 6/10 and 6/10 (8.66 s, 0.93x), R1's 2/10 and
0/10, R3's 0/10 twice (upright in 17 of 20, then fell), its last pose blended in over
0.3 s; over 1.0 s (the default since) R2's stood 9, 9, 10 and 9 of 10 at seeds 7000, 8000,
9000 and 9100, R1's 1-2, R3's and a fourth recording's (R4, which never rises) none. A stand
window search on top (``--window auto``, 91 evaluations) made R3's stand 9 of 10 twice. With
the torso term's fit beside (step 6; 2026-11-28, night) the chain's last copies (followed,
then the stand searched) stood in 6 of 6 development runs for all four recordings (R1's 1,
R4's none before) and in 9 or 10 of 10 in the league at unseen seeds 9400 and 9500, as did a
fifth recording's, fresh (10 of 10, followed alone too).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mimic.agents.neural_player import NeuralPlayer
from mimic.episode.observers import Observer
from mimic.errors import MimicError
from mimic.geometry import forward_axis_z
from mimic.improve.correction import WINDOW_RAMP_S, WindowedModel, windowed_model
from mimic.learn.dataset import dataset_from_file
from mimic.learn.train import pd_compensated_targets, recorded_torso
from mimic.model.keys import CORRECTION_KEY
from mimic.model.motion_model import MotionModel
from mimic.robot.registry import get_robot
from mimic.tasks.getup import GetupTrialConfig, play_getup
from mimic.trials.parallel import derive_seed
from mimic.world.base import CYCLE_S
from mimic.world.registry import open_world

__all__ = ["FollowConfig", "FollowRound", "FollowResult", "follow_recording"]

#: The copy has rolled onto its front once its torso's forward axis z is below this.
FACE_DOWN_Z = -0.9
#: The correction window starts this long after the copy first faced the ground [s].
START_AFTER_FACE_DOWN_S = 0.2


@dataclass(frozen=True)
class FollowConfig:
    """How the references are fitted (module docstring)."""

    rounds: int = 12
    # Runs per round (trial seeds ``derive_seed(seed, 0..runs-1)``).
    runs: int = 3
    seed: int = 0
    gain: float = 0.6
    lead_s: float = 0.06
    front_s: float = 2.0
    knot_s: float = 0.04
    fz_tolerance: float = 0.3
    height_tolerance_m: float = 0.08
    diverge_s: float = 0.3
    time_tolerance_s: float = 0.2
    # The recording's last ``stand_s`` [s] are its stand (0: off): the copy's last pose
    # starts as their compensated reference (mean), blended in over ``stand_blend_s`` [s]
    # before its end (over 0.3 s the copies fell back from the stand more often).
    stand_s: float = 1.0
    stand_blend_s: float = 1.0
    tolerance_s: float = 0.04
    # Window start [s of the copy's motion]; None: after the copy first faced the ground.
    start_s: float | None = None
    # The torso's pitch error (the recording's less the copy's, asin of the forward axis z,
    # clipped to ``torso_clip_rad``) times this is added to the hip pitch joints' error
    # [rad/rad] in a second fit beside the joints-only one (0: the joints-only fit alone).
    torso_gain: float = 0.5
    torso_clip_rad: float = 0.3
    # The front of two more fits [s] (0: none), each run's error mending only the front
    # before its own followed time; kept only if they follow further (module docstring, 7).
    short_front_s: float = 1.0
    # They are tried only while the 2 s fit's torso stays below this height [m] (None: the
    # robot's ``upright_above_m``): a copy that rises keeps its 2 s fit.
    short_front_below_m: float | None = None

    def __post_init__(self) -> None:
        if self.torso_gain < 0 or not self.torso_clip_rad > 0:
            raise MimicError(
                f"the torso term needs gain >= 0 and clip > 0, got {self.torso_gain}, "
                f"{self.torso_clip_rad}"
            )
        if self.rounds < 1 or self.runs < 1:
            raise MimicError(f"--follow needs >= 1 round and run, got {self.rounds}, {self.runs}")
        if self.short_front_s < 0:
            raise MimicError(f"the short front takes >= 0 s, got {self.short_front_s}")
        if self.stand_s > 0 and not self.stand_blend_s > 0:
            raise MimicError(f"the stand's blend takes > 0 s, got {self.stand_blend_s}")


@dataclass(frozen=True)
class FollowRound:
    """One round: how long each run followed the recording [s] and its torso's highest [m]."""

    followed_s: tuple[float, ...]
    highest_m: tuple[float, ...]
    error_rad: float
    kept: bool
    # The fit's torso gain (0: joints only).
    torso_gain: float = 0.0
    # The fit's front [s] and whether each run mended its own front (the short fits).
    front_s: float = 2.0
    per_run: bool = False

    @property
    def followed(self) -> float:
        return float(np.median(self.followed_s))


@dataclass
class FollowResult:
    """The fitted copy and how the rounds of each fit went (the kept fit's torso gain)."""

    model: WindowedModel
    start_s: float
    rounds: list[FollowRound] = field(default_factory=list)
    torso_gain: float = 0.0
    # The kept fit's front [s] and whether its runs mended their own fronts.
    front_s: float = 2.0
    per_run: bool = False

    @property
    def kept_rounds(self) -> list[FollowRound]:
        """The rounds of the fit kept."""
        fit = (self.torso_gain, self.front_s, self.per_run)
        return [r for r in self.rounds if (r.torso_gain, r.front_s, r.per_run) == fit]

    @property
    def best_followed_s(self) -> float:
        return _best_followed(self.kept_rounds)

    def describe(self) -> str:
        rounds = self.kept_rounds
        first, best = rounds[0], _best_round(rounds)
        fits = {(r.torso_gain, r.front_s, r.per_run) for r in self.rounds}
        front = f", each run's own {self.front_s:g} s front" if self.per_run else ""
        which = f"{len(rounds)} rounds" + (
            f" {'with' if self.torso_gain else 'without'} the torso term{front}, the further "
            f"of {len(fits)} fits"
            if len(fits) > 1
            else ""
        )
        return (
            f"--follow: window from {self.start_s:.2f} s; the copy followed its recording to "
            f"{first.followed:.2f} s as it was, {best.followed:.2f} s fitted "
            f"(torso highest {np.mean(best.highest_m):.2f} m, {which})"
        )


def _best_round(rounds: list[FollowRound]) -> FollowRound | None:
    """The kept round of ``rounds`` that followed furthest (None: none kept)."""
    return max((r for r in rounds if r.kept), key=lambda r: r.followed, default=None)


def _best_followed(rounds: list[FollowRound]) -> float:
    best = _best_round(rounds)
    return -np.inf if best is None else best.followed


def _rose(rounds: list[FollowRound], risen_m: float) -> bool:
    """Whether the best kept round of ``rounds`` raised the torso to ``risen_m`` [m] (the
    mean over its runs of each run's highest)."""
    best = _best_round(rounds)
    return best is not None and float(np.mean(best.highest_m)) >= risen_m


class _Reached(Observer):
    """Every cycle of the get-up: the agent's time, the joints reached, torso height and
    forward-axis z."""

    def __init__(self) -> None:
        self.rows: list[tuple[float, np.ndarray, float, float]] = []
        self._t0: float | None = None

    def after_step(self, world) -> None:
        if self._t0 is None:
            self._t0 = world.time_s - CYCLE_S
        self.rows.append(
            (
                world.time_s - self._t0,
                np.array(world.joint_angles_rad(), float),
                float(world.torso_pos_m()[2]),
                float(world.torso_forward_z()),
            )
        )

    def arrays(self):
        t, q, h, fz = zip(*self.rows)
        return np.array(t), np.stack(q), np.array(h), np.array(fz)


def _learned_rate(model: MotionModel) -> float:
    """Learned seconds per played second of a model corrected over its whole motion."""
    rate, record = 1.0, model.metadata.get(CORRECTION_KEY)
    while isinstance(record, dict):
        rate *= float(record.get("rate", 1.0))
        record = record.get("previous")
    return rate


def _followed_until(t, h, fz, tl, t_rec, h_rec, fz_rec, start_s, config: FollowConfig) -> float:
    """The time [s] the run's torso parted from the recording's (its end: never): off by
    more than the tolerances from the recording's torso at every time within
    ``time_tolerance_s`` of where the copy is in it, for ``diverge_s`` in a row."""
    shifts = np.arange(-config.time_tolerance_s, config.time_tolerance_s + 1e-9, CYCLE_S)
    near = np.zeros(len(t), bool)
    for shift in shifts:
        near |= (np.abs(fz - np.interp(tl + shift, t_rec, fz_rec)) <= config.fz_tolerance) & (
            np.abs(h - np.interp(tl + shift, t_rec, h_rec)) <= config.height_tolerance_m
        )
    off = (t > start_s) & ~near
    need = max(1, round(config.diverge_s / CYCLE_S))
    count = 0
    for i, bad in enumerate(off):
        count = count + 1 if bad else 0
        if count >= need:
            return float(t[i - need + 1])
    return float(t[-1])


def _pitch_up(fz):
    """The torso's pitch up from level [rad] from its forward axis z."""
    return np.arcsin(np.clip(fz, -1.0, 1.0))


def _hip_pitch_signs(robot: str, joints: list[int], n: int) -> np.ndarray:
    """(n,): for each of ``joints`` that is a hip pitch joint, the sign by which it pitches
    the torso up (its axis's y: with the legs still, a hip pitch about +y turns the torso's
    forward axis up); 0 elsewhere."""
    signs, specs = np.zeros(n), get_robot(robot).joints
    for i in joints:
        spec = specs[i]
        name = spec.name.lower()
        if "hip" in name and "pitch" in name:
            signs[i] = float(np.sign(spec.axis[1]))
    return signs


def follow_recording(
    model: MotionModel,
    recording: str | Path,
    joints: list[int],
    trial: GetupTrialConfig,
    config: FollowConfig = FollowConfig(),
    on_round=None,
) -> FollowResult:
    """``model`` (a get-up copy of ``recording``, corrected over its whole motion or not)
    with an offset track over ``joints`` fitted until it follows the recording in ``trial``'s
    get-up (module docstring).

    Raises:
        MimicError: a cyclic or windowed model, a recording without the torso's pose, a copy
            that never faces the ground.
    """
    if model.cyclic or isinstance(model, WindowedModel):
        raise MimicError(
            "--follow fits a one-shot copy as learned or corrected over its whole motion "
            "(not cyclic, not corrected in a window)"
        )
    recorded = dataset_from_file(recording, "/joint_states")
    torso = recorded_torso(recording, recorded)
    if torso is None:
        raise MimicError(f"--follow: {recording} has no torso pose on /tf to follow")
    if list(recorded.joint_names) != list(model.joint_names):
        raise MimicError(f"--follow: {recording} is not of this copy's robot ({model.robot})")
    t_rec, q_rec = recorded.time_s, recorded.angles_rad
    h_rec, fz_rec = torso[0][:, 2], forward_axis_z(torso[1])
    cut0 = float((model.metadata.get("cut_s") or [0.0])[0])
    scale = _learned_rate(model)  # learned s per played s
    n = model.num_joints
    mask = np.zeros(n)
    mask[joints] = 1.0
    hips = _hip_pitch_signs(model.robot, joints, n)
    seeds = [derive_seed(config.seed, i) for i in range(config.runs)]

    def play(candidate, seed):
        with open_world(trial.world, model.robot, server_command=trial.server_command) as world:
            reached = _Reached()
            play_getup(world, NeuralPlayer(candidate), seed, trial, observers=(reached,))
        return reached.arrays()

    start = config.start_s
    if start is None:
        t, _, _, fz = play(model, seeds[0])
        down = np.flatnonzero(fz < FACE_DOWN_Z)
        if not len(down):
            raise MimicError(
                "--follow: the copy never faces the ground in its first run (it does not "
                "roll); improve its roll over the whole motion first"
            )
        start = float(t[down[0]]) + START_AFTER_FACE_DOWN_S
    if not 0 <= start < model.duration_s:
        raise MimicError(f"--follow: the window start {start:.2f} s is outside the motion")
    warp = 1.0 / scale  # from the window on, at the recording's own speed
    end = model.duration_s + WINDOW_RAMP_S
    knots = np.arange(start - WINDOW_RAMP_S, model.duration_s + 0.5, config.knot_s)

    def candidate(table):
        return windowed_model(
            model, warp, (start, end), np.zeros(n), np.ones(n), track=(knots, table)
        )

    last = model.duration_s

    def learned_s(t):  # recording time at the copy's played times, and the copy's own time
        inner = np.where(t < start, t, start + warp * (t - start))
        return cut0 + scale * inner, np.minimum(inner, last)  # held at its end after it

    table = np.zeros((len(knots), n))
    if config.stand_s > 0:  # the copy ends where its recording's final stand was referenced
        stand = t_rec > t_rec[-1] - config.stand_s
        refs = pd_compensated_targets(
            t_rec,
            q_rec,
            torso[0],
            torso[1],
            model.robot,
            recorded.metadata.get("recording_world", "league"),
        )
        own_end = np.asarray(model.predict(np.array([last])))[0, :n]
        blend = np.clip((knots - (last - config.stand_blend_s)) / config.stand_blend_s, 0, 1)
        table = blend[:, None] * ((refs[stand].mean(axis=0) - own_end) * mask)[None, :]

    def step_from(times, error, use, until_inner, front_s):
        """(knots, n): the correction's step from one error trace over ``use`` (the copy's
        own times), zero outside the ``front_s`` before ``until_inner``; and where it is not
        zero (knots,); None: too little followed."""
        moving, held = use & (times < last), use & (times >= last)
        if moving.sum() < 3:
            return None
        lead = warp * config.lead_s
        step = np.stack(
            [np.interp(knots + lead, times[moving], error[moving, j]) for j in range(n)], axis=1
        )
        if held.any():  # after its end the copy holds its last pose: the stand's mean error
            step[knots >= last - config.knot_s] = error[held].mean(axis=0)
        front = (knots + lead < until_inner - 0.1) & (
            knots > max(start - WINDOW_RAMP_S, min(until_inner, last) - front_s)
        )
        step[~front] = 0.0
        return step, front

    def fit(torso_gain, front_s, per_run, rounds: list[FollowRound]) -> np.ndarray:
        """The best table of the rounds from ``first``, each appended to ``rounds``. With
        ``per_run`` each run's error steps the front before its own followed time (a knot
        gets the mean over the runs whose front holds it), else the mean error steps the
        front before the median's."""
        pitch = torso_gain * hips
        best_table, best_followed, gain, basis, table = first, -np.inf, config.gain, None, first
        for _ in range(config.rounds):
            followed, highest, errors, runs = [], [], [], []
            for seed in seeds:
                t, q, h, fz = play_table(table, seed)
                tl, inner = learned_s(t)
                followed.append(_followed_until(t, h, fz, tl, t_rec, h_rec, fz_rec, start, config))
                highest.append(float(h.max()))
                qr = np.stack([np.interp(tl, t_rec, q_rec[:, j]) for j in range(n)], axis=1)
                torso = np.clip(
                    _pitch_up(np.interp(tl, t_rec, fz_rec)) - _pitch_up(fz),
                    -config.torso_clip_rad,
                    config.torso_clip_rad,
                )
                errors.append((qr - q) * mask + torso[:, None] * pitch[None, :])
                runs.append((t, inner))
            played, times = min(runs, key=lambda r: len(r[0]))
            error = np.mean([e[: len(times)] for e in errors], axis=0)
            until = float(np.median(followed))
            use = (played > start - WINDOW_RAMP_S) & (played < until - 0.1)
            rms = float(np.sqrt(np.mean(error[use] ** 2))) if use.any() else float("nan")
            kept = until >= best_followed - config.tolerance_s
            rounds.append(
                FollowRound(
                    tuple(followed), tuple(highest), rms, kept, float(torso_gain), front_s, per_run
                )
            )
            if on_round is not None:
                on_round(rounds[-1])
            if kept:
                best_table, best_followed = table, max(best_followed, until)
                if per_run:  # each run's own trace, up to its own followed time
                    basis = []
                    for (t, inner), e, f in zip(runs, errors, followed):
                        own = (t > start - WINDOW_RAMP_S) & (t < f - 0.1)
                        basis.append((inner, e, own, start + warp * (f - start)))
                else:
                    basis = [(times, error, use, start + warp * (until - start))]
            else:  # undone: a smaller step from the best round's errors
                gain *= 0.5
            steps = [s for s in (step_from(*b, front_s) for b in basis) if s is not None]
            if not steps:
                break
            count = np.sum([front for _, front in steps], axis=0)
            step = np.sum([s for s, _ in steps], axis=0) / np.maximum(count, 1)[:, None]
            kernel = np.array([0.25, 0.5, 0.25])
            step = np.stack([np.convolve(col, kernel, "same") for col in step.T], axis=1)
            table = best_table + gain * step
        return best_table

    # Joints only, then with the torso term: the torso term mends a copy whose joints follow
    # while its torso tips, but can break one where the hips do not turn the torso as assumed
    # (a kneel at its balance point); the fit that follows further is kept, a tie (within
    # ``tolerance_s``) goes to the torso term's.
    first = table
    first_plays: dict[int, tuple] = {}

    def play_table(table, seed):
        """A round's run; both fits start from ``first``, whose runs are played once."""
        if table is not first:
            return play(candidate(table), seed)
        if seed not in first_plays:
            first_plays[seed] = play(candidate(table), seed)
        return first_plays[seed]

    result = FollowResult(candidate(table), start)
    gains = (0.0, config.torso_gain) if config.torso_gain > 0 and hips.any() else (0.0,)
    fits = [(g, config.front_s, False) for g in gains]
    if config.short_front_s > 0:  # kept only if they follow further than the fits above
        fits += [(g, config.short_front_s, True) for g in gains]
    risen_m = config.short_front_below_m
    if risen_m is None:
        risen_m = get_robot(model.robot).falls.upright_above_m
    best_table, best_followed, rose = table, -np.inf, None
    for torso_gain, front_s, per_run in fits:
        if per_run and rose is None:  # the fit kept so far is a 2 s one
            rose = _rose(result.kept_rounds, risen_m)
        if per_run and rose:
            continue  # the 2 s fit raises the copy: its stand is the stand search's to hold
        rounds: list[FollowRound] = []
        fitted = fit(torso_gain, front_s, per_run, rounds)
        result.rounds += rounds
        followed = _best_followed(rounds)
        if per_run:
            better = followed > best_followed + config.tolerance_s
        else:
            better = followed >= best_followed - (config.tolerance_s if torso_gain else 0.0)
        if better:
            best_table, best_followed = fitted, followed
            result.torso_gain, result.front_s, result.per_run = float(torso_gain), front_s, per_run
    result.model = candidate(best_table)
    return result
