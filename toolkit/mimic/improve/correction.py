"""The low-dimensional correction of a learned model, baked into an ordinary model file.

A learned motion has thousands of network weights; searching them with a few hundred noisy
trial episodes is hopeless. ``mimic improve MODEL.mimic`` searches three small things instead:

* a time warp ``rate``: the motion plays ``rate`` times faster (a kick's swing reaches the ball
  sooner; a walk's gait period shortens);
* per-joint offsets ``b_j`` [rad]: the reference of joint j moves by b_j throughout (e.g. the
  support leg leans against the tip toward the kicking side);
* per-joint gains ``g_j``: joint j's swing around the motion's mean output is scaled by g_j
  (a larger or smaller swing of the kicking leg).

So the corrected reference is ``q'_j(t) = mean_j + g_j (q_j(rate t) - mean_j) + b_j``, with
``mean_j`` the network's output mean for joint j. All three are exact edits of the model's
input mapping and output de-standardisation (``MotionModel``): time models get
``input_offset_s / rate`` and ``input_scale_per_s * rate``, phase models ``period_s / rate``;
outputs get ``output_std_j * g_j`` and ``output_mean_j + b_j``. The network weights stay as
they were, and the corrected model is an ordinary ``.mimic`` file that every command plays;
``source.correction`` in its metadata records the correction.

A correction over a **time window** (``windowed_model``, ``mimic improve --window A,B``)
moves the offsets and gains only within ``A..B`` seconds of the motion, faded in and out over
``WINDOW_RAMP_S`` (half a cosine), and warps time only from ``A`` on, so a search can work on
the part of a motion where the copy fails and leave the rest as learned (issue 35: the T1's
back get-up rolls onto its front as recorded, then falls back from its kneel-sit). That
correction is no edit of the output scaling: the model is a ``model.windowed.WindowedModel``
(the network's own output plus the correction, exact), and its file keeps the network as
learned and the correction in its metadata, which ``load_model`` reads back. (A network
trained again on the corrected output, every 0.02 s, was tried: the T1 back get-up's copy
that stood up in 9 of 10 runs with the exact correction stood in 2 of 10 distilled.)
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mimic.model.keys import CORRECTION_KEY
from mimic.model.motion_model import MotionModel
from mimic.model.windowed import WINDOW_RAMP_S, WindowedModel, window_weight

__all__ = [
    "corrected_model",
    "windowed_model",
    "WindowedModel",
    "window_weight",
    "WINDOW_RAMP_S",
    "CORRECTION_KEY",
]


def corrected_model(
    model: MotionModel,
    rate: float,
    offsets_rad: np.ndarray,
    gains: np.ndarray,
    *,
    provenance: dict | None = None,
) -> MotionModel:
    """``model`` with a time warp, per-joint offsets and gains baked in (module docstring).

    Args:
        rate: time warp (> 0; 1 = unchanged).
        offsets_rad: (N,) reference offsets [rad], the model's joint order.
        gains: (N,) swing gains around the output mean (1 = unchanged).
        provenance: extra JSON-able facts recorded beside the correction.
    """
    n = model.num_joints if hasattr(model, "num_joints") else len(model.joint_names)
    offsets_rad, gains = np.asarray(offsets_rad, float), np.asarray(gains, float)
    if offsets_rad.shape != (n,) or gains.shape != (n,):
        raise ValueError(
            f"offsets and gains need shape ({n},), got {offsets_rad.shape} and {gains.shape}"
        )
    if not rate > 0:
        raise ValueError(f"time warp rate must be > 0, got {rate}")
    mean = np.array(model.output_mean, dtype=np.float64)
    std = np.array(model.output_std, dtype=np.float64)
    mean[:n] += offsets_rad
    std[:n] *= gains
    timing = (
        dict(period_s=model.period_s / rate)
        if model.cyclic
        else dict(
            input_offset_s=model.input_offset_s / rate,
            input_scale_per_s=model.input_scale_per_s * rate,
            duration_s=model.duration_s / rate,
        )
    )
    previous = model.metadata.get(CORRECTION_KEY)
    record = {
        "rate": float(rate),
        "offsets_rad": {j: float(b) for j, b in zip(model.joint_names, offsets_rad) if b},
        "gains": {j: float(g) for j, g in zip(model.joint_names, gains) if g != 1.0},
        **(provenance or {}),
    }
    if previous:  # a correction of a corrected model: keep the chain
        record["previous"] = previous
    return dataclasses.replace(
        model,
        output_mean=mean,
        output_std=std,
        metadata={**model.metadata, CORRECTION_KEY: record},
        **timing,
    )


def windowed_model(
    model: MotionModel,
    rate: float,
    window_s: tuple[float, float],
    offsets_rad: np.ndarray,
    gains: np.ndarray,
    *,
    track: tuple[np.ndarray, np.ndarray] | None = None,
    provenance: dict | None = None,
) -> WindowedModel:
    """``model`` played ``rate`` times faster from the window's start on, with per-joint
    offsets and gains (as ``corrected_model``'s) only within ``window_s`` [s of the motion
    as learned]; before the window it plays as learned. A model corrected in a window
    already takes a second window on top (in its played time; e.g. the T1 back get-up's
    rise, then its stand). ``track``: offsets that vary within the window, (knot times (K,)
    [s of the motion as learned, increasing], offsets (K, N) [rad]), linear between knots
    (``improve.follow``)."""
    if model.cyclic:
        raise ValueError("a windowed correction is for one-shot motions (a cyclic one: none)")
    if not rate > 0:
        raise ValueError(f"time warp rate must be > 0, got {rate}")
    n = model.num_joints
    offsets_rad, gains = np.asarray(offsets_rad, float), np.asarray(gains, float)
    if offsets_rad.shape != (n,) or gains.shape != (n,):
        raise ValueError(
            f"offsets and gains need shape ({n},), got {offsets_rad.shape} and {gains.shape}"
        )
    lo, hi = (float(v) for v in window_s)
    if not 0 <= lo < hi:
        raise ValueError(f"a correction window runs from >= 0 to a later time, got {lo}-{hi}")
    record = {
        "rate": float(rate),
        "window_s": [lo, hi],
        "learned_duration_s": float(model.duration_s),
        "offsets_rad": {j: float(b) for j, b in zip(model.joint_names, offsets_rad) if b},
        "gains": {j: float(g) for j, g in zip(model.joint_names, gains) if g != 1.0},
        **(provenance or {}),
    }
    if track is not None:
        knots, values = np.asarray(track[0], float), np.asarray(track[1], float)
        if knots.ndim != 1 or values.shape != (len(knots), n) or len(knots) < 1:
            raise ValueError(
                f"an offset track needs K knot times and (K, {n}) offsets, got "
                f"{knots.shape} and {values.shape}"
            )
        if np.any(np.diff(knots) <= 0):
            raise ValueError("an offset track's knot times must increase")
        track = (knots, values)
        record["track_s"] = [float(v) for v in knots]
        record["track_offsets_rad"] = {
            j: [float(v) for v in values[:, i]]
            for i, j in enumerate(model.joint_names)
            if np.any(values[:, i])
        }
    previous = model.metadata.get(CORRECTION_KEY)
    if previous:
        record["previous"] = previous
    marked = dataclasses.replace(model, metadata={**model.metadata, CORRECTION_KEY: record})
    return WindowedModel.of(marked, (lo, hi), rate, offsets_rad, gains, track)
