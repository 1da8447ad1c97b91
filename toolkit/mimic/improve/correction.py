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
correction is no edit of the output scaling: the candidates are played as a
``WindowedModel`` (the model's own output plus the correction), and the one written is
distilled (``distilled``): a network of the same preset trained on the candidate's output
every ``DISTIL_STEP_S``, an ordinary model again.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields

import numpy as np

from mimic.learn.dataset import Dataset
from mimic.learn.presets import get_preset
from mimic.learn.train import TrainConfig, train_model
from mimic.model.keys import CORRECTION_KEY
from mimic.model.motion_model import MotionModel

__all__ = [
    "corrected_model",
    "windowed_model",
    "WindowedModel",
    "distilled",
    "window_weight",
    "CORRECTION_KEY",
]

#: How long a windowed correction takes to fade in and out at the window's edges [s].
WINDOW_RAMP_S = 0.2
#: Sample step of the output a windowed correction is distilled from [s] (a cycle).
DISTIL_STEP_S = 0.02
#: Epochs of the distillation (None: the model's preset as it is).
DISTIL_EPOCHS: int | None = None


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


def window_weight(time_s: np.ndarray, start_s: float, end_s: float) -> np.ndarray:
    """(T,) 0 outside ``start_s..end_s`` [s], 1 inside, a half cosine over ``WINDOW_RAMP_S``
    at either edge (inside the window)."""
    t = np.asarray(time_s, float)
    ramp = min(WINDOW_RAMP_S, 0.5 * (end_s - start_s))
    rise = np.clip((t - start_s) / ramp, 0.0, 1.0)
    fall = np.clip((end_s - t) / ramp, 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * np.minimum(rise, fall))


@dataclass
class WindowedModel(MotionModel):
    """A one-shot model corrected within a time window ``window_s`` [s of the motion as
    learned]: from the window's start on it plays ``warp_rate`` times faster, and within the
    window its references get offsets and gains on top of its own output. Played as it is,
    saved once ``distilled``."""

    window_s: tuple[float, float] = (0.0, 0.0)
    warp_rate: float = 1.0
    window_offsets_rad: np.ndarray | None = None
    window_gains: np.ndarray | None = None

    @classmethod
    def of(cls, model: MotionModel, window_s, rate, offsets_rad, gains) -> WindowedModel:
        values = {f.name: getattr(model, f.name) for f in fields(MotionModel)}
        lo = float(window_s[0])
        values["duration_s"] = lo + max(0.0, model.duration_s - lo) / rate
        return cls(
            **values,
            window_s=(lo, float(window_s[1])),
            warp_rate=float(rate),
            window_offsets_rad=np.asarray(offsets_rad, float),
            window_gains=np.asarray(gains, float),
        )

    def motion_time_s(self, time_s) -> np.ndarray:
        """(T,) the learned motion's time [s] at played times ``time_s`` [s]."""
        t = np.atleast_1d(np.asarray(time_s, float))
        lo = self.window_s[0]
        return np.where(t < lo, t, lo + self.warp_rate * (t - lo))

    def predict(self, time_s) -> np.ndarray:
        t = self.motion_time_s(time_s)
        out = np.atleast_2d(super().predict(t)).copy()
        n = self.num_joints
        w = window_weight(t, *self.window_s)[:, None]
        y, mean = out[:, :n], np.asarray(self.output_mean, float)[:n]
        out[:, :n] = y + w * (self.window_offsets_rad + (self.window_gains - 1.0) * (y - mean))
        return out[0] if np.ndim(time_s) == 0 else out


def windowed_model(
    model: MotionModel,
    rate: float,
    window_s: tuple[float, float],
    offsets_rad: np.ndarray,
    gains: np.ndarray,
    *,
    provenance: dict | None = None,
) -> WindowedModel:
    """``model`` played ``rate`` times faster from the window's start on, with per-joint
    offsets and gains (as ``corrected_model``'s) only within ``window_s`` [s of the motion
    as learned]; before the window it plays as learned."""
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
        "offsets_rad": {j: float(b) for j, b in zip(model.joint_names, offsets_rad) if b},
        "gains": {j: float(g) for j, g in zip(model.joint_names, gains) if g != 1.0},
        **(provenance or {}),
    }
    previous = model.metadata.get(CORRECTION_KEY)
    if previous:
        record["previous"] = previous
    marked = dataclasses.replace(model, metadata={**model.metadata, CORRECTION_KEY: record})
    return WindowedModel.of(marked, (lo, hi), rate, offsets_rad, gains)


def distilled(model: MotionModel, seed: int = 0) -> MotionModel:
    """An ordinary model (network, output scaling) trained on ``model``'s output every
    ``DISTIL_STEP_S`` over its duration, with ``model``'s preset and metadata."""
    t = np.arange(0.0, model.duration_s + 1e-9, DISTIL_STEP_S)
    if t[-1] < model.duration_s - 1e-9:
        t = np.r_[t, model.duration_s]
    targets = np.asarray(model.predict(t), float).copy()
    targets[:, -1] = 0.0
    targets[-1, -1] = 1.0  # a one-shot motion ends at its last sample
    ds = Dataset(t, targets, model.robot, model.joint_names, None, dict(model.metadata))
    out = train_model(ds, TrainConfig(get_preset(model.preset), seed=seed, epochs=DISTIL_EPOCHS))
    return dataclasses.replace(out, metadata=dict(model.metadata))
