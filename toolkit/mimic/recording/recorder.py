"""Recording an agent in a fresh world: the simulator's joint angles, our references, TF.

One-shot motions start from the ready pose: the robot is beamed standing in the ``stand``
motion's last keyframe, holds it ``settle_s``, the ball goes to the motion's ``ball_offset_m``
(robot frame) if it has one, and the recording starts as the motion starts (t = 0). Cyclic
agents (``period_s`` set) run ``warmup_s`` unrecorded, then whole periods are recorded.
Other-team agents are only observed: nothing beyond the ``Agent`` interface is read.

Ctrl-C (SIGINT) stops the recording at the end of the current cycle; the file is finished
normally and marked interrupted.
"""

from __future__ import annotations

import math
import signal
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import mujoco
import numpy as np

from mimic import __version__
from mimic.agents.base import Agent
from mimic.agents.tracking import TrackingController
from mimic.errors import MimicError
from mimic.recording import layout as L
from mimic.geometry import quat_mul, rotate
from mimic.recording.writer import RecordingWriter
from mimic.robot.description import BODIES
from mimic.robot.urdf import robot_urdf
from mimic.world.world import CYCLE_S, World

__all__ = ["record", "RecordResult", "RecordConfig", "TfSampler"]

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
    settle_s: float = 0.5
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
    """Link poses in their parents (the URDF tree under ``world``) and the ball in ``world``."""

    def __init__(self, world: World) -> None:
        m = world.model
        self.children = [b.name for b in BODIES] + [L.BALL_FRAME]
        self.parents = [b.parent or L.WORLD_FRAME for b in BODIES] + [L.WORLD_FRAME]
        self._child_ids = np.array([m.body(n).id for n in self.children])
        # Parent body ids; the world body (id 0) sits at the origin with identity rotation.
        self._parent_ids = np.array([m.body(b.parent).id if b.parent else 0 for b in BODIES]
                                    + [0])

    def sample(self, world: World) -> tuple[np.ndarray, np.ndarray]:
        """(n, 3) positions [m] and (n, 4) quaternions of each child in its parent."""
        mujoco.mj_kinematics(world.model, world.data)  # xpos lags qpos after mj_step
        xpos, xquat = world.data.xpos, world.data.xquat
        pc, qc = xpos[self._child_ids], xquat[self._child_ids]
        pp, qp = xpos[self._parent_ids], xquat[self._parent_ids]
        qp_inv = qp * np.array([1.0, -1.0, -1.0, -1.0])
        return rotate(qp_inv, pc - pp), quat_mul(qp_inv, qc)


def _ball_offset(agent: Agent, own: bool, given: tuple[float, float] | None):
    if given is not None or not own:
        return given
    offset = getattr(agent, "ball_offset_m", None)
    if offset is None:
        offset = getattr(getattr(agent, "movement", None), "ball_offset_m", None)
    return None if offset is None else (float(offset[0]), float(offset[1]))


class _SigintFlag:
    """Turns SIGINT into a flag checked once per cycle (main thread only)."""

    def __init__(self) -> None:
        self.raised = False
        self._old = None

    def __enter__(self) -> "_SigintFlag":
        if threading.current_thread() is threading.main_thread():
            self._old = signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame) -> None:
        self.raised = True

    def __exit__(self, *exc) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)


def record(agent: str | Agent, out_path: str | Path, *, duration_s: float | None = None,
           seed: int = 0, observe_only: bool = False, warmup_s: float | None = None,
           ball_offset_m: tuple[float, float] | None = None,
           config: RecordConfig = RecordConfig(), progress: Progress | None = None,
           compression: str = "zstd") -> RecordResult:
    """Run ``agent`` (a name for ``make_agent`` or an Agent) in a fresh World and record it.

    Args:
        duration_s: one-shot: record this long (holding the end pose after the motion ends;
            None: until the motion ends). Cyclic: rounded to whole periods (None: 10 periods).
        seed: seeds numpy's global generator for agents that draw random numbers; stored.
        observe_only: record only what the simulator shows (no ``/joint_references``).
        warmup_s: cyclic agents: time run before recording starts [s] (None:
            ``config.cyclic_warmup_s``).
        ball_offset_m: ball position in the robot frame (x forward, y left) [m]; default: the
            motion's own ``ball_offset_m`` (our agents only); None places the ball aside.

    Returns:
        A ``RecordResult``; ``interrupted`` is True when Ctrl-C stopped it (the file is valid).
    """
    if isinstance(agent, str):
        from mimic.agents.registry import make_agent

        agent = make_agent(agent)
    own = agent.team == "mimic"
    observe_only = observe_only or not own
    period_s = agent.period_s
    if duration_s is not None and duration_s <= 0:
        raise MimicError(f"--duration must be > 0 s, got {duration_s}")
    np.random.seed(seed)

    world = World()
    world.reset()
    from mimic.motion.files import stand_pose_rad

    stand = stand_pose_rad()
    x0, y0, yaw0 = config.start_x_m, config.start_y_m, config.start_yaw_rad
    posture = agent.start_posture
    world.beam(x0, y0, yaw0, stand,
               lying=posture.removeprefix("lying_") if posture != "standing" else None)
    offset = _ball_offset(agent, own, ball_offset_m)
    if offset is not None:
        c, s = math.cos(yaw0), math.sin(yaw0)
        world.place_ball(x0 + c * offset[0] - s * offset[1], y0 + s * offset[0] + c * offset[1])
    else:  # out of the way, beside the robot
        world.place_ball(x0, y0 + 3.0)

    info = L.RecordingInfo(
        motion=agent.name, agent=type(agent).__name__, team=agent.team,
        source="observed" if observe_only else "reference", control_rate_hz=1.0 / CYCLE_S,
        cycle_s=CYCLE_S, toolkit_version=__version__, seed=seed, period_s=period_s,
        ball_offset_m=offset, start_posture=posture)
    if period_s is not None:
        periods = max(1, round((duration_s or config.default_periods * period_s) / period_s))
        planned_cycles = int(round(periods * period_s / CYCLE_S))
    elif duration_s is not None:
        planned_cycles = int(round(duration_s / CYCLE_S)) + 1
    else:
        planned_cycles = int(round(config.max_duration_s / CYCLE_S)) + 1
    planned_s = (planned_cycles - 1) * CYCLE_S if (period_s or duration_s) else None

    hold = TrackingController()
    tf = TfSampler(world)
    samples, t_last = 0, 0.0
    with _SigintFlag() as sigint, RecordingWriter(out_path, info, urdf=robot_urdf(),
                                                  flush_period_s=config.flush_period_s,
                                                  compression=compression) as writer:
        for _ in range(int(round(config.settle_s / CYCLE_S))):
            if sigint.raised:
                break
            obs = world.observe()
            world.step(hold.speeds(stand, obs.joint_angles_rad))
        agent.reset(world.observe())
        if warmup_s is None:
            warmup_s = config.cyclic_warmup_s
        for _ in range(int(round(warmup_s / CYCLE_S)) if period_s is not None else 0):
            if sigint.raised:
                break
            world.step(np.asarray(agent.act(world.observe())))
        cycle_ns = int(round(CYCLE_S * L.NS_PER_S))
        for k in range(planned_cycles):
            if sigint.raised:
                break
            obs = world.observe()
            speeds = np.asarray(agent.act(obs))
            t_ns = k * cycle_ns
            last = k == planned_cycles - 1 or (agent.done and duration_s is None
                                               and period_s is None)
            ended = (agent.done and period_s is None) or (last and not sigint.raised)
            writer.write_joints(t_ns, obs.joint_angles_rad, obs.joint_speeds_rad_s)
            if not observe_only and agent.reference_rad is not None:
                writer.write_joints(t_ns, agent.reference_rad, topic=L.JOINT_REFERENCES)
            writer.write_ended(t_ns, ended)
            if k % config.tf_every == 0 or last:
                writer.write_tf(t_ns, tf.parents, tf.children, *tf.sample(world))
            samples, t_last = samples + 1, t_ns / L.NS_PER_S
            if progress is not None:
                progress(t_last, planned_s)
            if last:
                break
            world.step(speeds)
        interrupted = sigint.raised
        writer.finish(interrupted=interrupted, samples=samples)
    return RecordResult(Path(out_path), samples, t_last, interrupted, info)
