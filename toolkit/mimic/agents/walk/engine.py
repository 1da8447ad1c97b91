"""Our omnidirectional walk engine: LIPM foot trajectories, leg IK, IMU feedback.

Each cycle the engine advances the step phase, places both feet in the level walk frame
(``gait.feet_at``), tilts them into the torso frame by the torso lean, solves both legs with
the closed-form IK, adds gyro / tilt feedback on ankles and hips, and tracks the references
with the proportional ``TrackingController`` plus a feed-forward term (the reference's own
speed over the cycle), so the speed-capped joints do not lag the gait by 1/gain.
"""

from __future__ import annotations

import math

import numpy as np

from mimic.agents.base import Agent
from mimic.agents.tracking import TrackingController
from mimic.agents.walk.gait import StepPlan, WalkConfig, feet_at, nominal_foot, plan_step
from mimic.motion.files import stand_pose_rad
from mimic.robot.joints import joint_index
from mimic.robot.leg_ik import leg_ik, leg_joint_indices
from mimic.robot.mjcf import MAX_JOINT_SPEED_RAD_S
from mimic.world.world import CYCLE_S, Observation

__all__ = ["WalkEngine", "stand_pose_rad", "torso_pitch_roll"]

_LEGS = (leg_joint_indices("left"), leg_joint_indices("right"))
_SIDES = ("left", "right")
_SHOULDERS = (joint_index("left_shoulder_pitch"), joint_index("right_shoulder_pitch"))


def torso_pitch_roll(q_wxyz: np.ndarray) -> tuple[float, float]:
    """Torso pitch (positive = leaning forward) and roll (positive = leaning right) [rad]."""
    w, x, y, z = q_wxyz
    # Torso z axis in the world, then seen in the heading frame.
    zx = 2 * (x * z + w * y)
    zy = 2 * (y * z - w * x)
    zz = 1 - 2 * (x * x + y * y)
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    c, s = math.cos(yaw), math.sin(yaw)
    fwd, left = c * zx + s * zy, -s * zx + c * zy
    return math.atan2(fwd, zz), math.atan2(-left, zz)


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


def _rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def _rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


class WalkEngine(Agent):
    """Omnidirectional walk: ``set_velocity(vx, vy, yaw_rate)``, ``stop()``, ``reset(obs)``.

    States: ``starting`` (blend from the pose at reset into the walk posture), ``walking``,
    ``halting`` (last steps done, blend into the stand pose), ``standing`` (hold the stand
    pose; ``done`` is True). A new ``set_velocity`` restarts walking from any state.
    """

    name = "walk"
    team = "mimic"

    def __init__(self, config: WalkConfig = WalkConfig(),
                 tracking: TrackingController = TrackingController()) -> None:
        super().__init__()
        self.config = config
        self.tracking = tracking
        self.period_s = 2 * config.step_s
        self._stand = stand_pose_rad()
        self._velocity = np.zeros(3)
        self._stop_requested = False
        self._state = "standing"
        self.steps_taken = 0
        self._init_state(self._stand)

    # --- commands -------------------------------------------------------------------------
    def set_velocity(self, vx_m_s: float, vy_m_s: float = 0.0, yaw_rate_rad_s: float = 0.0) -> None:
        """Walk at this velocity in the robot frame [m/s, m/s, rad/s] (ramped, clipped)."""
        self._velocity = np.array([vx_m_s, vy_m_s, yaw_rate_rad_s], dtype=float)
        self._stop_requested = False
        if self._state in ("halting", "standing"):
            self._begin("starting")

    def stop(self) -> None:
        """Finish walking: ramp the steps down, then settle into the stand pose."""
        self._velocity = np.zeros(3)
        self._stop_requested = True

    @property
    def state(self) -> str:
        return self._state

    @property
    def velocity_command(self) -> np.ndarray:
        """(3,) the commanded velocity [m/s, m/s, rad/s]."""
        return self._velocity.copy()

    # --- agent ----------------------------------------------------------------------------
    def reset(self, obs: Observation) -> None:
        """Re-initialise from the current pose (e.g. after a get-up): blend into the walk."""
        self._init_state(obs.joint_angles_rad)
        self._last_time_s = obs.time_s
        self._heading_rad = obs.torso_yaw_rad
        if self._stop_requested and not np.any(self._velocity):
            self._begin("halting")
        else:
            self._begin("starting")

    def _init_state(self, pose: np.ndarray) -> None:
        cfg = self.config
        feet = np.array([nominal_foot(cfg, 0), nominal_foot(cfg, 1)])
        self._plan = StepPlan(0, feet, feet.copy(), np.zeros(3))
        self._phase = 0.0
        self._step_cmd = np.zeros(3)
        self._blend_from = np.asarray(pose, dtype=float).copy()
        self._blend_t = 0.0
        self._last_time_s = None
        self._prev_ref = None
        self._heading_rad = None
        self._yaw_rad = 0.0
        self.done = False

    def _begin(self, state: str) -> None:
        self._state = state
        self._blend_t = 0.0
        if state == "starting":
            self.done = False
        if state == "halting" and self._prev_ref is not None:
            self._blend_from = self._prev_ref.copy()

    def act(self, obs: Observation) -> np.ndarray:
        cfg = self.config
        dt = CYCLE_S
        if self._last_time_s is not None and obs.time_s > self._last_time_s:
            dt = obs.time_s - self._last_time_s
        self._last_time_s = obs.time_s
        self._yaw_rad = obs.torso_yaw_rad
        if self._heading_rad is None or self._state != "walking":
            self._heading_rad = self._yaw_rad
        else:
            self._heading_rad = _wrap(self._heading_rad + self._velocity[2] * dt)
        # The reference is planned one cycle ahead: the proportional term tracks where the
        # joints should be now, the feed-forward term is the speed that reaches the next
        # reference by the end of this cycle.
        ref_next = self._reference(obs, dt)
        ref_now = ref_next if self._prev_ref is None else self._prev_ref
        speeds = self.tracking.speeds(ref_now, obs.joint_angles_rad)
        if cfg.feedforward:
            speeds = np.clip(speeds + (ref_next - ref_now) / dt,
                             -MAX_JOINT_SPEED_RAD_S, MAX_JOINT_SPEED_RAD_S)
        self._prev_ref = ref_next
        self.reference_rad = ref_now
        return speeds

    # --- internals ------------------------------------------------------------------------
    def _walk_pose(self, feet: np.ndarray, lean_rad: float) -> np.ndarray:
        """(22,) joint angles putting the feet (2, 4) of the walk frame under a leaning torso."""
        q = self._stand.copy()
        tilt = _rot_y(lean_rad).T
        for side in (0, 1):
            x, y, z, yaw = feet[side]
            rot = tilt @ _rot_z(yaw)
            q[_LEGS[side]] = leg_ik(_SIDES[side], tilt @ np.array([x, y, z]), rot, passes=2)
        swing = self.config.arm_swing_rad_per_m
        if swing:
            # Shoulder pitch: positive lifts the arm forward... the arm goes with the other leg.
            q[_SHOULDERS[0]] += swing * (feet[1, 0] - self.config.ankle_x_m)
            q[_SHOULDERS[1]] += swing * (feet[0, 0] - self.config.ankle_x_m)
        return q

    def _lean(self) -> float:
        cfg = self.config
        return cfg.torso_pitch_rad + cfg.torso_pitch_per_speed * self._step_cmd[0] / cfg.step_s

    def _next_command(self) -> np.ndarray:
        cfg = self.config
        want = self._velocity * cfg.step_s
        if self._heading_rad is not None:
            want[2] += cfg.heading_gain * _wrap(self._heading_rad - self._yaw_rad)
        want = np.clip(want, [-cfg.max_step_x_m, -cfg.max_step_y_m, -cfg.max_step_yaw_rad],
                       [cfg.max_step_x_m, cfg.max_step_y_m, cfg.max_step_yaw_rad])
        lim = np.array([cfg.max_step_change_x_m, cfg.max_step_change_y_m,
                        cfg.max_step_change_yaw_rad])
        return self._step_cmd + np.clip(want - self._step_cmd, -lim, lim)

    def _reference(self, obs: Observation, dt: float) -> np.ndarray:
        cfg = self.config
        if self._state == "standing":
            self.done = True
            return self._stand.copy()
        if self._state in ("starting", "halting"):
            self._blend_t += dt
            a = min(1.0, self._blend_t / cfg.blend_s)
            a = 0.5 * (1 - math.cos(math.pi * a))
            if self._state == "starting":
                target = self._walk_pose(self._plan.start, self._lean())
            else:
                target = self._stand
            ref = (1 - a) * self._blend_from + a * target
            if self._blend_t >= cfg.blend_s - 1e-9:
                self._begin("walking" if self._state == "starting" else "standing")
                if self._state == "walking":
                    self._start_step(first=True)
            return ref
        # walking
        self._phase += dt / cfg.step_s
        if self._phase >= 1.0 - 1e-9:
            self._phase = 0.0
            if self._stop_requested and self._at_rest():
                self._begin("halting")
                self._blend_from = self._prev_ref.copy()
                return self._prev_ref.copy()
            self._start_step()
        feet = feet_at(cfg, self._plan, self._phase)
        ref = self._walk_pose(feet, self._lean())
        return self._feedback(ref, obs)

    def _at_rest(self) -> bool:
        feet = np.array([nominal_foot(self.config, 0), nominal_foot(self.config, 1)])
        return (not np.any(self._step_cmd)) and bool(np.allclose(self._plan.end, feet, atol=1e-6))

    def _start_step(self, first: bool = False) -> None:
        end = self._plan.end
        if first:
            support = 1 if self._velocity[1] >= 0 and self._velocity[2] >= 0 else 0
        else:
            support = 1 - self._plan.support
            self.steps_taken += 1
        self._step_cmd = self._next_command()
        self._plan = plan_step(self.config, support, end, self._step_cmd)

    def _feedback(self, ref: np.ndarray, obs: Observation) -> np.ndarray:
        cfg = self.config
        gx, gy, _ = obs.gyro_rad_s
        if cfg.gyro_pitch_gain or cfg.gyro_roll_gain:
            for side in (0, 1):
                legs = _LEGS[side]
                ref[legs[4]] += cfg.gyro_pitch_gain * gy
                ref[legs[5]] += cfg.gyro_roll_gain * gx
        if cfg.tilt_pitch_gain or cfg.tilt_roll_gain:
            pitch, roll = torso_pitch_roll(obs.torso_quat_wxyz)
            for side in (0, 1):
                legs = _LEGS[side]
                ref[legs[2]] += cfg.tilt_pitch_gain * (pitch - self._lean())
                ref[legs[1]] += cfg.tilt_roll_gain * roll
        return ref
