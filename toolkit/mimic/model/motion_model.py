"""A trained motion network with everything needed to query it: time (or phase) in, the robot's
N joint references [rad] + the ended flag out."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mimic.model.network import LEAKY_SLOPE, Layout
from mimic.robot.registry import DEFAULT_ROBOT, get_robot

__all__ = ["MotionModel", "INPUT_TIME", "INPUT_PHASE"]

#: Input kinds: time from the motion start, or the phase of a cyclic motion (sin, cos).
INPUT_TIME = "time"
INPUT_PHASE = "phase"


@dataclass
class MotionModel:
    """A motion network.

    Input mapping: ``time``: x = (t - input_offset_s) * input_scale_per_s (one input);
    ``phase``: x = (sin 2 pi t / period_s, cos 2 pi t / period_s). Output: y = net(x) *
    output_std + output_mean; y[:N] are joint references [rad] in ``joint_names`` order (the
    robot's), y[N] the ended flag (> 0.5: the motion has ended).

    Attributes:
        layout: network shape (``layout.out_dim`` = N + 1).
        params: (P,) float32 parameters in ``Layout`` order.
        input_kind: ``time`` or ``phase``.
        input_offset_s, input_scale_per_s: the time input mapping (time models).
        period_s: period of a cyclic motion [s] (phase models), else None.
        duration_s: time of the last training sample [s].
        output_mean, output_std: (N + 1,) output de-standardisation (None: 0 and 1).
        preset: name of the training preset.
        robot: name of the robot the motion was learned on (``mimic.robot.registry``).
        joint_names: (N,) the joint order of the outputs (empty: the registered robot's).
        metrics: training metrics (see ``mimic.learn.train.evaluate``).
        metadata: the source recording's metadata (motion, team, ball_offset_m, ...).
    """

    layout: Layout
    params: np.ndarray
    input_kind: str = INPUT_TIME
    input_offset_s: float = 0.0
    input_scale_per_s: float = 1.0
    period_s: float | None = None
    duration_s: float = 0.0
    output_mean: np.ndarray | None = None
    output_std: np.ndarray | None = None
    preset: str = "paper"
    robot: str = DEFAULT_ROBOT
    joint_names: tuple[str, ...] = ()
    metrics: dict = field(default_factory=dict)
    metadata: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not self.joint_names:
            self.joint_names = get_robot(self.robot).joint_names
        self.joint_names = tuple(self.joint_names)
        if len(self.joint_names) + 1 != self.layout.out_dim:
            raise ValueError(
                f"{len(self.joint_names)} {self.robot} joints + the ended flag "
                f"do not match a network with {self.layout.out_dim} outputs"
            )
        if self.output_mean is None:
            self.output_mean = np.zeros(self.layout.out_dim)
        if self.output_std is None:
            self.output_std = np.ones(self.layout.out_dim)
        # float64 copies of the layers for queries: a 5123-parameter network costs a few
        # microseconds per call this way.
        self._layers = self.layout.layers(np.asarray(self.params, dtype=np.float64))

    @property
    def name(self) -> str:
        return str(self.metadata.get("motion") or "motion")

    @property
    def num_joints(self) -> int:
        """N: joint outputs before the ended flag."""
        return len(self.joint_names)

    @property
    def cyclic(self) -> bool:
        return self.input_kind == INPUT_PHASE

    def network_inputs(self, time_s: np.ndarray) -> np.ndarray:
        """(T, in_dim) network inputs for times (T,) [s]."""
        t = np.asarray(time_s, dtype=np.float64).reshape(-1)
        if self.input_kind == INPUT_PHASE:
            angle = (2.0 * math.pi / self.period_s) * t
            return np.stack([np.sin(angle), np.cos(angle)], axis=1)
        return ((t - self.input_offset_s) * self.input_scale_per_s)[:, None]

    def raw(self, x: np.ndarray) -> np.ndarray:
        """Network output (T, N + 1) for network inputs x (T, in_dim), before de-standardising."""
        h = x
        last = len(self._layers) - 1
        for i, (w, b) in enumerate(self._layers):
            h = h @ w + b
            if i < last:
                h = np.maximum(h, LEAKY_SLOPE * h)  # LeakyReLU for slope < 1
        return h

    def predict(self, time_s) -> np.ndarray:
        """(T, N + 1) outputs for times (T,) [s] (a scalar time gives (N + 1,)): joint
        references [rad] in ``joint_names`` order, then the ended flag."""
        scalar = np.ndim(time_s) == 0
        y = self.raw(self.network_inputs(time_s)) * self.output_std + self.output_mean
        return y[0] if scalar else y
