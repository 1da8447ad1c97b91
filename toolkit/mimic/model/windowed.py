"""A learned one-shot model corrected within a time window (``mimic improve --window``,
``improve.correction.windowed_model``): the network as learned, and on its output a time warp
from the window's start on and per-joint offsets and gains inside the window, and optionally an
offset *track*: per-joint offsets that vary over the window, linear between knots
(``improve.follow`` fits one so the copy follows its recording). Its file keeps the network
and the correction (``model.keys.CORRECTION_KEY``: ``window_s``, ``rate``, ``offsets_rad``,
``gains``, ``learned_duration_s``, and with a track ``track_s`` and ``track_offsets_rad``);
``load_model`` gives this class back."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields

import numpy as np

from mimic.model.motion_model import MotionModel

__all__ = ["WindowedModel", "window_weight", "WINDOW_RAMP_S"]

#: How long a windowed correction takes to fade in and out at the window's edges [s].
WINDOW_RAMP_S = 0.2


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
    # An offset track on top of the constant offsets: knot times (K,) [s of the motion as
    # learned, like ``window_s``] and offsets (K, N) [rad], linear between knots, held flat
    # beyond the first and last; None: none.
    track_s: np.ndarray | None = None
    track_offsets_rad: np.ndarray | None = None
    # A model corrected in a window already (its own window, in its played time), corrected
    # again on top: this window's time and output are the inner model's played ones.
    inner: WindowedModel | None = None

    @classmethod
    def of(
        cls, model: MotionModel, window_s, rate, offsets_rad, gains, track=None
    ) -> WindowedModel:
        """``model`` (as learned, or corrected in a window already) with the correction;
        ``track``: (knot times (K,) [s], offsets (K, N) [rad]) or None."""
        values = {f.name: getattr(model, f.name) for f in fields(MotionModel)}
        lo = float(window_s[0])
        values["duration_s"] = lo + max(0.0, model.duration_s - lo) / rate
        return cls(
            **values,
            window_s=(lo, float(window_s[1])),
            warp_rate=float(rate),
            window_offsets_rad=np.asarray(offsets_rad, float),
            window_gains=np.asarray(gains, float),
            inner=model if isinstance(model, WindowedModel) else None,
            track_s=None if track is None else np.asarray(track[0], float),
            track_offsets_rad=None if track is None else np.asarray(track[1], float),
        )

    def track_at(self, time_s: np.ndarray) -> np.ndarray:
        """(T, N) the offset track at motion times ``time_s`` [s] (zeros without one)."""
        t = np.atleast_1d(np.asarray(time_s, float))
        if self.track_s is None:
            return np.zeros((len(t), self.num_joints))
        return np.stack(
            [np.interp(t, self.track_s, column) for column in self.track_offsets_rad.T], axis=1
        )

    def motion_time_s(self, time_s) -> np.ndarray:
        """(T,) the learned motion's time [s] at played times ``time_s`` [s]."""
        t = np.atleast_1d(np.asarray(time_s, float))
        lo = self.window_s[0]
        return np.where(t < lo, t, lo + self.warp_rate * (t - lo))

    def predict(self, time_s) -> np.ndarray:
        t = self.motion_time_s(time_s)
        below = super().predict(t) if self.inner is None else self.inner.predict(t)
        out = np.atleast_2d(below).copy()
        n = self.num_joints
        w = window_weight(t, *self.window_s)[:, None]
        y, mean = out[:, :n], np.asarray(self.output_mean, float)[:n]
        offsets = self.window_offsets_rad + self.track_at(t)
        out[:, :n] = y + w * (offsets + (self.window_gains - 1.0) * (y - mean))
        return out[0] if np.ndim(time_s) == 0 else out

    @classmethod
    def from_record(cls, model: MotionModel, record: dict) -> WindowedModel:
        """The model a file holds: ``model`` as loaded (the network as learned, the played
        duration) and the correction its metadata records (``CORRECTION_KEY``; a windowed
        correction it corrects in turn is its ``previous``)."""
        names = model.joint_names
        offsets = np.array([float(record.get("offsets_rad", {}).get(j, 0.0)) for j in names])
        gains = np.array([float(record.get("gains", {}).get(j, 1.0)) for j in names])
        previous = record.get("previous")
        if isinstance(previous, dict) and "window_s" in previous:
            learned = cls.from_record(model, previous)
        else:
            learned = dataclasses.replace(model, duration_s=float(record["learned_duration_s"]))
        track = None
        if "track_s" in record:
            knots = np.asarray(record["track_s"], float)
            columns = record.get("track_offsets_rad", {})
            track = (
                knots,
                np.stack(
                    [np.asarray(columns.get(j, np.zeros(len(knots))), float) for j in names], 1
                ),
            )
        return cls.of(learned, record["window_s"], float(record["rate"]), offsets, gains, track)
