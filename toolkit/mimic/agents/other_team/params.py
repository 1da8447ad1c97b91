"""The other team's parameter sets: their walk and their kick.

The numbers come from short evolution-strategy searches on our simulator, the way that team
optimises its own parameters: the walk for distance, speed, drift and heading swing under
speed-command noise with a heavy penalty for a fall; the kick for ball distance and staying
upright. ``docs/tuning-notes.md`` keeps the search history and why faster sets were not kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["WalkParams", "KickParams", "ServoParams"]


@dataclass(frozen=True)
class ServoParams:
    """How joint targets become speed commands: speed = gain * (target_next - angle) / cycle."""

    # Fraction of the angle error to close in one 20 ms cycle (1 = all of it).
    gain: float = 0.9
    # Share of the planned target speed sent ahead of the error term (0: none, 1: all of it).
    feedforward: float = 0.0


@dataclass(frozen=True)
class WalkParams:
    """A double-linear-inverted-pendulum walk with short, fixed-time steps."""

    # Duration of one step in 20 ms agent cycles (a gait period is two steps).
    step_cycles: int = 8
    # Forward speed the walk aims for [m/s]; the step length is speed * step time.
    speed_m_s: float = 0.5461
    # Longest forward step (torso advance per step) [m].
    max_step_m: float = 0.12
    # Step-length change allowed per step [m] (the start-up ramp).
    step_ramp_m: float = 0.004
    # Hip joint height above the ankle-roll point [m] (the pendulum length).
    walk_height_m: float = 0.1726
    # Peak lift of the swing foot [m].
    step_height_m: float = 0.09321
    # Part of the step the swing foot spends in the air (lands early to beat servo lag).
    swing_fraction: float = 0.8275
    # Swing foot's forward progress: 0 a cosine, 1 a trapezoidal speed profile (lower peak
    # joint speeds for the capped servos), in between a blend.
    swing_trapezoid: float = 0.0
    # Extra lateral distance of each foot from under its hip [m].
    foot_spread_m: float = -0.01113
    # Peak lateral torso shift toward the support foot, mid-step [m].
    sway_m: float = 0.00544
    # Forward offset of the feet below the torso centre [m] (negative: feet behind).
    foot_x_m: float = -0.03212
    # Forward lean of the torso [rad].
    lean_rad: float = 0.01014
    # Torso pitch feedback: hip pitch change per rad of measured tilt error.
    pitch_gain: float = 0.6086
    # Torso roll feedback: hip roll change per rad of measured roll.
    roll_gain: float = 0.3421
    # Torso pitch-rate damping: ankle pitch change per rad/s of gyro pitch rate.
    pitch_rate_gain: float = 0.03119
    # Torso roll-rate damping: ankle roll change per rad/s of gyro roll rate.
    roll_rate_gain: float = 0.02759
    # Share of the tilt feedback sent to the swing hip instead of the ankles (0..1).
    hip_share: float = 0.9887
    # Heading hold: foot yaw per step per rad of heading error.
    yaw_gain: float = 0.3357
    # Line hold: heading aimed back at the start line per metre of sideways offset [rad/m].
    line_gain: float = 0.7527
    # Largest foot-yaw turn per step [rad] (the heading hold's authority).
    max_turn_rad: float = 0.05
    # Time to bend from the start pose into the walking stance [s].
    startup_s: float = 0.4
    # Shoulder pitch and roll of the (still) arms [rad].
    shoulder_pitch_rad: float = math.radians(-90.0)
    shoulder_roll_rad: float = math.radians(8.0)
    # Soft proportional servo plus a third of the planned speed fed forward.
    servo: ServoParams = ServoParams(gain=0.3983, feedforward=0.3242)

    def step_s(self, cycle_s: float) -> float:
        """Duration of one step [s]."""
        return self.step_cycles * cycle_s


@dataclass(frozen=True)
class KickParams:
    """A foot-trajectory kick with the right foot, solved by the team's IK."""

    # Ball centre relative to the torso, robot frame (x forward, y left) [m].
    ball_x_m: float = 0.1627
    ball_y_m: float = -0.05265
    # Hip height above the ankle during the kick [m].
    stand_height_m: float = 0.2116
    # Lateral torso shift over the left foot [m].
    shift_m: float = 0.04671
    # Phase durations [s]: shift weight, lift and wind up, swing, retract, put down, recover.
    shift_s: float = 0.8358
    windup_s: float = 0.215
    swing_s: float = 0.1539
    retract_s: float = 0.4793
    down_s: float = 0.4923
    recover_s: float = 0.7688
    # Swing foot (ankle) positions relative to its stand position (x, z) [m].
    windup_x_m: float = -0.1113
    windup_z_m: float = 0.0648
    strike_x_m: float = 0.1822
    strike_z_m: float = 0.01952
    # Time to stand still after the last waypoint before reporting done [s].
    settle_s: float = 0.4
    # Torso tilt feedback into the ankles: angle change per rad of roll / pitch.
    roll_gain: float = 0.3031
    pitch_gain: float = -0.03683
    # Torso roll feedback into the support hip roll while on one foot [rad per rad].
    hip_roll_gain: float = -0.2
    # Tilt-rate damping into the ankles: angle change per rad/s of gyro rate.
    roll_rate_gain: float = 0.009823
    pitch_rate_gain: float = 0.0
    servo: ServoParams = ServoParams()
