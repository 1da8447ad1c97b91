"""What training should tell the user: input that may hold only part of a motion, and a fit
too poor to trust. Each function returns warnings as one-line strings (the CLI prints them;
``mimic train --strict`` refuses input with ``input_warnings``)."""

from __future__ import annotations

from mimic.learn.dataset import Dataset
from mimic.learn.window import describe_gaps
from mimic.model.motion_model import MotionModel
from mimic.motion.files import list_motions, load_motion

__all__ = ["input_warnings", "fit_warnings", "POOR_FIT_MAE_RAD", "CYCLES_TO_LEARN"]

#: A fit whose mean absolute joint error exceeds this is reported as poor [rad]. The study's
#: kick fit is 0.018 rad; our presets reach 0.004-0.016 rad on one motion or ten walk cycles.
POOR_FIT_MAE_RAD = 0.03
#: Cycles a cyclic recording holds by default (``mimic record`` of a walk); what to suggest.
CYCLES_TO_LEARN = 10


def _full_duration_s(name: str) -> float | None:
    """Length of a shipped keyframe motion [s], or None for other motions."""

    if name not in list_motions():
        return None
    return float(load_motion(name).duration_s)


def input_warnings(dataset: Dataset) -> list[str]:
    """Warnings about a dataset made from an interrupted or truncated recording, or from one
    whose motion never ends: the motion learned may be incomplete (``mimic train --strict``
    refuses such input)."""
    meta = dataset.metadata
    gaps = meta.get("resampled_gaps")
    if gaps:
        where = meta.get("source", dataset.name)
        return [
            f"{where}: {len(gaps)} gap{'s' if len(gaps) > 1 else ''} in the samples "
            f"compensated, resampled: {describe_gaps(gaps)} (seconds from the recording's "
            "first sample, and the gap's length)"
        ]
    if meta.get("cut_s") is not None:
        return []  # the user chose the piece (mimic train --start/--end): nothing is missing
    where = meta.get("source", dataset.name)
    got_s = float(dataset.time_s[-1]) if dataset.n_samples else 0.0
    if meta.get("recording_complete") is False or meta.get("recording_interrupted") is True:
        how = (
            f"truncated recording (the last {meta.get('recording_bytes_lost', '?')} bytes "
            "unreadable)"
            if meta.get("recording_complete") is False
            else "interrupted recording"
        )
        full = _full_duration_s(dataset.name) if dataset.period_s is None else None
        of = f" of {dataset.name}, which lasts {full:.2f} s" if full else ""
        return [
            f"{where}: {how}: recovered {got_s:.2f} s ({dataset.n_samples} samples){of}; "
            "the motion may be incomplete: record it again"
        ]
    if dataset.period_s is None and meta.get("recording_ended") is False:
        return [
            f"{where}: the motion never ends in the recording (no /ended true in "
            f"{got_s:.2f} s); it may be cut short"
        ]
    return []


def fit_warnings(model: MotionModel, dataset: Dataset) -> list[str]:
    """A warning when the fit is poor (mean absolute error above ``POOR_FIT_MAE_RAD``), with
    what to try."""
    mae = float(model.metrics.get("mae_rad", 0.0))
    if mae <= POOR_FIT_MAE_RAD:
        return []
    length_s = float(dataset.time_s[-1]) if dataset.n_samples else 0.0
    if dataset.period_s is not None and length_s > (CYCLES_TO_LEARN + 1) * dataset.period_s:
        cycles = length_s / dataset.period_s
        advice = (
            f"the recording holds {cycles:.0f} cycles of {dataset.period_s:g} s and one "
            "network learns their average cycle; learn one steady cycle from fewer "
            f"(mimic record without --duration records {CYCLES_TO_LEARN})"
        )
    elif dataset.period_s is None and length_s > 10.0:
        advice = (
            f"the motion is {length_s:.0f} s long; a network this size learns one motion "
            "of a few seconds or one cycle: record a shorter piece (mimic record "
            "--duration) or a cyclic agent, whose period makes the network learn one "
            "cycle"
        )
    else:
        advice = "train longer (--epochs) or with --preset paper"
    return [
        f"{model.name}: poor fit, mean absolute error {mae:.3f} rad (good fits stay below "
        f"{POOR_FIT_MAE_RAD} rad); {advice}"
    ]
