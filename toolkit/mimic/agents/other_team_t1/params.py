"""The T1 team's parameter sets: their walk and their kick (frozen dataclasses).

Units in the names; ``docs/tuning-notes.md`` keeps where the numbers came from.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["WalkParams", "KickParams", "PolicyWalkParams", "JITTERY_WALK"]


@dataclass(frozen=True)
class WalkParams:
    """A linear-inverted-pendulum walk with fixed-time steps, solved by the team's leg IK."""

    # Duration of one step in 20 ms agent cycles (a gait period is two steps).
    step_cycles: int = 21
    # Forward speed the plan aims for [m/s]: the step length is speed * step time. The walk
    # runs faster (~0.65 m/s): foot placement lengthens the steps of a torso that leans ahead.
    speed_m_s: float = 0.5514
    # Longest forward step (torso advance per step) [m].
    max_step_m: float = 0.22
    # Step-length change allowed per step [m]: the start-up ramp, and the ramp down after
    # ``stop()``.
    step_ramp_m: float = 0.03349
    stop_ramp_m: float = 0.07
    # Pendulum height for the model's time constant, sqrt(height / g) [m].
    pendulum_height_m: float = 0.8471
    # Torso (root link) height above the ankle-roll points while walking [m].
    torso_height_m: float = 0.5852
    # Peak lift of the swing foot [m].
    step_height_m: float = 0.04726
    # Part of the step when the swing foot leaves and when it lands (0..1).
    lift_off: float = 0.151
    touch_down: float = 0.9064
    # Lateral distance of each foot's ankle from the torso's centre line [m].
    foot_y_m: float = 0.09592
    # Peak lateral torso shift toward the support foot, mid-step [m].
    sway_m: float = 0.0482
    # Forward offset of the ankles below the torso [m] (negative: ankles behind the torso).
    foot_x_m: float = 0.04221
    # Forward lean of the torso [rad].
    lean_rad: float = 0.05485
    # Sag pre-compensation of the support leg at full load: the PD motors give way under the
    # robot's weight by about torque / kp, so the references ask for that much more: hip roll
    # and ankle roll against the droop toward the swing side [rad], the leg longer [m].
    hip_roll_sag_rad: float = 0.1622
    ankle_roll_sag_rad: float = 0.07378
    leg_sag_m: float = 0.02176
    # Torso tilt feedback into the support ankle: angle per rad of tilt (pitch, roll).
    ankle_pitch_gain: float = 0.5513
    ankle_roll_gain: float = 0.8408
    # Tilt-rate damping into the support ankle: angle per rad/s of gyro rate.
    ankle_pitch_rate_gain: float = 0.05505
    ankle_roll_rate_gain: float = 0.0513
    # Tilt feedback into the swing hip (foot placement): angle per rad of tilt.
    hip_pitch_gain: float = 0.1258
    hip_roll_gain: float = 0.232
    # Torso attitude feedback into the support hip: angle per rad of tilt (pitch, roll).
    torso_pitch_gain: float = 0.8056
    torso_roll_gain: float = 0.4565
    # Foot placement: the swing foot lands this much farther per metre of the torso's error
    # against the plan (measured over the support foot through the leg and the IMU), and per
    # m/s of its rate (capture-point style) [m/m, m/(m/s)].
    step_x_gain: float = 0.2604
    step_x_rate_gain: float = 0.1824
    step_y_gain: float = 0.3777
    step_y_rate_gain: float = 0.4057
    # Largest placement correction [m] and the error-rate filter time constant [s].
    max_step_adjust_m: float = 0.05
    rate_filter_s: float = 0.01119
    # Heading hold: foot yaw per step per rad of heading error.
    yaw_gain: float = 0.4
    # Line hold: heading aimed back at the start line per metre of sideways offset [rad/m].
    line_gain: float = 0.5
    # Largest foot-yaw turn per step [rad].
    max_turn_rad: float = 0.1
    # Time to bend from the start pose into the walking stance [s].
    startup_s: float = 0.5
    # Halting: time holding the stance after the last step, then to blend into the stand
    # pose [s].
    halt_hold_s: float = 0.4
    halt_blend_s: float = 0.6
    # Arm swing: shoulder pitch per metre of the opposite foot's forward offset [rad/m].
    arm_swing_rad_m: float = 1.822

    def step_s(self, cycle_s: float) -> float:
        """Duration of one step [s]."""
        return self.step_cycles * cycle_s


@dataclass(frozen=True)
class KickParams:
    """A kick step in the walk: the right foot's swing gets a path of its own."""

    # Ball centre relative to the torso, robot frame (x forward, y left) [m].
    ball_x_m: float = 0.30
    ball_y_m: float = -0.10
    # The kick step is the first right-foot swing from this step on (step 0 only rocks).
    not_before_step: int = 2
    # Steps on the spot after the kick step before the walk stops.
    steps_after: int = 0
    # The kick step's lift-off and touch-down (parts of the step, 0..1).
    lift_off: float = 0.1
    touch_down: float = 0.95
    # Kicking ankle relative to its swing path (x forward, z up) [m] and when it is there
    # (part of the step): wound up, then at the strike.
    windup_phase: float = 0.45
    windup_x_m: float = -0.10
    windup_z_m: float = 0.04
    strike_phase: float = 0.7
    strike_x_m: float = 0.20
    strike_z_m: float = 0.03
    # Where the kicking foot lands, ahead of its usual landing beside the other foot [m].
    land_x_m: float = 0.0
    # After the kick the walk stops: time holding its stance, then to blend into the stand
    # pose [s] (the walk's ``halt_*``); then time standing before reporting done [s].
    halt_hold_s: float = 0.4
    halt_blend_s: float = 0.6
    settle_s: float = 0.4


@dataclass(frozen=True)
class PolicyWalkParams:
    """How the policy-like walk commands the team's walk (``policy_walk``): a velocity command
    toward a target it sees with noise, and a step time that adapts every step."""

    # Forward speed command [m/s].
    speed_m_s: float = 0.45
    # The target lies this far ahead of the start, along the start heading [m].
    target_distance_m: float = 20.0
    # The target's estimate: sideways error [m] (stationary standard deviation) and how much of
    # it carries over from one step to the next (0..1; the rest is drawn anew).
    target_noise_m: float = 1.5
    target_noise_keep: float = 0.6
    # Turn command per rad of bearing to the estimated target [rad/s per rad], and its limit
    # [rad/s].
    turn_gain: float = 2.0
    max_turn_rad_s: float = 0.25
    # Sideways command per rad of bearing [m/s per rad], and its limit [m/s].
    side_gain: float = 0.5
    max_side_m_s: float = 0.02
    # Step time: longer by this share per metre the forward capture point runs ahead of the
    # plan at the step's start [1/m] (at the commanded speed a longer step lands farther, under
    # a torso falling ahead) ...
    timing_capture_gain: float = 1.0
    # ... plus the estimate's noise (stationary standard deviation, share of the step time,
    # and how much of it carries over from one step to the next) ...
    timing_noise: float = 0.15
    timing_noise_keep: float = 0.9
    # ... within these shares of the team's step time.
    min_step_scale: float = 0.7
    max_step_scale: float = 1.2
    # Largest change of the step time from one step to the next [cycles of 20 ms].
    max_step_change_cycles: int = 1
    # A learned policy's action jitter: each joint's reference gets its own AR(1) noise every
    # 20 ms cycle, of this stationary standard deviation [rad] on the head (0: none, the walk
    # as it was) ...
    action_noise_rad: float = 0.0
    # ... this share of it on the arms, and on the waist and legs (the walk stands on them:
    # 0.02 rad of white noise there fell in 3 of 3 runs, 0.01 in none; docs/real-team-walk.md)
    # ...
    action_noise_arm_share: float = 1.0
    action_noise_leg_share: float = 1.0
    # ... and this share of it carried over from one cycle to the next (0..1; the rest is
    # drawn anew). A policy's actions jitter from cycle to cycle: 0 is white noise.
    action_noise_keep: float = 0.0
    # Seed of the team's sensor noise (mixed with its first observation, so each episode
    # differs and a seeded episode replays exactly).
    seed: int = 0

    def __post_init__(self) -> None:
        if not self.action_noise_rad >= 0.0:
            raise ValueError(f"action_noise_rad must be >= 0, not {self.action_noise_rad}")
        if not (self.action_noise_arm_share >= 0.0 and self.action_noise_leg_share >= 0.0):
            raise ValueError("action_noise_arm_share and action_noise_leg_share must be >= 0")
        if not 0.0 <= self.action_noise_keep < 1.0:
            raise ValueError(f"action_noise_keep must be in [0, 1), not {self.action_noise_keep}")


#: ``other-team-jittery-walk``: the policy-like walk with a learned policy's action jitter, so
#: that its black-box recording's joints move as a real team's do (25 Hz differences, steady
#: part: 99th percentile about 10 rad/s, largest about 20; a real team's: up to 21). The walk
#: takes little jitter where it stands and balances: the legs and waist get 0.009 rad (0.018
#: fell in 9 of 20 scratch runs, 0.035 in 20 of 20), the arms 0.018, the head 0.35, which
#: carries the speeds. 0.4 kept per cycle: jitter the motors pass on (white noise of 0.1 rad
#: on the head and arms moved them at under 7 rad/s). It walks slower than the policy-like
#: walk (0.35 m/s): at 0.45 m/s this jitter fell in 4 of 10 runs, at 0.55 in 9 of 10, at
#: 0.35 in none (as a real team's walk, whose steps take twice as long). Tuned on 25 s
#: scratch episodes in the league (episode seeds 0-29): docs/real-team-walk.md.
JITTERY_WALK = PolicyWalkParams(
    speed_m_s=0.35,
    action_noise_rad=0.35,
    action_noise_arm_share=0.05,
    action_noise_leg_share=0.025,
    action_noise_keep=0.4,
)
