"""Where a trial's episodes play: our MuJoCo world or the league's simulation (RCSSServerMJ),
each world registered as data (``WorldSpec``: its field, referee, physics, command delay,
robots, and how it opens), so code asks ``get_world(name)`` for a fact instead of comparing
names. Configs and files keep the world's name.

Episode functions take their world from ``open_world(kind, robot)`` instead of building one:

* ``mujoco``: our MuJoCo world (``MujocoWorld``), any robot (the NAO on the study's field,
  league robots on the league's field). ``nao`` is accepted as another name for it.
* ``league``: the league server's own simulation stepped in this process
  (``LeagueInProcessWorld``, ``world.league_inprocess``): rcsssmj's soccer world, robot, referee and rules, the server's
  order of operations and command delay, perceptions as the server sends them; no server
  process. A fresh simulation per episode. A seeded episode gives the same perceptions, bit
  for bit, as on a hosted server (``tests/test_league_inprocess.py``); the ball and body poses
  are the simulation's own, not the monitor stream's view of them.
* ``league-server``: a league world (``LeagueWorld``, ``world.league_server``) on a real server hosted for this episode
  alone: sync mode, no real time, no render, free ports. The server is told to stop when the
  episode ends (and reaped when the next one starts, or when the process exits), so K workers
  run at most K servers, and a worker that is stopped takes its server with it (the server
  dies with the process that started it). Starting and joining a server costs about 1-2 s of
  wall time per episode, and every cycle goes over TCP.
* ``league-like``: our world with the league server's solver options and command delay
  (``LeagueLikeWorld``, ``world.league_like``).

Why a fresh simulation per episode rather than one per worker: a league simulation keeps what
earlier episodes did (MuJoCo's solver warm start, the referee's state, its clock), so an
episode replayed on a used one differs from the same episode on a fresh one, and which
episodes a worker happens to run would change the table. On a fresh server a seeded episode
repeats (the robot's perceptions exactly; see ``tests/test_league_trials.py``).
"""

from __future__ import annotations

import atexit
import contextlib
import importlib.util
import threading
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager
from dataclasses import dataclass

from mimic.errors import MimicError
from mimic.league.server import ServerConfig
from mimic.robot.league import LEAGUE_ROBOTS
from mimic.robot.registry import get_robot, robot_names
from mimic.world.base import World
from mimic.world.field import NAO_FIELD, Field
from mimic.world.league_field import league_field
from mimic.world.league_inprocess import LeagueInProcessWorld
from mimic.world.league_like import LeagueLikeWorld
from mimic.world.league_server import LeagueWorld
from mimic.world.mujoco_world import MujocoWorld

__all__ = [
    "WorldSpec",
    "get_world",
    "WORLDS",
    "MUJOCO",
    "LEAGUE",
    "LEAGUE_SERVER",
    "LEAGUE_LIKE",
    "LEAGUE_WORLDS",
    "world_kind",
    "world_owns_physics",
    "world_class",
    "open_world",
    "default_robot",
    "check_world",
    "recorded_as",
]

MUJOCO = "mujoco"
#: The league's simulation in this process (``world.league_inprocess``).
LEAGUE = "league"
#: The league's server, hosted per episode, our player over TCP (``world.league_server``).
LEAGUE_SERVER = "league-server"
#: Ours with the league server's solver options and command delay (``world.league_like``).
LEAGUE_LIKE = "league-like"
_ALIASES = {"nao": MUJOCO}

#: How a world opens for one episode: ``opener(robot, server_command)`` is a context manager
#: that yields the world and closes it (stops its server) on exit.
Opener = Callable[[str, "tuple[str, ...] | None"], AbstractContextManager[World]]


@dataclass(frozen=True)
class WorldSpec:
    """One world a trial can play in, as data.

    Attributes:
        name: its name in configs, tables and files (``mujoco``, ``league``, ...).
        title: how table titles name it.
        world_class: the ``World`` subclass an episode plays in.
        league_field: it plays on the league's field (RCSSServerMJ's default rule book's,
            ``world.league_field``), the trials lay their courses there; False: ours, the
            study's 30 m x 20 m field (``world.field.NAO_FIELD``) for the courses (a league
            robot in ours still gets the league's ball and pitch: ``field_for_robot``).
        league_referee: the league's referee runs and its rules apply (kick-off, fouls, the
            ball out of play).
        robots: the robots it plays (the league's worlds: league robots only).
        default_robot: the robot a trial in it uses unless told.
        needs_rcsssmj: it needs the league server's package installed.
        twin: the world of ours (mimic steps its physics) that stands in for it where the
            physics must be ours, e.g. fitting a walk in simulation: itself for ours,
            ``league-like`` for the league's.
        opener: how it opens for one episode (``Opener``; ``open_world`` calls it).
        recorded_as: the world a recording made in it names (``RecordingInfo.world``; ``nao``
            for ours, as recordings have always said; what ``mimic train`` reads the command
            delay from).

    ``owns_physics`` and ``command_delay_cycles`` are read from ``world_class``, so the class
    stays the one place that says them.
    """

    name: str
    title: str
    world_class: type[World]
    league_field: bool
    league_referee: bool
    robots: tuple[str, ...]
    default_robot: str
    needs_rcsssmj: bool
    twin: str
    opener: Opener
    recorded_as: str

    @property
    def owns_physics(self) -> bool:
        """Episodes here can push the robot and change friction and masses (mimic steps
        the physics: ``World.can_disturb_physics``)."""
        return self.world_class.can_disturb_physics

    @property
    def command_delay_cycles(self) -> int:
        """How many cycles after the one it was sent in a command acts
        (``World.command_delay_cycles``: 0 ours, 1 the league's)."""
        return self.world_class.command_delay_cycles

    def field(self) -> Field:
        """The field its trials lay their courses on (``league_field``: the league's)."""
        return league_field() if self.league_field else NAO_FIELD


def _construct(world_class: type[World]) -> Opener:
    """A world built per episode, nothing to close (ours)."""

    @contextlib.contextmanager
    def opener(robot: str, server_command: tuple[str, ...] | None) -> Iterator[World]:
        yield world_class(robot)

    return opener


@contextlib.contextmanager
def _open_in_process(robot: str, server_command: tuple[str, ...] | None) -> Iterator[World]:
    """A fresh league simulation in this process, closed after the episode."""
    with LeagueInProcessWorld(robot) as world:
        yield world


@contextlib.contextmanager
def _open_on_hosted_server(robot: str, server_command: tuple[str, ...] | None) -> Iterator[World]:
    """Our player on a league server hosted for this episode alone."""
    _reap()  # the previous episode's server has stopped by now
    config = ServerConfig(command=server_command, stop_timeout_s=_STOP_GRACE_S)
    world = LeagueWorld(robot, server_config=config)
    try:
        yield world
    finally:
        server, world.server = world.server, None
        world.close()  # our player and monitor leave; the server stops without us waiting
        if server is not None:
            server.request_stop()
            # Stopped in the background: a server that ignores the SIGINT (rcsssmj 0.2.1
            # now and then hangs in its own shutdown) is killed after the grace period, not
            # left running until this process starts another episode or exits.
            stopper = threading.Thread(target=server.stop, name="league-server-stop", daemon=True)
            stopper.start()
            _STOPPING.append(stopper)


_SPECS = (
    WorldSpec(
        name=MUJOCO,
        title="our MuJoCo world",
        world_class=MujocoWorld,
        league_field=False,
        league_referee=False,
        robots=tuple(robot_names()),
        default_robot="nao",
        needs_rcsssmj=False,
        twin=MUJOCO,
        opener=_construct(MujocoWorld),
        recorded_as="nao",
    ),
    WorldSpec(
        name=LEAGUE,
        title="league world (RCSSServerMJ's simulation, in process)",
        world_class=LeagueInProcessWorld,
        league_field=True,
        league_referee=True,
        robots=LEAGUE_ROBOTS,
        default_robot="t1",
        needs_rcsssmj=True,
        twin=LEAGUE_LIKE,
        opener=_open_in_process,
        recorded_as=LEAGUE,
    ),
    WorldSpec(
        name=LEAGUE_SERVER,
        title="league world (RCSSServerMJ server)",
        world_class=LeagueWorld,
        league_field=True,
        league_referee=True,
        robots=LEAGUE_ROBOTS,
        default_robot="t1",
        needs_rcsssmj=True,
        twin=LEAGUE_LIKE,
        opener=_open_on_hosted_server,
        recorded_as=LEAGUE,
    ),
    WorldSpec(
        name=LEAGUE_LIKE,
        title="our MuJoCo world with the league's solver and command delay",
        world_class=LeagueLikeWorld,
        league_field=False,
        league_referee=False,
        robots=tuple(robot_names()),
        default_robot="t1",
        needs_rcsssmj=False,
        twin=LEAGUE_LIKE,
        opener=_construct(LeagueLikeWorld),
        recorded_as=LEAGUE_LIKE,
    ),
)
_BY_NAME = {spec.name: spec for spec in _SPECS}

#: The worlds a trial can play in.
WORLDS = tuple(_BY_NAME)
#: The worlds that are the league's simulation (its field, referee and league robots only).
LEAGUE_WORLDS = tuple(spec.name for spec in _SPECS if spec.league_referee)


def world_kind(name: str) -> str:
    """The world called ``name`` (``mujoco``, ``nao``: the same, ``league``, ``league-server``
    or ``league-like``).

    Raises:
        MimicError: an unknown name, with the known ones.
    """
    kind = _ALIASES.get(name.lower(), name.lower())
    if kind not in WORLDS:
        raise MimicError(f"unknown world {name!r}; worlds: {', '.join(WORLDS)} (nao: mujoco)")
    return kind


def get_world(name: str) -> WorldSpec:
    """The world called ``name`` (any name ``world_kind`` accepts).

    Raises:
        MimicError: an unknown name, with the known ones.
    """
    return _BY_NAME[world_kind(name)]


def world_class(kind: str) -> type[World]:
    """The class of the world called ``kind``."""
    return get_world(kind).world_class


def world_owns_physics(kind: str) -> bool:
    """Episodes in this world can push the robot and change friction and masses (the
    physics runs in mimic's process: ``World.can_disturb_physics``)."""
    return get_world(kind).owns_physics


def default_robot(kind: str) -> str:
    """The robot a trial in this world uses unless told: the NAO in ours, the T1 in the
    league's."""
    return get_world(kind).default_robot


def check_world(kind: str, robot: str) -> None:
    """The robot can play in this world (the league's server has league robots only).

    Raises:
        MimicError: it cannot, in one line naming the option to change.
    """
    description = get_robot(robot)
    spec = get_world(kind)
    if description.name not in spec.robots:
        raise MimicError(
            f"the league world plays league robots ({', '.join(spec.robots)}), not the "
            f"{description.name}; pass --robot {spec.default_robot}, or leave out "
            f"--world {spec.name}"
        )
    if spec.needs_rcsssmj and importlib.util.find_spec("rcsssmj") is None:
        raise MimicError("the league world needs the league server: pip install rcsssmj")


def open_world(
    kind: str, robot: str, *, server_command: tuple[str, ...] | None = None
) -> AbstractContextManager[World]:
    """A world of this kind with this robot, closed (its server stopped) on exit.

    ``server_command``: ``league-server`` only, how to start the server (None: ``python -m
    mimic.league.hosted_server``, rcsssmj with safe sends; tests wrap it).
    """
    return get_world(kind).opener(robot, server_command)


#: How long a finished episode's server may take to stop on SIGINT before it is killed [s]
#: (a clean stop takes about 0.4 s).
_STOP_GRACE_S = 2.0

#: Threads stopping the servers of finished episodes: their shutdown overlaps the next
#: episode's start. Joined there, and when this process exits.
_STOPPING: list[threading.Thread] = []


def _reap() -> None:
    while _STOPPING:
        _STOPPING.pop().join()


atexit.register(_reap)


def recorded_as(world: World) -> str:
    """The world a recording made in ``world`` names (``WorldSpec.recorded_as``), from its
    class; a world no spec names (a test's own) counts as ours."""
    for spec in _SPECS:
        if type(world) is spec.world_class:
            return spec.recorded_as
    return _BY_NAME[MUJOCO].recorded_as
