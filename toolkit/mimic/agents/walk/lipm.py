"""The linear inverted pendulum, solved in closed form for one step.

The centre of mass at a constant height z_c over a point support obeys x'' = k^2 (x - p) with
k = sqrt(g / z_c). For a periodic gait whose step starts and ends with the centre of mass
symmetric about the support point, the solutions are hyperbolic: the sagittal position runs
from -d/2 to +d/2 over the support foot following a sinh, and the lateral position swings
toward the support foot following a cosh, with continuous velocity at the support exchange.
"""

from __future__ import annotations

import math

from mimic.world.base import GRAVITY_M_S2

__all__ = ["pendulum_rate_per_s", "sagittal_fraction", "lateral_fraction"]


def pendulum_rate_per_s(com_height_m: float) -> float:
    """k = sqrt(g / z_c) [1/s]."""
    return math.sqrt(GRAVITY_M_S2 / com_height_m)


def sagittal_fraction(phase: float, k_per_s: float, step_s: float) -> float:
    """Centre of mass ahead of the support point, as a fraction of the step length.

    Runs from -1/2 (phase 0) through 0 (mid-step) to +1/2 (phase 1); the LIPM solution
    x(t) = (d/2) sinh(k (t - T/2)) / sinh(k T / 2).
    """
    half = 0.5 * k_per_s * step_s
    return 0.5 * math.sinh(k_per_s * step_s * (phase - 0.5)) / math.sinh(half)


def lateral_fraction(phase: float, k_per_s: float, step_s: float) -> float:
    """Centre of mass shift toward the support foot, as a fraction of the foot's offset.

    The LIPM solution with the centre of mass on the mid-line at the support exchange:
    y(t) = w (1 - cosh(k (t - T/2)) / cosh(k T / 2)); 0 at phase 0 and 1, largest mid-step.
    """
    return 1.0 - math.cosh(k_per_s * step_s * (phase - 0.5)) / math.cosh(0.5 * k_per_s * step_s)
