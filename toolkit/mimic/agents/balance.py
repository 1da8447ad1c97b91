"""Closed-loop balance and heading around any motion that exposes references (a learned walk).

Open-loop replay cannot correct itself; walk engines use IMU feedback for that. This thin
layer adds the same kind of feedback to any agent and hands the shifted references to the
usual proportional tracking. Which foot carries the robot is read from the references
themselves (the support leg's knee is the straighter one; the sole force sensors bounce too
much on landing to tell), one cycle late because the joints follow their references about a
cycle behind (switching on the references themselves, the weight has not moved yet, and the
learned walk fell about six times as often). A correction means opposite things on the legs:

* Tilt (torso pitch/roll from the IMU quaternion, plus the gyro rate): the support ankle
  turns the foot under the lean (ankle pitch/roll against the lean) and the swing hip moves
  the swing foot toward the side the torso falls to (hip pitch/roll with the lean), so the
  foot lands under the body.
* One-shot motions (a kick): the swing leg is doing the motion, so only the support ankle
  corrects (``swing_feedback`` off by default). On our kick learned from ``/joint_states``
  the swing-hip correction made things worse: in 8 seeded kicks per model the four reached-angle
  copies fell 0/8 each with the support ankle alone; one of them fell 5/8 with the swing-hip
  correction and 8/8 without any balance.
* Torso attitude (``torso_pitch``, ``torso_roll``; 0 for the NAO): the support hip turns the
  torso back over the planted leg, as a walk engine's hip holds the torso where weak ankles
  cannot (the T1's walk copy stands through its start-up only with it).
* Torso yaw rate (``torso_yaw_rate_s``; on in the T1's walk): the support hip yaw turns the
  support foot with the torso's yaw rate (the gyro), so the hip damps the torso's yaw swing
  over the planted foot. The T1's walk swings the torso by +-10-16 degrees a step; in its
  copies the planted foot turned on the ground with it (52 degrees/s against the original's
  30) and some copies fell spinning. With the term they walked, but only within a narrow
  band of gains (docs/real-team-walk.md, "Damping the torso's yaw").
* Foot placement (cyclic motions that carry their recording's foot track, gains
  ``place_*``, off by default): the support foot under the torso is compared with where the
  recording had it at the same phase, and the swing foot lands farther along that error and
  its rate (``model.foot_track``); the support foot keeps the shift it landed with.
* Heading: walk engines turn by yawing the feet in each step: the swing foot is put down
  turned by half the step's turn and the support foot turns back by the other half, so the
  torso rotates over the planted foot. We do the same with the hip yaw-pitch joints (their
  axis is tilted 45 degrees, so a pure foot yaw needs a matching hip pitch change). The
  turn of each step aims the torso at the start heading, bent back toward the start line in
  proportion to the sideways offset (``torso_pos_m`` is the localisation estimate).

Any robot with two legs: the joints are found by their roles (``left_hip_pitch``,
``Left_Hip_Pitch``, ...; ``leg_joints``) and every shift is signed by the joint's own axis in
the robot description, so one layer serves the NAO (pitch axes along -y, a hip yaw-pitch
joint at 45 degrees) and the league's T1 (pitch axes along +y, a pure hip yaw). Written for
the NAO: for a planted foot raising its ankle pitch leans the shank forward, raising ankle
roll leans it left, raising hip pitch bends the torso forward over the leg, raising hip roll
tilts the torso left over it. A left hip yaw-pitch of q yaws the left foot by -q sin 45 deg
(right: +q sin 45 deg) and pitches it by q sin 45 deg, which a hip pitch change of the same
size cancels (left: -yaw, right: +yaw). Gains are per robot, and per kind of motion where a
robot needs it (a walk or a one-shot kick; ``default_gains``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from mimic.agents.base import Agent, JointCommand
from mimic.errors import MimicError
from mimic.geometry import yaw_from_quat
from mimic.model.keys import BALANCE_GAINS_KEY
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.world.base import CYCLE_S, Observation
from mimic.world.kinematics import FootKinematics

__all__ = [
    "BalanceGains",
    "HeadingGains",
    "BalancedAgent",
    "LegJoints",
    "leg_joints",
    "default_gains",
    "default_heading",
    "gains_with",
    "with_balance_gains",
    "torso_lean_rad",
    "torso_yaw_rad",
    "foot_yaw_shift_rad",
]

# Leg sides: +1 left, -1 right.
_SIDES = {1.0: "left", -1.0: "right"}
_ROLES = ("hip_pitch", "hip_roll", "ankle_pitch", "ankle_roll", "knee_pitch")


@dataclass(frozen=True)
class BalanceGains:
    """Tilt feedback: reference shifts [rad] per rad of torso lean (and per rad/s of its rate).

    The defaults were chosen on seeded 15 m walks of the learned copy of the other team's walk
    (``benchmarks/learned_walk.py``); the walk is sensitive to them (``docs/tuning-notes.md``).
    """

    # Support ankle pitch against a forward lean; swing hip pitch gets ``hip_share`` of it.
    pitch: float = 0.6
    # Support ankle roll against a sideways lean; swing hip roll gets ``hip_share`` of it.
    roll: float = 0.4
    # Lean rate terms [s]: gyro rate [rad/s] counted as this much extra lean.
    pitch_rate_s: float = 0.05
    roll_rate_s: float = 0.08
    # Share of the tilt correction sent to the swing hip (the swing ankle gets the rest).
    hip_share: float = 1.0
    # Torso attitude: the support hip turns the torso back over the leg [rad per rad of lean,
    # pitch and roll; 0: off]. A walk engine's hip holds the torso where the weak ankles cannot
    # (the T1 other team's walk: 0.81 and 0.46).
    torso_pitch: float = 0.0
    torso_roll: float = 0.0
    # Torso yaw rate: the support foot's yaw reference relative to the torso moves with the
    # torso's yaw rate [rad per rad/s; 0: off], so the support hip holds the torso against
    # turning over the planted foot.
    torso_yaw_rate_s: float = 0.0
    # Forward lean [rad] the walk holds on its own (no correction at this lean).
    lean_rad: float = 0.0
    # Largest shift applied to any joint [rad].
    limit_rad: float = 0.25
    # The support side switches once the other knee reference is straighter by this [rad] ...
    support_hysteresis_rad: float = 0.02
    # ... and this many 20 ms cycles later (the tracking lag: weight moves with the joints).
    support_delay_cycles: int = 1
    # Foot placement (cyclic motions that carry their recording's foot track;
    # ``model.foot_track``): the swing foot lands this much farther forward / leftward
    # per metre of the torso's error over the support foot against the track, and per m/s of
    # the error's rate (capture-point style) [m/m, m/(m/s)]; all 0 switch it off.
    place_x: float = 0.0
    place_x_rate_s: float = 0.0
    place_y: float = 0.0
    place_y_rate_s: float = 0.0
    # Largest landing shift [m]; how far inward (toward the support foot) it may go [m].
    place_limit_m: float = 0.05
    place_inward_m: float = 0.02
    # Time constant of the error-rate filter [s] (the measured error jumps at touch-down).
    place_rate_filter_s: float = 0.05

    @property
    def placement_on(self) -> bool:
        """Whether foot placement acts (any of its four gains is not 0)."""
        return any((self.place_x, self.place_x_rate_s, self.place_y, self.place_y_rate_s))


# Each robot's gains (a robot not listed starts with the NAO's). How the T1's were searched and
# what they do on copies the search never saw: docs/tuning-notes.md ("The balance layer on the
# T1").
_DEFAULT_GAINS: dict[str, BalanceGains] = {
    "nao": BalanceGains(),
    "t1": BalanceGains(
        pitch=0.161,
        roll=0.674,
        pitch_rate_s=0.095,
        roll_rate_s=-0.018,
        limit_rad=0.268,
        hip_share=0.12,
        torso_pitch=0.334,
        torso_roll=0.96,
        # Swept on the copies of four recordings of the regular walk, one of its fixed-period
        # copies and five copies of the policy-like walk (docs/real-team-walk.md, "Damping the
        # torso's yaw"): 0.01 is the only gain tried at which every copy walked; 0.005 and
        # 0.015 each fell with one of them. A narrow margin, not a tuned optimum.
        torso_yaw_rate_s=0.01,
    ),
}
# One-shot motions (a kick) where a robot needs other gains than its walk (the T1's kick
# copies fall sideways over the support foot while the kicking foot comes back); how they were
# chosen: docs/tuning-notes.md ("The balance layer on the T1").
_ONE_SHOT_GAINS: dict[str, BalanceGains] = {
    "t1": BalanceGains(pitch=0.21, roll=0.8, pitch_rate_s=0.084, roll_rate_s=0.19),
}


@dataclass(frozen=True)
class HeadingGains:
    """Heading and line hold through per-step foot yaw (0 gains switch it off)."""

    # Turn per step [rad] per rad of heading error.
    yaw_gain: float = 0.35
    # Heading aimed back at the start line per metre of sideways offset [rad/m].
    line_gain: float = 1.5
    # Largest turn per step [rad] and largest aim off the start heading [rad] (how the line
    # gain and the turn were chosen: docs/tuning-notes.md, "Heading and line hold").
    max_turn_rad: float = 0.08
    max_aim_rad: float = 0.3
    # A turn every step learns to hold against a copy that turns by itself (its recording's
    # own heading corrections replayed): each step adds this much of the step's heading error
    # [rad of turn per rad] to a standing turn, at most ``max_bias_rad`` either way (0: off).
    yaw_integral: float = 0.0
    max_bias_rad: float = 0.1


def _smooth(s: float) -> float:
    """Smoothstep of ``s`` in 0..1 (zero slope at both ends)."""
    return s * s * (3.0 - 2.0 * s)


def torso_lean_rad(obs: Observation) -> tuple[float, float]:
    """(forward lean, leftward lean) of the torso from vertical [rad], from the IMU quaternion."""
    w, x, y, z = obs.torso_quat_wxyz
    # World up expressed in the torso frame is the third row of the rotation matrix.
    up_x = 2 * (x * z - w * y)
    up_y = 2 * (y * z + w * x)
    return float(-np.arcsin(np.clip(up_x, -1, 1))), float(-np.arcsin(np.clip(up_y, -1, 1)))


def torso_yaw_rad(obs: Observation) -> float:
    """Heading of the torso x axis in the field frame [rad] (0: toward the opponent goal)."""
    return yaw_from_quat(obs.torso_quat_wxyz)


@dataclass(frozen=True)
class LegJoints:
    """Where the balance layer acts on one robot, read from its description.

    Attributes:
        index: per side (+1 left, -1 right) the joint index of each role (``_ROLES``, plus
            ``hip_yaw``: the joint that turns the foot, a hip yaw or the NAO's yaw-pitch).
        axis: per side and role, the joint axis (in its parent link, the zero pose).
        sign: per side and tilt role (hip/ankle pitch/roll), +1 where the joint turns the way
            the NAO's does (pitch axes along -y, roll axes along +x), -1 where it turns the
            other way (the T1's pitch joints): the layer's shifts are written for the NAO.
        knee_bend_sign: +1 when a knee bends with positive angles, -1 when with negative.
        num_joints: the robot's joint count.
    """

    index: dict
    axis: dict
    sign: dict
    knee_bend_sign: float
    num_joints: int


def leg_joints(robot: RobotDescription | str) -> LegJoints:
    """The robot's leg joints by role (names matched without case: ``left_hip_pitch`` or
    ``Left_Hip_Pitch``).

    Raises:
        MimicError: the robot lacks one of the roles (the balance layer needs two legs).
    """
    robot = get_robot(robot)
    by_name = {j.name.lower(): (i, j) for i, j in enumerate(robot.joints)}
    index, axis = {}, {}
    for side, name in _SIDES.items():
        index[side], axis[side] = {}, {}
        for role in (*_ROLES, "hip_yaw"):
            found = by_name.get(f"{name}_{role}")
            if found is None and role == "hip_yaw":
                found = by_name.get(f"{name}_hip_yaw_pitch")
            if found is None:
                raise MimicError(
                    f"the balance layer needs two legs; the {robot.name} has no {name} {role} joint"
                )
            index[side][role], axis[side][role] = found[0], np.asarray(found[1].axis, float)
    knee = robot.joints[index[1.0]["knee_pitch"]]
    bend = 1.0 if abs(knee.upper_rad) >= abs(knee.lower_rad) else -1.0
    sign = {
        side: {
            role: float(-axis[side][role][1] if "pitch" in role else axis[side][role][0])
            for role in ("hip_pitch", "hip_roll", "ankle_pitch", "ankle_roll")
        }
        for side in _SIDES
    }
    return LegJoints(index, axis, sign, bend, robot.num_joints)


def foot_yaw_shift_rad(
    yaw_left_rad: float, yaw_right_rad: float, legs: LegJoints | None = None
) -> np.ndarray:
    """(N,) reference shifts that yaw each foot relative to the torso by the given angles
    [rad] (positive: toes turned left) with the hip yaw joint, plus the hip pitch change that
    cancels the pitch a tilted yaw axis (the NAO's yaw-pitch at 45 degrees) brings along
    (default: the NAO's legs)."""
    legs = legs or leg_joints("nao")
    shift = np.zeros(legs.num_joints)
    for side, yaw in ((1.0, yaw_left_rad), (-1.0, yaw_right_rad)):
        ax = legs.axis[side]["hip_yaw"]
        q = yaw / ax[2]  # the foot turns by q times the axis's vertical part
        shift[legs.index[side]["hip_yaw"]] = q
        if abs(ax[1]) > 1e-9:
            shift[legs.index[side]["hip_pitch"]] = -q * ax[1] / legs.axis[side]["hip_pitch"][1]
    return shift


def gains_with(base: BalanceGains, fields: dict, where: str = "balance gains") -> BalanceGains:
    """``base`` with the named ``BalanceGains`` fields replaced (a model's own gains).

    Raises:
        MimicError: a field that ``BalanceGains`` lacks, or a value that is not a number.
    """
    known = BalanceGains.__dataclass_fields__
    unknown = sorted(set(fields) - set(known))
    if unknown:
        raise MimicError(
            f"{where}: unknown balance gain {', '.join(unknown)}; known: {', '.join(known)}"
        )
    try:
        values = {k: type(getattr(base, k))(v) for k, v in fields.items()}
    except (TypeError, ValueError):
        raise MimicError(f"{where}: balance gains must be numbers, got {fields}") from None
    return replace(base, **values)


def with_balance_gains(model, fields: dict):
    """A learned model (``model.motion_model.MotionModel``) that carries its own balance gains: the
    named ``BalanceGains`` fields (checked), on top of any it carries already, over the
    robot's defaults wherever the balance layer plays it (``M.mimic+balance``)."""
    gains_with(BalanceGains(), fields, f"{model.name}'s balance gains")
    own = {**model.metadata.get(BALANCE_GAINS_KEY, {}), **{k: float(v) for k, v in fields.items()}}
    return replace(model, metadata={**model.metadata, BALANCE_GAINS_KEY: own})


#: Each robot's heading gains (a robot not listed has the ``HeadingGains`` defaults). The
#: T1's: the search above (a standing turn of up to 0.06 rad per step).
_DEFAULT_HEADING: dict[str, HeadingGains] = {
    "t1": HeadingGains(
        yaw_gain=0.314,
        line_gain=0.937,
        max_turn_rad=0.072,
        yaw_integral=0.164,
        max_bias_rad=0.062,
    ),
}


def default_heading(robot: str) -> HeadingGains:
    """The heading gains a robot's balance layer starts with on a cyclic motion."""
    return _DEFAULT_HEADING.get(robot, HeadingGains())


def default_gains(robot: str, one_shot: bool = False) -> BalanceGains:
    """The tilt gains a robot's balance layer starts with (tuned per robot), for a cyclic
    motion (a walk) or, with ``one_shot``, a motion that runs once (a kick). Foot placement is
    off in every default (its gains are 0): see ``BalanceGains.place_x``."""
    walk = _DEFAULT_GAINS.get(robot, BalanceGains())
    return _ONE_SHOT_GAINS.get(robot, walk) if one_shot else walk


class BalancedAgent(Agent):
    """Wraps an agent; adds IMU tilt feedback and per-step heading control to its references.

    The corrections use the inner agent's robot's legs (``leg_joints``); ``gains=None`` takes
    that robot's ``default_gains`` for the inner agent's kind (cyclic or one-shot), with the
    inner agent's own ``balance_gains`` (a dict of fields; a model file may carry them) on top.

    Heading control acts on cyclic agents only (``period_s`` set: a walk), with the robot's
    ``default_heading`` unless ``heading`` gives other gains; ``heading=None`` switches it
    off. ``swing_feedback`` sends part of the tilt correction to the swing leg (default: on
    for cyclic agents, whose swing foot lands where the hip puts it; off for one-shot
    motions, whose swing leg kicks). Agents that expose no references
    (``reference_rad`` None) pass through unchanged.
    """

    def __init__(
        self,
        inner: Agent,
        gains: BalanceGains | None = None,
        heading: HeadingGains | None | str = "default",
        swing_feedback: bool | None = None,
    ) -> None:
        super().__init__()
        self.legs = leg_joints(inner.robot)
        self.inner = inner
        cyclic = bool(inner.period_s)
        track = getattr(inner, "foot_track", None) if cyclic else None
        if gains is None:
            gains = default_gains(inner.robot, one_shot=not cyclic)
            own = getattr(inner, "balance_gains", None)
            if own:
                gains = gains_with(gains, own, f"{inner.name}'s balance gains")
        self.gains = gains
        if isinstance(heading, str):
            heading = default_heading(inner.robot)
        self.heading = heading if cyclic else None
        self.swing_feedback = cyclic if swing_feedback is None else swing_feedback
        self.start_posture = inner.start_posture
        self.ball_offset_m = getattr(inner, "ball_offset_m", None)
        self.name, self.team, self.period_s = inner.name, inner.team, inner.period_s
        self.robot, self.robot_only = inner.robot, inner.robot_only
        self._idx = self.legs.index
        self._knee = {side: self.legs.index[side]["knee_pitch"] for side in _SIDES}
        # Foot placement: cyclic agents that carry their recording's foot track.
        self.placement = track is not None and self.gains.placement_on
        self._kin = FootKinematics(inner.robot) if self.placement else None
        self._reset_state(0.0, (0.0, 0.0))

    def _reset_state(self, yaw_rad: float, xy_m: tuple[float, float]) -> None:
        self.support = 1.0  # +1: the left foot carries the robot, -1: the right one
        # Support side the references show now, and cycles left until ``support`` follows it.
        self._support_ref, self._switch_in = 1.0, -1
        self._start_yaw, self._start_xy = yaw_rad, xy_m
        # Foot yaw relative to the torso [rad] per side: where the current step began and the
        # turn it aims for; ``_step_t`` counts time into the step [s].
        self._yaw_from = {1.0: 0.0, -1.0: 0.0}
        self._yaw_to = dict(self._yaw_from)
        self._step_t = 0.0
        # Sum and count of the heading error samples over the current step (their mean is the
        # step's heading: the torso yaw swings with every step, a single sample aliases).
        self._err_sum, self._err_n = 0.0, 0
        self._turn_bias = 0.0  # the standing turn per step [rad] (``HeadingGains.yaw_integral``)
        # Foot placement: each foot's landing shift (x, y) [m] where its current swing (or
        # support) began, and now; the support foot's error [m] and its filtered rate [m/s].
        self._place_from = {1.0: np.zeros(2), -1.0: np.zeros(2)}
        self._place = {1.0: np.zeros(2), -1.0: np.zeros(2)}
        self._place_err: np.ndarray | None = None
        self._place_rate = np.zeros(2)
        self._place_step_t = 0.0

    def reset(self, obs: Observation) -> None:
        self.inner.reset(obs)
        self._reset_state(
            torso_yaw_rad(obs), (float(obs.torso_pos_m[0]), float(obs.torso_pos_m[1]))
        )
        self.done = False

    def resume(self, obs: Observation) -> None:
        """The inner agent resumes; the layer keeps its start heading and line, so its
        heading hold turns the robot back to them."""
        self.inner.resume(obs)
        self._reset_state(self._start_yaw, self._start_xy)
        self.done = False

    # --- support foot ---------------------------------------------------------------------
    def _update_support(self, reference_rad: np.ndarray) -> bool:
        """Track the support leg from the knee references; True when it changed this cycle."""
        # The support knee is the straighter one (the NAO's bend negative, the T1's positive).
        straighter = self.legs.knee_bend_sign * (
            reference_rad[self._knee[-1.0]] - reference_rad[self._knee[1.0]]
        )
        if self._support_ref * straighter < -self.gains.support_hysteresis_rad:
            self._support_ref = -self._support_ref
            self._switch_in = self.gains.support_delay_cycles
        if self._switch_in < 0:
            return False
        self._switch_in -= 1
        if self._switch_in >= 0 or self.support == self._support_ref:
            return False
        self.support = self._support_ref
        return True

    # --- feedback -------------------------------------------------------------------------
    def tilt_correction_rad(self, obs: Observation) -> np.ndarray:
        """(N,) reference shifts [rad] for the current lean (support ankle; swing hip and
        ankle when ``swing_feedback``)."""
        g = self.gains
        forward, left = torso_lean_rad(obs)
        # The gyro's y axis is positive for pitching nose-down, its x axis for rolling right.
        d_pitch = g.pitch * (forward - g.lean_rad + g.pitch_rate_s * obs.gyro_rad_s[1])
        d_roll = g.roll * (left - g.roll_rate_s * obs.gyro_rad_s[0])
        shift = np.zeros(self.legs.num_joints)
        sup, swing = self._idx[self.support], self._idx[-self.support]
        s_sup, s_swing = self.legs.sign[self.support], self.legs.sign[-self.support]
        shift[sup["ankle_pitch"]] = -d_pitch * s_sup["ankle_pitch"]
        shift[sup["ankle_roll"]] = -d_roll * s_sup["ankle_roll"]
        # Raising the support hip pitch bends the torso forward over the leg, raising its roll
        # tilts it left: both against the lean.
        shift[sup["hip_pitch"]] = -g.torso_pitch * (forward - g.lean_rad) * s_sup["hip_pitch"]
        shift[sup["hip_roll"]] = -g.torso_roll * left * s_sup["hip_roll"]
        if g.torso_yaw_rate_s:
            yaw = {self.support: g.torso_yaw_rate_s * float(obs.gyro_rad_s[2]), -self.support: 0.0}
            shift += foot_yaw_shift_rad(yaw[1.0], yaw[-1.0], self.legs)
        if not self.swing_feedback:
            return np.clip(shift, -g.limit_rad, g.limit_rad)
        h = g.hip_share
        shift[swing["hip_pitch"]] = h * d_pitch * s_swing["hip_pitch"]
        shift[swing["hip_roll"]] = h * d_roll * s_swing["hip_roll"]
        shift[swing["ankle_pitch"]] = -(1.0 - h) * d_pitch * s_swing["ankle_pitch"]
        shift[swing["ankle_roll"]] = -(1.0 - h) * d_roll * s_swing["ankle_roll"]
        return np.clip(shift, -g.limit_rad, g.limit_rad)

    def _step_s(self) -> float:
        """Duration of one step [s]: half the inner agent's gait period."""
        return self.inner.period_s / 2

    def heading_error_rad(self, obs: Observation) -> float:
        """Torso heading minus the aim [rad]: the start heading bent back toward the start
        line in proportion to the sideways offset from it."""
        h = self.heading
        # Sideways offset from the start line, in the start heading's frame [m].
        dx = float(obs.torso_pos_m[0]) - self._start_xy[0]
        dy = float(obs.torso_pos_m[1]) - self._start_xy[1]
        off = -math.sin(self._start_yaw) * dx + math.cos(self._start_yaw) * dy
        aim = self._start_yaw - float(np.clip(h.line_gain * off, -h.max_aim_rad, h.max_aim_rad))
        return math.remainder(torso_yaw_rad(obs) - aim, 2 * math.pi)

    def _begin_step(self, obs: Observation) -> None:
        h = self.heading
        err = self._err_sum / self._err_n if self._err_n else self.heading_error_rad(obs)
        self._err_sum, self._err_n = 0.0, 0
        self._turn_bias = float(
            np.clip(self._turn_bias - h.yaw_integral * err, -h.max_bias_rad, h.max_bias_rad)
        )
        turn = float(np.clip(-h.yaw_gain * err, -h.max_turn_rad, h.max_turn_rad))
        turn += self._turn_bias
        self._yaw_from = {s: self._current_yaw(s) for s in (1.0, -1.0)}
        # The support foot turns back by half the turn (rotating the torso over it); the swing
        # foot lands turned by the other half.
        self._yaw_to = {self.support: -turn / 2, -self.support: turn / 2}
        self._step_t = 0.0

    def _current_yaw(self, side: float) -> float:
        s = min(1.0, self._step_t / self._step_s())
        return self._yaw_from[side] + s * (self._yaw_to[side] - self._yaw_from[side])

    def heading_correction_rad(self) -> np.ndarray:
        """(N,) reference shifts [rad] of the current foot yaw plan."""
        return foot_yaw_shift_rad(self._current_yaw(1.0), self._current_yaw(-1.0), self.legs)

    def placement_shift_m(self, obs: Observation, changed: bool) -> dict[float, np.ndarray]:
        """Per side the (x, y) landing shift [m] of foot placement this cycle: the swing foot
        moves toward the capture-point shift over its step, the support foot keeps where it
        landed (``model.foot_track``)."""
        g, inner = self.gains, self.inner
        if changed:  # the old swing foot landed with its shift; the new one starts from its own
            self._place_from = {s: v.copy() for s, v in self._place.items()}
            self._place_err, self._place_step_t = None, 0.0
        if inner.cycle_phase is None:
            return self._place
        sup = self.support
        # The track at the swing's start-up amplitude (``NeuralPlayer.start_weights``).
        track, k = inner.foot_track, 0 if sup > 0 else 1
        mean = track.mean_m[k]
        nominal = mean + inner.swing_weight * (track.at(inner.cycle_phase)[k] - mean)
        nominal = nominal + self._place[sup]
        measured = self._kin.feet_m(obs.joint_angles_rad, obs.torso_quat_wxyz)[k]
        err = nominal - measured  # > 0: the torso is ahead of / left of where it should be
        if self._place_err is not None:
            a = CYCLE_S / (g.place_rate_filter_s + CYCLE_S)
            self._place_rate = (1 - a) * self._place_rate + a * (err - self._place_err) / CYCLE_S
        self._place_err = err
        adjust = inner.swing_weight * (
            np.array([g.place_x, g.place_y]) * err
            + np.array([g.place_x_rate_s, g.place_y_rate_s]) * self._place_rate
        )
        adjust = np.clip(adjust, -g.place_limit_m, g.place_limit_m)
        if sup * adjust[1] > g.place_inward_m:  # the feet must not meet
            adjust[1] = sup * g.place_inward_m
        self._place_step_t += CYCLE_S
        s = _smooth(min(1.0, self._place_step_t / self._step_s()))
        start = self._place_from[-sup]
        self._place[-sup] = start + s * (adjust - start)
        return self._place

    def correction_rad(self, obs: Observation, reference_rad: np.ndarray) -> np.ndarray:
        """(N,) reference shifts [rad] for the inner agent's (N,) references this cycle:
        tilt feedback, foot placement and heading (updates the support leg and step state)."""
        changed = self._update_support(reference_rad)
        shift = self.tilt_correction_rad(obs)
        if self.placement:
            place = self.placement_shift_m(obs, changed)
            maps = self._kin.shift_map(obs.joint_angles_rad)
            shift = shift + sum(maps[s] @ place[s] for s in _SIDES)
        if self.heading is not None:
            self._err_sum += self.heading_error_rad(obs)
            self._err_n += 1
            if changed:
                self._begin_step(obs)
            self._step_t += CYCLE_S
            shift = shift + self.heading_correction_rad()
        return shift

    def act(self, obs: Observation) -> JointCommand:
        command = self.inner.act(obs)
        self.done = self.inner.done
        if self.inner.reference_rad is None:
            return command
        ref = self.inner.reference_rad
        self.reference_rad = ref + self.correction_rad(obs, ref)
        return JointCommand.references(self.reference_rad)
