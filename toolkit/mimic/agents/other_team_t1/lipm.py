"""The T1 team's step plan: the linear inverted pendulum over one fixed-time step.

The centre of mass at a constant height z over the zero-moment point p obeys
x'' = w^2 (x - p), w = sqrt(g / z). With the ZMP kept at the support foot and a gait whose
steps are mirror images, the closed-form solutions give the torso's path over a step:

* sagittal: from half a step behind the support foot to half a step ahead,
  x(t) = (L / 2) sinh(w (t - T/2)) / sinh(w T / 2) (fastest at the support exchange);
* lateral: from the centre line toward the support foot and back,
  y(t) = A (1 - cosh(w (t - T/2)) / cosh(w T / 2)) / (1 - 1 / cosh(w T / 2)), peak A mid-step.

The swing foot travels on a cosine between lift-off and touch-down and lifts on a raised
cosine. Everything here is per step and dimensionless in the step's phase (0..1).
"""

from __future__ import annotations

import math

from mimic.world.base import GRAVITY_M_S2

__all__ = ["pendulum_rate_per_s", "advance", "sway", "swing"]


def pendulum_rate_per_s(height_m: float) -> float:
    """w = sqrt(g / z) [1/s]."""
    return math.sqrt(GRAVITY_M_S2 / height_m)


def advance(phase: float, w_per_s: float, step_s: float) -> float:
    """How far the torso has advanced over the step, as a fraction of the step (0 .. 1)."""
    half = 0.5 * w_per_s * step_s
    return 0.5 + 0.5 * math.sinh(w_per_s * step_s * (phase - 0.5)) / math.sinh(half)


def sway(phase: float, w_per_s: float, step_s: float) -> float:
    """Torso shift toward the support foot as a fraction of its peak (0 at both ends, 1
    mid-step)."""
    peak = math.cosh(0.5 * w_per_s * step_s)
    return (peak - math.cosh(w_per_s * step_s * (phase - 0.5))) / (peak - 1.0)


def swing(phase: float, lift_off: float, touch_down: float) -> tuple[float, float]:
    """Swing foot progress (0 .. 1 from its start to its target) and lift (0 .. 1 of the
    step height) at ``phase``; on the ground before ``lift_off`` and after ``touch_down``."""
    u = min(1.0, max(0.0, (phase - lift_off) / (touch_down - lift_off)))
    return 0.5 - 0.5 * math.cos(math.pi * u), 0.5 - 0.5 * math.cos(2 * math.pi * u)
