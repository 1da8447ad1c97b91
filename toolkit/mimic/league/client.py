"""One player on a league server: perceptions in, motor commands out, every 20 ms cycle.

An agent connects to the server's agent port, says ``(init MODEL TEAM UNUM)`` and then gets
one perception message per cycle: time, game state, joint angles and speeds (degrees), gyro
(degrees per second), accelerometer, torso orientation and position, vision. It answers with
one motor command per joint, ``(EFFECTOR q dq kp kd tau)`` (q, dq in degrees), which the server
applies as torque = kp (q - q_now) + kd (dq - dq_now) + tau until the next command.

``AgentClient`` turns perceptions into ``Perception`` values in the robot's joint order and
a ``JointCommand`` into that message, with the robot's own PD gains (``PDMotors``). Names on
the wire come from the robot's MJCF (``mimic.league.names``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimic.league.errors import LeagueConnectionError, LeagueError
from mimic.league.names import WireNames, wire_names
from mimic.league.protocol import Connection, connect, parse_sexp
from mimic.league.rsmp import is_rsmp
from mimic.robot.actuators import JointCommand, PDMotors
from mimic.robot.model import RobotDescription

__all__ = ["AgentClient", "Perception", "parse_perception", "format_command", "wire_targets_rad"]

#: How long to wait for the server's first perception after ``init`` [s].
FIRST_PERCEPTION_TIMEOUT_S = 10.0


@dataclass(frozen=True)
class Perception:
    """One cycle's perception, in the robot's joint order (N joints).

    Attributes:
        time_s: the server's clock [s] (truncated to 0.01 s by the server).
        joint_angles_rad: (N,) [rad]; joint_speeds_rad_s: (N,) [rad/s].
        gyro_rad_s: (3,) torso angular velocity, torso frame [rad/s].
        accelerometer_m_s2: (3,) torso proper acceleration, torso frame [m/s^2].
        torso_quat_wxyz: (4,) torso orientation in the field frame.
        torso_pos_m: (3,) torso origin in the field frame [m].
        play_mode: the game's play mode (``BeforeKickOff``, ``PlayOn``, ...).
    """

    time_s: float
    joint_angles_rad: np.ndarray
    joint_speeds_rad_s: np.ndarray
    gyro_rad_s: np.ndarray
    accelerometer_m_s2: np.ndarray
    torso_quat_wxyz: np.ndarray
    torso_pos_m: np.ndarray
    play_mode: str


def _floats(item: list, start: int = 1) -> np.ndarray:
    return np.array([float(v) for v in item[start:]])


def _field(expr: list, key: bytes) -> list | None:
    return next((e for e in expr[1:] if isinstance(e, list) and e and e[0] == key), None)


def parse_perception(message: bytes, robot: RobotDescription, names: WireNames) -> Perception:
    """A perception message as a ``Perception`` in ``robot``'s joint order.

    Raises:
        LeagueError: the message lacks joints of the robot (another robot's perceptions).
    """
    n = robot.num_joints
    angles, speeds = np.full(n, np.nan), np.zeros(n)
    time_s, mode = math.nan, ""
    gyro, acc, quat, pos = np.zeros(3), np.zeros(3), np.array([1.0, 0, 0, 0]), np.zeros(3)
    for expr in parse_sexp(message):
        if not isinstance(expr, list) or not expr:
            continue
        tag = expr[0]
        if tag == b"HJ":
            name, ax, vx = _field(expr, b"n"), _field(expr, b"ax"), _field(expr, b"vx")
            joint = names.joint_by_sensor.get(name[1].decode()) if name else None
            if joint is not None and robot.has_joint(joint) and ax is not None:
                i = robot.joint_index(joint)
                angles[i] = math.radians(float(ax[1]))
                speeds[i] = math.radians(float(vx[1])) if vx is not None else 0.0
        elif tag == b"time":
            now = _field(expr, b"now")
            time_s = float(now[1]) if now else math.nan
        elif tag == b"GYR":
            gyro = np.radians(_floats(_field(expr, b"rt")))
        elif tag == b"ACC":
            acc = _floats(_field(expr, b"a"))
        elif tag == b"quat":
            quat = _floats(_field(expr, b"q"))
        elif tag == b"pos":
            pos = _floats(_field(expr, b"p"))
        elif tag == b"GS":
            pm = _field(expr, b"pm")
            mode = pm[1].decode() if pm else ""
    if np.isnan(angles).any():
        missing = [robot.joint_names[i] for i in np.nonzero(np.isnan(angles))[0]]
        raise LeagueError(
            f"the server's perceptions lack {len(missing)} {robot.name} joints "
            f"({', '.join(missing[:3])}...): is the player another robot?"
        )
    norm = float(np.linalg.norm(quat))
    return Perception(
        time_s,
        angles,
        speeds,
        gyro,
        acc,
        quat / norm if norm > 0 else np.array([1.0, 0, 0, 0]),
        pos,
        mode,
    )


def format_command(command: JointCommand, robot: RobotDescription, names: WireNames) -> bytes:
    """The motor message for one cycle: every joint's reference with the robot's PD gains."""
    motors = robot.actuator
    if not isinstance(motors, PDMotors):
        raise LeagueError(f"the {robot.name} has {motors.kind}; league robots have PD motors")
    target = np.degrees(
        robot.check_vector(motors.targets(command, robot.name.upper()), "joint command")
    )
    kp, kd = motors.kp_nm_rad, motors.kd_nm_s_rad
    return "".join(
        f"({e} {q:.4f} 0 {p:g} {d:g} 0)" for e, q, p, d in zip(names.effectors, target, kp, kd)
    ).encode()


def wire_targets_rad(targets_rad: np.ndarray) -> np.ndarray:
    """(N,) joint targets [rad] as a server reads them from ``client.format_command``'s text:
    degrees with 4 decimals, back to radians (``math.radians(float(text))``). Vectorised with
    the same arithmetic (``np.degrees`` and ``np.radians`` multiply by 180/pi and pi/180, as
    ``math.radians`` does); should a value lie within 1e-6 of a rounding tie, or be too large
    for the test, the values are formatted as text instead."""
    scaled = targets_rad * _DEGREES_E4  # the degrees x 1e4, within 5e-10 of exact
    whole = np.rint(scaled)
    # The two tests on floats: two numpy reductions on 23 values cost more than the lists
    # (a NaN target gives NaN on either path; an infinite one fails the second test).
    off = np.abs(scaled - whole).tolist()
    if not max(off) <= 0.5 - 1e-6 or not max(map(abs, whole.tolist())) < 1e9:
        degrees = np.degrees(targets_rad)
        return np.radians([float(f"{q:.4f}") for q in degrees])
    return whole / 1e4 * (math.pi / 180)  # k / 1e4: the double nearest k/10000, as float() reads


#: Radians to degrees x 1e4, one product (``wire_targets_rad``).
_DEGREES_E4 = 180 / math.pi * 1e4


class AgentClient:
    """A player connected to a league server (a context manager).

    Args:
        robot: the robot it plays (a league robot).
        host, port: the server's agent port.
        team: team name; player: shirt number (1-99).
    """

    def __init__(
        self, robot: RobotDescription, host: str, port: int, team: str, player: int
    ) -> None:
        self.robot, self.team, self.player = robot, team, player
        self.names = wire_names(robot)
        if not 0 < player < 100:
            raise LeagueError(f"--player must be 1..99, got {player}")
        if not team or any(c.isspace() or c in "()" for c in team):
            raise LeagueError(f"--team must be one word without parentheses, got {team!r}")
        self._conn: Connection = connect(host, port, "agent port")
        self._conn.send(f"(init {self.names.model_name} {team} {player})".encode())

    def receive(self, *, latest: bool = False, timeout_s: float | None = None) -> Perception:
        """The next perception (``latest``: skip to the newest one that has arrived).

        Raises:
            LeagueConnectionError: the server closed the connection (it stopped, refused the
                player, or dropped it for answering too late).
        """
        try:
            message = self._conn.receive(timeout_s=timeout_s)
        except LeagueConnectionError:
            raise LeagueConnectionError(
                f"the server at {self._conn.where} closed the connection of {self.team} "
                f"#{self.player} (server stopped, number taken, or team full)"
            ) from None
        if message is None:
            raise LeagueConnectionError(
                f"no perception from {self._conn.where} within {timeout_s:g} s"
            )
        if latest:
            newer = self._conn.receive_available()
            message = newer[-1] if newer else message
        if is_rsmp(message[:16]):
            raise LeagueConnectionError(
                f"{self._conn.where} is a monitor port; a player "
                "connects to the agent port (rcssservermj --aport)"
            )
        return parse_perception(message, self.robot, self.names)

    def send(self, command: JointCommand) -> None:
        """Answer this cycle with ``command`` (joint references)."""
        self._conn.send(format_command(command, self.robot, self.names))

    def send_raw(self, message: bytes) -> None:
        """Send a message as it is (``(syn)``, a ``(beam X Y DEG)``)."""
        self._conn.send(message)

    def close(self) -> None:
        self._conn.close()

    def __enter__(self) -> AgentClient:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
