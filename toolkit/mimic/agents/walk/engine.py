"""Our omnidirectional walk engine: LIPM foot trajectories, leg IK, IMU feedback.

Each 20 ms cycle the engine advances the step phase (a step lasts a whole number of cycles),
places both feet in the level walk frame (``gait.feet_at``), tilts them into the torso frame
by the torso lean, solves both legs with the closed-form IK, adds IMU feedback (torso tilt
onto the swing hip and the ankles, gyro damping onto the ankles), and tracks the references
with the NAO's proportional tracking (``SpeedServos.track``) plus a feed-forward term: the planned
(feedback-free) reference's own speed over the cycle, so the speed-capped joints do not lag
the gait by 1/gain, while the noisy IMU feedback is never differentiated.

Step-level feedback: the torso pitch at each step start lengthens or shortens the step
(capture the fall), and a step that rocked the torso hard (tilt above ``caution_tilt_rad``)
makes the next one shorter and straight. Odometry feedback closes the gap between the
commanded short steps and the walked ones (from the localisation estimate over whole gait
periods), so slow, sideways and in-place steps do not creep. Every planned joint reference is
rate-limited to what the speed-capped servos can follow.

Heading is held from the torso orientation averaged over the last gait period (the commanded
yaw rate integrates into a desired heading that may lead the torso by at most what the rate
asks for; a heading knocked away is steered back, not given up); while walking straight the
desired heading also points back at the line walked so far (from the localisation estimate
``torso_pos_m``), so the lateral drift stays bounded.

Stop: the steps ramp down to zero, the feet close at the nominal stance, the robot holds
the walk stance on both feet with balance feedback (``halt_settle_s``), then blends into
the NAO's stand pose (``RobotDescription.stand_pose``), from which the keyframe kicks start.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.walk.gait import (
    StepPlan,
    WalkConfig,
    foot_fractions,
    foot_rows,
    nominal_foot,
    plan_step,
)
from mimic.floats import RecentMeans, clamp, clip_element
from mimic.geometry import torso_pitch_roll as _pitch_roll_left
from mimic.geometry import yaw_from_quat
from mimic.robot.joints import joint_index
from mimic.robot.leg_ik import leg_fk, leg_ik_floats, leg_joint_indices
from mimic.robot.nao import nao
from mimic.world.base import CYCLE_S, Observation

__all__ = ["WalkEngine", "torso_pitch_roll"]

_LEGS = (leg_joint_indices("left"), leg_joint_indices("right"))
# The same indices as plain ints, for the per-joint feedback.
_LEG_JOINTS = tuple(tuple(int(i) for i in legs) for legs in _LEGS)
# Each leg's joints follow each other in the NAO's joint table: its angles go in as a slice.
_LEG_SLICES = tuple(slice(legs[0], legs[-1] + 1) for legs in _LEG_JOINTS)
assert all(list(legs) == list(range(legs[0], legs[-1] + 1)) for legs in _LEG_JOINTS)
_SIDES = ("left", "right")
_SHOULDERS = (joint_index("left_shoulder_pitch"), joint_index("right_shoulder_pitch"))


def torso_pitch_roll(q_wxyz: np.ndarray, yaw_rad: float | None = None) -> tuple[float, float]:
    """Torso pitch (positive = leaning forward) and roll (positive = leaning *right*) [rad].

    The engine's gains were written for a right-positive roll: this is ``geometry``'s
    left-positive roll negated, nothing more (``yaw_rad``: as there).
    """
    pitch, roll_left = _pitch_roll_left(q_wxyz, yaw_rad)
    return pitch, -roll_left


def _wrap(a: float) -> float:
    return (a + _PI) % _TWO_PI - _PI


_PI, _TWO_PI = math.pi, 2 * math.pi


class WalkEngine(Agent):
    """Omnidirectional walk: ``set_velocity(vx, vy, yaw_rate)``, ``stop()``, ``reset(obs)``.

    States: ``starting`` (blend from the pose at reset into the walk posture), ``walking``,
    ``halting`` (last steps done, blend into the stand pose), ``standing`` (hold the stand
    pose; ``done`` is True). A new non-zero ``set_velocity`` restarts walking from any state.
    """

    name = "walk"
    team = "mimic"
    # The gait, IK and feedback are the NAO's geometry.
    robot_only = True

    def __init__(self, config: WalkConfig = WalkConfig()) -> None:
        super().__init__()
        self.config = config
        self._servos = nao().actuator
        self.period_s = 2 * config.step_time_s
        self._stand = nao().stand_pose()
        self._stand_list = self._stand.tolist()
        # Phases repeat: a step lasts whole cycles, so the feet's fractions of the way
        # (``foot_fractions``) are worked out once for each cycle of a step.
        self._fractions = [
            foot_fractions(config, i / config.step_cycles) for i in range(config.step_cycles + 1)
        ]
        # The step command's bounds (hoisted: constant over the engine's life).
        self._step_high = (config.max_step_x_m, config.max_step_y_m, config.max_step_yaw_rad)
        self._step_change = (
            config.max_step_change_x_m,
            config.max_step_change_y_m,
            config.max_step_change_yaw_rad,
        )
        self._odometry_high = (config.max_odometry_x_m, config.max_odometry_y_m)
        self._velocity = (0.0, 0.0, 0.0)
        self._stop_requested = False
        self._state = "standing"
        self.steps_taken = 0
        self._halt_shift_m: float | None = None
        self._init_state(self._stand)

    # --- commands -------------------------------------------------------------------------
    def set_velocity(self, vx_m_s: float, vy_m_s: float = 0.0, yaw_rate_rad_s: float = 0.0) -> None:
        """Walk at this velocity in the robot frame [m/s, m/s, rad/s] (ramped, clipped).

        An all-zero velocity keeps stepping in place; ``stop()`` ends the walk.
        """
        velocity = (float(vx_m_s), float(vy_m_s), float(yaw_rate_rad_s))
        if velocity[2] != self._velocity[2] or velocity[1] != self._velocity[1]:
            self._line = self._resume_line = None  # a new path: a line from where it is
        self._velocity = velocity
        self._stop_requested = False
        if self._state in ("halting", "standing"):
            self._begin("starting")

    def stop(self) -> None:
        """Finish walking: ramp the steps down, then settle into the stand pose."""
        self._velocity = (0.0, 0.0, 0.0)
        self._stop_requested = True
        if self._state == "starting":
            self._begin("halting")

    @property
    def state(self) -> str:
        """``starting``, ``walking``, ``halting`` or ``standing``."""
        return self._state

    @property
    def halt_shift_m(self) -> float:
        """How far the torso moves forward [m] (negative: back) over the feet when the
        nominal walk stance blends into the stand pose on halting: the walk carries the
        torso ahead of the ankles, the stand pose nearly over them."""
        if self._halt_shift_m is None:
            stand_x = np.mean(
                [leg_fk(side, self._stand[_LEGS[i]])[0][0] for i, side in enumerate(_SIDES)]
            )
            self._halt_shift_m = float(self.config.ankle_x_m - stand_x)
        return self._halt_shift_m

    @property
    def velocity_command(self) -> np.ndarray:
        """(3,) the commanded velocity [m/s, m/s, rad/s]."""
        return np.array(self._velocity)

    # --- agent ----------------------------------------------------------------------------
    def reset(self, obs: Observation) -> None:
        """Re-initialise from the current pose (e.g. after a get-up): blend into the walk."""
        self._restart(obs)

    def resume(self, obs: Observation) -> None:
        """As ``reset``, but a straight walk keeps the line it held (its start and heading):
        once walking again, it turns back to it. (A walk stopped before it held one starts a
        new line, as after ``reset``.)"""
        line = self._line
        self._restart(obs)
        self._resume_line = line

    def _restart(self, obs: Observation) -> None:
        self._init_state(obs.joint_angles_rad)
        if self._stop_requested and not any(self._velocity):
            self._begin("halting")
        else:
            self._begin("starting")

    def _init_state(self, pose: np.ndarray) -> None:
        cfg = self.config
        feet = np.array([nominal_foot(cfg, 0), nominal_foot(cfg, 1)])
        self._plan = StepPlan(0, feet, feet.copy(), np.zeros(3))
        self._cycle_in_step = 0
        # The step command, its ramped part and the odometry correction: plain floats.
        self._set_step_cmd((0.0, 0.0, 0.0))
        self._step_base = [0.0, 0.0, 0.0]
        self._pitch_state = (0.0, 0.0)
        self._tilt = (0.0, 0.0)  # this cycle's torso (pitch, roll), set by act
        self._gyro = [0.0, 0.0, 0.0]  # this cycle's gyro rates [rad/s], set by act
        self._peak_tilt = 0.0
        self._blend_from = np.asarray(pose, dtype=float).copy()
        self._blend_t = 0.0
        # Last cycle's nominal and reference poses and their difference, lists of floats.
        self._prev_nominal = None
        self._prev_ref = None
        self._prev_offset = None
        self._start_pose = None  # (plan, lean, pose): see _start_target
        self._heading_rad = None
        self._line = None
        # The line to take up again once walking (``resume``); None: a new one.
        self._resume_line: tuple[float, float, float] | None = None
        # cos and sin of the torso yaw over the last gait period (two steps).
        self._yaw_means = RecentMeans(2, 2 * cfg.step_cycles)
        # Odometry: torso positions of the last gait period (walking only), the step
        # commands that should have produced them, and the correction learnt from both.
        self._pos_history: deque[tuple[float, float]] = deque(maxlen=2 * cfg.step_cycles + 1)
        self._base_history: list[tuple[float, float]] = []
        self._odometry = (0.0, 0.0)
        self._line_step = (0.0, 0.0)
        self.done = False

    def _begin(self, state: str) -> None:
        self._state_before = self._state
        self._state = state
        self._blend_t = 0.0
        if state == "starting":
            self.done = False
            if self._prev_ref is not None:
                self._blend_from = np.array(self._prev_ref)  # restart from where the joints are
        if state == "halting":
            self._halt_from_walk = self._state_before == "walking"
            # The pose the halt holds, then leaves for the stand pose: floats.
            if self._halt_from_walk:
                self._halt_hold = self._walk_pose(self._plan.end.tolist(), self._lean_rad)
            elif self._prev_ref is not None:
                self._halt_hold = self._prev_ref.copy()
            else:
                self._halt_hold = self._blend_from.tolist()

    def act(self, obs: Observation, yaw_rad: float | None = None) -> JointCommand:
        """``yaw_rad``: ``obs.torso_yaw_rad`` if the caller has read it already."""
        cfg = self.config
        quat = obs.torso_quat_wxyz.tolist()
        yaw = yaw_from_quat(quat) if yaw_rad is None else yaw_rad
        self._update_heading(obs, yaw)
        # This cycle's torso tilt, read once (the feedback uses it too).
        pitch, roll_left = _pitch_roll_left(quat, yaw)
        roll = -roll_left  # right-positive: see torso_pitch_roll
        self._tilt = (pitch, roll)
        lean = self._lean_rad
        self._gyro = obs.gyro_rad_s.tolist()  # the feedback reads it too
        self._pitch_state = (pitch - lean, self._gyro[1])
        self._peak_tilt = max(self._peak_tilt, abs(pitch - lean), abs(roll))
        # References are planned for the end of this cycle: the proportional term closes the
        # gap to them, the feed-forward term adds the plan's own speed over the cycle.
        nominal, ref = self._reference()
        aim = ref if self._prev_ref is None or not cfg.track_previous else self._prev_ref
        angles = obs.joint_angles_rad.tolist()
        gain, top = cfg.tracking_gain_per_s, self._servos.max_speed_rad_s
        low = -top
        offset, speeds = [], []  # offset: the IMU feedback's part of the reference
        # Joint by joint on plain floats: the numbers of the servos' ``track`` (the gap to the
        # aim times the gain, capped: ``clip_symmetric``) plus the feed-forward, capped again.
        if self._prev_nominal is None:
            for a, q, n, r in zip(aim, angles, nominal, ref):
                offset.append(r - n)
                speed = gain * (a - q)
                speed = low if low > speed else speed
                speeds.append(top if top < speed else speed)
        else:
            ff, fb_ff, cycle_s = cfg.feedforward, cfg.feedback_feedforward, CYCLE_S
            for a, q, n, r, n0, o0 in zip(
                aim, angles, nominal, ref, self._prev_nominal, self._prev_offset
            ):
                o = r - n
                offset.append(o)
                speed = gain * (a - q)
                speed = low if low > speed else speed
                speed = top if top < speed else speed
                # The planned (feedback-free) reference's speed, the feedback's change.
                speed = speed + (ff * (n - n0) + fb_ff * (o - o0)) / cycle_s
                speed = low if low > speed else speed
                speeds.append(top if top < speed else speed)
        self._prev_nominal = nominal
        self._prev_ref = ref
        self._prev_offset = offset
        self._reference_floats, self._reference_array = ref, None
        # JointCommand.speeds without its np.asarray: the array is new, and float.
        return JointCommand(speed_rad_s=np.array(speeds))

    @property
    def reference_rad(self) -> np.ndarray | None:
        """(N,) the joint references of the last cycle [rad] (``Agent.reference_rad``),
        made into an array from the engine's floats when first read."""
        if self._reference_array is None and self._reference_floats is not None:
            self._reference_array = np.array(self._reference_floats)
        return self._reference_array

    @reference_rad.setter
    def reference_rad(self, value: np.ndarray | None) -> None:
        self._reference_floats, self._reference_array = None, value

    # --- heading and line -----------------------------------------------------------------
    def _update_heading(self, obs: Observation, yaw: float) -> None:
        """``yaw``: the torso's (``obs.torso_yaw_rad``) [rad]."""
        cfg = self.config
        self._yaw_rad = yaw
        # The torso yaws back and forth with every step: the heading hold steers on the
        # heading averaged over the last gait period (two steps).
        c, s = self._yaw_means.add(math.cos(yaw), math.sin(yaw))
        self._mean_yaw_rad = math.atan2(s, c) if cfg.smooth_heading else yaw
        if self._state != "walking":
            self._heading_rad = yaw
            self._line = None
            self._pos_history.clear()
            self._base_history = []
            return
        pos = obs.torso_pos_m.tolist()
        self._pos_history.append((pos[0], pos[1]))  # a full deque drops its oldest
        vx, vy, yaw_rate = self._velocity
        # Anti-windup: when the turn lags the command, the desired heading waits for it. Only
        # the command's own advance waits: a heading knocked away (a slipping foot, a rocking
        # step) is not given up, else every such knock would stay in the walked direction.
        # The lead allowed grows with the commanded rate: a slow turn asked for by an outer
        # loop (go-to-pose) must not run far ahead of the torso, or the two loops ring.
        lead = min(cfg.max_heading_error_rad, abs(yaw_rate) * cfg.heading_lead_s)
        ahead = _wrap(self._heading_rad + yaw_rate * CYCLE_S - self._mean_yaw_rad)
        if abs(ahead) <= lead or abs(ahead) < abs(_wrap(self._heading_rad - self._mean_yaw_rad)):
            self._heading_rad = _wrap(self._heading_rad + yaw_rate * CYCLE_S)
        self._aim_rad = self._heading_rad
        if cfg.line_gain and vy == 0.0 and yaw_rate == 0.0:
            if self._line is None:
                resumed, self._resume_line = self._resume_line, None
                self._line = resumed or (pos[0], pos[1], self._heading_rad)
            x0, y0, h = self._line
            c, s = math.cos(h), math.sin(h)
            offset = -s * (pos[0] - x0) + c * (pos[1] - y0)
            sign = 1.0 if vx >= 0 else -1.0
            aim = clamp(cfg.line_gain * offset, -cfg.max_line_aim_rad, cfg.max_line_aim_rad)
            self._aim_rad = _wrap(h - sign * float(aim))
        elif cfg.side_line_gain and vy != 0.0 and yaw_rate == 0.0:
            # Sideways or diagonal: the heading must stay (it is part of the command), so the
            # line is held with steps across it instead of by steering.
            if self._line is None:
                travel = self._heading_rad + math.atan2(vy, vx)
                self._line = (pos[0], pos[1], travel)
            x0, y0, h = self._line
            offset = -math.sin(h) * (pos[0] - x0) + math.cos(h) * (pos[1] - y0)
            most = cfg.max_side_line_step_m
            back = float(clamp(cfg.side_line_gain * offset, -most, most))
            across = h + math.pi / 2 - self._mean_yaw_rad  # the line's left, robot frame
            self._line_step = (-back * math.cos(across), -back * math.sin(across))
        else:
            self._line = None
        if self._line is None or vy == 0.0:
            self._line_step = (0.0, 0.0)

    # --- internals ------------------------------------------------------------------------
    def _walk_pose(self, feet: list[list[float]], lean_rad: float) -> list[float]:
        """The N joint angles putting the feet (left, right: x, y, z, yaw) of the walk frame
        under a leaning torso."""
        q = self._stand_list.copy()  # joint by joint: plain floats
        c, s = math.cos(lean_rad), math.sin(lean_rad)
        for side in (0, 1):
            x, y, z, yaw = feet[side]
            # Into the torso frame: tilt = Ry(lean)^T onto the foot position and onto the
            # foot rotation Rz(yaw), written out (each entry is the one non-zero product).
            cz, sz = math.cos(yaw), math.sin(yaw)
            ankle = (c * x - s * z, y, s * x + c * z)
            rot = ((c * cz, c * -sz, -s), (sz, cz, 0.0), (s * cz, s * -sz, c))
            q[_LEG_SLICES[side]] = leg_ik_floats(_SIDES[side], ankle, rot, 2)
        cfg = self.config
        swing = cfg.arm_swing_rad_per_m
        if swing:
            # The arm goes with the opposite leg, cancelling part of its yaw moment.
            q[_SHOULDERS[0]] += swing * (feet[1][0] - cfg.ankle_x_m)
            q[_SHOULDERS[1]] += swing * (feet[0][0] - cfg.ankle_x_m)
        return q

    def _set_step_cmd(self, cmd) -> None:
        """This step's command (dx, dy, dyaw), and the torso lean it asks for [rad] (worked
        out once per step: the walk reads it several times a cycle)."""
        cfg = self.config
        self._step_cmd = cmd
        self._lean_rad = (
            cfg.torso_pitch_rad + cfg.torso_pitch_per_speed * float(cmd[0]) / cfg.step_time_s
        )

    def _next_command(self) -> tuple[float, float, float]:
        """This step's command (dx, dy, dyaw): the velocity command ramped and clipped, its
        forward part corrected by the torso pitch at the step start (capture the fall).

        On plain floats, component by component (``clip_element``: np.clip's numbers)."""
        cfg = self.config
        t = cfg.step_time_s
        vx, vy, yaw_rate = self._velocity
        want_x, want_y, want_yaw = vx * t * cfg.stride_scale, vy * t, yaw_rate * t
        if not self._stop_requested:
            yaw = self._mean_yaw_rad
            want_yaw += cfg.heading_gain * _wrap(self._aim_rad - yaw)
        (high_x, high_y, high_yaw), (ramp_x, ramp_y, ramp_yaw) = self._step_high, self._step_change
        want_x = clip_element(want_x, -high_x, high_x)
        want_y = clip_element(want_y, -high_y, high_y)
        want_yaw = clip_element(want_yaw, -high_yaw, high_yaw)
        base_x, base_y, base_yaw = self._step_base
        base = [
            base_x + clip_element(want_x - base_x, -ramp_x, ramp_x),
            base_y + clip_element(want_y - base_y, -ramp_y, ramp_y),
            base_yaw + clip_element(want_yaw - base_yaw, -ramp_yaw, ramp_yaw),
        ]
        if cfg.caution_tilt_rad and self._peak_tilt > cfg.caution_tilt_rad:
            # The last step rocked the torso hard: shorter, straight steps until it calms.
            base[0] *= cfg.caution_step_scale
            base[2] = 0.0
        self._step_base = base
        calm = self._peak_tilt < cfg.odometry_calm_tilt_rad
        self._peak_tilt = 0.0
        pitch_err, pitch_rate = self._pitch_state
        x, y, yaw = base
        odometry_x, odometry_y = self._odometry_correction(calm)
        x += odometry_x
        y += odometry_y
        if not self._stop_requested:
            x += self._line_step[0]
            y += self._line_step[1]
        x += cfg.step_per_pitch_m * pitch_err + cfg.step_per_pitch_rate_m_s * pitch_rate
        return (
            clip_element(x, -high_x, high_x),
            clip_element(y, -high_y, high_y),
            clip_element(yaw, -high_yaw, high_yaw),
        )

    def _odometry_correction(self, calm: bool) -> tuple[float, float]:
        """Forward and sideways step correction [m]: the integrated gap between the
        steps commanded over the last gait period and the torso motion they produced.

        Short steps carry a bias of the gait (stepping in place or sideways creeps backward
        by a few cm/s, more on a slippery or heavier robot); the stride scale, calibrated at
        full speed, cannot see it, so the walked velocity is measured from the localisation
        estimate over whole gait periods (the torso's sway cancels) and fed back. It fades
        out toward full-speed forward steps, whose per-period motion is dominated by the
        heading's swing and the capture steps (there the stride scale and the line hold do
        the job). It learns only from calm steps: a lurch is the capture steps' business,
        and shortening the steps against it would trip the robot. Off while stopping, so the
        last steps still close the feet at the nominal stance."""
        cfg = self.config
        if self._stop_requested or not cfg.odometry_gain:
            self._odometry = (0.0, 0.0)
            return self._odometry
        n = 2 * cfg.step_cycles
        if calm and len(self._pos_history) > n and len(self._base_history) >= 2:
            (x0, y0), (x1, y1) = self._pos_history[0], self._pos_history[-1]
            c, s = math.cos(self._mean_yaw_rad), math.sin(self._mean_yaw_rad)
            walked = (c * (x1 - x0) + s * (y1 - y0), -s * (x1 - x0) + c * (y1 - y0))
            (bx0, by0), (bx1, by1) = self._base_history[-2], self._base_history[-1]
            wanted = ((bx0 + bx1) / cfg.stride_scale, by0 + by1)
            gain = cfg.odometry_gain
            (odometry_x, odometry_y), (lim_x, lim_y) = self._odometry, self._odometry_high
            self._odometry = (
                clip_element(odometry_x + gain * (wanted[0] - walked[0]) / 2, -lim_x, lim_x),
                clip_element(odometry_y + gain * (wanted[1] - walked[1]) / 2, -lim_y, lim_y),
            )
        weight = self._odometry_weight()
        return self._odometry[0] * weight, self._odometry[1] * weight

    def _odometry_weight(self) -> float:
        """1 for short forward steps, fading to 0 at ``odometry_fade_step_m``."""
        fade = self.config.odometry_fade_step_m
        return float(clamp(1.0 - abs(self._step_base[0]) / fade, 0.0, 1.0)) if fade else 1.0

    def _reference(self) -> tuple[list[float], list[float]]:
        """(nominal, reference) joint angles for the end of this cycle, N floats each [rad]."""
        cfg = self.config
        if self._state == "standing":
            self.done = True
            return self._stand_list.copy(), self._stand_list.copy()
        if self._state == "halting":
            return self._halt_reference()
        if self._state == "starting":
            self._blend_t += CYCLE_S
            a = min(1.0, self._blend_t / cfg.blend_s)
            a = 0.5 * (1 - math.cos(math.pi * a))
            ref = ((1 - a) * self._blend_from + a * self._start_target()).tolist()
            if self._blend_t >= cfg.blend_s - 1e-9:
                self._begin("walking")
                self._heading_rad = self._yaw_rad
                self._aim_rad = self._yaw_rad
                self._start_step(first=True)
            return ref, ref.copy()
        # walking
        self._cycle_in_step += 1
        if self._cycle_in_step > cfg.step_cycles:
            if self._stop_requested and self._at_rest():
                self._begin("halting")
                return self._halt_reference()
            self._start_step()
            self._cycle_in_step = 1
        feet = foot_rows(self._plan, self._fractions[self._cycle_in_step])
        if cfg.yaw_hold_gain:
            err = clamp(_wrap(self._yaw_rad - self._aim_rad), -0.3, 0.3)
            feet[self._plan.support][3] += cfg.yaw_hold_gain * err
        nominal = self._walk_pose(feet, self._lean_rad)
        if self._prev_nominal is not None and cfg.max_reference_speed_rad_s:
            nominal = self._rate_limited(nominal)
        return nominal, self._feedback(nominal)

    def _start_target(self) -> np.ndarray:
        """The walk posture the start blends into: the feet where the first step starts,
        under the leaning torso (worked out once: neither changes while starting)."""
        plan, lean = self._plan, self._lean_rad
        cached = self._start_pose
        if cached is None or cached[0] is not plan or cached[1] != lean:
            pose = np.array(self._walk_pose(plan.start.tolist(), lean))
            cached = self._start_pose = (plan, lean, pose)
        return cached[2]

    def _halt_reference(self) -> tuple[list[float], list[float]]:
        """Halting: after the last step, hold the walk stance with both feet down for
        ``halt_settle_s`` (balance feedback on, so the last steps' rocking dies out), then
        blend into the stand pose while the feedback fades out."""
        cfg = self.config
        self._blend_t += CYCLE_S
        settle = cfg.halt_settle_s if self._halt_from_walk else 0.0
        a = min(1.0, max(0.0, self._blend_t - settle) / cfg.blend_s)
        a = 0.5 * (1 - math.cos(math.pi * a))
        keep = 1 - a
        # Joint by joint on plain floats: (1 - a) hold + a stand, then the feedback faded.
        nominal = [keep * h + a * s for h, s in zip(self._halt_hold, self._stand_list)]
        fed = self._feedback(nominal, both_support=True)
        ref = [n + keep * (f - n) for n, f in zip(nominal, fed)]
        if self._blend_t >= settle + cfg.blend_s - 1e-9:
            self._begin("standing")
        return nominal, ref

    def _rate_limited(self, nominal: list[float]) -> list[float]:
        """The planned pose moved from last cycle's by at most the reference speed cap per
        joint: the servos cannot follow faster, and a reachable plan keeps the feed-forward
        honest (the swing leg then lifts and swings as fast as its joints can go)."""
        step = self.config.max_reference_speed_rad_s * CYCLE_S
        limited = []
        for q, q0 in zip(nominal, self._prev_nominal):
            # ``clip_symmetric``'s numbers, joint by joint.
            move = q - q0
            move = -step if -step > move else move
            limited.append(q0 + (step if step < move else move))
        return limited

    def _at_rest(self) -> bool:
        """The ramped command is zero and the last step ended near the nominal stance."""
        feet = np.array([nominal_foot(self.config, 0), nominal_foot(self.config, 1)])
        return not any(self._step_base) and bool(
            np.abs(self._plan.end - feet).max() < self.config.rest_tolerance_m
        )

    def _start_step(self, first: bool = False) -> None:
        end = self._plan.end
        if first:
            support = 1 if self._velocity[1] >= 0 and self._velocity[2] >= 0 else 0
            self._cycle_in_step = 0
        else:
            support = 1 - self._plan.support
            self.steps_taken += 1
        self._set_step_cmd(self._next_command())
        self._base_history.append((self._step_base[0], self._step_base[1]))
        del self._base_history[:-2]
        self._plan = plan_step(self.config, support, end, self._step_cmd)

    def _feedback(self, nominal: list[float], both_support: bool = False) -> list[float]:
        """``nominal`` plus IMU feedback (a new list): torso tilt and gyro rates (this
        cycle's, read by ``act``): the tilt onto both hips and, as foot placement, onto the
        swing hip, and onto the support ankle; the gyro rates onto both ankles."""
        cfg = self.config
        ref = nominal.copy()
        gx, gy, _ = self._gyro
        pitch, roll = self._tilt
        pitch -= self._lean_rad
        # Each term once (both legs add the same numbers).
        gyro_pitch, gyro_roll = cfg.gyro_pitch_gain * gy, cfg.gyro_roll_gain * gx
        tilt_pitch, tilt_roll = cfg.tilt_pitch_gain * pitch, cfg.tilt_roll_gain * roll
        swing_pitch, swing_roll = cfg.swing_pitch_gain * pitch, cfg.swing_roll_gain * roll
        ankle_pitch, ankle_roll = cfg.ankle_pitch_gain * pitch, cfg.ankle_roll_gain * roll
        for side in (0, 1):
            legs = _LEG_JOINTS[side]
            ref[legs[4]] += gyro_pitch
            ref[legs[5]] += gyro_roll
            ref[legs[2]] += tilt_pitch
            ref[legs[1]] += tilt_roll
            if side != self._plan.support and not both_support:
                ref[legs[2]] += swing_pitch
                ref[legs[1]] += swing_roll
            else:
                ref[legs[4]] += ankle_pitch
                ref[legs[5]] += ankle_roll
        return ref
