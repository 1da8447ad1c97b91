"""Where a trial's episodes play: our MuJoCo world or the league's simulation (RCSSServerMJ).

Episode functions take their world from ``open_world(kind, robot)`` instead of building one:

* ``mujoco``: our MuJoCo world (``MujocoWorld``), any robot (the NAO on the study's field,
  league robots on the league's field). ``nao`` is accepted as another name for it.
* ``league``: the league server's own simulation stepped in this process
  (``LeagueInProcessWorld``): rcsssmj's soccer world, robot, referee and rules, the server's
  order of operations and command delay, perceptions as the server sends them; no server
  process. A fresh simulation per episode. A seeded episode gives the same perceptions, bit
  for bit, as on a hosted server (``tests/test_league_inprocess.py``); the ball and body poses
  are the simulation's own, not the monitor stream's view of them.
* ``league-server``: a league world (``LeagueWorld``) on a real server hosted for this episode
  alone: sync mode, no real time, no render, free ports. The server is told to stop when the
  episode ends (and reaped when the next one starts, or when the process exits), so K workers
  run at most K servers, and a worker that is stopped takes its server with it (the server
  dies with the process that started it). Starting and joining a server costs about 1-2 s of
  wall time per episode, and every cycle goes over TCP.
* ``league-like``: our world with the league server's solver options and command delay.

Why a fresh simulation per episode rather than one per worker: a league simulation keeps what
earlier episodes did (MuJoCo's solver warm start, the referee's state, its clock), so an
episode replayed on a used one differs from the same episode on a fresh one, and which
episodes a worker happens to run would change the table. On a fresh server a seeded episode
repeats (the robot's perceptions exactly; see ``tests/test_league_trials.py``).
"""

from __future__ import annotations

import atexit
import contextlib
import threading
from collections.abc import Iterator

from mimic.errors import MimicError
from mimic.robot.registry import get_robot
from mimic.world.base import World

__all__ = [
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
]

MUJOCO = "mujoco"
#: The league's simulation in this process (``league.inprocess``).
LEAGUE = "league"
#: The league's server, hosted per episode, our player over TCP (``league.world``).
LEAGUE_SERVER = "league-server"
#: Ours with the league server's solver options and command delay (``world.league_like``).
LEAGUE_LIKE = "league-like"
#: The worlds a trial can play in.
WORLDS = (MUJOCO, LEAGUE, LEAGUE_SERVER, LEAGUE_LIKE)
#: The worlds that are the league's simulation (its field, referee and league robots only).
LEAGUE_WORLDS = (LEAGUE, LEAGUE_SERVER)
_ALIASES = {"nao": MUJOCO}


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


def world_class(kind: str) -> type[World]:
    """The class of the world called ``kind`` (imported only when asked for)."""
    kind = world_kind(kind)
    if kind == LEAGUE:
        from mimic.league.inprocess import LeagueInProcessWorld

        return LeagueInProcessWorld
    if kind == MUJOCO:
        from mimic.world.mujoco_world import MujocoWorld

        return MujocoWorld
    if kind == LEAGUE_LIKE:
        from mimic.world.league_like import LeagueLikeWorld

        return LeagueLikeWorld
    from mimic.league.world import LeagueWorld

    return LeagueWorld


def world_owns_physics(kind: str) -> bool:
    """Episodes in this world can push the robot and change friction and masses (the
    physics runs in mimic's process: ``World.can_disturb_physics``)."""
    return world_class(kind).can_disturb_physics


def default_robot(kind: str) -> str:
    """The robot a trial in this world uses unless told: the NAO in ours, the T1 in the
    league's."""
    return "t1" if world_kind(kind) in (*LEAGUE_WORLDS, LEAGUE_LIKE) else "nao"


def check_world(kind: str, robot: str) -> None:
    """The robot can play in this world (the league's server has league robots only).

    Raises:
        MimicError: it cannot, in one line naming the option to change.
    """
    description = get_robot(robot)
    kind = world_kind(kind)
    if kind in LEAGUE_WORLDS and description.world != "league":
        raise MimicError(
            f"the league world plays league robots (t1, k1), not the {description.name}; "
            f"pass --robot t1, or leave out --world {kind}"
        )
    if kind in LEAGUE_WORLDS:
        import importlib.util

        if importlib.util.find_spec("rcsssmj") is None:
            raise MimicError("the league world needs the league server: pip install rcsssmj")


@contextlib.contextmanager
def open_world(
    kind: str, robot: str, *, server_command: tuple[str, ...] | None = None
) -> Iterator[World]:
    """A world of this kind with this robot, closed (its server stopped) on exit.

    ``server_command``: ``league-server`` only, how to start the server (None: ``python -m
    mimic.league.hosted_server``, rcsssmj with safe sends; tests wrap it).
    """
    kind = world_kind(kind)
    if kind == LEAGUE:
        with world_class(kind)(robot) as world:
            yield world
        return
    if kind in (MUJOCO, LEAGUE_LIKE):
        yield world_class(kind)(robot)
        return
    from mimic.league.server import ServerConfig
    from mimic.league.world import LeagueWorld

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
