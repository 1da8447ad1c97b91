"""How fast each world runs the same episode work: real-time factors in one run.

The work is a kick trial's: the robot is placed behind the ball, stands, kicks, and stands
while the ball rolls (the ``kick-from-stand`` task without start noise), again and again
until ``seconds`` of simulated time have passed. Each world is timed from its first
placement (``rtf``) and with its opening and closing included (``rtf_with_start``: for the
hosted league server that is hosting and joining it, once per episode in a trial). CPU
seconds count this process and, for the hosted server, the server process too. The baseline
(``bench_bare``) is bare ``mj_step`` of the league's own model with the T1 standing in it:
no agent, no world, nothing but MuJoCo. A standing robot is not the kick's physics (other
contacts, other solver work), so ``bench_bare_same`` replays the league world's own physics
steps of the same work (every cycle's integration state, set and stepped): the baseline for
what the world adds around MuJoCo.

    rows = bench_worlds(seconds=20)
    print(format_world_speeds(rows))
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from mimic.agents.keyframe_player import KeyframePlayer
from mimic.agents.registry import agent_spec
from mimic.episode import PoseNoise, Scene
from mimic.motion.files import list_motions, load_motion
from mimic.robot.actuators import JointCommand
from mimic.tasks import kick_from_stand
from mimic.tasks.kick_from_stand import After, KickFromStandConfig
from mimic.world.base import CYCLE_S
from mimic.world.registry import LEAGUE, LEAGUE_SERVER, MUJOCO, open_world

__all__ = [
    "WorldSpeed",
    "bench_world",
    "bench_bare",
    "bench_bare_same",
    "bench_worlds",
    "format_world_speeds",
    "default_kick",
    "BARE",
    "BARE_SAME",
]

#: The baseline's name in the table: MuJoCo stepping the league's model, nothing else.
BARE = "bare"
#: Bare stepping of the league world's own physics steps of the kick work.
BARE_SAME = "bare-same"

#: Seconds one kick cycle lasts at most: stand, kick, stand while the ball rolls [s].
_STAND_S, _KICK_MAX_S, _ROLL_S = 0.5, 6.0, 3.0
#: Without a kick the robot stands this long in its place [s].
_STAND_ONLY_S = 1.5


@dataclass(frozen=True)
class WorldSpeed:
    """One world's timing.

    Attributes:
        world, robot, kick: what ran (``kick``: the agent spec; ``stand``: none).
        simulated_s: simulated time [s]; wall_s: wall time of the episode work [s];
        start_s: wall time to open and close the world [s];
        cpu_s: CPU time of this process and the world's server, if any [s].
    """

    world: str
    robot: str
    kick: str
    simulated_s: float
    wall_s: float
    start_s: float
    cpu_s: float

    @property
    def rtf(self) -> float:
        """Simulated seconds per wall second."""
        return self.simulated_s / self.wall_s

    @property
    def rtf_with_start(self) -> float:
        """The same with opening and closing the world counted."""
        return self.simulated_s / (self.wall_s + self.start_s)

    @property
    def cpu_per_simulated_s(self) -> float:
        return self.cpu_s / self.simulated_s

    @property
    def simulated_per_cpu_s(self) -> float:
        """Simulated seconds per CPU second."""
        return self.simulated_s / self.cpu_s


def default_kick(robot: str) -> str | None:
    """The robot's shipped ``kick_right``, if it has one."""

    return "kick_right" if "kick_right" in list_motions(robot) else None


def _process_cpu_s(pid: int) -> float:
    """CPU time of another process (Linux /proc; 0 elsewhere) [s]."""
    stat = Path(f"/proc/{pid}/stat")
    if not stat.exists():
        return 0.0
    fields = stat.read_text().split(")")[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _cpu_s(world) -> float:
    server = getattr(world, "server", None)
    proc = getattr(server, "_proc", None)
    return time.process_time() + (_process_cpu_s(proc.pid) if proc is not None else 0.0)


def bench_world(
    world: str,
    robot: str,
    kick: str | None,
    *,
    seconds: float = 20.0,
    seed: int = 0,
    passes: int = 1,
) -> WorldSpeed:
    """Time ``seconds`` of kick-trial work of ``robot`` (``kick``: an agent spec; None: the
    robot only stands) in ``world``; with ``passes`` > 1 the work is done that many times in
    the same world and the pass that took the least CPU time is kept (the others met more
    of what else the machine was doing)."""
    spec = agent_spec(kick, robot=robot) if kick else None
    config = _kick_config(spec)
    t0 = time.perf_counter()
    with open_world(world, robot) as w:
        opened_s = time.perf_counter() - t0
        timed = []  # (cpu, wall, simulated) of each pass
        for _ in range(passes):
            cpu0, t1, simulated = _cpu_s(w), time.perf_counter(), 0.0
            while simulated < seconds:
                # Without start noise every episode is the same; the seed changes nothing.
                agent = spec.build() if spec is not None else _stand_agent(robot)
                kick_from_stand.play(w, agent, seed, config)
                simulated += w.time_s
            timed.append((_cpu_s(w) - cpu0, time.perf_counter() - t1, simulated))
        cpu, wall, simulated = min(timed)
        t2 = time.perf_counter()
    closed_s = time.perf_counter() - t2
    return WorldSpeed(world, robot, kick or "stand", simulated, wall, opened_s + closed_s, cpu)


def _kick_config(spec) -> KickFromStandConfig:
    """The benchmark's episode: placed behind the ball without noise, stand, kick (or stand
    on), stand while the ball rolls."""
    offset = spec.ball_offset_m() if spec else (0.3, 0.0)
    return KickFromStandConfig(
        robot_xy_m=(-offset[0], -offset[1]),
        ball_offset_m=tuple(offset),
        noise=PoseNoise(),
        settle_s=_STAND_S,
        ball_after_settle=True,
        settle_into_stand=True,
        kick_max_s=_KICK_MAX_S if spec is not None else _STAND_ONLY_S,
        abort_on_fall=True,
        after=After.STAND_OR_LIMP,
        after_s=_ROLL_S,
        roll_max_s=None,
    )


def _stand_agent(robot: str) -> KeyframePlayer:
    """The robot moving into its stand pose and holding it (a kick trial's standing)."""
    return KeyframePlayer(load_motion("stand", robot), hold_s=math.inf)


def bench_bare(robot: str = "t1", *, seconds: float = 20.0) -> WorldSpeed:
    """Time bare ``mj_step`` of the league's model (rcsssmj's, as the league world compiles it
    with ``robot`` in it) for ``seconds`` of simulated time: the robot standing behind the
    ball, holding its stand pose, 4 physics steps per cycle as the league steps them."""

    with open_world(LEAGUE, robot) as w:
        Scene(robot_xy_m=(-0.3, 0.0), ball_offset_m=(0.3, 0.0), settle_s=_STAND_S).setup(
            w, np.random.default_rng(0)
        )
        w.step(JointCommand.references(w.robot.stand_pose()))  # its targets in the controls
        model, data = w.simulation.mj_model, w.simulation.mj_data
        substeps = round(CYCLE_S / model.opt.timestep)
        cycles = max(1, round(seconds / CYCLE_S))
        cpu0, t0 = time.process_time(), time.perf_counter()
        for _ in range(cycles):
            mujoco.mj_step(model, data, substeps)
        wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    return WorldSpeed(BARE, robot, "stand", cycles * CYCLE_S, wall, 0.0, cpu)


def bench_bare_same(
    robot: str, kick: str | None, *, seconds: float = 20.0, seed: int = 0, passes: int = 1
) -> WorldSpeed:
    """Bare ``mj_step`` of exactly the physics steps the league world in process takes for
    ``bench_world(LEAGUE, robot, kick, seconds)``: that work is played once untimed while
    every cycle's integration state (positions, speeds, controls, applied forces, warm
    start, time) is kept before its physics steps; then each state is set and stepped as the
    league steps a cycle, ``passes`` times (the fastest kept, as in ``bench_world``). The
    time spent setting states, timed alone, is subtracted."""
    spec = agent_spec(kick, robot=robot) if kick else None
    with open_world(LEAGUE, robot) as w:
        sim = w.simulation
        model, data = sim.mj_model, sim.mj_data
        kind = mujoco.mjtState.mjSTATE_INTEGRATION
        states: list[np.ndarray] = []
        step = sim.step

        def kept(commands) -> None:  # the state a cycle's physics starts from, then the cycle
            state = np.empty(mujoco.mj_stateSize(model, kind))
            mujoco.mj_getState(model, data, state, kind)
            states.append(state)
            step(commands)

        sim.step = kept
        simulated = 0.0
        config = _kick_config(spec)
        while simulated < seconds:
            agent = spec.build() if spec is not None else _stand_agent(robot)
            kick_from_stand.play(w, agent, seed, config)
            simulated += w.time_s
        sim.step = step
        substeps = round(CYCLE_S / model.opt.timestep)
        stepped, setting = [], []
        for _ in range(passes):
            cpu0 = time.process_time()
            for state in states:
                mujoco.mj_setState(model, data, state, kind)
                mujoco.mj_step(model, data, substeps)
            stepped.append(time.process_time() - cpu0)
            cpu0 = time.process_time()
            for state in states:
                mujoco.mj_setState(model, data, state, kind)
            setting.append(time.process_time() - cpu0)
    cpu = max(min(stepped) - min(setting), 1e-9)
    return WorldSpeed(BARE_SAME, robot, kick or "stand", len(states) * CYCLE_S, cpu, 0.0, cpu)


def bench_worlds(
    seconds: float = 20.0, kicks: dict[str, str | None] | None = None
) -> list[WorldSpeed]:
    """Bare stepping of the league's T1 model (the baseline) and of the league world's own
    physics steps of the T1's work, then that work in the league's simulation in this
    process, on a hosted league server, in our world with the T1 and in our world with the
    NAO (``kicks``: robot -> kick spec; default: each robot's shipped ``kick_right``). The
    league world and its own steps' baseline keep the fastest of 3 passes each."""
    kicks = dict(kicks or {})
    for robot in ("nao", "t1"):
        kicks.setdefault(robot, default_kick(robot))
    runs = [(LEAGUE, "t1"), (LEAGUE_SERVER, "t1"), (MUJOCO, "t1"), (MUJOCO, "nao")]
    passes = {LEAGUE: 3}
    return [
        bench_bare("t1", seconds=seconds),
        bench_bare_same("t1", kicks["t1"], seconds=seconds, passes=3),
    ] + [
        bench_world(world, robot, kicks[robot], seconds=seconds, passes=passes.get(world, 1))
        for world, robot in runs
    ]


def format_world_speeds(rows: list[WorldSpeed]) -> str:
    """A table under 80 columns: real-time factor (RTF), with the world's start (+start), CPU
    seconds per simulated second, and simulated seconds per CPU second as a ratio of the bare
    stepping row's (the first ``BARE`` row; else the first row's)."""
    base = next((r for r in rows if r.world == BARE), rows[0] if rows else None)
    per_cpu = base.simulated_per_cpu_s if base else math.nan
    lines = [
        f"{'world':13} {'robot':5} {'kick':14} {'sim s':>5} {'wall s':>6} {'RTF':>5} "
        f"{'+start':>6} {'CPU/sim':>7} {'xbare':>5}"
    ]
    for r in rows:
        kick = Path(r.kick).stem if r.kick.endswith(".txt") else r.kick
        kick = kick if len(kick) <= 14 else kick[:13] + "~"
        lines.append(
            f"{r.world:13} {r.robot:5} {kick:14} {r.simulated_s:5.1f} {r.wall_s:6.2f} "
            f"{r.rtf:5.1f} {r.rtf_with_start:6.1f} {r.cpu_per_simulated_s:7.4f} "
            f"{r.simulated_per_cpu_s / per_cpu:5.2f}"
        )
    same = next((r for r in rows if r.world == BARE_SAME), None)
    league = next((r for r in rows if r.world == LEAGUE), None)
    if same is not None and league is not None:
        lines.append(
            f"league per CPU s: {league.simulated_per_cpu_s / same.simulated_per_cpu_s:.2f} "
            f"of {BARE_SAME}"
        )
    return "\n".join(lines)
