"""Gait parameters and the foot trajectories of one step.

Feet are planned in the *walk frame*: origin at the torso centre, x forward, y left, z up,
but level (no torso tilt). A foot pose is (x, y, z, yaw) of its ankle-roll anchor [m, rad].
Each step has a support foot and a swing foot; both move between a start pose (where the
previous step left them) and an end pose fixed when the step begins:

    support end = nominal - c/2 + bias,   swing end = nominal + c/2 + bias,

where c = (dx, dy, dyaw) is the step command (torso motion per step) and the bias moves both
feet outward by |dy|/2 and |dyaw|/2, so that the feet open toward the walking side and never
cross (the hip yaw-pitch joints can only turn the feet outward).

The support foot slides back under the torso along the pendulum's sinh profile; the swing
foot lifts and travels on a cosine between ``lift_start_fraction`` and ``swing_fraction`` of
the step (landing a little early, before the support exchange); the torso sways toward the
support foot along the pendulum's cosh profile.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from mimic.agents.walk.lipm import lateral_fraction, pendulum_rate_per_s, sagittal_fraction
from mimic.floats import clamp
from mimic.world.base import CYCLE_S

__all__ = [
    "WalkConfig",
    "StepPlan",
    "nominal_foot",
    "plan_step",
    "feet_at",
    "foot_rows_at",
    "foot_fractions",
    "foot_rows",
]


@dataclass(frozen=True)
class WalkConfig:
    """Walk engine parameters.

    The defaults come from our own evolution-strategy search over ~30 of these fields, then a
    few hand-set values (``docs/tuning-notes.md`` tells how).
    """

    # Duration of one step (half a gait cycle) [s]; rounded to whole 20 ms agent cycles.
    step_s: float = 0.14
    # Ankle-roll anchors below the torso centre while walking [m] (stand pose: 0.325).
    ankle_depth_m: float = 0.2785
    # Ankle x in the walk frame at the nominal stance [m] (moves the CoM over the feet).
    ankle_x_m: float = -0.02225
    # Half the lateral distance between the ankles at the nominal stance [m].
    ankle_half_width_m: float = 0.06129
    # Swing foot lift at mid-swing [m].
    step_height_m: float = 0.05622
    # Part of the step the swing foot spends in the air; < 1 lands it early, so the
    # speed-capped joints have put it down before the support exchange.
    swing_fraction: float = 0.9352
    # Part of the step both feet stay down before the swing foot lifts (double support).
    lift_start_fraction: float = 0.01291
    # Pendulum height for k = sqrt(g / z) [m].
    com_height_m: float = 0.2592
    # Lateral sway: torso shift toward the support foot = this * ankle_half_width * LIPM
    # fraction (1.0 = the LIPM amplitude for point feet).
    sway_gain: float = 0.5736
    # Blend of the sagittal profile between linear (0) and LIPM sinh (1).
    lipm_blend: float = 0.8958
    # Torso forward lean [rad] (feet rotated back in the torso frame).
    torso_pitch_rad: float = 0.04059
    # Torso pitch added per m/s of forward speed [rad s/m].
    torso_pitch_per_speed: float = -0.005936
    # Forward step actually commanded per metre of wanted torso advance, calibrated so the
    # walked speed matches the commanded one (the soles slip a little each step).
    stride_scale: float = 1.01
    # Largest torso motion per step: forward/backward [m], sideways [m], turn [rad].
    max_step_x_m: float = 0.13
    max_step_y_m: float = 0.04
    max_step_yaw_rad: float = 0.35
    # Largest change of the per-step command from one step to the next: [m], [m], [rad].
    max_step_change_x_m: float = 0.01141
    max_step_change_y_m: float = 0.01
    max_step_change_yaw_rad: float = 0.1
    # Gyro feedback [rad per rad/s]: torso pitch rate onto the ankle pitch angles, torso roll
    # rate (positive: rolling right) onto the ankle roll angles.
    gyro_pitch_gain: float = -0.01097
    gyro_roll_gain: float = 0.03224
    # Posture feedback [rad/rad]: torso pitch error (positive: leaning forward) and roll
    # (positive: leaning right) onto the hip pitch / roll angles of both legs.
    tilt_pitch_gain: float = 0.5612
    tilt_roll_gain: float = -0.1824
    # Foot placement [rad/rad]: the same errors onto the swing hip only, so the swing foot
    # lands where the torso is falling.
    swing_pitch_gain: float = 0.4197
    swing_roll_gain: float = -0.725
    # Ankle strategy [rad/rad]: the same errors onto the support ankle pitch / roll.
    ankle_pitch_gain: float = -0.2234
    ankle_roll_gain: float = 0.01346
    # Step length feedback at each step start [m/rad], [m per rad/s]: a torso falling
    # forward (pitch error, pitch rate) lengthens the step, one falling back shortens it.
    step_per_pitch_m: float = 0.1077
    step_per_pitch_rate_m_s: float = 0.003554
    # Odometry feedback: each step, this share of the per-step gap between the commanded
    # steps and the torso motion over the last gait period (from ``torso_pos_m``) is added
    # to an integrated correction of the step [1/step], at most these many m per step.
    odometry_gain: float = 0.25
    max_odometry_x_m: float = 0.015
    max_odometry_y_m: float = 0.01
    # The odometry learns only from steps whose torso tilt (pitch error or roll) stayed
    # below this [rad].
    odometry_calm_tilt_rad: float = 0.1
    # The odometry correction fades out linearly toward forward steps this long [m] (0: never).
    odometry_fade_step_m: float = 0.05
    # Caution: when the torso tilted (pitch error or roll) more than this during a step
    # [rad], the next step's forward length is scaled by ``caution_step_scale`` and its turn
    # dropped (0: off).
    caution_tilt_rad: float = 0.25
    caution_step_scale: float = 0.6
    # The walk halts once the ramped command is zero and the feet are this close to the
    # nominal stance (foot pose error, m or rad).
    rest_tolerance_m: float = 0.015
    # Yaw hold within the step [rad/rad]: the support foot turns against the torso's heading
    # error (torso yaw minus the aimed heading), so the torso turns back over a gripping foot.
    yaw_hold_gain: float = 0.03878
    # Heading hold: the commanded yaw rate is integrated into a desired heading and each step's
    # turn gets this fraction of the heading error (from the torso orientation) added.
    heading_gain: float = 0.325
    # Steer the heading hold on the torso yaw averaged over the last gait period (else on
    # the yaw at the step start, which swings with the steps).
    smooth_heading: bool = True
    # Largest lead of the desired heading over the measured one [rad] (anti-windup).
    max_heading_error_rad: float = 0.25
    # ... and at most the commanded yaw rate times this [s].
    heading_lead_s: float = 0.4
    # Line hold while walking straight: the desired heading points back at the line walked
    # so far, this much per metre of sideways offset [rad/m] (at most ``max_line_aim_rad``).
    line_gain: float = 0.2478
    max_line_aim_rad: float = 0.3
    # Line hold while walking sideways or diagonally without turning: a step across the line,
    # this much per metre of offset [m/m], at most ``max_side_line_step_m`` [m].
    side_line_gain: float = 0.05
    max_side_line_step_m: float = 0.01
    # Arm swing: shoulder pitch offset per metre of the opposite foot's forward offset
    # [rad/m]; cancels part of the swing leg's yaw moment.
    arm_swing_rad_per_m: float = -2.661
    # Time to blend into the walk posture on start and into the stand pose on halt [s].
    blend_s: float = 0.4
    # On halt, time to hold the walk stance on both feet (with balance feedback) before
    # blending into the stand pose [s].
    halt_settle_s: float = 0.3
    # Joint speed cap of the planned reference [rad/s] (the servos stop at 6.14 rad/s):
    # the swing leg then lifts and swings as fast as the joints can go, not faster (0: off).
    max_reference_speed_rad_s: float = 4.889
    # Proportional tracking gain of the joint speed commands [1/s] (``SpeedServos.track``).
    tracking_gain_per_s: float = 32.18
    # Feed-forward: share of the planned (feedback-free) reference speed added to the
    # proportional tracking command (0: none, 1: all of it).
    feedforward: float = 0.8934
    # Share of the IMU feedback's change over the cycle fed forward the same way.
    feedback_feedforward: float = 0.4279
    # The proportional term tracks the previous cycle's reference (where the joints should
    # be now) instead of this cycle's (where they should be at its end).
    track_previous: bool = True

    # Worked out once per config (it is frozen): the walk reads them several times a cycle.
    @cached_property
    def step_cycles(self) -> int:
        """Agent cycles per step."""
        return max(2, round(self.step_s / CYCLE_S))

    @cached_property
    def step_time_s(self) -> float:
        """Duration of one step as walked, in whole agent cycles [s]."""
        return self.step_cycles * CYCLE_S


@dataclass
class StepPlan:
    """One step: which foot supports and where both feet start and end, rows (left, right),
    columns (x, y, z, yaw)."""

    support: int  # 0 left, 1 right
    start: np.ndarray  # (2, 4)
    end: np.ndarray  # (2, 4)
    command: np.ndarray  # (3,) dx, dy, dyaw per step
    # ``start`` and ``end - start`` as plain floats, two lists (left, right) of four each:
    # worked out once per step for ``foot_rows``, every cycle (a plan is not changed once
    # made).
    rows: tuple[list[list[float]], list[list[float]]] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.rows = (self.start.tolist(), (self.end - self.start).tolist())


def nominal_foot(cfg: WalkConfig, side: int) -> np.ndarray:
    """(4,) nominal pose of foot ``side`` (0 left, 1 right) in the walk frame."""
    s = 1.0 if side == 0 else -1.0
    return np.array([cfg.ankle_x_m, s * cfg.ankle_half_width_m, -cfg.ankle_depth_m, 0.0])


def plan_step(cfg: WalkConfig, support: int, start: np.ndarray, command: np.ndarray) -> StepPlan:
    """The step that starts from feet ``start`` (2, 4) with step command (dx, dy, dyaw)."""
    command = np.asarray(command, dtype=float)
    dx, dy, dyaw = command.tolist()
    x, z = cfg.ankle_x_m, -cfg.ankle_depth_m
    end = []
    for side in (0, 1):
        # Column by column on plain floats: nominal_foot + sign * (dx, dy, 0, dyaw) + bias,
        # bias = (0, s |dy| / 2, 0, s |dyaw| / 2).
        s = 1.0 if side == 0 else -1.0
        sign = -0.5 if side == support else 0.5
        end.append(
            [
                x + sign * dx + 0.0,
                s * cfg.ankle_half_width_m + sign * dy + s * abs(dy) / 2,
                z + sign * 0.0 + 0.0,
                0.0 + sign * dyaw + s * abs(dyaw) / 2,
            ]
        )
    return StepPlan(support, np.asarray(start, dtype=float).copy(), np.array(end), command)


def feet_at(cfg: WalkConfig, plan: StepPlan, phase: float, sway_scale: float = 1.0) -> np.ndarray:
    """(2, 4) foot poses in the walk frame at ``phase`` in [0, 1] of the step."""
    return np.array(foot_rows_at(cfg, plan, phase, sway_scale))


def foot_rows_at(
    cfg: WalkConfig, plan: StepPlan, phase: float, sway_scale: float = 1.0
) -> list[list[float]]:
    """``feet_at`` as two lists (left, right) of four floats: the walk engine's form, every
    cycle, so worked out on plain floats."""
    return foot_rows(plan, foot_fractions(cfg, phase, sway_scale))


def foot_fractions(
    cfg: WalkConfig, phase: float, sway_scale: float = 1.0
) -> tuple[float, float, float, float]:
    """What of a step depends on its phase only: the support and the swing foot's shares of
    the way from start to end, the swing foot's lift [m] and the torso's sway toward the
    support foot [m]. The walk engine works them out once for each cycle of a step."""
    k = pendulum_rate_per_s(cfg.com_height_m)
    phase = clamp(phase, 0.0, 1.0)
    lipm = sagittal_fraction(phase, k, cfg.step_time_s) + 0.5
    support_f = cfg.lipm_blend * lipm + (1 - cfg.lipm_blend) * phase
    lift = cfg.lift_start_fraction
    swing = min(1.0, max(0.0, phase - lift) / max(cfg.swing_fraction - lift, 1e-6))
    swing_f = 0.5 * (1 - math.cos(math.pi * swing))
    lift_m = cfg.step_height_m * 0.5 * (1 - math.cos(2 * math.pi * swing))
    sway_m = (
        sway_scale
        * cfg.sway_gain
        * cfg.ankle_half_width_m
        * lateral_fraction(phase, k, cfg.step_time_s)
    )
    return support_f, swing_f, lift_m, sway_m


def foot_rows(plan: StepPlan, fractions: tuple[float, float, float, float]) -> list[list[float]]:
    """The feet (two lists, left and right, of x, y, z, yaw) of ``plan`` at the phase of
    ``fractions`` (``foot_fractions``)."""
    support_f, swing_f, lift_m, sway_m = fractions
    sup = plan.support
    start, way = plan.rows
    # Torso sways toward the support foot: both feet shift the other way in the walk frame.
    shift = (1.0 if sup == 0 else -1.0) * sway_m
    # Each foot moves from its start toward its end (written out: this runs every cycle).
    feet = [None, None]
    for side, f in ((sup, support_f), (1 - sup, swing_f)):
        (x, y, z, yaw), (dx, dy, dz, dyaw) = start[side], way[side]
        feet[side] = [x + f * dx, y + f * dy - shift, z + f * dz, yaw + f * dyaw]
    feet[1 - sup][2] += lift_m
    return feet
