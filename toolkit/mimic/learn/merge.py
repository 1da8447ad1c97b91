"""Several recordings of one motion as one dataset (``mimic train A B ... --merge``).

Why: the league's monitor shows a robot every second cycle (25 Hz), so one recording of a
kick holds every other cycle of it. Which half depends on the cycle the kick happened to
start on. A keyframe kick's references bend at keyframe boundaries; a recording sampled
between them cuts the corners, and a copy learned from it kicks about a quarter shorter
(our T1 kick, ``benchmarks/t1_copyable_kick.py``: tables from the same kick sampled on the
even cycles 3.9-4.0 m, on the odd ones 3.0-3.1 m). Recordings of the same motion started on
other cycles hold the missing half; aligned and pooled they give the motion at 50 Hz, and
their placement noise (where the ball lay) averages out.

How: each recording's observed angles are compared with the first's at every whole-cycle
shift (samples of every world lie on its 20 ms cycles), and the shift with the smallest mean
squared difference over at least half of the shorter recording wins. Each recording is then
made into training targets on its own (``training_dataset``: compensation needs its own
sample times), cut at the first recording's ``start_s``/``end_s`` moved by its shift, and the
samples are pooled on the first recording's clock. Of three or more recordings, one whose
angles stray from the others' (a robot that fell during its kick) is left out.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import combinations
from pathlib import Path

import numpy as np

from mimic.errors import DatasetError
from mimic.learn.dataset import Dataset, dataset_from_file
from mimic.learn.train import training_dataset
from mimic.world.base import CYCLE_S

__all__ = ["Alignment", "align_shift_s", "merged_training_dataset"]

#: The least overlap of two recordings, as a share of the shorter, for a shift to count.
MIN_OVERLAP_SHARE = 0.5
#: Of three or more recordings, one whose angles differ from the closest other one's (rms)
#: by more than OUTLIER_FACTOR times what is typical of the set, and by more than
#: OUTLIER_FLOOR_RAD [rad], is left out: a robot that fell, or another motion (our T1 kick:
#: 0.007-0.013 rad to the closest other kick, 0.042 rad for one whose robot fell).
OUTLIER_FACTOR, OUTLIER_FLOOR_RAD = 2.5, 0.02


@dataclass(frozen=True)
class Alignment:
    """Where one recording lies on the first one's clock.

    Attributes:
        shift_s: recording time = first recording's time + ``shift_s`` [s] (a whole number of
            cycles).
        rms_rad: root mean square difference of the observed angles at that shift [rad].
        spread_rad: with three or more recordings, this one's rms difference to the closest
            other one, each pair aligned on its own [rad] (0: not measured).
        kept: False when the recording was left out (``OUTLIER_FACTOR``).
    """

    shift_s: float
    rms_rad: float
    spread_rad: float = 0.0
    kept: bool = True


def _rms_at(reference: Dataset, other: Dataset, shift_s: float, need_s: float) -> float | None:
    """RMS difference [rad] of ``other``'s angles from ``reference``'s (linearly interpolated)
    with ``other`` shifted by ``shift_s`` [s]; None when they overlap less than ``need_s``."""
    t_ref, q_ref = reference.time_s, reference.angles_rad
    on_ref = other.time_s - shift_s  # other's samples on the reference's clock
    inside = (on_ref >= t_ref[0] - 1e-9) & (on_ref <= t_ref[-1] + 1e-9)
    if inside.sum() < 3 or on_ref[inside][-1] - on_ref[inside][0] < need_s - 1e-9:
        return None
    ref_at = np.stack(
        [np.interp(on_ref[inside], t_ref, q_ref[:, j]) for j in range(q_ref.shape[1])], 1
    )
    return float(np.sqrt(np.mean((other.angles_rad[inside] - ref_at) ** 2)))


def align_shift_s(reference: Dataset, other: Dataset, *, grid_s: float = CYCLE_S) -> Alignment:
    """The shift of ``other`` on ``reference``'s clock that best matches their angles.

    Every multiple of ``grid_s`` [s] with an overlap of at least ``MIN_OVERLAP_SHARE`` of the
    shorter recording is tried; ``other``'s samples are compared with ``reference`` linearly
    interpolated at the same instants (all joints, radians).

    Raises:
        DatasetError: the two never overlap enough (too short, or not the same robot).
    """
    t_ref, t = reference.time_s, other.time_s
    need = MIN_OVERLAP_SHARE * min(t_ref[-1] - t_ref[0], t[-1] - t[0])
    lo = int(np.floor((t[0] - t_ref[-1]) / grid_s))
    hi = int(np.ceil((t[-1] - t_ref[0]) / grid_s))
    best: Alignment | None = None
    for k in range(lo, hi + 1):
        rms = _rms_at(reference, other, k * grid_s, need)
        if rms is not None and (best is None or rms < best.rms_rad - 1e-12):
            best = Alignment(round(k * grid_s, 6), rms)
    if best is None:
        raise DatasetError(
            f"{other.metadata.get('source', 'a recording')} never overlaps "
            f"{reference.metadata.get('source', 'the first recording')} for half of the "
            "shorter one; merge recordings of the same motion"
        )
    return best


def _align_all(seen: list[Dataset]) -> list[Alignment]:
    """Every recording on the first one's clock. With three or more, every pair is aligned
    on its own (so a stray first recording does not skew the rest) and each one's spread is
    its rms difference to the closest other; a spread above ``OUTLIER_FACTOR`` times the
    median spread (and ``OUTLIER_FLOOR_RAD``) marks a recording as left out."""
    n = len(seen)
    wanted = combinations(range(n), 2) if n >= 3 else [(0, 1)]
    found = {(i, j): align_shift_s(seen[i], seen[j]) for i, j in wanted}
    alignments = [Alignment(0.0, 0.0)] + [found[(0, j)] for j in range(1, n)]
    if n < 3:
        return alignments
    rms = np.zeros((n, n))
    for (i, j), a in found.items():
        rms[i, j] = rms[j, i] = a.rms_rad
    spreads = [float(np.delete(rms[i], i).min()) for i in range(n)]
    limit = max(OUTLIER_FACTOR * float(np.median(spreads)), OUTLIER_FLOOR_RAD)
    return [
        replace(a, spread_rad=round(spread, 6), kept=spread <= limit)
        for a, spread in zip(alignments, spreads)
    ]


def merged_training_dataset(
    paths: Sequence[str | Path],
    topic: str | None = None,
    target: str | None = None,
    *,
    start_s: float | None = None,
    end_s: float | None = None,
) -> tuple[Dataset, list[Alignment]]:
    """One dataset from recordings of one motion (module docstring), and where each lies on
    the first one's clock (the first: shift 0).

    ``start_s``/``end_s`` [s from the first recording's first sample] cut the motion as
    ``training_dataset`` does; ``topic`` and ``target`` as there. The ball offset of a kick is
    the mean over the recordings that show one. Of three or more recordings, one that differs
    from the others (``OUTLIER_FACTOR``) is left out; its ``Alignment`` says so.

    Raises:
        DatasetError: fewer than two recordings; recordings of different robots or of a
            cyclic motion; a recording that does not overlap the first; a cut outside one;
            a first recording that differs from the others.
    """

    if len(paths) < 2:
        raise DatasetError("--merge pools several recordings of one motion: give at least two")
    seen = [dataset_from_file(p, topic) for p in paths]
    first = seen[0]
    for p, d in zip(paths, seen):
        if d.robot != first.robot or d.joint_names != first.joint_names:
            raise DatasetError(
                f"{p} is a {d.robot} recording, {paths[0]} a {first.robot} one; merge "
                "recordings of the same robot"
            )
        if d.period_s is not None:
            raise DatasetError(
                f"{p} holds a cyclic motion; --merge pools one-shot motions (train a walk "
                "from one recording with --period)"
            )
    alignments = _align_all(seen)
    if not alignments[0].kept:
        raise DatasetError(
            f"{paths[0]} differs from the other recordings ({alignments[0].spread_rad:.3f} rad "
            "rms, more than they differ among themselves): a fall, or another motion? Put a "
            "recording of the motion first, its clock is the model's"
        )
    lo = 0.0 if start_s is None else float(start_s)
    hi = float(first.time_s[-1]) if end_s is None else float(end_s)
    parts = []
    for p, d, a in zip(paths, seen, alignments):
        if not a.kept:
            continue
        last = float(d.time_s[-1])
        cut_lo, cut_hi = max(0.0, lo + a.shift_s), min(last, hi + a.shift_s)
        if cut_hi - cut_lo < 2 * CYCLE_S:
            raise DatasetError(
                f"{p}: shifted {a.shift_s:+.2f} s onto {paths[0]}, it holds nothing of the cut "
                f"{lo:.2f}-{hi:.2f} s; merge recordings that all show the motion"
            )
        part = training_dataset(p, topic, target, start_s=cut_lo, end_s=cut_hi)
        # The cut's clock starts at its first sample: back onto the first recording's cut.
        first_sample_s = part.metadata["cut_s"][0] if "cut_s" in part.metadata else 0.0
        parts.append((part, first_sample_s - a.shift_s - lo))
    time_s = np.concatenate([part.time_s + offset for part, offset in parts])
    targets = np.concatenate([part.targets for part, _ in parts])
    order = np.argsort(time_s, kind="stable")
    first_s = float(time_s[order[0]])  # every offset is >= 0: the cuts start at or after lo
    time_s, targets = time_s[order] - first_s, targets[order]
    # The motion has ended from the earliest of the recordings' last samples on.
    ended_s = min(part.time_s[-1] + offset for part, offset in parts) - first_s
    targets[:, -1] = (time_s >= ended_s - 1e-9).astype(targets.dtype)
    base = parts[0][0]
    metadata = {
        **base.metadata,
        "merged_from": [str(p) for p, a in zip(paths, alignments) if a.kept],
        "merge_shift_s": [a.shift_s for a in alignments if a.kept],
    }
    left_out = [str(p) for p, a in zip(paths, alignments) if not a.kept]
    if left_out:
        metadata["merge_left_out"] = left_out
    offsets = [
        part.metadata["ball_offset_m"] for part, _ in parts if "ball_offset_m" in part.metadata
    ]
    if offsets:
        metadata["ball_offset_m"] = [round(float(v), 4) for v in np.mean(offsets, axis=0)]
    return replace(base, time_s=time_s, targets=targets, metadata=metadata), alignments
