"""How an agent's joint command reaches a robot's joints: the actuator models.

An agent says what it wants as a ``JointCommand``: joint references [rad] (any robot), or
joint speeds [rad/s] (only robots with speed servos, such as our NAO, whose own controllers
think in speeds). The robot's actuator model turns that into MuJoCo controls:

* ``SpeedServos`` (the NAO of the study's simulator): velocity servos whose command is capped
  at 6.1395 rad/s. References are tracked proportionally, speed = gain * (reference - angle),
  as the study's agents did, so a learned copy meets exactly the attenuation the original met.
* ``PDMotors`` (the league's Booster T1 and K1): torque = kp (q_ref - q) + kd (0 - dq),
  applied by MuJoCo position and velocity actuators every physics step, as RCSSServerMJ
  applies the ``(NAME q dq kp kd tau)`` effector command.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimic.errors import MimicError
from mimic.floats import clip_symmetric

__all__ = [
    "JointCommand",
    "SpeedServos",
    "PDMotors",
    "ActuatorModel",
    "MAX_JOINT_SPEED_RAD_S",
    "DEFAULT_TRACKING_GAIN_PER_S",
]

#: The study's simulator caps commanded joint speed at this [rad/s] (7.035 deg per 20 ms).
MAX_JOINT_SPEED_RAD_S = 6.1395
#: Proportional tracking gain of the NAO's own agents [1/s]: a 0.1 rad error asks 2.5 rad/s.
DEFAULT_TRACKING_GAIN_PER_S = 25.0


@dataclass(frozen=True, eq=False)
class JointCommand:
    """One cycle's command, in the robot's joint order. Exactly one field is set.

    Attributes:
        reference_rad: (N,) joint references [rad].
        speed_rad_s: (N,) joint speeds [rad/s] (speed-servo robots only).
    """

    reference_rad: np.ndarray | None = None
    speed_rad_s: np.ndarray | None = None

    def __post_init__(self) -> None:
        if (self.reference_rad is None) == (self.speed_rad_s is None):
            raise ValueError("a JointCommand holds references or speeds, exactly one of them")

    @classmethod
    def references(cls, reference_rad: np.ndarray) -> JointCommand:
        return cls(reference_rad=np.asarray(reference_rad, dtype=float))

    @classmethod
    def speeds(cls, speed_rad_s: np.ndarray) -> JointCommand:
        return cls(speed_rad_s=np.asarray(speed_rad_s, dtype=float))


@dataclass(frozen=True)
class SpeedServos:
    """Velocity servos with a capped command (the study's simulator).

    Attributes:
        max_speed_rad_s: command cap [rad/s].
        tracking_gain_per_s: proportional gain turning a reference error into a speed [1/s].
        kv_nm_s_rad: servo gain [N m s / rad]: torque = kv (commanded - actual speed).
        max_torque_nm: motor torque limit [N m].
        armature_kg_m2: reflected rotor inertia added to each hinge [kg m^2].
        damping_nm_s_rad: passive viscous damping [N m s / rad].
    """

    max_speed_rad_s: float = MAX_JOINT_SPEED_RAD_S
    tracking_gain_per_s: float = DEFAULT_TRACKING_GAIN_PER_S
    kv_nm_s_rad: float = 5.0
    max_torque_nm: float = 10.0
    armature_kg_m2: float = 0.002
    damping_nm_s_rad: float = 0.02

    kind = "speed servos"
    takes_speeds = True

    def track(
        self, reference_rad: np.ndarray, angles_rad: np.ndarray, gain_per_s: float | None = None
    ) -> np.ndarray:
        """(N,) speeds [rad/s] = gain (reference - angle), capped."""
        gain = self.tracking_gain_per_s if gain_per_s is None else gain_per_s
        return clip_symmetric(gain * (reference_rad - angles_rad), self.max_speed_rad_s)

    def speed_commands(self, command: JointCommand, angles_rad: np.ndarray) -> np.ndarray:
        """(N,) capped speed commands [rad/s] for ``command`` at the current angles."""
        if command.speed_rad_s is not None:
            return clip_symmetric(command.speed_rad_s, self.max_speed_rad_s)
        return self.track(command.reference_rad, angles_rad)

    def controls(
        self, command: JointCommand, angles_rad: np.ndarray, robot_name: str = ""
    ) -> np.ndarray:
        """(N,) MuJoCo controls: the velocity servos' speed commands [rad/s]."""
        return self.speed_commands(command, angles_rad)

    def describe(self) -> str:
        return f"speed servos, capped at {self.max_speed_rad_s:g} rad/s"


@dataclass(frozen=True, eq=False)
class PDMotors:
    """Position-torque motors: torque = kp (q_ref - q) + kd (dq_ref - dq) + tau, limited.

    Attributes:
        kp_nm_rad: (N,) proportional gains [N m / rad], robot joint order.
        kd_nm_s_rad: (N,) derivative gains [N m s / rad].
        max_torque_nm: (N,) torque limits [N m] (the MJCF's ``actuatorfrcrange``).
    """

    kp_nm_rad: np.ndarray
    kd_nm_s_rad: np.ndarray
    max_torque_nm: np.ndarray

    kind = "PD motors"
    takes_speeds = False

    def targets(self, command: JointCommand, robot_name: str = "this robot") -> np.ndarray:
        """(N,) position targets [rad]; a speed command is refused with one clear line."""
        if command.reference_rad is None:
            raise MimicError(
                f"{robot_name} has PD motors, which take joint references; this "
                "agent sends joint speeds (a NAO-only controller)"
            )
        return command.reference_rad

    def controls(
        self, command: JointCommand, angles_rad: np.ndarray, robot_name: str = "this robot"
    ) -> np.ndarray:
        """(N,) MuJoCo controls: the position actuators' targets [rad] (their kp and kv are
        the motors' gains, so MuJoCo applies the PD law every physics step)."""
        return self.targets(command, robot_name)

    def describe(self) -> str:
        kp = np.asarray(self.kp_nm_rad)
        return f"PD motors, kp {kp.min():g}-{kp.max():g} N m/rad"


ActuatorModel = SpeedServos | PDMotors
