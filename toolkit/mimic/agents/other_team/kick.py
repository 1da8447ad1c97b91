"""The other team's kick: the right foot swung along a planned path, solved by their IK.

Not keyframes of joint angles: the team plans where the kicking foot's ankle goes (shift the
torso over the left foot, lift and wind the right foot back, swing it through the ball,
retract, put it down, shift back), interpolates those foot waypoints with a cosine blend and
solves both legs every cycle with their analytic IK. Torso roll feeds back into the support
ankle and hip while on one foot.
"""

from __future__ import annotations

import math

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.other_team.ik import LEG
from mimic.agents.other_team.motor import LEG_IDX, legs_to_joints, servo_speeds, torso_pitch_roll
from mimic.agents.other_team.params import KickParams
from mimic.robot.nao import nao
from mimic.world.base import CYCLE_S, Observation

__all__ = ["OtherTeamKick"]

_SUPPORT, _KICKER = 1.0, -1.0  # left foot stands, right foot kicks
_ARMS_RAD = (math.radians(-90.0), math.radians(8.0))


class OtherTeamKick(Agent):
    """A one-shot right-foot kick from a stand; ``ball_offset_m`` is where it wants the ball."""

    name = "other_team_kick"
    team = "other_team"
    period_s = None
    # Its IK and kick are the NAO's geometry.
    robot_only = True

    def __init__(self, params: KickParams = KickParams()) -> None:
        super().__init__()
        self.params = params
        #: Ball centre relative to the torso, robot frame (x forward, y left) [m].
        self.ball_offset_m = (params.ball_x_m, params.ball_y_m)
        p = params
        # Waypoints: (time [s], torso shift over the support foot (0..1), kicker (dx, dz) [m]).
        t, marks = 0.0, []
        for dur, shift, dx, dz in (
            (0.0, 0.0, 0.0, 0.0),
            (p.shift_s, 1.0, 0.0, 0.0),
            (p.windup_s, 1.0, p.windup_x_m, p.windup_z_m),
            (p.swing_s, 1.0, p.strike_x_m, p.strike_z_m),
            (p.retract_s, 1.0, 0.0, p.windup_z_m),
            (p.down_s, 1.0, 0.0, 0.0),
            (p.recover_s, 0.0, 0.0, 0.0),
        ):
            t += dur
            marks.append((t, shift, dx, dz))
        self._marks = marks
        self.duration_s = t
        self._cycle = 0
        self._start_rad = nao().zeros()

    def reset(self, obs: Observation) -> None:
        self._cycle = 0
        self._start_rad = obs.joint_angles_rad.copy()
        self.done = False

    def _plan(self, t_s: float) -> tuple[float, float, float, bool]:
        """Shift (0..1), kicker dx, dz [m] and whether the right foot is off the ground."""
        m = self._marks
        for (t0, *a), (t1, *b) in zip(m, m[1:]):
            if t_s <= t1:
                w = 0.5 - 0.5 * math.cos(math.pi * min(1.0, (t_s - t0) / max(t1 - t0, 1e-9)))
                vals = [x + (y - x) * w for x, y in zip(a, b)]
                airborne = m[1][0] < t_s < m[5][0]
                return vals[0], vals[1], vals[2], airborne
        return 0.0, 0.0, 0.0, False

    def _feet(self, shift: float, dx: float, dz: float):
        p = self.params
        feet = {}
        for side in (_SUPPORT, _KICKER):
            hip = LEG.hip(side)
            pos = np.array([hip[0], hip[1] - shift * p.shift_m, hip[2] - p.stand_height_m])
            if side == _KICKER:
                pos += (dx, 0.0, dz)
            feet[side] = (pos, np.eye(3))
        return feet

    def act(self, obs: Observation) -> JointCommand:
        p = self.params
        self._cycle += 1
        t = self._cycle * CYCLE_S
        shift, dx, dz, airborne = self._plan(t)
        target = legs_to_joints(self._feet(shift, dx, dz), *_ARMS_RAD)
        if t < p.shift_s:  # blend in from whatever pose the kick started in
            w = 0.5 - 0.5 * math.cos(math.pi * t / p.shift_s)
            w = min(1.0, 2 * w)
            target = (1 - w) * self._start_rad + w * target
        pitch, roll = torso_pitch_roll(obs.torso_quat_wxyz)
        # Gyro x > 0 tips the torso to the right (roll < 0).
        d_roll = p.roll_gain * roll - p.roll_rate_gain * obs.gyro_rad_s[0]
        d_pitch = p.pitch_gain * pitch + p.pitch_rate_gain * obs.gyro_rad_s[1]
        for side in (_SUPPORT, _KICKER):
            if side == _SUPPORT or not airborne:
                idx = LEG_IDX[side]
                target[idx[5]] -= d_roll
                target[idx[4]] -= d_pitch
        if airborne:
            target[LEG_IDX[_SUPPORT][1]] -= p.hip_roll_gain * roll
        self.done = t >= self.duration_s + p.settle_s
        return JointCommand.speeds(servo_speeds(target, obs.joint_angles_rad, p.servo))
