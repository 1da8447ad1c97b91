"""Any mimic agent as an ordinary team process on a league server.

``play`` connects one player (``LeagueWorld``) and runs the agent in the episode layer's loop:
perceptions in, joint references out with the robot's PD gains, every cycle. On a server of
its own (no address given) it first puts the robot on the field as ``mimic record`` does
(standing 1 m behind the centre spot, or lying for a get-up) and lets it settle; on someone
else's server it plays from wherever the robot is, as a team process does.

With an output file it records what the player knew: ``/joint_references`` (our agents),
``/joint_states`` (the angles it perceived), ``/ended``, ``/tf`` (the torso under ``world``,
as the server reports it, and the ball when the monitor shows it, as ``mimic record`` writes
them), the robot's URDF and metadata (world ``league``). Ctrl-C or a server that stops end the
run with the file finished. A kick on a server of its own gets a ball where the kick wants it,
and the result says how far it went once it rests (the robot holding its last pose meanwhile,
at most ``BALL_ROLL_OUT_S``). The result also says what the robot did while the agent played:
how far its torso went, how fast, and how often it fell.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mimic import __version__
from mimic.agents.base import Agent
from mimic.agents.hold import HoldPose
from mimic.agents.registry import kick_ball_offset_m, make_agent
from mimic.episode import Observer, Scene, run
from mimic.league.errors import LeagueConnectionError, LeagueError
from mimic.recording import layout as L
from mimic.recording.recorder import McapObserver, PerceivedTf
from mimic.recording.writer import RecordingWriter
from mimic.robot.registry import get_robot
from mimic.sigint import SigintFlag
from mimic.world.base import CYCLE_S, POSTURES
from mimic.world.league_server import LeagueWorld, LeagueWorldConfig

__all__ = ["play", "PlayResult", "MAX_PLAY_S", "settle_note"]

#: How long an agent that never says it is done plays without ``seconds`` [s].
MAX_PLAY_S = 60.0
#: Where a hosted server's robot starts (field frame) [m].
HOSTED_START_XY_M = (-1.0, 0.0)
#: After a kick on a hosted server: the longest wait for the ball to come to rest [s], and
#: the speed that counts as rest [m/s].
BALL_ROLL_OUT_S, BALL_AT_REST_M_S = 3.0, 0.05
_NS_PER_CYCLE = int(round(CYCLE_S * L.NS_PER_S))


@dataclass(frozen=True)
class PlayResult:
    """How a game ended: ``end`` is ``done`` (the agent finished), ``timeout`` (``seconds``
    ran out), ``interrupted`` (Ctrl-C) or ``server stopped``; ``path`` is the recording."""

    end: str
    cycles: int
    duration_s: float
    path: Path | None
    # How far the ball went [m]: a kick on a hosted server, which places the ball where the
    # kick wants it; None otherwise.
    ball_moved_m: float | None = None
    # How far the torso went on the ground while the agent played [m] (start to end,
    # straight), and its mean speed [m/s]; None when no cycle ran.
    distance_m: float | None = None
    speed_m_s: float | None = None
    # Falls while the agent played (upright -> fallen; a robot that starts lying has not
    # fallen).
    falls: int = 0

    @property
    def interrupted(self) -> bool:
        return self.end in ("interrupted", "server stopped")


class PlayTrack(Observer):
    """Where the torso started and ended while the agent played, and the falls."""

    def __init__(self) -> None:
        self.start_xy_m: np.ndarray | None = None
        self.end_xy_m: np.ndarray | None = None
        self.start_s = self.end_s = 0.0
        self.falls = self.cycles = 0
        self._was_fallen = False

    def start(self, world, agent) -> None:
        self.start_xy_m = self.end_xy_m = np.asarray(world.torso_pos_m(), float)[:2].copy()
        self.start_s = self.end_s = world.time_s
        self._was_fallen = world.fallen()  # a get-up starts lying: not a fall

    def after_step(self, world) -> None:
        self.cycles += 1
        self.end_xy_m = np.asarray(world.torso_pos_m(), float)[:2].copy()
        self.end_s = world.time_s
        fallen = world.fallen()
        if fallen and not self._was_fallen:
            self.falls += 1
        self._was_fallen = fallen

    def distance_speed(self) -> tuple[float | None, float | None]:
        """(distance [m], mean speed [m/s]) from start to end; (None, None) if nothing ran."""
        if self.start_xy_m is None or not self.end_s > self.start_s:
            return None, None
        distance = float(np.hypot(*(self.end_xy_m - self.start_xy_m)))
        return distance, distance / (self.end_s - self.start_s)


def play(
    agent: str | Agent,
    *,
    robot: str = "t1",
    agent_address: str | None = None,
    team: str = "mimic",
    player: int = 1,
    seconds: float | None = None,
    out_path: str | Path | None = None,
    progress: Callable[[float, float | None], None] | None = None,
    settle_s: float = 1.0,
) -> PlayResult:
    """Play ``agent`` (a spec for ``make_agent`` or an Agent) as ``team`` #``player``.

    Args:
        robot: the robot the player is (the agent must drive it).
        agent_address: ``HOST:PORT`` of a server's agent port (None: host one).
        seconds: how long to play [s] (None: until the agent is done, at most ``MAX_PLAY_S``).
        out_path: record to this ``.mcap`` file (None: no recording).
        settle_s: how long the robot holds its stand pose before the agent starts [s]: on a
            hosted server after mimic places it, on a given server where the server put it
            (it arrives with straight joints; a walk started at once fell within 1.2 s).

    Raises:
        LeagueConnectionError: nothing listens at ``agent_address`` (before anything ran).
        MimicError: an agent made for another robot, a bad spec, bad options.
    """
    if isinstance(agent, str):
        agent = make_agent(agent, robot=robot)
    if seconds is not None and not seconds > 0:
        raise LeagueError(f"--seconds must be > 0, got {seconds}")

    agent.check_robot(get_robot(robot))
    config = LeagueWorldConfig(team=team, player=player)
    with (
        SigintFlag() as sigint,
        LeagueWorld(robot, agent_address=agent_address, config=config) as world,
    ):
        ball_offset = kick_ball_offset_m(agent) if world.server is not None else None
        if agent.start_posture not in POSTURES:
            raise LeagueError(
                f"{agent.name} starts {agent.start_posture}; mimic can put a robot down "
                "standing or lying only (train from where it stands or lies: --start)"
            )
        if world.server is not None:
            Scene(
                robot_xy_m=HOSTED_START_XY_M,
                posture=agent.start_posture,
                settle_s=settle_s,
                ball_offset_m=ball_offset,
            ).setup(world, np.random.default_rng(0))
        elif settle_s > 0:
            # On a server mimic does not host, the robot stands where the server put it,
            # whatever posture the agent starts from (``settle_note``).
            stand = np.asarray(world.robot.stand_pose_rad)
            run(
                world,
                HoldPose(stand, world.robot.name),
                max_s=settle_s,
                stop=lambda w: sigint.raised,
            )
        ball_start = None if ball_offset is None else world.ball_pos_m()[:2].copy()
        writer = (
            None
            if out_path is None
            else RecordingWriter(
                out_path, _info(agent, world, agent_address), urdf=world.robot.urdf()
            )
        )
        # The one recorder, showing on /tf what the player perceives (its torso, the ball).
        recorder = (
            None
            if writer is None
            else McapObserver(
                writer,
                world,
                planned_cycles=None,
                one_shot=True,
                with_references=True,
                tf=PerceivedTf(world.robot.root_link),
            )
        )
        planned_s = seconds
        track = PlayTrack()
        watchers: list[Observer] = [track] if recorder is None else [track, recorder]
        if progress is not None:
            watchers.append(_Progress(progress, planned_s))
        end, cycles = "error", 0
        try:
            outcome = run(
                world,
                agent,
                max_s=seconds or MAX_PLAY_S,
                observers=watchers,
                stop=lambda w: sigint.raised,
                stop_when_done=seconds is None,
            )
            end = {"stop": "interrupted"}.get(outcome.end, outcome.end)
            cycles = outcome.cycles
        except LeagueConnectionError:
            end = "server stopped"  # keep what was recorded
            cycles = track.cycles  # the cycles that ran before it stopped
        except KeyboardInterrupt:  # SIGTERM (Ctrl-C is the flag): kept, marked interrupted
            end = "interrupted"
            raise
        except BaseException:  # a failed run leaves the target as it was
            if writer is not None:
                writer.abandon()
                writer = None
            raise
        finally:
            if writer is not None:
                writer.finish(
                    interrupted=end not in ("done", "timeout", "fell"),
                    samples=recorder.samples,
                    end=end,
                )
        duration = recorder.t_last_s if recorder is not None else cycles * CYCLE_S
        moved = None
        if ball_start is not None and end in ("done", "timeout"):
            # The robot holds its last pose while the ball rolls out (not recorded).
            last = agent.reference_rad
            if last is not None:
                run(
                    world,
                    HoldPose(last, world.robot.name),
                    max_s=BALL_ROLL_OUT_S,
                    stop=lambda w: sigint.raised or w.ball_speed_m_s() < BALL_AT_REST_M_S,
                )
            moved = float(np.hypot(*(world.ball_pos_m()[:2] - ball_start)))
        distance, speed = track.distance_speed()
        return PlayResult(
            end,
            cycles,
            duration,
            None if out_path is None else Path(out_path),
            moved,
            distance,
            speed,
            track.falls,
        )


def settle_note(agent: Agent, hosted: bool, settle_s: float) -> str | None:
    """What happens to an agent that starts lying on a server mimic does not host (it cannot
    lay the robot down there), in one line; None when it starts as the agent wants."""
    if hosted or agent.start_posture == "standing":
        return None
    return (
        f"{agent.name} starts {agent.start_posture.replace('_', ' on its ')}, but on a "
        "server mimic does not host the robot starts where the server put it, standing: it "
        f"holds its stand pose {settle_s:g} s (--settle), then plays from there (let mimic "
        "host the server to start it lying)"
    )


def _info(agent: Agent, world: LeagueWorld, agent_address: str | None) -> L.RecordingInfo:
    return L.RecordingInfo(
        motion=agent.name,
        agent=type(agent).__name__,
        team=world.team,
        source="reference" if agent.team == "mimic" else "observed",
        robot=world.robot.name,
        world="league",
        joint_order=world.robot.joint_names,
        toolkit_version=__version__,
        period_s=agent.period_s,
        start_posture=agent.start_posture,
        extra={"player": str(world.player), "server": agent_address or "hosted"},
    )


class _Progress(Observer):
    def __init__(self, progress, planned_s) -> None:
        self.progress, self.planned_s, self._t0 = progress, planned_s, None

    def after_step(self, world) -> None:
        self._t0 = world.time_s if self._t0 is None else self._t0
        self.progress(world.time_s - self._t0, self.planned_s)
