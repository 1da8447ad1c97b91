"""Training data: a joint table (polars) in, time and target arrays out.

A joint table has the layout of ``mimic.recording.reader.read_joint_table``: ``time_s`` [s]
from the motion start, the robot's N joint names in its order [rad], optionally ``ended``
(0/1). A dataset carries its robot (name) and joint names; its targets are the N joints plus
the ended flag, which is 1 on the last sample only (as in the study); a table whose ``ended``
column turns 1 is cut after that row (samples after the motion ended are not part of it).
Cyclic motions (``period_s`` given) never end: their flag target is 0 everywhere and the
network input is the periodic phase (sin, cos).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import polars as pl

from mimic.errors import DatasetError, MimicError
from mimic.files import input_file
from mimic.recording.layout import ENDED_COLUMN, TIME_COLUMN
from mimic.recording.paper_import import STUDY_ROBOT, read_paper_table
from mimic.recording.reader import read_joint_table, read_recording
from mimic.robot.model import RobotDescription
from mimic.robot.registry import DEFAULT_ROBOT, get_robot

__all__ = [
    "Dataset",
    "dataset_from_frame",
    "dataset_from_file",
    "cut_dataset",
    "detect_period_s",
    "as_cyclic",
    "drop_non_repeating",
    "average_jittery_joints",
    "symmetric_cycle",
    "phase_bins",
    "bin_count",
    "NON_REPEATING_RAD",
]

#: A cyclic motion's sample whose targets differ from the cycle's median at its phase by more
#: than this in some joint [rad] is no part of the cycle, and is left out of training: a
#: black-box recording of a walk ends however the other team's process ends (there, the
#: robot falling once it is no longer driven), and the PD-compensated targets of the T1 other
#: team's walk show single glitches of 0.2 rad. Its steady samples stay within 0.045 rad of
#: the median (observed) and 0.04 (compensated).
NON_REPEATING_RAD = 0.1
#: ... or by more than this many times the joint's jitter, where that is the larger. A walk
#: whose joints jitter (a learned policy's actions, cycle to cycle) has nearly every sample off
#: the cycle by more than 0.1 rad in some joint, and none of them is a glitch. The jitter is
#: read from the deviations from the cycle, sample to sample: 1.4826 times the median absolute
#: second difference of consecutive deviations, over sqrt 6 (a white noise's standard
#: deviation). A cycle at the wrong period, a motion that is not one cycle, or a fall drift off
#: the cycle smoothly, and their second differences stay small, so they are still refused. A
#: steady walk's joints jitter so little that its limit stays 0.1 rad. The jitter is read at the
#: league monitor's 25 Hz; at 50 Hz the motors smooth it over a few samples and a jittery
#: recording is still refused (docs/real-team-walk.md: the figures, and why a wider span was
#: not kept).
NON_REPEATING_JITTERS = 6.0


#: A normal spread's standard deviation per median absolute deviation.
_MAD_TO_SD = 1.4826


@dataclass(frozen=True)
class Dataset:
    """One motion to learn.

    Attributes:
        time_s: (T,) sample times from the motion start [s], increasing.
        targets: (T, N + 1) joint angles [rad] in ``joint_names`` order + the ended flag (0/1).
        robot: name of the robot the motion belongs to (``mimic.robot.registry``).
        joint_names: (N,) the robot's joint names, its order.
        period_s: period of a cyclic motion [s] (input = phase), or None (input = time).
        metadata: where it came from: ``motion``, ``team``, ``ball_offset_m``, ``source``
            (file), ``topic``, ``target`` (``reached`` or ``compensated``), ...
    """

    time_s: np.ndarray
    targets: np.ndarray
    robot: str
    joint_names: tuple[str, ...]
    period_s: float | None = None
    metadata: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.targets.shape[1:] != (self.num_joints + 1,):
            raise ValueError(
                f"targets of shape {self.targets.shape} for {self.num_joints} "
                f"{self.robot} joints + the ended flag"
            )

    @property
    def n_samples(self) -> int:
        return len(self.time_s)

    @property
    def num_joints(self) -> int:
        return len(self.joint_names)

    @property
    def angles_rad(self) -> np.ndarray:
        """(T, N) joint targets [rad]."""
        return self.targets[:, : self.num_joints]

    @property
    def name(self) -> str:
        return str(self.metadata.get("motion") or "motion")

    def with_angles(self, angles_rad: np.ndarray, **metadata) -> Dataset:
        """The same dataset with other joint targets (e.g. compensated), metadata updated."""
        targets = self.targets.copy()
        targets[:, : self.num_joints] = angles_rad
        return replace(self, targets=targets, metadata={**self.metadata, **metadata})


def _where(metadata: dict) -> str:
    return str(metadata.get("source") or "joint table")


def dataset_from_frame(
    frame: pl.DataFrame,
    *,
    robot: str | RobotDescription = DEFAULT_ROBOT,
    period_s: float | None = None,
    metadata: dict | None = None,
) -> Dataset:
    """Build a dataset of ``robot`` from a joint table (see module docstring).

    Raises:
        DatasetError: empty table, a single sample, joint columns other than the robot's (or
            in another order), NaN values, non-increasing time, or a non-positive period.
    """
    robot = get_robot(robot)
    names = robot.joint_names
    metadata = dict(metadata or {})
    where = _where(metadata)
    if TIME_COLUMN not in frame.columns:
        raise DatasetError(
            f"{where}: no {TIME_COLUMN!r} column; columns: {', '.join(frame.columns)}"
        )
    joints = [c for c in frame.columns if c not in (TIME_COLUMN, ENDED_COLUMN)]
    if tuple(joints) != names:
        missing = [n for n in names if n not in joints]
        extra = [n for n in joints if n not in names]
        detail = "; ".join(
            s
            for s in (
                f"missing {', '.join(missing)}" if missing else "",
                f"unexpected {', '.join(extra)}" if extra else "",
                "wrong order" if not (missing or extra) else "",
            )
            if s
        )
        raise DatasetError(
            f"{where}: expected the {robot.num_joints} {robot.name} joints in "
            f"its order, got {len(joints)} joint columns ({detail})"
        )
    if frame.height == 0:
        raise DatasetError(f"{where}: the joint table is empty; record or import a motion first")
    if frame.height == 1:
        raise DatasetError(f"{where}: a single sample cannot make a motion; need at least 2")
    t = frame[TIME_COLUMN].cast(pl.Float64).to_numpy().copy()
    angles = frame.select(names).cast(pl.Float64).to_numpy().copy()
    ended = (
        frame[ENDED_COLUMN].cast(pl.Float64).fill_null(0.0).to_numpy()
        if ENDED_COLUMN in frame.columns
        else np.zeros(len(t))
    )
    bad = np.argwhere(~np.isfinite(angles))
    if len(bad) or not np.isfinite(t).all() or np.isnan(ended).any():
        if len(bad):
            row, col = bad[0]
            what = f"{names[col]} at row {row}"
        else:
            what = TIME_COLUMN if not np.isfinite(t).all() else ENDED_COLUMN
        raise DatasetError(f"{where}: NaN or infinite value ({what}); fix or re-record the motion")
    if np.any(np.diff(t) <= 0):
        row = int(np.argmax(np.diff(t) <= 0)) + 1
        raise DatasetError(f"{where}: time does not increase at row {row} (t = {t[row]:.3f} s)")
    if period_s is None:
        hit = np.nonzero(ended > 0.5)[0]
        if len(hit) and hit[0] >= 1:  # keep at least two samples
            t, angles = t[: hit[0] + 1], angles[: hit[0] + 1]
        flag = np.zeros(len(t))
        flag[-1] = 1.0
    else:
        if not (period_s > 0 and math.isfinite(period_s)):
            raise DatasetError(
                f"{where}: period must be a positive number of seconds, got {period_s}"
            )
        flag = np.zeros(len(t))
    t = t - t[0]
    targets = np.concatenate([angles, flag[:, None]], axis=1)
    return Dataset(t, targets, robot.name, names, period_s, metadata)


def _read_table(path: Path, topic: str | None):
    """(joint table, robot name, metadata dict, period) from an MCAP recording or a study
    text file (NAO data)."""
    suffix = path.suffix.lower()
    if suffix == ".mcap":
        rec = read_recording(path)
        topic = topic or rec.joint_topic()
        frame = read_joint_table(rec, topic)
        info = rec.info
        meta = {
            "source": str(path),
            "topic": topic,
            # How complete the recording is (``mimic.learn.checks`` warns about it).
            "recording_complete": rec.recovery.complete,
            "recording_interrupted": rec.interrupted,
            "recording_bytes_lost": rec.recovery.bytes_lost,
            "recording_duration_s": (float(frame[TIME_COLUMN][-1]) if frame.height else 0.0),
            "recording_ended": bool(
                ENDED_COLUMN in frame.columns and frame.height and frame[ENDED_COLUMN].max() > 0.5
            ),
        }
        period, robot = None, rec.robot.name
        if info is not None:
            meta.update(
                motion=info.motion,
                team=info.team,
                agent=info.agent,
                source_kind=info.source,
                recording_seed=info.seed,
                # Where it moved: ``nao`` (our MuJoCo world) or ``league`` (RCSSServerMJ).
                recording_world=info.world,
                recording_toolkit_version=info.toolkit_version,
            )
            if info.ball_offset_m is not None:
                meta["ball_offset_m"] = list(info.ball_offset_m)
            if info.start_posture != "standing":
                meta["start_posture"] = info.start_posture
            period = info.period_s
        meta.setdefault("motion", path.stem)
        return frame, robot, meta, period
    if suffix == ".txt":
        frame = read_paper_table(path)
        meta = {"source": str(path), "topic": "paper", "motion": path.stem, "team": "paper"}
        return frame, STUDY_ROBOT, meta, None
    raise DatasetError(
        f"{path}: unknown input kind {suffix or '(no suffix)'!r}; "
        "give a .mcap recording or a study .txt table"
    )


def dataset_from_file(
    path: str | Path, topic: str | None = None, *, period_s: float | None = None
) -> Dataset:
    """Dataset from an MCAP recording (``topic``: None picks ``/joint_references`` when
    present, else ``/joint_states``) or a study ``::`` text file (``.txt``).

    The robot comes from the recording's metadata (study files: the NAO); the period too,
    unless ``period_s`` is given.

    Raises:
        DatasetError: unreadable content for a dataset (see ``dataset_from_frame``);
        RecordingError: the recording cannot be read.
    """

    try:
        path = input_file(path, "file", "give a .mcap recording or a study .txt table")
    except MimicError as err:
        raise DatasetError(str(err)) from None
    try:
        frame, robot, meta, period = _read_table(path, topic)
    except MimicError:
        raise
    except (OSError, ValueError) as err:
        raise DatasetError(f"{path}: cannot read ({err})") from None
    return dataset_from_frame(
        frame, robot=robot, period_s=period_s if period_s is not None else period, metadata=meta
    )


def cut_dataset(ds: Dataset, start_s: float | None = None, end_s: float | None = None) -> Dataset:
    """The samples from ``start_s`` to ``end_s`` [s of the recording, from its first sample],
    timed from the cut's first sample (a black-box recording holds more than the motion: the
    robot put down, standing, the walk's start). A one-shot motion ends at the cut's last
    sample; a cyclic one keeps its period.

    Raises:
        DatasetError: bounds that are not numbers, out of order, or keep fewer than 2 samples.
    """
    if start_s is None and end_s is None:
        return ds
    where = _where(ds.metadata)
    last = float(ds.time_s[-1])
    lo = 0.0 if start_s is None else float(start_s)
    hi = last if end_s is None else float(end_s)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
        raise DatasetError(
            f"{where}: cut from {lo} s to {hi} s; --start must be >= 0 and before --end"
        )
    keep = (ds.time_s >= lo - 1e-9) & (ds.time_s <= hi + 1e-9)
    if keep.sum() < 2:
        raise DatasetError(
            f"{where}: the cut {lo:.2f}-{hi:.2f} s keeps {int(keep.sum())} samples of a "
            f"{last:.2f} s recording; choose --start/--end inside it"
        )
    targets = ds.targets[keep].copy()
    targets[:, -1] = 0.0
    if ds.period_s is None:
        targets[-1, -1] = 1.0
    t = ds.time_s[keep]
    cut = {"cut_s": [round(float(t[0]), 4), round(float(t[-1]), 4)]}
    return replace(ds, time_s=t - t[0], targets=targets, metadata={**ds.metadata, **cut})


def detect_period_s(
    time_s: np.ndarray, angles_rad: np.ndarray, min_s: float = 0.3, max_s: float = 3.0
) -> float:
    """The period [s] of a cyclic motion (a walk) from its joint angles: the first lag at
    which their summed autocorrelation (each joint's mean removed) comes within 10 % of its
    highest value between ``min_s`` and ``max_s`` (at most half the samples' span), refined
    by a parabola through the neighbouring lags. A gait's full cycle (two steps) is found
    before its multiples, and before its half (the legs alternate, so the two-step lag wins
    on the asymmetric joints).

    Raises:
        DatasetError: too short for two periods of ``min_s``, or nothing repeats.
    """
    t = np.asarray(time_s, dtype=float)
    q = np.asarray(angles_rad, dtype=float)
    dt = float(np.median(np.diff(t)))
    x = q - q.mean(axis=0)
    n = len(x)
    lo = max(1, int(math.ceil(min_s / dt)))
    hi = min(int(max_s / dt), n // 2)
    if hi <= lo + 1:
        raise DatasetError(
            f"cannot find a period in {t[-1] - t[0]:.2f} s; a cyclic motion needs at least "
            f"{2 * min_s:.1f} s (two cycles)"
        )
    energy = float((x * x).sum())
    acf = np.array([(x[:-lag] * x[lag:]).sum() * n / (n - lag) for lag in range(lo, hi + 1)])
    acf /= energy if energy > 0 else 1.0
    # Peaks: local maxima that rise at least 0.2 above a dip before them (a slow drift is
    # highest at the shortest lag and never dips: it has no period).
    peaks = [
        i
        for i in range(1, len(acf))
        if acf[i] >= acf[i - 1]
        and (i == len(acf) - 1 or acf[i] >= acf[i + 1])
        and acf[i] - acf[:i].min() >= 0.2
    ]
    best = max((float(acf[i]) for i in peaks), default=0.0)
    if best < 0.3:
        raise DatasetError(
            "the joint angles do not repeat (no autocorrelation peak above 0.3): not a cyclic "
            "motion, or cut it to its steady part (--start/--end)"
        )
    # The first peak that comes close to the highest.
    peaks = [i for i in peaks if acf[i] >= 0.9 * best]
    i = peaks[0]
    shift = 0.0
    if 0 < i < len(acf) - 1:
        a, b, c = acf[i - 1], acf[i], acf[i + 1]
        denom = a - 2 * b + c
        shift = 0.5 * (a - c) / denom if denom < 0 else 0.0
    return (lo + i + shift) * dt


def as_cyclic(ds: Dataset, period_s: float) -> Dataset:
    """The dataset as one cyclic motion of ``period_s`` [s] (the ended flag cleared)."""
    if not (period_s > 0 and math.isfinite(period_s)):
        raise DatasetError(f"{_where(ds.metadata)}: period must be > 0 s, got {period_s}")
    targets = ds.targets.copy()
    targets[:, -1] = 0.0
    return replace(ds, targets=targets, period_s=float(period_s))


def phase_bins(time_s: np.ndarray, period_s: float, most: int | None = None) -> np.ndarray:
    """(T,) the phase bin of each sample of a cyclic motion: the cycle cut into as many bins
    as it holds samples (at most ``most``), each sample in the bin whose centre is nearest its
    phase ``time_s / period_s``. No more bins than samples per cycle: a cycle that is a whole
    number of samples long puts every cycle's samples at the same phases, and a finer bin
    between them would stay empty (``bin_count``)."""
    t = np.asarray(time_s, float)
    bins = bin_count(t, period_s, most)
    return np.round((t / period_s % 1.0) * bins).astype(int) % bins


def bin_count(time_s: np.ndarray, period_s: float, most: int | None = None) -> int:
    """Phase bins of a cycle sampled at ``time_s``: its samples per cycle (>= 2, <= ``most``)."""
    bins = max(2, int(period_s / float(np.median(np.diff(np.asarray(time_s, float))))))
    return bins if most is None else max(2, min(bins, most))


def drop_non_repeating(
    ds: Dataset, limit_rad: float = NON_REPEATING_RAD, jitters: float = NON_REPEATING_JITTERS
) -> Dataset:
    """A cyclic dataset without the samples that do not repeat: those whose targets differ by
    more than ``limit_rad`` in some joint from the median of the samples at the same phase
    (phases binned at the sampling step; a bin of fewer than 3 samples judges nothing), or by
    more than ``jitters`` times that joint's jitter where that is larger
    (``NON_REPEATING_JITTERS``). The number left out is in ``metadata["non_repeating"]``.
    One-shot datasets are returned as they are.

    Raises:
        DatasetError: more than half the samples do not repeat (not one cyclic motion).
    """
    if ds.period_s is None or ds.n_samples < 3:
        return ds
    t = ds.time_s
    deviation, judged = _cycle_deviation(ds)
    limit = np.maximum(float(limit_rad), jitters * _jitter_rad(deviation, judged))
    keep = ~judged | np.all(np.abs(deviation) <= limit, axis=1)
    dropped = int((~keep).sum())
    if dropped == 0:
        return ds
    if dropped > len(t) / 2:
        raise DatasetError(
            f"{_where(ds.metadata)}: {dropped} of {len(t)} samples differ from the cycle by "
            f"more than {limit_rad} rad (or {jitters:g} times a joint's jitter): not one cyclic "
            f"motion at {ds.period_s:.3f} s (cut it "
            "to its steady part with --start/--end, or give --period)"
        )
    return replace(
        ds,
        time_s=t[keep],
        targets=ds.targets[keep],
        metadata={**ds.metadata, "non_repeating": dropped},
    )


def _cycle_deviation(ds: Dataset) -> tuple[np.ndarray, np.ndarray]:
    """(T, N) each sample's targets less the median of the samples at its phase (signed; NaN
    where the phase bin holds fewer than 3 samples: it judges nothing), and (T,) whether the
    sample was judged."""
    t, q = ds.time_s, ds.targets[:, :-1]
    k = phase_bins(t, ds.period_s)
    deviation = np.full(q.shape, np.nan)
    for b in range(bin_count(t, ds.period_s)):
        at = k == b
        if at.sum() >= 3:
            deviation[at] = q[at] - np.median(q[at], axis=0)
    return deviation, ~np.isnan(deviation[:, 0])


def _jitter_rad(deviation: np.ndarray, judged: np.ndarray) -> np.ndarray:
    """(N,) each joint's jitter about the cycle (``NON_REPEATING_JITTERS``); zeros when fewer
    than 4 samples were judged."""
    if judged.sum() < 4:
        return np.zeros(deviation.shape[1])
    bend = np.diff(deviation[judged], n=2, axis=0)  # consecutive judged samples
    return _MAD_TO_SD * np.median(np.abs(bend), axis=0) / math.sqrt(6)


def average_jittery_joints(
    ds: Dataset, limit_rad: float = NON_REPEATING_RAD, jitters: float = NON_REPEATING_JITTERS
) -> Dataset:
    """A cyclic dataset whose jittery joints' targets are their cycle's mean: for each joint
    whose jitter (``NON_REPEATING_JITTERS``) times ``jitters`` exceeds ``limit_rad``, every
    sample's target becomes the mean of the samples at its phase (bins at the sampling step,
    linear between their centres, around the cycle). Their names are in
    ``metadata["jittery_joints"]``; a dataset without such joints is returned as it is.

    Why: a learned policy's joints jitter from sample to sample, and the compensated targets
    (``learn.pd_compensate`` differentiates the angles twice) jitter more. A network fitted to
    that cloud learns wiggles of its own: the copy of the T1 jittery walk swung its head's
    references at up to 58 rad/s, where the original's mean head hardly moves.
    """
    if ds.period_s is None or ds.n_samples < 4:
        return ds
    deviation, judged = _cycle_deviation(ds)
    jittery = np.flatnonzero(jitters * _jitter_rad(deviation, judged) > limit_rad)
    if len(jittery) == 0:
        return ds
    t = ds.time_s
    bins = bin_count(t, ds.period_s)
    k = phase_bins(t, ds.period_s)
    filled = np.array([np.any(k == b) for b in range(bins)])
    centres = np.arange(bins)[filled] / bins
    phase = t / ds.period_s % 1.0
    targets = ds.targets.copy()
    for j in jittery:
        means = np.array([targets[k == b, j].mean() for b in range(bins) if filled[b]])
        targets[:, j] = np.interp(phase, centres, means, period=1.0)
    names = [ds.joint_names[j] for j in jittery]
    return replace(ds, targets=targets, metadata={**ds.metadata, "jittery_joints": names})


def symmetric_cycle(ds: Dataset) -> Dataset:
    """A cyclic dataset made left-right symmetric: every sample joined by its mirror image
    (``RobotDescription.mirror_angles``: left and right legs swapped, rolls and yaws negated)
    half a cycle later. The network then learns the mean of each step and its mirrored twin.

    Why: a straight walk's second step is its first, mirrored. A black-box recording also
    holds the other team's own corrections of that run (a lean to one side, a turn it was
    making), and a copy that replays them drifts and turns by itself; the mirrored samples
    cancel them. Only for motions meant to be symmetric (a straight walk, walking on the spot),
    not a curve. ``metadata["symmetric"]`` is set.

    Raises:
        DatasetError: the dataset is not cyclic.
    """
    if ds.period_s is None:
        raise DatasetError(
            f"{_where(ds.metadata)}: only a cyclic motion can be mirrored half a cycle on "
            "(give --period)"
        )
    mirrored = ds.targets.copy()
    mirrored[:, :-1] = get_robot(ds.robot).mirror_angles(ds.angles_rad)
    time_s = np.concatenate([ds.time_s, ds.time_s + ds.period_s / 2])
    by_time = np.argsort(time_s, kind="stable")
    return replace(
        ds,
        time_s=time_s[by_time],
        targets=np.concatenate([ds.targets, mirrored])[by_time],
        metadata={**ds.metadata, "symmetric": True},
    )
