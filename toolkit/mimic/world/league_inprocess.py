"""``LeagueInProcessWorld``: RCSSServerMJ's own soccer simulation stepped inside mimic's process.

The hosted server (``LeagueWorld``) runs rcsssmj's ``SoccerSimulation`` in another process and
talks to it over TCP every cycle. This world builds the same simulation object (the same world
MJCF, solver options, robot model, rule book, field and referee, via rcsssmj's own classes),
adds our player as the server adds a joining agent and steps it the way the server's loop does,
without sockets, threads or text:

* **The server's order of operations.** The server's loop (``SimServer._parallel_update_loop``,
  sync mode) runs, in cycle n: perceptions of state n; take the agent's answer to the
  perception of cycle n-1; send the perception of cycle n; take the monitor commands queued
  so far; step (the answer's motor commands set in ``pre_step``, 4 physics steps, then the
  monitor commands and the referee in ``post_step``). So an answer to what the agent saw in
  cycle n acts from cycle n+1 to n+2: one cycle later than in our MuJoCo world
  (``command_delay_cycles`` = 1). ``step(command)`` here advances one cycle with the command
  of the call before (none right after joining) and keeps this one for the next cycle, and a
  placement asked for between two steps is carried out with the command of the next call, in
  the step after it, as on a server whose monitor command arrives before that command.
* **Commands as the wire carries them.** Targets go as degrees with 4 decimals and gains with 6
  significant digits (``client.format_command``); the server parses them back. This world
  rounds the same way, so the simulation receives the same numbers.
* **Perceptions.** Read straight from MjData's sensors with rcsssmj's truncation (joint angles
  and speeds to 0.01 deg and deg/s, gyro to 0.01 deg/s, accelerometer to 0.01 m/s^2,
  orientation and position to 0.001), then turned into radians as ``client.parse_perception``
  does: the same ``Perception`` values an agent on a server receives. Vision and hearing,
  which no observation uses, are not generated. As on the server, sensors are computed at the
  start of a cycle's last physics step, so they lag the state by 5 ms, and right after a
  placement they still show the robot where it was (the placing steps wait for it to show).
* **The truth.** The ball's position and speed come from its joint's qpos and qvel; body poses
  from the robot's qpos through MuJoCo's kinematics (in a scratch MjData): the current state.
  ``LeagueWorld``'s come from the monitor stream, which shows ``xpos`` (computed one physics
  step before qpos), every second cycle, to 4 decimals, and a body only when it moved more
  than 5 mm since last shown. A ball placed but not yet put down reads as where it will be.
* **Play mode.** The game stays in ``BeforeKickOff`` as on a hosted server: motors obey, the
  referee penalises nobody, a ball over a line is put back on it, a goal changes the mode.

* **Time.** ``time_s`` counts cycles since ``reset``, which starts on an even cycle as
  ``LeagueWorld``'s does (one step holding the joints, if needed), so both take the same steps.

The player joins after one cycle of the empty field (rcsssmj 0.2.1's audio engine fails on a
player joining before the first cycle), like a player joining a fresh server. Three changes to
rcsssmj's objects alter no result (``league_simulation.LeagueSimulation``): no audio step once
the player is in (nobody speaks; it changes only what a microphone hears), the ball's touches
found through a table made once per model, and a joining robot's controls zeroed (a server
leaves them uninitialised until the first command, and MuJoCo warns about them into
``MUJOCO_LOG.TXT``).

A seeded episode gives the same perceptions as on a hosted server, bit for bit; the true state
agrees to about 1e-13, as closely as two fresh servers agree with each other
(``tests/test_league_inprocess.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from rcsssmj.games.soccer.server.soccer_command_parser import SoccerCommandParser

from mimic.league.client import wire_targets_rad
from mimic.league.errors import LeagueError
from mimic.league.monitor import place_ball_command, place_player_command
from mimic.league.names import wire_names
from mimic.league.senses import Senses
from mimic.robot.actuators import JointCommand, PDMotors
from mimic.robot.league import LEAGUE_ROBOTS
from mimic.robot.model import RobotDescription
from mimic.robot.registry import get_robot
from mimic.world.base import (
    CYCLE_S,
    LEAGUE_COMMAND_DELAY_CYCLES,
    POSTURES,
    BodyPoses,
    Observation,
    World,
    posture_quat,
)
from mimic.world.league_field import league_field
from mimic.world.league_perceived import PerceivedRobot
from mimic.world.league_server import LeagueWorldConfig, lowest_point_m
from mimic.world.league_simulation import LeagueSimulation
from mimic.world.physics_scales import NominalPhysics

__all__ = ["LeagueInProcessWorld", "InProcessConfig"]

_SERVER = LeagueWorldConfig()


@dataclass(frozen=True)
class InProcessConfig:
    """Our player and how things are placed (the placing defaults are ``LeagueWorld``'s)."""

    # Team name and shirt number of our player.
    team: str = _SERVER.team
    player: int = _SERVER.player
    # Gap between the robot's lowest point and the ground when it is placed [m].
    drop_clearance_m: float = _SERVER.drop_clearance_m
    # How long to step waiting for a placement to show [s of simulated time].
    place_timeout_s: float = _SERVER.place_timeout_s
    # How close the perceived torso must be to where it was put to count as placed [m].
    place_tolerance_m: float = _SERVER.place_tolerance_m


@dataclass(frozen=True)
class _Joining:
    """What a joining agent tells the server (rcsssmj's ``PAgentParameter``)."""

    model_name: str
    team_name: str
    player_no: int


class LeagueInProcessWorld(PerceivedRobot, World):
    """One player in rcsssmj's soccer simulation, stepped in this process.

    Args:
        robot: the robot our player is (a league robot; default ``t1``).
        config: team, number and placement settings.

    The rule book and field are the server's defaults (``rcssservermj`` without ``--rules``
    or ``--field``), as ``league_field()`` describes them.
    """

    command_delay_cycles = LEAGUE_COMMAND_DELAY_CYCLES

    def __init__(
        self, robot: RobotDescription | str = "t1", *, config: InProcessConfig = InProcessConfig()
    ) -> None:
        self.robot = get_robot(robot)
        if self.robot.name not in LEAGUE_ROBOTS:
            raise LeagueError(f"the {self.robot.name} is not a league robot; league robots: t1, k1")
        if not isinstance(self.robot.actuator, PDMotors):
            raise LeagueError(f"the {self.robot.name} has no PD motors")
        self.config = config
        self.field = league_field()
        names = wire_names(self.robot)
        self._sim = LeagueSimulation()
        if not self._sim.init():
            raise LeagueError("rcsssmj could not build its soccer world")
        self._sim.step([])  # the empty field's first cycle, with its audio engine
        joined = self._sim.add_players([_Joining(names.model_name, config.team, config.player)])
        if joined[0] is None:
            raise LeagueError(
                f"rcsssmj refused {config.team} #{config.player} (a {names.model_name})"
            )
        self._agent = joined[0]
        self._agent.set_actions(())  # our motor commands go straight to the controls
        self._sim.hearing = False
        m, d = self._sim.mj_model, self._sim.mj_data
        prefix = self._agent.agent_id.prefix
        self._senses = Senses(m, self.robot, names, prefix)
        self._kinematics = mujoco.MjData(m)
        motors = self.robot.actuator
        self._kp = np.array([float(f"{v:g}") for v in motors.kp_nm_rad])
        self._kd = np.array([float(f"{v:g}") for v in motors.kd_nm_s_rad])

        def ids(suffix: str) -> np.ndarray:
            return np.array([m.actuator(prefix + e + suffix).id for e in names.effectors])

        self._pos_ids, self._vel_ids, self._tau_ids = ids("_pos"), ids("_vel"), ids("_tau")
        self._link_ids = np.array([m.body(prefix + link.name).id for link in self.robot.links])
        ball = m.joint(self._sim.ball.root_joint_name)
        self._ball_q, self._ball_v = int(ball.qposadr[0]), int(ball.dofadr[0])
        self._ball_body = int(m.jnt_bodyid[ball.id])
        self._parser = SoccerCommandParser()
        self._motors_set = False
        self._last_reference, self._last_targets = b"", None  # the last reference's bytes
        self._pending: np.ndarray | None = None  # targets [rad] of the next cycle
        self._pending_commands: list = []  # monitor commands carried out with them
        # The last cycle carried out monitor commands: its perception (read by the sensors in
        # its physics step, before them, as a server's) does not show them yet.
        self._perceived_before_commands = False
        self._queued: list = []  # monitor commands asked for since the last step
        self._ball_target: np.ndarray | None = None  # until the last placement is carried out
        self._ball_command: object | None = None
        self._perception = self._senses.read(d, self._play_mode())
        self._origin_cycle = self._cycle()
        # Friction and masses as built: what ``scale_physics`` scales.
        self._nominal = NominalPhysics.of(self._sim.mj_model)

    # --- lifecycle ------------------------------------------------------------------------
    @property
    def team(self) -> str:
        return self.config.team

    @property
    def player(self) -> int:
        return self.config.player

    @property
    def simulation(self) -> LeagueSimulation:
        """rcsssmj's simulation this world steps (its ``mj_model``, ``mj_data``, referee)."""
        return self._sim

    def close(self) -> None:
        """Drop the simulation (nothing runs outside this process)."""
        self._sim.shutdown()

    def __enter__(self) -> LeagueInProcessWorld:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # --- time -----------------------------------------------------------------------------
    def _cycle(self) -> int:
        """The cycle of the current perception (the simulation is one cycle ahead)."""
        return self._sim.frame_id - 1

    @property
    def time_s(self) -> float:
        return (self._cycle() - self._origin_cycle) * CYCLE_S

    @property
    def server_time_s(self) -> float:
        """The simulation's clock at the current perception [s]."""
        return self._cycle() * CYCLE_S

    # --- placing things -------------------------------------------------------------------
    def reset(self) -> None:
        """Start counting time again on an even cycle, as ``LeagueWorld`` does (one step
        holding the joints where they are, if needed); the game goes on."""
        if self._cycle() % 2:
            self.step(JointCommand.references(self._perception.joint_angles_rad))
        self._origin_cycle = self._cycle()

    def play_mode(self) -> str:
        """The referee's play mode (``BeforeKickOff`` until a goal or the ball leaving the field
        changes it; ``Goal_Left``, ``KickIn_Right``, ...)."""
        return self._play_mode()

    def _play_mode(self) -> str:
        return self._sim.game_state.play_mode.value

    def _monitor(self, message: bytes) -> list:
        """Queue monitor commands, parsed from the bytes a monitor would send."""
        commands = self._parser.parse(message)
        self._queued.extend(commands)
        return commands

    def place_robot(
        self,
        x_m: float,
        y_m: float,
        yaw_rad: float = 0.0,
        joint_angles_rad: np.ndarray | None = None,
        *,
        posture: str = "standing",
    ) -> None:
        if posture not in POSTURES:
            raise ValueError(f"posture must be one of {', '.join(POSTURES)}, got {posture!r}")
        pose = (
            self.robot.zeros()
            if joint_angles_rad is None
            else self.robot.check_vector(joint_angles_rad, "start pose")
        )
        quat = posture_quat(yaw_rad, posture)
        z = self.config.drop_clearance_m - lowest_point_m(self.robot, tuple(quat))
        self._monitor(place_player_command(self.team, self.player, (x_m, y_m, z), quat))
        self._hold_until_placed(x_m, y_m, pose, "rcsssmj")

    def _placing(self) -> bool:
        # Monitor commands act in the cycle after the one they were queued in, and the
        # perception shows them one cycle later.
        return bool(self._queued or self._pending_commands or self._perceived_before_commands)

    def place_ball(self, x_m: float, y_m: float) -> None:
        pos = np.array([x_m, y_m, self.field.ball_radius_m])
        (self._ball_command,) = self._monitor(place_ball_command(pos))
        self._ball_target = pos

    # --- disturbances (``episode.disturbance``) --------------------------------------------
    can_disturb_physics = True

    def scale_physics(self, friction_scale: float, link_mass_scales: np.ndarray) -> None:
        self._nominal.apply(self._sim.mj_model, self._link_ids, friction_scale, link_mass_scales)

    def push_torso(self, force_n: np.ndarray) -> None:
        self._sim.mj_data.xfrc_applied[self._link_ids[0], :3] = force_n

    def robot_mass_kg(self) -> float:
        return float(self._sim.mj_model.body_subtreemass[self._link_ids[0]])

    def describe(self) -> str:
        return f"league world in process ({self.robot.name})"

    # --- stepping and sensing -------------------------------------------------------------
    def step(self, command: JointCommand) -> None:
        """Advance one cycle with the previous call's command; this one acts in the next."""
        motors = self.robot.actuator
        reference = self.robot.check_vector(
            motors.targets(command, self.robot.name.upper()), "command"
        )
        held = reference.tobytes()
        if held != self._last_reference:  # a pose held: the same wire targets as before
            self._last_reference, self._last_targets = held, wire_targets_rad(reference)
        targets = self._last_targets
        self._advance()
        self._pending, self._pending_commands, self._queued = targets, self._queued, []

    def _advance(self) -> None:
        """One cycle of the server's loop: the pending motor commands, physics, the pending
        monitor commands and the referee; then the new perception."""
        d = self._sim.mj_data
        if self._pending is not None:  # as SimAgent.pre_step -> BaseSimulation.ctrl_motor
            if not self._motors_set:
                self._set_motors()
            d.ctrl[self._pos_ids] = self._pending
        commands = self._pending_commands
        self._perceived_before_commands = bool(commands)
        self._sim.step(commands)
        if commands:
            self._pending_commands = []
            if any(c is self._ball_command for c in commands):
                self._ball_target = self._ball_command = None
        self._perception = self._senses.read(d, self._play_mode())

    def _set_motors(self) -> None:
        """What every motor command sets besides the target, the same each cycle (zero speed
        and torque, the robot's gains): set once, at the first."""
        m, d = self._sim.mj_model, self._sim.mj_data
        d.ctrl[self._tau_ids] = 0.0
        d.ctrl[self._vel_ids] = 0.0
        m.actuator_gainprm[self._pos_ids, 0] = self._kp
        m.actuator_biasprm[self._pos_ids, 1] = -self._kp
        m.actuator_gainprm[self._vel_ids, 0] = self._kd
        m.actuator_biasprm[self._vel_ids, 2] = -self._kd
        self._motors_set = True

    def observe(self) -> Observation:
        return self._observation(self.time_s, self.ball_pos_m())

    def ball_pos_m(self) -> np.ndarray:
        """(3,) the ball's centre now [m] (where it will be put, while a placement waits)."""
        if self._ball_target is not None:
            return self._ball_target.copy()
        return self._sim.mj_data.qpos[self._ball_q : self._ball_q + 3].copy()

    def ball_speed_m_s(self) -> float:
        if self._ball_target is not None:
            return 0.0
        d = self._sim.mj_data
        return float(np.linalg.norm(d.qvel[self._ball_v : self._ball_v + 3]))

    def ball_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The ball's centre and orientation now, from qpos (its spin included)."""
        m, k = self._sim.mj_model, self._kinematics
        k.qpos[:] = self._sim.mj_data.qpos
        mujoco.mj_kinematics(m, k)
        return k.xpos[self._ball_body].copy(), k.xquat[self._ball_body].copy()

    def body_poses(self) -> BodyPoses:
        """Every link's pose now, from qpos (not the monitor's ``xpos``, 5 ms older)."""
        m, k = self._sim.mj_model, self._kinematics
        k.qpos[:] = self._sim.mj_data.qpos
        mujoco.mj_kinematics(m, k)
        return BodyPoses(
            tuple(link.name for link in self.robot.links),
            k.xpos[self._link_ids].copy(),
            k.xquat[self._link_ids].copy(),
        )
