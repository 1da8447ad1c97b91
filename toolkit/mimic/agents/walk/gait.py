"""Gait parameters and the foot trajectories of one step.

Feet are planned in the *walk frame*: origin at the torso centre, x forward, y left, z up,
but level (no torso tilt). A foot pose is (x, y, z, yaw) of its ankle-roll anchor [m, rad].
Each step has a support foot and a swing foot; both move between a start pose (where the
previous step left them) and an end pose fixed when the step begins:

    support end = nominal - c/2 + bias,   swing end = nominal + c/2 + bias,

where c = (dx, dy, dyaw) is the step command (torso motion per step) and the bias moves both
feet outward by |dy|/2 and |dyaw|/2, so that the feet open toward the walking side and never
cross (the hip yaw-pitch joints can only turn the feet outward).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.walk.lipm import lateral_fraction, pendulum_rate_per_s, sagittal_fraction

__all__ = ["WalkConfig", "StepPlan", "nominal_foot", "plan_step", "feet_at"]


@dataclass(frozen=True)
class WalkConfig:
    """Walk engine parameters."""

    # Duration of one step (half a gait cycle) [s].
    step_s: float = 0.1799
    # Ankle-roll anchors below the torso centre while walking [m] (stand pose: 0.325).
    ankle_depth_m: float = 0.2709
    # Ankle x in the walk frame at the nominal stance [m] (moves the CoM over the feet).
    ankle_x_m: float = -0.0185
    # Half the lateral distance between the ankles at the nominal stance [m].
    ankle_half_width_m: float = 0.055
    # Swing foot lift at mid-step [m].
    step_height_m: float = 0.05
    # Pendulum height for k = sqrt(g / z) [m].
    com_height_m: float = 0.2256
    # Lateral sway: torso shift toward the support foot = this * ankle_half_width * LIPM
    # fraction (1.0 = the LIPM amplitude for point feet).
    sway_gain: float = 0.129
    # Blend of the sagittal profile between linear (0) and LIPM sinh (1).
    lipm_blend: float = 0.9635
    # Torso forward lean [rad] (feet rotated back in the torso frame).
    torso_pitch_rad: float = -0.0125
    # Torso pitch added per m/s of forward speed [rad s/m].
    torso_pitch_per_speed: float = 0.0
    # Largest torso motion per step: forward/backward [m], sideways [m], turn [rad].
    max_step_x_m: float = 0.13
    max_step_y_m: float = 0.04
    max_step_yaw_rad: float = 0.35
    # Largest change of the per-step command from one step to the next: [m], [m], [rad].
    max_step_change_x_m: float = 0.04
    max_step_change_y_m: float = 0.01
    max_step_change_yaw_rad: float = 0.1
    # Gyro feedback [rad per rad/s] from torso pitch rate onto the ankle pitch angles and from
    # torso roll rate onto the ankle roll angles.
    gyro_pitch_gain: float = -0.0258
    gyro_roll_gain: float = 0.0202
    # Posture feedback [rad/rad]: torso pitch / roll error onto the hip pitch / roll angles.
    tilt_pitch_gain: float = 0.0345
    tilt_roll_gain: float = -0.3801
    # Heading hold: the commanded yaw rate is integrated into a desired heading and each step's
    # turn gets this fraction of the heading error (from the torso orientation) added.
    heading_gain: float = 0.5944
    # Arm swing: shoulder pitch offset per metre of the opposite foot's forward offset
    # [rad/m]; cancels part of the swing leg's yaw moment.
    arm_swing_rad_per_m: float = -3.2455
    # Time to blend into the walk posture on start and into the stand pose on halt [s].
    blend_s: float = 0.4
    # Feed-forward: add the reference's own speed to the proportional tracking command.
    feedforward: bool = True


@dataclass
class StepPlan:
    """One step: which foot supports and where both feet start and end, rows (left, right),
    columns (x, y, z, yaw)."""

    support: int  # 0 left, 1 right
    start: np.ndarray  # (2, 4)
    end: np.ndarray  # (2, 4)
    command: np.ndarray  # (3,) dx, dy, dyaw per step


def nominal_foot(cfg: WalkConfig, side: int) -> np.ndarray:
    """(4,) nominal pose of foot ``side`` (0 left, 1 right) in the walk frame."""
    s = 1.0 if side == 0 else -1.0
    return np.array([cfg.ankle_x_m, s * cfg.ankle_half_width_m, -cfg.ankle_depth_m, 0.0])


def plan_step(cfg: WalkConfig, support: int, start: np.ndarray, command: np.ndarray) -> StepPlan:
    """The step that starts from feet ``start`` (2, 4) with step command (dx, dy, dyaw)."""
    end = np.empty((2, 4))
    dx, dy, dyaw = command
    for side in (0, 1):
        s = 1.0 if side == 0 else -1.0
        sign = -0.5 if side == support else 0.5
        bias = np.array([0.0, s * abs(dy) / 2, 0.0, s * abs(dyaw) / 2])
        end[side] = nominal_foot(cfg, side) + sign * np.array([dx, dy, 0.0, dyaw]) + bias
    return StepPlan(support, np.asarray(start, dtype=float).copy(), end, np.asarray(command))


def feet_at(cfg: WalkConfig, plan: StepPlan, phase: float, sway_scale: float = 1.0) -> np.ndarray:
    """(2, 4) foot poses in the walk frame at ``phase`` in [0, 1] of the step."""
    k = pendulum_rate_per_s(cfg.com_height_m)
    phase = min(max(phase, 0.0), 1.0)
    lipm = sagittal_fraction(phase, k, cfg.step_s) + 0.5
    support_f = cfg.lipm_blend * lipm + (1 - cfg.lipm_blend) * phase
    swing_f = 0.5 * (1 - math.cos(math.pi * phase))
    feet = np.empty((2, 4))
    sup, sw = plan.support, 1 - plan.support
    feet[sup] = plan.start[sup] + support_f * (plan.end[sup] - plan.start[sup])
    feet[sw] = plan.start[sw] + swing_f * (plan.end[sw] - plan.start[sw])
    feet[sw, 2] += cfg.step_height_m * 0.5 * (1 - math.cos(2 * math.pi * phase))
    # Torso sways toward the support foot: both feet shift the other way in the walk frame.
    toward = 1.0 if sup == 0 else -1.0
    sway = sway_scale * cfg.sway_gain * cfg.ankle_half_width_m * lateral_fraction(phase, k, cfg.step_s)
    feet[:, 1] -= toward * sway
    return feet
