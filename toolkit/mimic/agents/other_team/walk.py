"""The other team's fast walk: a double linear inverted pendulum gait with short fixed steps.

Feet are planned in a walk frame at the torso centre with the torso's heading but upright
(x forward, y left, z up). In step n the support foot slides back linearly (the torso moves
forward over it) while the swing foot travels forward on a cosine (blended with a
trapezoidal speed profile by ``swing_trapezoid``) and lifts by 0.5 (1 - cos(2 pi phase));
the torso shifts toward the support foot along the pendulum's
cosh(k t) curve, k = sqrt(g / walk height). Step length is rate-limited (the start-up ramp);
IMU tilt and roll feed back into the ankles and a heading error into the foot yaw. Step timing
is fixed in whole 20 ms cycles, so the steady gait repeats exactly every two steps.

Heading: once per step the foot yaw turns the torso toward an aim heading, which points back
at the start line in proportion to the sideways offset (the team's localisation), so the
walk stays on its line. Servo commands feed the planned joint speed forward on top of a
soft proportional term, which keeps the legs close to the plan despite the servo lag.
"""

from __future__ import annotations

import math

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.other_team.ik import LEG
from mimic.agents.other_team.motor import LEG_IDX, legs_to_joints, servo_speeds, torso_pitch_roll
from mimic.agents.other_team.params import WalkParams
from mimic.geometry import rot_y, rot_z
from mimic.robot.nao import nao
from mimic.world.base import CYCLE_S, GRAVITY_M_S2, Observation

__all__ = ["OtherTeamWalk"]

_MAX_AIM_RAD = 0.3
# Share of the swing spent speeding up (and as much slowing down) on the trapezoidal profile.
_SWING_RAMP = 0.2


def swing_progress(u: float, trapezoid: float) -> float:
    """Share of its forward travel the swing foot has covered at ``u`` in [0, 1] of the swing.

    A blend of a cosine (``trapezoid`` 0: smooth, peak speed pi/2 of the mean) and a trapezoidal
    speed profile (``trapezoid`` 1: speeds up and slows down over ``_SWING_RAMP`` of the swing,
    peak speed 1 / (1 - ramp) of the mean). The servos are capped at 6.1395 rad/s and long fast
    steps saturate the hip pitch on the cosine's peak, so a flatter profile asks less of them.
    """
    cosine = 0.5 - 0.5 * math.cos(math.pi * u)
    if trapezoid <= 0.0:
        return cosine
    r = _SWING_RAMP
    top = 1.0 / (1.0 - r)
    if u < r:
        flat = top * u * u / (2 * r)
    elif u <= 1.0 - r:
        flat = top * (u - r / 2)
    else:
        flat = 1.0 - top * (1.0 - u) ** 2 / (2 * r)
    return (1.0 - trapezoid) * cosine + trapezoid * flat


class OtherTeamWalk(Agent):
    """Walks straight ahead at ``params.speed_m_s`` from a standing start."""

    name = "other_team_walk"
    team = "other_team"
    # Its IK and gait are the NAO's geometry.
    robot_only = True

    def __init__(self, params: WalkParams = WalkParams()) -> None:
        super().__init__()
        self.params = params
        self.step_s = params.step_s(CYCLE_S)
        self.period_s = 2 * self.step_s
        self._k_m = math.sqrt(GRAVITY_M_S2 / params.walk_height_m)
        self._startup_cycles = max(1, round(params.startup_s / CYCLE_S))
        self._reset_state(nao().zeros(), 0.0)

    # --- state ----------------------------------------------------------------------------
    def _reset_state(
        self, start_rad: np.ndarray, yaw_rad: float, xy_m: tuple[float, float] = (0.0, 0.0)
    ) -> None:
        self._cycle = 0
        self._start_xy_m = xy_m
        self._start_rad = np.asarray(start_rad, dtype=float).copy()
        # Planned (feedback-free) targets of the last cycle [rad], for the servo feed-forward.
        self._nominal_rad = self._start_rad.copy()
        self._heading_rad = yaw_rad
        self._step_index = -1
        self._step_m = 0.0
        self._turn_rad = 0.0
        # Per foot: (x [m], yaw [rad]) where the current step began and where it will end.
        self._from = {1.0: (0.0, 0.0), -1.0: (0.0, 0.0)}
        self._to = dict(self._from)

    def reset(self, obs: Observation) -> None:
        self._reset_state(
            obs.joint_angles_rad,
            obs.torso_yaw_rad,
            (float(obs.torso_pos_m[0]), float(obs.torso_pos_m[1])),
        )
        self.done = False

    def resume(self, obs: Observation) -> None:
        """Start walking again from ``obs`` on the same line (start line and heading): the
        heading hold turns the robot back to it."""
        self._reset_state(obs.joint_angles_rad, self._heading_rad, self._start_xy_m)
        self.done = False

    # --- gait -----------------------------------------------------------------------------
    def _support(self, step_index: int) -> float:
        """Support side of a step: the left foot (+1) carries the even steps."""
        return 1.0 if step_index % 2 == 0 else -1.0

    def _begin_step(self, n: int, obs: Observation) -> None:
        p = self.params
        self._step_index = n
        target = min(p.max_step_m, p.speed_m_s * self.step_s)
        self._step_m += float(np.clip(target - self._step_m, -p.step_ramp_m, p.step_ramp_m))
        # Steer back toward the start line: aim the heading at it, in proportion to the offset.
        off_m = -math.sin(self._heading_rad) * (
            obs.torso_pos_m[0] - self._start_xy_m[0]
        ) + math.cos(self._heading_rad) * (obs.torso_pos_m[1] - self._start_xy_m[1])
        aim = self._heading_rad - float(np.clip(p.line_gain * off_m, -_MAX_AIM_RAD, _MAX_AIM_RAD))
        err = math.remainder(obs.torso_yaw_rad - aim, 2 * math.pi)
        self._turn_rad = float(np.clip(-p.yaw_gain * err, -p.max_turn_rad, p.max_turn_rad))
        support = self._support(n)
        self._from = dict(self._to)
        self._to = {
            support: (-self._step_m / 2, -self._turn_rad / 2),
            -support: (self._step_m / 2, self._turn_rad / 2),
        }

    def _sway_m(self, phase: float) -> float:
        """Torso shift toward the support foot: pendulum cosh curve, 0 at both ends."""
        half = self._k_m * self.step_s / 2
        peak = math.cosh(half)
        return self.params.sway_m * (peak - math.cosh(half * (2 * phase - 1))) / (peak - 1)

    def _feet(self, phase: float, support: float) -> dict[float, tuple[np.ndarray, np.ndarray]]:
        """Foot poses in the torso frame at ``phase`` in (0, 1] of the current step."""
        p = self.params
        lean = rot_y(p.lean_rad)  # torso orientation in the walk frame
        sway = self._sway_m(phase) * support
        feet = {}
        for side in (1.0, -1.0):
            (x0, a0), (x1, a1) = self._from[side], self._to[side]
            if side == support:
                s, lift = phase, 0.0
            else:
                swing = min(1.0, phase / p.swing_fraction)
                s = swing_progress(swing, p.swing_trapezoid)
                lift = p.step_height_m * 0.5 * (1 - math.cos(2 * math.pi * swing))
            hip_w = lean @ LEG.hip(side)
            pos_w = np.array(
                [
                    p.foot_x_m + x0 + (x1 - x0) * s,
                    hip_w[1] + side * p.foot_spread_m - sway,
                    hip_w[2] - p.walk_height_m + lift,
                ]
            )
            yaw = a0 + (a1 - a0) * s
            feet[side] = (lean.T @ pos_w, lean.T @ rot_z(yaw))
        return feet

    def _stance(self) -> np.ndarray:
        p = self.params
        self._from = {1.0: (0.0, 0.0), -1.0: (0.0, 0.0)}
        self._to = dict(self._from)
        return legs_to_joints(self._feet(0.0, 1.0), p.shoulder_pitch_rad, p.shoulder_roll_rad)

    def targets_rad(self, obs: Observation) -> np.ndarray:
        """(N,) joint targets [rad] for the end of this cycle (internal to the team)."""
        p = self.params
        k = self._cycle + 1
        if k <= self._startup_cycles:
            w = 0.5 - 0.5 * math.cos(math.pi * k / self._startup_cycles)
            self._nominal_rad = (1 - w) * self._start_rad + w * self._stance()
            return self._nominal_rad.copy()
        c = k - self._startup_cycles - 1
        n, j = divmod(c, p.step_cycles)
        if n != self._step_index:
            self._begin_step(n, obs)
        support = self._support(n)
        q = legs_to_joints(
            self._feet((j + 1) / p.step_cycles, support), p.shoulder_pitch_rad, p.shoulder_roll_rad
        )
        self._nominal_rad = q.copy()
        pitch, roll = torso_pitch_roll(obs.torso_quat_wxyz)
        # Gyro in the torso frame: +y tips it forward, +x tips it to the right.
        d_pitch = p.pitch_gain * (pitch - p.lean_rad) + p.pitch_rate_gain * obs.gyro_rad_s[1]
        d_roll = p.roll_gain * roll - p.roll_rate_gain * obs.gyro_rad_s[0]
        for side in (1.0, -1.0):
            idx = LEG_IDX[side]
            ankle = 1.0 if side == support else 1.0 - p.hip_share
            q[idx[4]] -= ankle * d_pitch
            q[idx[5]] -= ankle * d_roll
            if side != support:
                # Swing hip: put the foot down where the torso is falling.
                q[idx[2]] += p.hip_share * d_pitch
                q[idx[1]] += p.hip_share * d_roll
        return q

    def act(self, obs: Observation) -> JointCommand:
        planned_now = self._nominal_rad
        target = self.targets_rad(obs)
        self._cycle += 1
        # Feed forward the plan's own speed only: the IMU feedback is too noisy to differentiate.
        return JointCommand.speeds(
            servo_speeds(
                target,
                obs.joint_angles_rad,
                self.params.servo,
                target_now_rad=planned_now + (target - self._nominal_rad),
            )
        )
