"""The T1 team's walk: a linear-inverted-pendulum step plan, leg IK under the PD motors,
foot placement and ankle feedback from the IMU.

Feet are planned relative to the torso, in a walk frame with the torso's heading but upright
(x forward, y left, z up). Step n (fixed time, whole 20 ms cycles) stands on one foot: the
torso advances over it along the pendulum's sinh curve (``lipm.advance``) and sways toward it
along the cosh curve (``lipm.sway``), while the other foot swings from behind to half a step
ahead. The step length is rate-limited (start-up and stopping ramp). The team's leg IK turns
the two foot poses into joint references every cycle; the league's PD motors track them, and
the support leg asks for a little more than it wants, for what its motors give way under the
robot's weight (``WalkParams.*_sag_rad``).

Feedback:

* foot placement: where the torso is over the support foot, measured through the support
  leg's joint angles and the IMU's tilt, is compared with the plan; the swing foot lands
  farther along the error and its rate (a capture-point rule), and the plan carries on from
  where it landed;
* the support ankle takes the torso's tilt and tilt rate (pitch and roll);
* heading: the feet turn a little every step, aiming back at the start line in proportion to
  the sideways offset (the team's localisation, ``torso_pos_m``).

``stop()`` ramps the steps down to zero, then holds the stance with both feet down and blends
into the robot's stand pose; ``done`` is then True. States: ``starting``, ``walking``,
``halting``, ``standing``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.other_team_t1.body import Body
from mimic.agents.other_team_t1.lipm import advance, pendulum_rate_per_s, sway, swing
from mimic.agents.other_team_t1.params import WalkParams
from mimic.geometry import rot_y, rot_z, torso_pitch_roll, yaw_from_quat
from mimic.robot.registry import get_robot
from mimic.world.base import CYCLE_S, Observation

__all__ = ["OtherTeamT1Walk"]

#: Largest heading correction the line hold aims for [rad].
_MAX_AIM_RAD = 0.3
#: How far the swing foot may land inward of its nominal track [m] (the feet must not meet).
_MAX_INWARD_M = 0.02
_SIDES = (1.0, -1.0)


def _quat_matrix(q) -> np.ndarray:
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


class OtherTeamT1Walk(Agent):
    """Walks straight ahead at ``params.speed_m_s`` from a standing start until ``stop()``."""

    name = "other_team_walk"
    team = "other_team"
    robot = "t1"
    # Its IK and gait are the T1's geometry.
    robot_only = True

    def __init__(self, params: WalkParams = WalkParams()) -> None:
        super().__init__()
        self.params = params
        self._body = Body(get_robot(self.robot))
        self.step_s = params.step_s(CYCLE_S)
        self.period_s = 2 * self.step_s
        # The step under way: its length in cycles and seconds (fixed here; a walk that adapts
        # its timing sets them per step in ``_step_timing``).
        self._step_cycles, self._cur_step_s = params.step_cycles, self.step_s
        self._w_per_s = pendulum_rate_per_s(params.pendulum_height_m)
        self._stop_requested = False
        # A kick step: (its swing side, its first eligible step, swing offset (dx, dz) [m] by
        # phase); the step it became, once taken.
        self._kick: tuple[float, int, Callable[[float], tuple[float, float]]] | None = None
        self.kick_step: int | None = None
        self._reset_state(self._body.stand_rad, 0.0, (0.0, 0.0))

    # --- commands -------------------------------------------------------------------------
    def stop(self) -> None:
        """Finish walking: ramp the steps down, then settle into the stand pose."""
        self._stop_requested = True

    def kick(
        self, side: float, path: Callable[[float], tuple[float, float]], not_before_step: int = 2
    ) -> None:
        """Make the first step from ``not_before_step`` on whose swing foot is ``side`` (+1
        left, -1 right) a kick step: the swing foot follows its usual path plus
        ``path(phase)`` = (dx forward, dz up) [m], zero at lift-off (dz also at touch-down).
        ``kick_step`` then says which step it was; the step after it plans from where the
        feet really are."""
        self._kick = (side, not_before_step, path)
        self.kick_step = None

    @property
    def state(self) -> str:
        """``starting``, ``walking``, ``halting`` or ``standing``."""
        return self._state

    @property
    def steps_taken(self) -> int:
        """Steps begun since the start (the step under way included)."""
        return self._step_index + 1

    # --- state ----------------------------------------------------------------------------
    def _reset_state(
        self, start_rad: np.ndarray, yaw_rad: float, xy_m: tuple[float, float]
    ) -> None:
        p = self.params
        self._state = "starting"
        self._t_in_state_s = 0.0
        self._start_rad = np.asarray(start_rad, dtype=float).copy()
        self._start_xy_m = xy_m
        self._heading_rad = yaw_rad
        self._body.reset(self._start_rad)
        self._step_index, self._cycle_in_step = -1, 0
        self._step_cycles, self._cur_step_s = p.step_cycles, self.step_s
        self._step_m = 0.0
        self.kick_step = None
        # Steps in a row of zero length (two bring the feet side by side after a stop).
        self._zero_steps = 0
        # Per foot: (x, y, yaw) relative to the torso [m, m, rad] where the step began and
        # where it ends (the support foot's y stays; the torso's sway is added on top).
        self._from = {side: np.array([0.0, side * p.foot_y_m, 0.0]) for side in _SIDES}
        self._to = {side: v.copy() for side, v in self._from.items()}
        self._halt_from: np.ndarray | None = None
        # The last planned (feedback-free) references [rad]: where halting starts from.
        self._last_plan_rad = self._start_rad.copy()
        # Torso error against the plan over the support foot (x, y) [m], its filtered rate
        # [m/s], and the swing foot's placement correction (x, y) [m].
        self._err_m: np.ndarray | None = None
        self._err_rate = np.zeros(2)
        self._adjust_m = np.zeros(2)

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

    # --- the plan -------------------------------------------------------------------------
    def _support(self, n: int) -> float:
        """The support foot of step ``n``: the left (+1) carries the even steps."""
        return 1.0 if n % 2 == 0 else -1.0

    def _begin_step(self, obs: Observation) -> None:
        p = self.params
        if self._step_index >= 0:  # the swing foot landed where the placement put it
            swing_side = -self._support(self._step_index)
            self._to[swing_side][:2] += self._adjust_m
        self._step_index += 1
        self._step_cycles = self._step_timing(obs)
        self._cur_step_s = self._step_cycles * CYCLE_S
        self._adjust_m = np.zeros(2)
        self._err_m, self._err_rate = None, np.zeros(2)
        speed, side_m = self._velocity_command(obs)
        target = 0.0 if self._stop_requested else min(p.max_step_m, speed * self._cur_step_s)
        ramp = p.stop_ramp_m if self._stop_requested else p.step_ramp_m
        self._step_m += float(np.clip(target - self._step_m, -ramp, ramp))
        self._zero_steps = self._zero_steps + 1 if self._step_m == 0.0 else 0
        turn = 0.0 if self._stop_requested else self._turn_rad(obs)
        side_m = 0.0 if self._stop_requested else side_m
        support = self._support(self._step_index)
        if self.kick_step is not None and self._step_index == self.kick_step + 1:
            self._to = self._measured_feet(obs)  # the kicking foot landed where it could
        if (
            self._kick is not None
            and self.kick_step is None
            and -support == self._kick[0]
            and self._step_index >= self._kick[1]
            and not self._stop_requested
        ):
            self.kick_step = self._step_index
        self._from = {side: v.copy() for side, v in self._to.items()}
        self._to = {
            support: self._from[support] - (self._step_m, side_m, 0.0),
            -support: np.array([self._step_m / 2, -support * p.foot_y_m + side_m / 2, turn / 2]),
        }
        self._to[support][2] = -turn / 2

    def _step_timing(self, obs: Observation) -> int:
        """Cycles of the step about to begin: the team's fixed step time."""
        return self.params.step_cycles

    def _sway_m(self) -> float:
        """Peak sideways torso shift of the step under way [m]."""
        return self.params.sway_m

    def _velocity_command(self, obs: Observation) -> tuple[float, float]:
        """(forward speed [m/s], sideways shift of the torso over this step [m]) of the step
        about to begin: straight ahead at the team's speed."""
        return self.params.speed_m_s, 0.0

    def _turn_rad(self, obs: Observation) -> float:
        """This step's turn: toward an aim heading that points back at the start line."""
        p = self.params
        dx = obs.torso_pos_m[0] - self._start_xy_m[0]
        dy = obs.torso_pos_m[1] - self._start_xy_m[1]
        off_m = -math.sin(self._heading_rad) * dx + math.cos(self._heading_rad) * dy
        aim = self._heading_rad - float(np.clip(p.line_gain * off_m, -_MAX_AIM_RAD, _MAX_AIM_RAD))
        err = math.remainder(obs.torso_yaw_rad - aim, 2 * math.pi)
        return float(np.clip(-p.yaw_gain * err, -p.max_turn_rad, p.max_turn_rad))

    def _plan(self, phase: float, support: float) -> dict[float, np.ndarray]:
        """Foot (x, y, z, yaw) relative to the torso in the walk frame at ``phase`` (0..1]."""
        p = self.params
        step_s = self._cur_step_s
        torso_y = support * self._sway_m() * sway(phase, self._w_per_s, step_s)
        feet = {}
        for side in _SIDES:
            a, b = self._from[side], self._to[side]
            if side == support:  # the leg a little longer for its sag under the load
                s = advance(phase, self._w_per_s, step_s)
                z = -p.torso_height_m - p.leg_sag_m * sway(phase, self._w_per_s, step_s)
            else:  # the first step only rocks the weight over (the pendulum needs momentum)
                s, lift = swing(phase, p.lift_off, p.touch_down)
                z = -p.torso_height_m + p.step_height_m * lift * (self._step_index > 0)
                b = b.copy()
                b[:2] += self._adjust_m
            x, y, yaw = a + (b - a) * s
            if side != support and self._step_index == self.kick_step:
                dx, dz = self._kick[2](phase)
                x, z = x + dx, z + dz
            feet[side] = np.array([p.foot_x_m + x, y - torso_y, z, yaw])
        return feet

    def _poses(self, plan: dict[float, np.ndarray]) -> dict[float, tuple[np.ndarray, np.ndarray]]:
        """Planned feet as poses in the torso frame (the torso leaning as planned)."""
        lean = rot_y(self.params.lean_rad)  # the torso's orientation in the walk frame
        return {side: (lean.T @ f[:3], lean.T @ rot_z(f[3])) for side, f in plan.items()}

    def _stance(self) -> dict[float, tuple[np.ndarray, np.ndarray]]:
        """Both feet down side by side under the torso (the walking stance)."""
        p = self.params
        return self._poses(
            {
                side: np.array([p.foot_x_m, side * p.foot_y_m, -p.torso_height_m, 0.0])
                for side in _SIDES
            }
        )

    def _arms(self, plan: dict[float, np.ndarray]) -> dict[float, float]:
        """Shoulder pitch swing [rad] per side: with the opposite foot's forward offset."""
        k, x0 = self.params.arm_swing_rad_m, self.params.foot_x_m
        return {side: k * float(plan[-side][0] - x0) for side in plan}

    def _measured_feet(self, obs: Observation) -> dict[float, np.ndarray]:
        """Both feet (x, y, yaw) relative to the torso in the walk frame, as the legs' joint
        angles and the IMU show them (the plan's convention: x without ``foot_x_m``)."""
        r = rot_z(-yaw_from_quat(obs.torso_quat_wxyz)) @ _quat_matrix(obs.torso_quat_wxyz)
        q, feet = obs.joint_angles_rad, {}
        for side, chain in self._body.chains.items():
            pos, rot = chain.fk(q[chain.joints], q[chain.fixed])
            pos, rot = r @ pos, r @ rot
            feet[side] = np.array(
                [pos[0] - self.params.foot_x_m, pos[1], math.atan2(rot[1, 0], rot[0, 0])]
            )
        return feet

    # --- feedback -------------------------------------------------------------------------
    def _place(self, obs: Observation, plan: dict[float, np.ndarray], support: float) -> None:
        """Foot placement: compare the support foot under the torso with the plan."""
        p = self.params
        chain = self._body.chains[support]
        q = obs.joint_angles_rad
        foot_t, _ = chain.fk(q[chain.joints], q[chain.fixed])
        r = _quat_matrix(obs.torso_quat_wxyz)
        yaw = yaw_from_quat(obs.torso_quat_wxyz)
        foot_w = rot_z(-yaw) @ r @ foot_t  # measured, walk frame
        err = plan[support][:2] - foot_w[:2]  # > 0: the torso is ahead / left of the plan
        if self._err_m is not None:
            a = CYCLE_S / (p.rate_filter_s + CYCLE_S)
            self._err_rate = (1 - a) * self._err_rate + a * (err - self._err_m) / CYCLE_S
        self._err_m = err
        adjust = (
            np.array([p.step_x_gain, p.step_y_gain]) * err
            + np.array([p.step_x_rate_gain, p.step_y_rate_gain]) * self._err_rate
        )
        adjust = np.clip(adjust, -p.max_step_adjust_m, p.max_step_adjust_m)
        # Inward (toward the support foot) only a little.
        if support * adjust[1] > _MAX_INWARD_M:
            adjust[1] = support * _MAX_INWARD_M
        self._adjust_m = adjust

    def _presag(self, q: np.ndarray, support: float, load: float) -> None:
        """Ask the support leg for what its PD motors will give way under ``load`` (0..1):
        hip roll and ankle roll against the droop toward the swing side (the leg's length is
        in the plan)."""
        p, leg = self.params, self._body.leg[support]
        q[leg["Hip_Roll"]] += support * p.hip_roll_sag_rad * load
        q[leg["Ankle_Roll"]] += support * p.ankle_roll_sag_rad * load

    def _feedback(
        self, q: np.ndarray, obs: Observation, support: float | None, share: float = 1.0
    ) -> np.ndarray:
        """Add ``share`` of the IMU feedback: tilt and rate into the support ankle(s), tilt
        into the swing hip. ``support`` None: both feet carry the robot."""
        p = self.params
        pitch, roll = torso_pitch_roll(obs.torso_quat_wxyz)
        pitch_err = pitch - p.lean_rad
        gx, gy = float(obs.gyro_rad_s[0]), float(obs.gyro_rad_s[1])
        # Ankle pitch up tips the body back; ankle roll up tips it left.
        d_ankle_pitch = share * (p.ankle_pitch_gain * pitch_err + p.ankle_pitch_rate_gain * gy)
        d_ankle_roll = share * (-p.ankle_roll_gain * roll + p.ankle_roll_rate_gain * gx)
        leg = self._body.leg
        for side in _SIDES:
            if support is None or side == support:
                q[leg[side]["Ankle_Pitch"]] += d_ankle_pitch
                q[leg[side]["Ankle_Roll"]] += d_ankle_roll
                # Torso attitude: the hip rotates the torso back over the leg.
                q[leg[side]["Hip_Pitch"]] += share * p.torso_pitch_gain * pitch_err
                q[leg[side]["Hip_Roll"]] -= share * p.torso_roll_gain * roll
            else:  # negative hip pitch swings the leg forward, positive hip roll outward left
                q[leg[side]["Hip_Pitch"]] -= p.hip_pitch_gain * pitch_err
                q[leg[side]["Hip_Roll"]] += p.hip_roll_gain * roll
        return self._body.robot.clip(q)

    # --- the agent ------------------------------------------------------------------------
    def act(self, obs: Observation) -> JointCommand:
        return JointCommand.references(self._references(obs))

    def _references(self, obs: Observation) -> np.ndarray:
        p = self.params
        self._t_in_state_s += CYCLE_S
        if self._state == "starting":
            w = min(1.0, self._t_in_state_s / p.startup_s)
            w = 0.5 - 0.5 * math.cos(math.pi * w)
            stance = self._body.joints(self._stance())
            if w >= 1.0:
                self._enter("halting" if self._stop_requested else "walking")
            self._last_plan_rad = (1 - w) * self._start_rad + w * stance
            return self._feedback(self._last_plan_rad.copy(), obs, None, w)
        if self._state == "walking":
            self._cycle_in_step += 1
            if self._step_index < 0 or self._cycle_in_step > self._step_cycles:
                if self._stop_requested and self._zero_steps >= 2:
                    self._enter("halting")
                    return self._references(obs)
                self._begin_step(obs)
                self._cycle_in_step = 1
            support = self._support(self._step_index)
            phase = self._cycle_in_step / self._step_cycles
            self._place(obs, self._plan(phase, support), support)
            plan = self._plan(phase, support)
            q = self._body.joints(self._poses(plan), self._arms(plan))
            self._last_plan_rad = q.copy()
            self._presag(q, support, sway(phase, self._w_per_s, self._cur_step_s))
            return self._feedback(q, obs, support)
        # halting, then standing: hold the last stance, blend into the stand pose
        if self._halt_from is None:
            self._halt_from = self._last_plan_rad.copy()
        w = min(1.0, max(0.0, self._t_in_state_s - p.halt_hold_s) / p.halt_blend_s)
        w = 0.5 - 0.5 * math.cos(math.pi * w)
        q = (1 - w) * self._halt_from + w * self._body.stand_rad
        if w >= 1.0:
            self._state, self.done = "standing", True
            return q
        return self._feedback(q, obs, None, 1.0 - w)

    def _enter(self, state: str) -> None:
        self._state, self._t_in_state_s = state, 0.0
