"""Go to a pose on the field with the walk engine, steering from ground-truth localisation.

Far from the target the robot turns toward it and walks forward (slowing when the target is
off to the side); near it, it strafes and turns onto the final heading with speeds
proportional to the remaining error (the walk engine itself trims the creep of slow steps);
inside the tolerance it stops. All errors use the torso pose averaged over the last gait
period, since the torso sways and yaws with every step. ``arrived`` becomes True once the
engine stands still within the tolerance; if the halt left it outside, it walks again (a
few retries at most; after the last one ``arrived`` is set anyway and ``errors()`` tells how
close it got).

Ball avoidance: when the target sits behind the ball (``pose_behind_ball``), the robot first
walks to a staging point behind the target (going round the ball when it is in the way),
then straight in along the final heading. Closer to the ball than ``ball_inner_m`` it
first backs away; when the way to the staging point passes the ball it orbits the ball at
``ball_clearance_m`` in short chords. Within ``ball_slow_radius_m`` of the ball it takes short
steps only and steps forward only once lined up sideways and in heading (the sideways and
turning steps are the ones that reach the ball), so a swinging foot rarely reaches the ball
(not never: measured in ``benchmarks/goto_ball.py``), and the arrival tolerance is a little
looser there, since each extra correction risks a touch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.agents.walk.engine import WalkEngine
from mimic.floats import RecentMeans, clamp
from mimic.geometry import yaw_from_quat
from mimic.world.base import CYCLE_S, Observation

__all__ = ["GoToConfig", "GoToPose", "pose_behind_ball", "wrap_angle"]


def wrap_angle(a: float) -> float:
    """Angle wrapped to [-pi, pi) [rad]."""
    return (a + _PI) % _TWO_PI - _PI


_PI, _TWO_PI = math.pi, 2 * math.pi


def pose_behind_ball(ball_xy, target_xy, ball_offset_m) -> tuple[float, float, float]:
    """Torso pose (x, y, heading) [m, m, rad] in the field frame that faces ``target_xy``
    from the ball with the ball at ``ball_offset_m`` = (forward, left) in the robot frame."""
    bx, by = ball_xy
    heading = math.atan2(target_xy[1] - by, target_xy[0] - bx)
    c, s = math.cos(heading), math.sin(heading)
    ox, oy = ball_offset_m
    return bx - (c * ox - s * oy), by - (s * ox + c * oy), heading


@dataclass(frozen=True)
class GoToConfig:
    """Steering gains and tolerances."""

    # Arrival tolerance: position [m] and heading [rad].
    tolerance_m: float = 0.03
    tolerance_rad: float = math.radians(6)
    # Stop is triggered at this fraction of the tolerance (the halt adds a little drift).
    stop_fraction: float = 0.7
    # Beyond this distance [m] walk facing the target; inside it, align with the heading.
    far_m: float = 0.5
    # Top speeds: forward [m/s], sideways [m/s], turning [rad/s].
    max_vx_m_s: float = 0.45
    max_vy_m_s: float = 0.15
    max_yaw_rate_rad_s: float = 0.6
    # Proportional gains: speed per metre of error [1/s], turn rate per radian [1/s].
    position_gain_per_s: float = 1.5
    heading_gain_per_s: float = 2.0
    # Near the target: heading gain [1/s] and top turn rate [rad/s].
    near_heading_gain_per_s: float = 1.0
    near_max_yaw_rate_rad_s: float = 0.3
    # Integral gain near the target [1/s^2] (at most ``max_integral_m_s``). Off: the walk
    # engine's odometry feedback removes the creep of small steps, and an integral on top
    # winds up while the robot turns in place and pushes it past the target (0: off).
    integral_gain_per_s2: float = 0.0
    max_integral_m_s: float = 0.12
    # Smallest useful speed near the target (the walk quantises steps) [m/s].
    min_speed_m_s: float = 0.04
    # How many times to walk again when a halt ends outside the tolerance.
    max_retries: int = 4
    # Walk around the ball (``Observation.ball_pos_m``) when it lies near the target.
    avoid_ball: bool = True
    # The ball counts as "near the target" within this distance of it [m].
    ball_near_target_m: float = 0.35
    # Clearance of the torso from the ball while going around it; the staging point is this
    # far behind the target [m].
    ball_clearance_m: float = 0.3
    # Closer than this to the ball [m], outside the approach lane, the robot first backs away.
    ball_inner_m: float = 0.22
    # Going round the ball, each waypoint lies this much farther round it [rad].
    ball_orbit_step_rad: float = 0.7
    # Half-width of the lane behind the target from which the robot walks straight in [m].
    approach_lane_m: float = 0.1
    # Within this distance of the ball [m] the robot walks at most ``ball_approach_speed``.
    ball_slow_radius_m: float = 0.45
    ball_approach_speed_m_s: float = 0.12
    # The robot enters the approach lane only facing the final heading this closely [rad].
    approach_heading_rad: float = math.radians(15)
    # Next to the ball, step forward only once lined up sideways and in heading (within
    # twice the tolerance; full speed within one).
    ball_line_up_first: bool = True
    # Arrival tolerances are scaled by this next to the ball.
    near_ball_tolerance_scale: float = 1.4
    # The integral term only works this close to the target [m] (no wind-up on the way in).
    integral_radius_m: float = 0.08
    # Speed toward the goal point at most sqrt(2 * this * distance) [m/s^2]: a walking robot
    # braked harder pitches forward over its feet (and the last steps overshoot).
    max_decel_m_s2: float = 0.25


class GoToPose(Agent):
    """Walks the robot to ``set_target(x, y, heading)`` and stops there."""

    name = "goto"
    team = "mimic"
    robot_only = True

    def __init__(self, engine: WalkEngine, config: GoToConfig = GoToConfig()) -> None:
        super().__init__()
        self.engine = engine
        self.config = config
        self.period_s = engine.period_s
        # Cycles in the steering's averaging window (a gait period).
        self._window = max(1, round(engine.period_s / CYCLE_S))
        self._history = RecentMeans(4, self._window)  # torso x, y, cos and sin of its yaw
        self._target = None
        self._integral = (0.0, 0.0)
        self._approaching = False
        self._retries = 0
        self._stopping = False
        self._arrived = False

    def set_target(self, x_m: float, y_m: float, heading_rad: float) -> None:
        """Target torso pose in the field frame [m, m, rad]."""
        self._target = (float(x_m), float(y_m), float(heading_rad))
        # The target frame's axes (the ball waypoint reads them every cycle).
        self._target_axes = (math.cos(self._target[2]), math.sin(self._target[2]))
        self._integral = (0.0, 0.0)
        self._approaching = False
        self._retries = 0
        self._stopping = False
        self._arrived = False
        self.done = False

    @property
    def arrived(self) -> bool:
        """Standing still within the tolerance of the target."""
        return self._arrived

    def errors(self, obs: Observation) -> tuple[float, float, float]:
        """Target in the robot frame: (forward [m], left [m], heading error [rad])."""
        return self._errors(obs.torso_pos_m[0], obs.torso_pos_m[1], obs.torso_yaw_rad)

    def _errors(self, px: float, py: float, yaw: float) -> tuple[float, float, float]:
        x, y, heading = self._target
        dx, dy = x - px, y - py
        c, s = math.cos(yaw), math.sin(yaw)
        return c * dx + s * dy, -s * dx + c * dy, wrap_angle(heading - yaw)

    def _smoothed_errors(self, x: float, y: float, yaw: float) -> tuple[float, float, float]:
        """``errors`` of the torso pose (``x``, ``y`` [m], heading ``yaw`` [rad]) averaged
        over the last gait period: the torso sways and yaws with every step, and steering on
        that swing would feed it."""
        px, py, c, s = self._history.add(x, y, math.cos(yaw), math.sin(yaw))
        return self._errors(px, py, math.atan2(s, c))

    def reset(self, obs: Observation) -> None:
        self.engine.reset(obs)
        self._history.clear()
        self._stopping = False
        self._arrived = False
        self.done = False

    def act(self, obs: Observation) -> JointCommand:
        # obs.torso_yaw_rad, read once, for the steering and the engine.
        yaw = yaw_from_quat(obs.torso_quat_wxyz.tolist())
        if self._target is not None:
            self._steer(obs, yaw)
        speeds = self.engine.act(obs, yaw)
        self.done = self._arrived
        return speeds

    @property
    def reference_rad(self) -> np.ndarray | None:
        """The engine's references (``WalkEngine.reference_rad``): this agent only steers."""
        return self.engine.reference_rad

    @reference_rad.setter
    def reference_rad(self, value: np.ndarray | None) -> None:
        # Only Agent.__init__ sets it (to None): the references are the engine's.
        if value is not None:
            raise AttributeError("GoToPose's references are its engine's")

    def _ball_waypoint(self, ball_xy, torso_xy, yaw: float) -> tuple[float, float] | None:
        """Waypoint (forward, left) [m] in the robot frame (torso at ``torso_xy``, heading
        ``yaw`` [rad]; the ball at ``ball_xy``, field frame [m]) that leads around the ball to
        a staging point behind it, or None once the robot is in the approach lane (or the
        ball is not near the target)."""
        cfg = self.config
        x, y, heading = self._target
        ball_x, ball_y = ball_xy
        torso_x, torso_y = torso_xy
        bx, by = ball_x - x, ball_y - y
        if not cfg.avoid_ball or math.hypot(bx, by) > cfg.ball_near_target_m:
            return None
        # Target frame: x along the final heading, origin at the target.
        c, s = self._target_axes
        ball_fwd, ball_left = c * bx + s * by, -s * bx + c * by
        rx, ry = torso_x - x, torso_y - y
        robot_fwd, robot_left = c * rx + s * ry, -s * rx + c * ry
        lane = cfg.approach_lane_m
        if self._approaching:
            self._approaching = abs(robot_left) < 2 * lane and robot_fwd < ball_fwd - 0.1
        else:
            aligned = abs(wrap_angle(heading - yaw)) < cfg.approach_heading_rad
            self._approaching = (
                abs(robot_left) < lane and robot_fwd < -lane and aligned
            ) or _hypot_below(robot_fwd, robot_left, cfg.tolerance_m)
        if self._approaching:
            return None
        stage_fwd, stage_left = -cfg.ball_clearance_m, 0.0
        way_fwd, way_left = stage_fwd, stage_left
        away_fwd, away_left = robot_fwd - ball_fwd, robot_left - ball_left
        if _hypot_below(away_fwd, away_left, cfg.ball_inner_m):
            # Too close to the ball anywhere but the lane: back straight away from it first.
            reach = float(np.hypot(away_fwd, away_left))
            back_m = cfg.ball_clearance_m + 0.05
            way_fwd = ball_fwd + away_fwd / max(reach, 1e-9) * back_m
            way_left = ball_left + away_left / max(reach, 1e-9) * back_m
        elif _segment_distance_below(
            (ball_fwd, ball_left),
            (robot_fwd, robot_left),
            (stage_fwd, stage_left),
            cfg.ball_clearance_m,
        ):
            # The way to the staging point passes the ball: orbit it at the clearance, one
            # short chord at a time, on the side that reaches the staging point sooner.
            reach = float(np.hypot(away_fwd, away_left))
            here = math.atan2(away_left, away_fwd)
            there = math.atan2(stage_left - ball_left, stage_fwd - ball_fwd)
            turn = wrap_angle(there - here)
            if abs(abs(turn) - math.pi) < 0.3:  # straight opposite: pass on the robot's side
                turn = math.copysign(abs(turn), away_left if away_left else 1.0)
            angle = here + math.copysign(min(abs(turn), cfg.ball_orbit_step_rad), turn)
            radius = max(cfg.ball_clearance_m, min(reach, 1.5 * cfg.ball_clearance_m))
            way_fwd = ball_fwd + radius * math.cos(angle)
            way_left = ball_left + radius * math.sin(angle)
        # Back to the field frame, then into the robot frame.
        wx, wy = c * way_fwd - s * way_left + x, s * way_fwd + c * way_left + y
        dx, dy = wx - torso_x, wy - torso_y
        cy, sy = math.cos(yaw), math.sin(yaw)
        return cy * dx + sy * dy, -sy * dx + cy * dy

    def _steer(self, obs: Observation, yaw: float) -> None:
        """``yaw``: the torso's (``obs.torso_yaw_rad``) [rad]."""
        cfg = self.config
        state = self.engine.state  # the engine's until stop() or set_velocity() below
        if state == "standing":
            self._history.clear()  # standing still: the pose is exact
        tx, ty = obs.torso_pos_m.tolist()[:2]
        bx, by = obs.ball_pos_m.tolist()[:2]
        fx, fy, dh = self._smoothed_errors(tx, ty, yaw)
        # Next to the ball every extra correction risks touching it: settle for a little less.
        loose = 1.0
        ball_slow = _hypot_below(bx - tx, by - ty, cfg.ball_slow_radius_m)
        near_ball = cfg.avoid_ball and ball_slow
        if near_ball:
            loose = cfg.near_ball_tolerance_scale
        elif state != "standing":
            # Steer the pose the robot will stand in once halted, not the walking one. Not
            # next to the ball: there the torso must not get closer to it than the target,
            # and the halt moving it back is the safe side.
            fx -= self.engine.halt_shift_m
        dist = math.hypot(fx, fy)
        inside = dist < loose * cfg.tolerance_m and abs(dh) < loose * cfg.tolerance_rad
        if self._stopping:
            if state == "standing":
                if inside:
                    self._arrived = True
                elif self._retries < cfg.max_retries:
                    self._retries += 1
                    self._stopping = False
                    self._integral = (0.0, 0.0)
                else:
                    self._arrived = True  # best effort; errors() tells how close
            return
        if (
            dist < cfg.stop_fraction * cfg.tolerance_m
            and abs(dh) < cfg.stop_fraction * cfg.tolerance_rad
        ):
            self.engine.stop()
            self._stopping = True
            return
        way = self._ball_waypoint((bx, by), (tx, ty), yaw)
        if way is not None:
            fx, fy = way  # head for the waypoint; on arrival there, the next one takes over
            dist = math.hypot(fx, fy)
        if dist > cfg.far_m or (way is not None and dist > 0.5 * cfg.far_m):
            # Far: face the goal point and walk forward.
            bearing = math.atan2(fy, fx)
            yaw_rate = cfg.heading_gain_per_s * bearing
            vx = cfg.max_vx_m_s * max(0.0, math.cos(bearing)) ** 2
            vx = min(vx, cfg.position_gain_per_s * dist)
            vy = 0.0
        else:
            # Near: face the final heading and move sideways / forward onto the point.
            # Gentler near the target: the torso's yaw swings with every step, and a fast
            # heading loop on top of the walk's own heading hold rings.
            most = cfg.near_max_yaw_rate_rad_s
            yaw_rate = float(clamp(cfg.near_heading_gain_per_s * dh, -most, most))
            if state == "walking" and way is None and dist < cfg.integral_radius_m:
                # clip_symmetric's numbers (its limit > 0), component by component.
                gain, most_m_s = cfg.integral_gain_per_s2 * CYCLE_S, cfg.max_integral_m_s
                self._integral = (
                    clamp(self._integral[0] + gain * fx, -most_m_s, most_m_s),
                    clamp(self._integral[1] + gain * fy, -most_m_s, most_m_s),
                )
            vx = cfg.position_gain_per_s * fx + self._integral[0]
            vy = cfg.position_gain_per_s * fy + self._integral[1]
            low = cfg.min_speed_m_s if way is None else 2 * cfg.min_speed_m_s
            if way is None and dist < cfg.tolerance_m:
                vx = vy = 0.0  # in place: only the heading is left to fix
            elif dist > cfg.stop_fraction * cfg.tolerance_m:
                scale = max(1.0, low / max(math.hypot(vx, vy), 1e-9))
                vx, vy = vx * scale, vy * scale
        vx = float(clamp(vx, -0.5 * cfg.max_vx_m_s, cfg.max_vx_m_s))
        vy = float(clamp(vy, -cfg.max_vy_m_s, cfg.max_vy_m_s))
        if cfg.max_decel_m_s2:
            brake = math.sqrt(2 * cfg.max_decel_m_s2 * dist)
            scale = min(1.0, brake / max(math.hypot(vx, vy), 1e-9))
            vx, vy = vx * scale, vy * scale
        if cfg.avoid_ball and way is None:
            # Short steps near the ball: a long stride's swing foot would reach it.
            if ball_slow:
                scale = min(1.0, cfg.ball_approach_speed_m_s / max(math.hypot(vx, vy), 1e-9))
                vx, vy = vx * scale, vy * scale
                if cfg.ball_line_up_first and vx > 0.0:
                    # Line up first, then step in: sideways and turning steps next to the
                    # ball are the ones that reach it, so the forward part waits for them.
                    off = max(abs(fy) / cfg.tolerance_m, abs(dh) / cfg.tolerance_rad)
                    vx *= float(clamp(2.0 - off, 0.0, 1.0))
        most = cfg.max_yaw_rate_rad_s
        self.engine.set_velocity(vx, vy, float(clamp(yaw_rate, -most, most)))


# The steering compares distances from np.hypot with bounds, and that is all it uses them for
# (but on rare branches). The squared distance answers such a comparison unless it lies
# within a relative _BAND of the squared bound: np.hypot's result (within an ulp of the
# exact distance) cannot fall on the other side of the bound then; inside the band np.hypot
# decides. The same answers, without np.hypot's per-call cost on every cycle.
_BAND = 1e-9


def _hypot_below(dx: float, dy: float, bound: float) -> bool:
    """``np.hypot(dx, dy) < bound``: the same answer, np.hypot called only near the bound."""
    below = _squared_below(dx * dx + dy * dy, bound)
    return float(np.hypot(dx, dy)) < bound if below is None else below


def _squared_below(squared: float, bound: float) -> bool | None:
    """Whether the distance whose square (on plain floats) is ``squared`` is below ``bound``;
    None within the band around the bound (and for a bound too small or too large to square
    safely), where the exact distance must decide."""
    if 1e-100 < bound < 1e100:
        bound2 = bound * bound
        if squared < bound2 * (1 - _BAND):
            return True
        if squared > bound2 * (1 + _BAND):
            return False
    return None


def _segment_distance_below(point, a, b, bound: float) -> bool:
    """``_segment_distance(point, a, b) < bound``, the same answer: the distance worked out
    on plain floats (it differs from numpy's by roundings only, far inside the band), numpy's
    deciding near the bound."""
    (px, py), (ax, ay), (bx, by) = point, a, b
    abx, aby = bx - ax, by - ay
    along = ((px - ax) * abx + (py - ay) * aby) / max(abx * abx + aby * aby, 1e-12)
    t = clamp(along, 0.0, 1.0)
    dx, dy = ax + t * abx - px, ay + t * aby - py
    below = _squared_below(dx * dx + dy * dy, bound)
    return _segment_distance(point, a, b) < bound if below is None else below


def _segment_distance(point, a, b) -> float:
    """Distance [m] from ``point`` to the segment a-b (2-D, each a pair of floats)."""
    point, a, b = np.array(point), np.array(a), np.array(b)
    ab = b - a
    t = float(clamp(np.dot(point - a, ab) / max(float(np.dot(ab, ab)), 1e-12), 0.0, 1.0))
    return float(np.hypot(*(a + t * ab - point)))
