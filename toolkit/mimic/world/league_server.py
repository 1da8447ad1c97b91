"""``LeagueWorld``: the world interface on an RCSSServerMJ server.

Our agent is one player process (``AgentClient``); a monitor connection (``MonitorClient``)
places robot and ball and shows the ball and every body. Episodes, recordings and trials then
run in the league unchanged (``mimic.episode.run``).

* ``observe`` and the torso pose come from the player's own perceptions (joint angles and
  speeds, gyro, accelerometer, torso orientation and position sensors); the T1 has no foot
  touch sensors in the league, so ``foot_forces_n`` is zero. The ball and ``body_poses`` come
  from the monitor stream (25 Hz, the scene graph decoded through the robot's tree).
* ``time_s`` counts cycles since ``reset`` (the server reports its clock truncated to 0.01 s).
  ``reset`` starts on a cycle the monitor shows (every second one), so the ball and bodies are
  seen the same way in every episode, whatever the server's clock when the player joined.
* ``place_robot`` sends ``(agent (unum N)(team T)(move3d X Y Z Q))``: the server puts the robot
  there with every joint at zero, so the world then steps, commanding the requested pose,
  until the robot shows up at the new place (a few cycles of server time). ``place_ball``
  sends ``(ball (pos X Y R)(vel 0 0 0))``. The server takes monitor commands in its own thread,
  in whichever cycle they reach its queue; the world waits ``command_settle_s`` before and after
  each one (the server blocks on our next action meanwhile), so a command takes effect in the
  same cycle every time and a seeded episode repeats exactly on a fresh server.
* Play mode: the game is left in ``BeforeKickOff``. Motors obey in every play mode, and before
  the kick-off the referee penalises nobody (no relocation of a robot that lies too long or
  stands in the wrong half). The referee still watches the ball: a ball over a line is put
  back on it (throw-in) and a goal changes the play mode, as in a game.

Without a server address the world hosts its own (``LeagueServer``: sync, as fast as the
agent answers). Close the world (or use it as a context manager) to stop it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import cache

import mujoco
import numpy as np

from mimic.geometry import quat_mul, rotate
from mimic.league.client import AgentClient
from mimic.league.decode import PlayerDecoder, PlayerSample
from mimic.league.errors import LeagueError
from mimic.league.monitor import MonitorClient
from mimic.league.protocol import parse_address
from mimic.league.server import LeagueServer, ServerConfig
from mimic.robot.actuators import JointCommand
from mimic.robot.league import LEAGUE_ROBOTS
from mimic.robot.mjcf_reader import collision_geoms, geom_box_corners, load_model
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

__all__ = ["LeagueWorld", "LeagueWorldConfig", "lowest_point_m"]


@dataclass(frozen=True)
class LeagueWorldConfig:
    """How our player joins and how things are placed."""

    # Team name and shirt number of our player.
    team: str = "mimic"
    player: int = 1
    # Gap between the robot's lowest point and the ground when it is placed [m].
    drop_clearance_m: float = 0.005
    # How long to step waiting for a placement to take effect [s of server time].
    place_timeout_s: float = 1.0
    # How close the torso must be to where it was put to count as placed [m].
    place_tolerance_m: float = 0.05
    # How long to wait for the server's answer to a command, wall clock [s].
    receive_timeout_s: float = 10.0
    # Wall-clock pause before and after each monitor command [s]: the server's current cycle
    # ends and its monitor thread queues the command before our next action arrives.
    command_settle_s: float = 0.02


class LeagueWorld(PerceivedRobot, World):
    """One player of a league server, seen by its own sensors and a monitor.

    Args:
        robot: the robot our player is (a league robot; default ``t1``).
        agent_address: ``HOST:PORT`` of a running server's agent port (None: host a server).
        monitor_address: ``HOST:PORT`` of its monitor port (None with a given agent address:
            no monitor, so no placing and no ball).
        config: team, number and placement settings.
        server_config: how to host the server (used only without ``agent_address``).
    """

    command_delay_cycles = LEAGUE_COMMAND_DELAY_CYCLES

    def describe(self) -> str:
        return "league server (another process: its physics is its own)"

    def __init__(
        self,
        robot: RobotDescription | str = "t1",
        *,
        agent_address: str | None = None,
        monitor_address: str | None = None,
        config: LeagueWorldConfig = LeagueWorldConfig(),
        server_config: ServerConfig | None = None,
    ) -> None:
        self.robot = get_robot(robot)
        if self.robot.name not in LEAGUE_ROBOTS:
            raise LeagueError(f"the {self.robot.name} is not a league robot; league robots: t1, k1")
        self.config = config
        self.field = league_field()  # the server's default rule book's
        self.server: LeagueServer | None = None
        self.monitor: MonitorClient | None = None
        self._client: AgentClient | None = None
        try:
            if agent_address is None:
                self.server = LeagueServer(server_config or ServerConfig())
                self.server.start()
                agent_address, monitor_address = (
                    self.server.agent_address,
                    self.server.monitor_address,
                )
            if monitor_address is not None:
                self.monitor = MonitorClient(*parse_address(monitor_address, "monitor port"))
            self._client = AgentClient(
                self.robot, *parse_address(agent_address, "--server"), config.team, config.player
            )
            self._perception = self._client.receive(timeout_s=config.receive_timeout_s)
        except BaseException:
            self.close()
            raise
        self._decoder = PlayerDecoder(self.robot)
        self._origin_cycle = self._server_cycle()
        self._pending_ball: tuple[np.ndarray, float] | None = None
        self._last_sample: PlayerSample | None = None
        self._ball_track: list[tuple[float, np.ndarray]] = []

    # --- connection ---------------------------------------------------------------------
    @property
    def team(self) -> str:
        return self.config.team

    @property
    def player(self) -> int:
        return self.config.player

    def close(self) -> None:
        """Leave the game; stop the hosted server."""
        for part in (self._client, self.monitor):
            if part is not None:
                part.close()
        self._client = self.monitor = None
        if self.server is not None:
            self.server.stop()
            self.server = None

    def __enter__(self) -> LeagueWorld:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _need_monitor(self, what: str) -> MonitorClient:
        if self.monitor is None:
            raise LeagueError(
                f"{what} needs the server's monitor port; give monitor_address "
                "(or let the world host its server)"
            )
        return self.monitor

    # --- time ---------------------------------------------------------------------------
    def _server_cycle(self) -> int:
        # The server truncates its clock to 0.01 s (29.999... shows as 0.29): round up half
        # a centisecond before rounding to whole cycles.
        return int(round((self._perception.time_s + 0.005) / CYCLE_S))

    @property
    def time_s(self) -> float:
        return (self._server_cycle() - self._origin_cycle) * CYCLE_S

    @property
    def server_time_s(self) -> float:
        """The server's clock at the current perception [s]."""
        return self._server_cycle() * CYCLE_S

    # --- placing things -------------------------------------------------------------------
    def reset(self) -> None:
        """Start counting time again (the server's game goes on; scenes place everything),
        on a cycle with a monitor frame (one step holding the joints where they are, if
        needed)."""
        if self._server_cycle() % 2:
            self.step(JointCommand.references(self._perception.joint_angles_rad))
        self._origin_cycle = self._server_cycle()

    def play_mode(self) -> str:
        """The referee's play mode as the monitor shows it (``BeforeKickOff`` until a goal or
        the ball leaving the field changes it; ``Goal_Left``, ``KickIn_Right``, ...)."""
        from rcsssmj.games.soccer.play_mode import PlayMode

        index = self._synced_monitor("the play mode").state.game.get("play_mode", "0")
        return list(PlayMode)[int(index)].value

    def _command(self, send) -> None:
        """Send one monitor command so that it takes effect with our next action."""
        time.sleep(self.config.command_settle_s)
        send()
        time.sleep(self.config.command_settle_s)

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
        monitor = self._need_monitor("placing the robot")
        pose = (
            self.robot.zeros()
            if joint_angles_rad is None
            else self.robot.check_vector(joint_angles_rad, "start pose")
        )
        quat = posture_quat(yaw_rad, posture)
        z = self.config.drop_clearance_m - lowest_point_m(self.robot, tuple(quat))
        self._command(lambda: monitor.place_player(self.team, self.player, (x_m, y_m, z), quat))
        self._hold_until_placed(x_m, y_m, pose, "the server")

    def place_ball(self, x_m: float, y_m: float) -> None:
        monitor = self._need_monitor("placing the ball")
        pos = np.array([x_m, y_m, self.field.ball_radius_m])
        self._command(lambda: monitor.place_ball(pos))
        self._pending_ball = (pos, self.server_time_s)
        self._ball_track.clear()

    # --- stepping and sensing -------------------------------------------------------------
    def step(self, command: JointCommand) -> None:
        """Send this cycle's motor commands and wait for the next perception."""
        self._client.send(command)
        # The newest perception: a real-time server does not wait for a slow player.
        self._perception = self._client.receive(
            latest=True, timeout_s=self.config.receive_timeout_s
        )
        if self.monitor is not None:
            self.monitor.drain()  # keep the stream flowing (the server blocks on a full pipe)

    def observe(self) -> Observation:
        ball = self.ball_pos_m() if self.monitor is not None else np.full(3, np.nan)
        return self._observation(self.time_s, ball)

    def _synced_monitor(self, what: str) -> MonitorClient:
        """The monitor, with the frame of the current perception's cycle applied, or on a cycle
        without one, the next cycle's (frames come every second cycle; the server steps and
        sends that frame right after our perception, without waiting for our answer). Waiting
        for a fixed frame keeps what the world sees of the ball independent of timing."""
        monitor = self._need_monitor(what)
        monitor.drain()
        monitor.wait_until(self.server_time_s - 1e-6, timeout_s=self.config.receive_timeout_s)
        return monitor

    def ball_pos_m(self) -> np.ndarray:
        state = self._synced_monitor("the ball position").state
        seen = state.ball_pos_m()
        if self._pending_ball is not None:
            target, sent_s = self._pending_ball
            arrived = seen is not None and (
                np.linalg.norm(seen[:2] - target[:2]) < 0.05 or state.time_s > sent_s + 5 * CYCLE_S
            )
            if not arrived:
                return target.copy()
            self._pending_ball = None
        if seen is None:
            raise LeagueError("the monitor stream shows no ball")
        self._track_ball(state.time_s, seen)
        return seen

    def _track_ball(self, time_s: float, pos: np.ndarray) -> None:
        if not self._ball_track or self._ball_track[-1][0] < time_s:
            self._ball_track = [*self._ball_track[-1:], (time_s, pos)]

    def ball_speed_m_s(self) -> float:
        self.ball_pos_m()
        if len(self._ball_track) < 2:
            return 0.0
        (t0, p0), (t1, p1) = self._ball_track
        return float(np.linalg.norm(p1 - p0) / max(t1 - t0, 1e-9))

    def body_poses(self) -> BodyPoses:
        state = self._synced_monitor("body poses").state
        sample = self._decoder.sample(state, self.team, self.player)
        if sample is None:  # the frame after a teleport: the last pose that decoded
            sample = self._last_sample
        if sample is None:
            raise LeagueError(f"{self.team} #{self.player} does not show in the monitor stream")
        self._last_sample = sample
        pos, quat = _world_poses(self.robot, sample.link_pos_m, sample.link_quat_wxyz)
        return BodyPoses(tuple(link.name for link in self.robot.links), pos, quat)


@cache
def lowest_point_m(robot: RobotDescription, quat_wxyz: tuple[float, ...]) -> float:
    """Height of the robot's lowest collision point below its root origin, zero pose, root
    turned by ``quat_wxyz`` [m] (negative: below)."""
    m = load_model(robot.mjcf_path)
    d = mujoco.MjData(m)
    root = m.body(robot.root_link)
    d.qpos[m.jnt_qposadr[m.body_jntadr[root.id]] + 3 :][:4] = quat_wxyz
    mujoco.mj_kinematics(m, d)
    lowest = math.inf
    for b in range(1, m.nbody):
        for g in collision_geoms(m, b):
            world = geom_box_corners(m, g) @ d.xmat[b].reshape(3, 3).T + d.xpos[b]
            lowest = min(lowest, float(world[:, 2].min()))
    return lowest - float(d.xpos[root.id, 2])


def _world_poses(
    robot: RobotDescription, pos_m: np.ndarray, quat_wxyz: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Compose links' poses in their parents (root: in the field) into field poses."""
    index = {link.name: i for i, link in enumerate(robot.links)}
    out_pos, out_quat = pos_m.copy(), quat_wxyz.copy()
    for i, link in enumerate(robot.links):  # parents come before children
        if link.parent is None:
            continue
        p = index[link.parent]
        out_pos[i] = out_pos[p] + rotate(out_quat[p : p + 1], pos_m[i : i + 1])[0]
        out_quat[i] = quat_mul(out_quat[p : p + 1], quat_wxyz[i : i + 1])[0]
    return out_pos, out_quat
