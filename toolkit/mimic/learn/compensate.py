"""Compensated targets: references that reproduce an *observed* trajectory through the tracking.

The study learned its walk from joint angles *reached* in the simulator and replayed the
network's output through the same proportional tracking, so the motion was attenuated twice
(and the learned walk lost most of its speed). Given observed angles q[k] (``/joint_states``,
one sample per 20 ms cycle) we instead solve for the reference r[k] that the robot's speed
servos (``mimic.robot.actuators.SpeedServos.track``, gain and cap from the robot's actuator
model)

    speed[k] = clip(gain * (r[k] - q[k]), -cap, cap)

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

Only robots with speed servos (our NAO) track references this way; for a robot with PD
motors (the league's T1 and K1) compensation is not defined and is refused.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.errors import MimicError
from mimic.robot.actuators import SpeedServos
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot

__all__ = [
    "CompensationConfig",
    "compensate_references",
    "references_from_angles",
    "simulate_tracking",
    "speed_servos",
]


@dataclass(frozen=True)
class CompensationConfig:
    """How references are reconstructed from observed angles (the gain and the speed cap
    are the robot's: its ``SpeedServos``)."""

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


def speed_servos(robot: str | RobotDescription) -> SpeedServos:
    """The robot's speed servos, or one clear line for a robot that has none.

    Raises:
        MimicError: the robot has PD motors (they track a reference by torque, so there is no
            speed command to invert).
    """
    robot = get_robot(robot)
    if not isinstance(robot.actuator, SpeedServos):
        raise MimicError(
            f"compensated targets need speed servos; the {robot.name} has "
            f"{robot.actuator.kind}: learn its reached angles (--target reached)"
        )
    return robot.actuator


def compensate_references(
    time_s: np.ndarray,
    angles_rad: np.ndarray,
    robot: str | RobotDescription,
    config: CompensationConfig = CompensationConfig(),
) -> np.ndarray:
    """References (T, N) that reproduce observed angles (T, N) [rad] of ``robot`` (its joint
    order) sampled at times (T,) [s] through its speed servos, clipped to its joint limits
    widened by ``config.limit_margin_rad``.

    Raises:
        MimicError: the robot has no speed servos (``speed_servos``), or the angles are not
            (T, N) for its N joints.
    """
    robot = get_robot(robot)
    servos = speed_servos(robot)
    q = np.asarray(angles_rad, dtype=float)
    if q.ndim != 2 or q.shape[1] != robot.num_joints:
        raise MimicError(
            f"compensation: the {robot.name} has {robot.num_joints} joints, got "
            f"angles of shape {q.shape}"
        )
    ref = references_from_angles(time_s, q, servos, config)
    gain, cap = servos.tracking_gain_per_s, servos.max_speed_rad_s
    m = cap / gain if config.limit_margin_rad is None else config.limit_margin_rad
    return np.clip(ref, robot.lower_limits_rad - m, robot.upper_limits_rad + m)


def references_from_angles(
    time_s: np.ndarray,
    angles_rad: np.ndarray,
    servos: SpeedServos,
    config: CompensationConfig = CompensationConfig(),
) -> np.ndarray:
    """The inversion alone: references (T, J) that drive ``servos`` through observed angles
    (T, J) [rad] at times (T,) [s], for any J joints (no limit clip)."""
    if config.saturated_reference not in ("nearest", "toward"):
        raise ValueError(
            f"saturated_reference must be 'nearest' or 'toward', got {config.saturated_reference!r}"
        )
    t = np.asarray(time_s, dtype=float)
    q = np.asarray(angles_rad, dtype=float)
    gain, cap = servos.tracking_gain_per_s, servos.max_speed_rad_s
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
    return ref


def simulate_tracking(
    time_s: np.ndarray, reference_rad: np.ndarray, start_rad: np.ndarray, servos: SpeedServos
) -> np.ndarray:
    """Angles (T, J) of ideal first-order joints driven by ``servos`` toward references
    (T, J) [rad]: q[k+1] = q[k] + dt * servos.track(r[k], q[k]).

    The model ``references_from_angles`` inverts (no servo lag, no stops, no load).
    """
    t = np.asarray(time_s, dtype=float)
    r = np.asarray(reference_rad, dtype=float)
    q = np.empty_like(r)
    q[0] = start_rad
    for k in range(len(t) - 1):
        q[k + 1] = q[k] + (t[k + 1] - t[k]) * servos.track(r[k], q[k])
    return q
