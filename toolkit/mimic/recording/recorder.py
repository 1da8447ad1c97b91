"""Recording an agent in a fresh world: the simulator's joint angles, our references, TF.

A recording is a scene, a run and an observer that writes MCAP (``McapObserver``). One-shot
motions start from the ready pose: the robot is placed standing in its stand pose (or lying,
for a get-up), holds it ``settle_s``, the ball goes to the motion's ``ball_offset_m`` (robot
frame) if it has one, and the recording starts as the motion starts (t = 0). Cyclic agents
(``period_s`` set) run ``warmup_s`` unrecorded, then whole periods are recorded. Other-team
agents are only observed: nothing beyond the ``Agent`` interface is read.

Ctrl-C (SIGINT) stops the recording at the end of the current cycle; the file is finished
normally and marked interrupted.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mimic import __version__
from mimic.agents.base import Agent
from mimic.agents.registry import make_agent
from mimic.episode import Observer, Scene, run
from mimic.episode.scene import SETTLE_S
from mimic.errors import MimicError
from mimic.geometry import quat_mul, rotate
from mimic.recording import layout as L
from mimic.recording.writer import RecordingWriter
from mimic.robot.model import RobotDescription
from mimic.sigint import SigintFlag
from mimic.world.base import CYCLE_S, Observation, World
from mimic.world.registry import MUJOCO, check_world, get_world, open_world, recorded_as

__all__ = ["record", "RecordResult", "RecordConfig", "TfSampler", "McapObserver"]

#: Called after each recorded cycle with (recorded time [s], planned total [s] or None).
Progress = Callable[[float, float | None], None]


@dataclass(frozen=True)
class RecordConfig:
    """How a recording is made (besides agent, file and seed)."""

    # Robot placement in the field frame: x, y [m] and heading [rad].
    start_x_m: float = -1.0
    start_y_m: float = 0.0
    start_yaw_rad: float = 0.0
    # Time to hold the stand pose before the motion starts [s].
    settle_s: float = SETTLE_S
    # Upper bound on a one-shot recording without --duration [s] (a motion that never ends).
    max_duration_s: float = 60.0
    # Periods recorded for a cyclic agent without --duration.
    default_periods: int = 10
    # Time a cyclic agent runs unrecorded by default [s]: walks lengthen their steps for ~3.5 s
    # after starting, and a copy learned from that start-up walks ~10 % slower.
    cyclic_warmup_s: float = 4.0
    # Write /tf every this many cycles (1: every cycle).
    tf_every: int = 1
    # Close a chunk and flush the file after this much recorded time [s].
    flush_period_s: float = 0.25


@dataclass(frozen=True)
class RecordResult:
    """What ``record`` wrote."""

    path: Path
    samples: int
    duration_s: float
    interrupted: bool
    info: L.RecordingInfo


class TfSampler:
    """Link poses in their parents (the URDF tree under ``world``) and the ball in ``world``,
    from any world's ``body_poses`` and ``ball_pose``."""

    def __init__(self, robot: RobotDescription) -> None:
        links = robot.links
        self.children = [link.name for link in links] + [L.BALL_FRAME]
        self.parents = [link.parent or L.WORLD_FRAME for link in links] + [L.WORLD_FRAME]
        index = {link.name: i for i, link in enumerate(links)}
        # Each child's parent among the links; -1: the field frame (origin, no rotation).
        self._parent = np.array([index[link.parent] if link.parent else -1 for link in links])

    def frames(self, world: World, obs: Observation):
        """(parents, children, (n, 3) positions [m], (n, 4) quaternions) of this cycle."""
        return (self.parents, self.children, *self.sample(world))

    def sample(self, world: World) -> tuple[np.ndarray, np.ndarray]:
        """(n, 3) positions [m] and (n, 4) quaternions of each child in its parent."""
        poses = world.body_poses()
        ball_pos, ball_quat = world.ball_pose()
        pc = np.vstack([poses.pos_m, ball_pos])
        qc = np.vstack([poses.quat_wxyz, ball_quat])
        pp = np.zeros_like(pc)
        qp = np.zeros_like(qc)
        qp[:, 0] = 1.0
        linked = np.flatnonzero(self._parent >= 0)
        pp[linked] = poses.pos_m[self._parent[linked]]
        qp[linked] = poses.quat_wxyz[self._parent[linked]]
        qp_inv = qp * np.array([1.0, -1.0, -1.0, -1.0])
        return rotate(qp_inv, pc - pp), quat_mul(qp_inv, qc)


class PerceivedTf:
    """What a player perceives of itself and the ball, for ``/tf``: its root link (the torso)
    and, when shown, the ball, both under ``world`` (a team process on a league server knows
    no more than its perceptions)."""

    def __init__(self, root_link: str) -> None:
        self.root_link = root_link

    def frames(self, world: World, obs: Observation):
        """(parents, children, (n, 3) positions [m], (n, 4) quaternions) of this cycle."""
        pos = [np.asarray(obs.torso_pos_m, float)]
        quat = [np.asarray(obs.torso_quat_wxyz, float)]
        children = [self.root_link]
        ball = np.asarray(obs.ball_pos_m, float)
        if ball.shape == (3,) and np.all(np.isfinite(ball)):
            pos.append(ball)
            quat.append(np.array([1.0, 0.0, 0.0, 0.0]))
            children.append(L.BALL_FRAME)
        return [L.WORLD_FRAME] * len(children), children, np.array(pos), np.array(quat)


class McapObserver(Observer):
    """The recorder: writes every cycle it sees, in any world: joint states, the agent's
    references, the ended flag, ``/tf``. Times are the world's clock from the first cycle
    written (a real-time server's missed cycles leave gaps).

    Args:
        writer: an open ``RecordingWriter``.
        planned_cycles: the last cycle to write (its ``ended`` flag is set); None: no
            planned end.
        one_shot: the agent's ``done`` marks the motion's end (``ended`` from then on).
        with_references: write ``/joint_references`` when the agent has them.
        tf_every: write ``/tf`` every this many cycles (and on the last).
        tf: what ``/tf`` shows: None, every link in its parent and the ball, from the world
            (``TfSampler``); or ``PerceivedTf`` (what a player perceives).
        progress: called after each written cycle with (time [s], planned total [s] or None).
    """

    def __init__(
        self,
        writer: RecordingWriter,
        world: World,
        *,
        planned_cycles: int | None,
        one_shot: bool,
        with_references: bool,
        tf_every: int = 1,
        tf: PerceivedTf | None = None,
        planned_s: float | None = None,
        progress: Progress | None = None,
    ) -> None:
        self.writer, self.planned_cycles, self.one_shot = writer, planned_cycles, one_shot
        self.with_references, self.tf_every = with_references, tf_every
        self.planned_s, self.progress = planned_s, progress
        self.tf = TfSampler(world.robot) if tf is None else tf
        self.samples, self.t_last_s = 0, 0.0
        self.interrupted = False
        self._cycle_ns = int(round(CYCLE_S * L.NS_PER_S))
        self._first_cycle: int | None = None

    @property
    def finished(self) -> bool:
        return self.planned_cycles is not None and self.samples >= self.planned_cycles

    def before_step(self, world, obs, agent, command) -> None:
        k = self.samples
        cycle = int(round(obs.time_s / CYCLE_S))
        self._first_cycle = cycle if self._first_cycle is None else self._first_cycle
        t_ns = (cycle - self._first_cycle) * self._cycle_ns
        last = self.planned_cycles is not None and k == self.planned_cycles - 1
        ended = bool(agent.done and self.one_shot) or (last and not self.interrupted)
        self.writer.write_joints(t_ns, obs.joint_angles_rad, obs.joint_speeds_rad_s)
        if self.with_references and agent.reference_rad is not None:
            self.writer.write_joints(t_ns, agent.reference_rad, topic=L.JOINT_REFERENCES)
        self.writer.write_ended(t_ns, ended)
        if k % self.tf_every == 0 or last or (agent.done and self.one_shot):
            self.writer.write_tf(t_ns, *self.tf.frames(world, obs))
        self.samples, self.t_last_s = k + 1, t_ns / L.NS_PER_S
        if self.progress is not None:
            self.progress(self.t_last_s, self.planned_s)


def _ball_offset(agent: Agent, own: bool, given: tuple[float, float] | None):
    if given is not None or not own:
        return given
    offset = getattr(agent, "ball_offset_m", None)
    if offset is None:
        offset = getattr(getattr(agent, "movement", None), "ball_offset_m", None)
    return None if offset is None else (float(offset[0]), float(offset[1]))


def record(
    agent: str | Agent,
    out_path: str | Path,
    *,
    duration_s: float | None = None,
    seed: int = 0,
    observe_only: bool = False,
    warmup_s: float | None = None,
    ball_offset_m: tuple[float, float] | None = None,
    config: RecordConfig = RecordConfig(),
    progress: Progress | None = None,
    compression: str = "zstd",
    world: World | str | None = None,
) -> RecordResult:
    """Run ``agent`` (an agent spec for ``make_agent``, or an Agent) in a fresh world and
    record it.

    Args:
        duration_s: one-shot: record this long (holding the end pose after the motion ends;
            None: until the motion ends). Cyclic: rounded to whole periods (None: 10 periods).
        seed: seeds the scene's random generator (and is stored in the recording).
        observe_only: record only what the simulator shows (no ``/joint_references``).
        warmup_s: cyclic agents: time run before recording starts [s] (None:
            ``config.cyclic_warmup_s``).
        ball_offset_m: ball position in the robot frame (x forward, y left) [m]; default: the
            motion's own ``ball_offset_m`` (our agents only); None places the ball aside.
        world: the world to record in: a world, or the name of one to open for this recording
            (``world.registry``: ``mujoco``, ``league``, ``league-server``, ``league-like``;
            default: ours, with the agent's robot).

    Returns:
        A ``RecordResult``; ``interrupted`` is True when Ctrl-C stopped it (the file is valid).
    """
    if isinstance(agent, str):
        agent = make_agent(agent)
    if duration_s is not None and not duration_s > 0:
        raise MimicError(f"--duration must be > 0 s, got {duration_s}")
    if seed < 0:
        raise MimicError(f"--seed must be >= 0, got {seed}")
    settings = dict(
        duration_s=duration_s,
        seed=seed,
        observe_only=observe_only,
        warmup_s=warmup_s,
        ball_offset_m=ball_offset_m,
        config=config,
        progress=progress,
        compression=compression,
    )
    if world is None or isinstance(world, str):
        spec = get_world(world or MUJOCO)
        check_world(spec.name, agent.robot)
        with open_world(spec.name, agent.robot) as opened:
            return _record(agent, out_path, opened, spec.recorded_as, **settings)
    return _record(agent, out_path, world, recorded_as(world), **settings)


def _record(
    agent: Agent,
    out_path: str | Path,
    world: World,
    world_name: str,
    *,
    duration_s: float | None,
    seed: int,
    observe_only: bool,
    warmup_s: float | None,
    ball_offset_m: tuple[float, float] | None,
    config: RecordConfig,
    progress: Progress | None,
    compression: str,
) -> RecordResult:
    own = agent.team == "mimic"
    observe_only = observe_only or not own
    period_s = agent.period_s
    agent.check_robot(world.robot)
    offset = _ball_offset(agent, own, ball_offset_m)
    scene = Scene(
        robot_xy_m=(config.start_x_m, config.start_y_m),
        robot_yaw_rad=config.start_yaw_rad,
        posture=agent.start_posture,
        ball_offset_m=offset,
        settle_s=config.settle_s,
    )

    info = L.RecordingInfo(
        motion=agent.name,
        agent=type(agent).__name__,
        team=agent.team,
        source="observed" if observe_only else "reference",
        robot=world.robot.name,
        joint_order=world.robot.joint_names,
        toolkit_version=__version__,
        seed=seed,
        period_s=period_s,
        ball_offset_m=offset,
        start_posture=agent.start_posture,
        world=world_name,
    )
    if period_s is not None:
        periods = max(1, round((duration_s or config.default_periods * period_s) / period_s))
        planned_cycles = int(round(periods * period_s / CYCLE_S))
    elif duration_s is not None:
        planned_cycles = int(round(duration_s / CYCLE_S)) + 1
    else:
        planned_cycles = int(round(config.max_duration_s / CYCLE_S)) + 1
    planned_s = (planned_cycles - 1) * CYCLE_S if (period_s or duration_s) else None

    with (
        SigintFlag() as sigint,
        RecordingWriter(
            out_path,
            info,
            urdf=world.robot.urdf(),
            flush_period_s=config.flush_period_s,
            compression=compression,
        ) as writer,
    ):
        scene.setup(world, np.random.default_rng(seed))
        agent.check_robot(world.robot)
        agent.reset(world.observe())
        if period_s is not None:
            run(
                world,
                agent,
                max_s=config.cyclic_warmup_s if warmup_s is None else warmup_s,
                reset=False,
                stop_when_done=False,
                stop=lambda w: sigint.raised,
            )
        mcap = McapObserver(
            writer,
            world,
            planned_cycles=planned_cycles,
            one_shot=period_s is None,
            with_references=not observe_only,
            tf_every=config.tf_every,
            planned_s=planned_s,
            progress=progress,
        )
        run(
            world,
            agent,
            max_s=planned_cycles * CYCLE_S,
            reset=False,
            observers=(mcap,),
            stop_when_done=duration_s is None and period_s is None,
            stop=lambda w: sigint.raised or mcap.finished,
        )
        interrupted = mcap.interrupted = sigint.raised
        writer.finish(interrupted=interrupted, samples=mcap.samples)
    return RecordResult(Path(out_path), mcap.samples, mcap.t_last_s, interrupted, info)
