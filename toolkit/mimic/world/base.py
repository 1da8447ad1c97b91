"""The world interface: what every world (ours in MuJoCo, the league's server) offers.

An agent lives in cycles of ``CYCLE_S``: it observes, answers with a ``JointCommand`` and the
world advances one cycle. Positions are in the field frame (origin at the centre spot, x toward
the opponent goal, y left, z up) [m]; angles [rad].
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from mimic.errors import MimicError
from mimic.floats import acos_domain
from mimic.geometry import forward_axis_z, in_robot_frame, yaw_from_quat
from mimic.robot.actuators import JointCommand
from mimic.robot.model import RobotDescription
from mimic.world.field import Field

__all__ = [
    "World",
    "Observation",
    "CYCLE_S",
    "GRAVITY_M_S2",
    "LEAGUE_COMMAND_DELAY_CYCLES",
    "BodyPoses",
    "POSTURES",
    "posture_quat",
]

#: The agent cycle [s]: agents see the world and command the joints at 50 Hz, in both the
#: study's simulator and the league's.
CYCLE_S = 0.02
#: Gravity in both worlds (MuJoCo's default, which the league's model keeps) [m/s^2].
GRAVITY_M_S2 = 9.81
#: How a robot can be put down: standing, or lying on its front or back (get-ups).
POSTURES = ("standing", "lying_front", "lying_back")
#: Cycles by which the league server applies a command later than our world does: its parallel
#: loop acts on an answer to a perception one cycle later, so a step in a reference shows two
#: cycles after it was sent, not one (``World.command_delay_cycles`` of ``LeagueWorld`` and
#: ``LeagueLikeWorld``; ``mimic train`` sends references early by it).
LEAGUE_COMMAND_DELAY_CYCLES = 1


def posture_quat(yaw_rad: float, posture: str) -> np.ndarray:
    """(4,) root orientation for a heading [rad] and a posture (lying: pitched 90 degrees
    onto the front or the back)."""
    import mujoco

    if posture not in POSTURES:
        raise ValueError(f"posture must be one of {', '.join(POSTURES)}, got {posture!r}")
    rot = np.zeros(4)
    mujoco.mju_euler2Quat(rot, np.array([0.0, 0.0, yaw_rad]), "xyz")
    if posture != "standing":
        pitch = math.pi / 2 if posture == "lying_front" else -math.pi / 2
        tilt = np.zeros(4)
        mujoco.mju_euler2Quat(tilt, np.array([0.0, pitch, 0.0]), "xyz")
        mujoco.mju_mulQuat(rot, rot, tilt)
    return rot


@dataclass
class Observation:
    """What an agent perceives at the start of a cycle (N: the robot's joint count).

    Attributes:
        time_s: simulated time since reset [s].
        joint_angles_rad: (N,) joint angles in the robot's joint order [rad].
        joint_speeds_rad_s: (N,) joint speeds [rad/s].
        gyro_rad_s: (3,) torso angular velocity in the torso frame [rad/s].
        accelerometer_m_s2: (3,) torso proper acceleration in the torso frame [m/s^2].
        torso_quat_wxyz: (4,) torso orientation in the field frame.
        foot_forces_n: (2,) normal force under the left and right sole [N].
        torso_pos_m: (3,) torso centre in the field frame [m] (a localisation estimate).
        ball_pos_m: (3,) ball centre in the field frame [m] (the vision estimate).
    """

    time_s: float
    joint_angles_rad: np.ndarray
    joint_speeds_rad_s: np.ndarray
    gyro_rad_s: np.ndarray
    accelerometer_m_s2: np.ndarray
    torso_quat_wxyz: np.ndarray
    foot_forces_n: np.ndarray
    torso_pos_m: np.ndarray
    ball_pos_m: np.ndarray

    @property
    def torso_yaw_rad(self) -> float:
        """Heading of the torso x axis in the field frame [rad]."""
        return yaw_from_quat(self.torso_quat_wxyz)


@dataclass(frozen=True)
class BodyPoses:
    """Every robot link's pose in the field frame at one instant.

    names: link names (the robot's ``links`` order); pos_m: (B, 3); quat_wxyz: (B, 4).
    """

    names: tuple[str, ...]
    pos_m: np.ndarray
    quat_wxyz: np.ndarray


def _up_z(quat_wxyz: list[float]) -> float:
    """z component of the up axis of orientation ``quat_wxyz`` (floats): 1 upright, 0 lying."""
    _, x, y, _ = quat_wxyz
    return 1 - 2 * (x * x + y * y)


def _tilt_rad(quat_wxyz: list[float]) -> float:
    """The angle between the up axis of ``quat_wxyz`` and the vertical [rad]."""
    return math.acos(acos_domain(_up_z(quat_wxyz)))


class World(ABC):
    """One robot, a ball and a field, advanced in agent cycles."""

    #: The robot this world simulates.
    robot: RobotDescription
    #: The field and ball it plays on.
    field: Field
    #: Cycles between the cycle a command is sent in and the cycle it starts to act in (0:
    #: the next physics steps; the league server applies it one 20 ms cycle later).
    command_delay_cycles: int = 0

    # --- placing things -------------------------------------------------------------------
    @abstractmethod
    def reset(self) -> None:
        """Everything back to the start."""

    @abstractmethod
    def place_robot(
        self,
        x_m: float,
        y_m: float,
        yaw_rad: float = 0.0,
        joint_angles_rad: np.ndarray | None = None,
        *,
        posture: str = "standing",
    ) -> None:
        """Put the robot at (x, y) facing ``yaw_rad``, at rest, in ``posture`` (``POSTURES``).

        ``joint_angles_rad``: (N,) pose of the joints (default: zero pose).
        """

    @abstractmethod
    def place_ball(self, x_m: float, y_m: float) -> None:
        """Put the ball at rest on the ground at (x, y)."""

    # --- stepping and sensing -------------------------------------------------------------
    @abstractmethod
    def step(self, command: JointCommand) -> None:
        """Apply one cycle's joint command and advance one cycle."""

    @abstractmethod
    def observe(self) -> Observation:
        """What the agent perceives now."""

    @property
    @abstractmethod
    def time_s(self) -> float:
        """Simulated time since reset [s]."""

    @abstractmethod
    def joint_angles_rad(self) -> np.ndarray:
        """(N,) joint angles [rad]."""

    @abstractmethod
    def torso_pos_m(self) -> np.ndarray:
        """(3,) torso centre [m]."""

    @abstractmethod
    def torso_quat_wxyz(self) -> np.ndarray:
        """(4,) torso orientation."""

    @abstractmethod
    def ball_pos_m(self) -> np.ndarray:
        """(3,) ball centre [m]."""

    @abstractmethod
    def ball_speed_m_s(self) -> float:
        """Ball speed [m/s]."""

    @abstractmethod
    def body_poses(self) -> BodyPoses:
        """Every link's pose in the field frame."""

    def ball_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The ball's (3,) centre [m] and (4,) orientation (w, x, y, z) in the field frame,
        for recordings; a world that does not show the ball's spin gives no rotation."""
        return self.ball_pos_m(), np.array([1.0, 0.0, 0.0, 0.0])

    # --- disturbances (``episode.disturbance``) ----------------------------------------------
    #: The world owns its physics: it can scale friction and masses per episode and push the
    #: robot (a server in another process cannot).
    can_disturb_physics: bool = False

    def scale_physics(self, friction_scale: float, link_mass_scales: np.ndarray) -> None:
        """Scale the sliding friction of every contact by ``friction_scale`` and each robot
        link's mass and inertia by ``link_mass_scales`` ((L,), the robot's ``links`` order),
        from the world's nominal values (so calls do not compound). Call before placing."""
        raise MimicError(f"the {self.describe()} cannot change its friction or masses")

    def push_torso(self, force_n: np.ndarray) -> None:
        """Apply ``force_n`` ((3,), field frame [N]) at the torso's centre of mass in every
        following step until changed (zeros: no push)."""
        raise MimicError(f"the {self.describe()} cannot push the robot")

    def robot_mass_kg(self) -> float:
        """The robot's whole mass [kg] (after ``scale_physics``)."""
        return self.robot.mass_kg

    def describe(self) -> str:
        """What this world is, for messages."""
        return type(self).__name__

    # --- derived quantities and events (shared by every world) ------------------------------
    def torso_yaw_rad(self) -> float:
        return yaw_from_quat(self.torso_quat_wxyz())

    def ball_in_robot_frame_m(self) -> np.ndarray:
        """(2,) ball centre relative to the torso, robot frame (x forward, y left) [m]."""
        return in_robot_frame(self.ball_pos_m(), self.torso_pos_m(), self.torso_yaw_rad())

    def torso_up_z(self) -> float:
        """z component of the torso's up axis: 1 upright, 0 lying."""
        return _up_z(self._torso_height_and_quat()[1])

    def _torso_height_and_quat(self) -> tuple[float, list[float]]:
        """The torso's height [m] and its (4,) orientation (w, x, y, z), as Python floats: the
        fall checks read them every cycle, twice (a world may read them more cheaply)."""
        return float(self.torso_pos_m()[2]), self.torso_quat_wxyz().tolist()

    def torso_forward_z(self) -> float:
        """z component of the torso's forward axis: negative when it faces the ground."""
        return forward_axis_z(self.torso_quat_wxyz())

    def fallen(self) -> bool:
        """Torso too low or tilted too far (the robot's ``FallThresholds``)."""
        f = self.robot.falls
        z, quat = self._torso_height_and_quat()
        return z < f.fallen_below_m or _tilt_rad(quat) > f.fallen_tilt_rad

    def upright(self) -> bool:
        """Standing: torso high and nearly vertical (the success test of a get-up)."""
        f = self.robot.falls
        z, quat = self._torso_height_and_quat()
        return z > f.upright_above_m and _tilt_rad(quat) < f.upright_tilt_rad

    def lying_side(self) -> str:
        """``front`` if the torso faces the ground, else ``back``."""
        return "front" if self.torso_forward_z() < 0 else "back"

    def goal_scored(self) -> bool:
        """Ball wholly behind the opponent goal line, between the posts, under the bar."""
        return self.field.goal(self.ball_pos_m())

    def ball_out(self) -> bool:
        """Ball wholly outside the field lines (and not a goal)."""
        return self.field.out(self.ball_pos_m())
