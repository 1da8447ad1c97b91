"""Compensated targets: references that reproduce an *observed* trajectory through the tracking.

The study learned its walk from joint angles *reached* in the simulator and replayed the
network's output through the same proportional tracking, so the motion was attenuated twice
(and the learned walk lost most of its speed). Given observed angles q[k] (``/joint_states``,
one sample per 20 ms cycle) we instead solve for the reference r[k] that the controller

    speed[k] = clip(gain * (r[k] - q[k]), -cap, cap)      (``mimic.agents.tracking``)

must receive so the joint moves from q[k] to q[k+1]:

* unsaturated: r[k] = q[k] + v[k] / gain with v[k] = (q[k+1] - q[k]) / dt[k]. The forward
  difference is the right one: the command sent at cycle k is what moves the joint during
  [t_k, t_k+1]; a central difference would mix in the previous command and lag half a cycle.
  The last sample has no successor: its reference is the angle itself (hold).
* saturated (|v[k]| >= cap * (1 - saturation_tol)): any r[k] with gain*(r - q) >= cap gives the
  same speed, so the reference is not identifiable; we only know r[k] >= q[k] + cap/gain in the
  direction of motion. Choice (``saturated_reference="nearest"``): the nearest such reference,
  r[k] = q[k] + (1 + margin) cap/gain, which keeps the command at the cap and moves smoothly
  with the joint. The alternative, ``"toward"``, jumps to the first unsaturated reference after
  the segment (the point the joint runs toward); the network can fit such a step only as a
  ramp that starts early. On our kick, learned from observed angles with 4 network seeds, no
  "toward" model kicked without falling, and one "nearest" model stayed up in 3 of 4 tries;
  the kick is marginal either way. On the other team's walk with balance, both rules finished 28-29 of 32 runs.
* finally every reference is clipped to the joint limits widened by ``limit_margin_rad``
  (default cap/gain: a reference that far past a stop already asks for the full speed cap at
  the stop, so clipping there changes no command; farther references only make the network's
  job harder).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.agents.tracking import DEFAULT_GAIN_PER_S
from mimic.robot.joints import lower_limits_rad, upper_limits_rad
from mimic.robot.mjcf import MAX_JOINT_SPEED_RAD_S

__all__ = ["CompensationConfig", "compensate_references", "simulate_tracking"]


@dataclass(frozen=True)
class CompensationConfig:
    """How references are reconstructed from observed angles."""

    # Proportional tracking gain [1/s] (the players' ``TrackingController``).
    gain_per_s: float = DEFAULT_GAIN_PER_S
    # Joint speed cap [rad/s].
    max_speed_rad_s: float = MAX_JOINT_SPEED_RAD_S
    # A sample counts as saturated when |speed| >= cap * (1 - this).
    saturation_tol: float = 0.02
    # Extra lead past the saturation bound (share of cap/gain), so the replayed command stays
    # at the cap despite small tracking differences.
    saturation_margin: float = 0.05
    # References are clipped to [lower - m, upper + m] [rad]; None: m = cap / gain.
    limit_margin_rad: float | None = None
    # Reference in a saturated segment: "nearest" (angle + the lead that keeps the command at
    # the cap) or "toward" (the first unsaturated reference after the segment, if farther).
    saturated_reference: str = "nearest"


def compensate_references(time_s: np.ndarray, angles_rad: np.ndarray,
                          config: CompensationConfig = CompensationConfig()) -> np.ndarray:
    """References (N, J) that reproduce observed angles (N, J) [rad] sampled at times (N,) [s].

    J is 22 for clipping to the robot's joint limits; other widths skip the limit clip.
    """
    if config.saturated_reference not in ("nearest", "toward"):
        raise ValueError(f"saturated_reference must be 'nearest' or 'toward', "
                         f"got {config.saturated_reference!r}")
    t = np.asarray(time_s, dtype=float)
    q = np.asarray(angles_rad, dtype=float)
    gain, cap = config.gain_per_s, config.max_speed_rad_s
    speed = np.zeros_like(q)
    if len(t) > 1:
        speed[:-1] = np.diff(q, axis=0) / np.diff(t)[:, None]
    ref = q + speed / gain
    saturated = np.abs(speed) >= cap * (1.0 - config.saturation_tol)
    lead = (1.0 + config.saturation_margin) * cap / gain
    for j in range(q.shape[1]):
        k, n = 0, len(t)
        while k < n:
            if not saturated[k, j]:
                k += 1
                continue
            sign = np.sign(speed[k, j])
            end = k
            while end < n and saturated[end, j] and np.sign(speed[end, j]) == sign:
                end += 1
            target = ref[end, j] if end < n else q[-1, j]
            seg = slice(k, end)
            bound = q[seg, j] + sign * lead
            if config.saturated_reference == "nearest":
                ref[seg, j] = bound
            else:
                ref[seg, j] = np.maximum(bound, target) if sign > 0 else np.minimum(bound, target)
            k = end
    if q.shape[1] == len(lower_limits_rad()):
        m = cap / gain if config.limit_margin_rad is None else config.limit_margin_rad
        ref = np.clip(ref, lower_limits_rad() - m, upper_limits_rad() + m)
    return ref


def simulate_tracking(time_s: np.ndarray, reference_rad: np.ndarray, start_rad: np.ndarray,
                      config: CompensationConfig = CompensationConfig()) -> np.ndarray:
    """Angles (N, J) of ideal first-order joints driven by the proportional speed controller
    toward references (N, J): q[k+1] = q[k] + dt * clip(gain (r[k] - q[k]), +-cap).

    The model ``compensate_references`` inverts (no servo lag, no stops, no load).
    """
    t = np.asarray(time_s, dtype=float)
    r = np.asarray(reference_rad, dtype=float)
    q = np.empty_like(r)
    q[0] = start_rad
    for k in range(len(t) - 1):
        v = np.clip(config.gain_per_s * (r[k] - q[k]), -config.max_speed_rad_s,
                    config.max_speed_rad_s)
        q[k + 1] = q[k] + (t[k + 1] - t[k]) * v
    return q
