"""What several benchmarks share, in one public module (the benchmarks import it by name:
Python puts a script's own folder on its path).

- The T1 copy studies' episodes (``t1_copy_gain.py``, ``t1_copyable_kick.py``,
  ``league_copies.py``): a kick from a stand (the ``kick-from-stand`` task, the ball far from
  the goals, 1 deg start-pose noise, standing = never fell by 2 s after the motion, holding
  the stand pose) or a walk from the walk trial's start, watched as the league's monitor
  shows it (``Seen``, ``monitor_view``).
- Recording one player black-box, as a user would (``record_black_box``: an agent plays on a
  league server mimic hosts while ``mimic record --server``, a process of its own, records it
  from the monitor stream), and running the ``mimic`` command line (``mimic``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from mimic.agents.base import Agent
from mimic.episode import Episode, FallCounter, Observer, Scene
from mimic.geometry import in_robot_frame
from mimic.learn.train import pd_compensated_targets
from mimic.tasks import kick_from_stand
from mimic.tasks.kick_from_stand import After, KickFromStandConfig, Standing
from mimic.tasks.perturbation import Perturbation
from mimic.tasks.walk import WalkTrialConfig, walk_scene
from mimic.world.base import CYCLE_S
from mimic.world.league_server import LeagueWorld
from mimic.world.registry import open_world

__all__ = [
    "T1",
    "SAMPLE_EVERY",
    "Seen",
    "t1_kick_config",
    "t1_scene",
    "play_t1",
    "monitor_view",
    "per_cycle",
    "MIMIC",
    "record_black_box",
    "mimic",
]

T1 = "t1"
#: Every second cycle: the league's monitor rate.
SAMPLE_EVERY = 2
#: Where the T1 studies' kicks put the ball, field frame [m]: far from the goals.
KICK_BALL_START_M = (-8.0, 0.0)
#: After a kick the robot stands this long before standing is read [s].
KICK_AFTER_S = 2.0


class Seen(Observer):
    """Angles, torso position and orientation every cycle; when the robot first fell [s];
    the ball in the torso's frame at the first cycle (x forward, y left [m]), where a
    recording shows it to ``mimic train``."""

    def __init__(self) -> None:
        self.angles, self.pos, self.quat = [], [], []
        self.fell_s: float | None = None
        self.ball_offset_m: tuple[float, float] | None = None

    def before_step(self, world, obs, agent, command) -> None:
        if self.ball_offset_m is None:
            ball = in_robot_frame(
                world.ball_pos_m()[:2], world.torso_pos_m()[:2], world.torso_yaw_rad()
            )
            self.ball_offset_m = (float(ball[0]), float(ball[1]))
        self.angles.append(obs.joint_angles_rad)
        self.pos.append(world.torso_pos_m().copy())
        self.quat.append(world.torso_quat_wxyz().copy())
        if self.fell_s is None and world.fallen():
            self.fell_s = len(self.angles) * CYCLE_S


def t1_kick_config(offset_m, seconds: float = 8.0) -> KickFromStandConfig:
    """The T1 studies' kick from a stand, the ball at ``offset_m`` (robot frame [m]), the
    kick playing at most ``seconds`` [s]."""
    return KickFromStandConfig(
        robot_xy_m=(KICK_BALL_START_M[0] - offset_m[0], -offset_m[1]),
        ball_offset_m=tuple(offset_m),
        noise=Perturbation().noise(),
        settle_s=0.2,
        kick_max_s=seconds,
        abort_on_fall=False,
        after=After.STAND,
        after_s=KICK_AFTER_S,
        standing=Standing.NEVER_FELL,
        roll_max_s=None,
    )


def t1_scene(motion: str, world_kind: str, offset_m) -> Scene:
    """Where a T1 study's episode starts: a ``kick`` from a stand, or a ``walk`` from the
    walk trial's start in ``world_kind``."""
    if motion == "walk":
        return walk_scene(WalkTrialConfig(world=world_kind))
    return kick_from_stand.scene(t1_kick_config(offset_m), tuple(offset_m))


def play_t1(agent, motion: str, world_kind: str, offset_m, seed: int, seconds: float):
    """(``Seen``, ball or torso distance [m], standing at the end) of one T1 episode: a kick
    from a stand (the ball's travel on the ground) or ``seconds`` of a walk (the torso's
    advance along x)."""
    with open_world(world_kind, T1) as world:
        seen = Seen()
        if motion == "kick":
            config = t1_kick_config(offset_m, seconds)
            outcome = kick_from_stand.play(world, agent, seed, config, observers=(seen,))
            return seen, outcome.distance_m, outcome.standing
        t1_scene(motion, world_kind, offset_m).setup(world, np.random.default_rng(seed))
        torso0 = world.torso_pos_m()[:2].copy()
        falls = FallCounter()
        episode = Episode(world, observers=(seen,), falls=falls)
        episode.run(agent, max_s=seconds, abort_on_fall=False)
        distance = float(world.torso_pos_m()[0] - torso0[0])
        return seen, distance, falls.falls == 0 and not world.fallen()


def monitor_view(seen: Seen, robot, world_kind: str):
    """(sample times [s], reached angles [rad], compensated references [rad]) of an episode
    as the league's monitor shows it: every ``SAMPLE_EVERY``-th cycle."""
    q = np.array(seen.angles)[::SAMPLE_EVERY]
    pos, quat = np.array(seen.pos)[::SAMPLE_EVERY], np.array(seen.quat)[::SAMPLE_EVERY]
    t = np.arange(len(q)) * CYCLE_S * SAMPLE_EVERY
    return t, q, pd_compensated_targets(t, q, pos, quat, robot, world_kind)


def per_cycle(t: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(T, N) ``values`` sampled at times ``t`` [s], interpolated to one row per cycle."""
    cycles = np.arange(0, t[-1] + 1e-9, CYCLE_S)
    return np.stack([np.interp(cycles, t, values[:, j]) for j in range(values.shape[1])], 1)


#: The ``mimic`` command of the running interpreter's environment.
MIMIC = str(Path(sys.executable).with_name("mimic"))
#: Wall time for the recorder to join before the agent starts [s]: in sync mode the server
#: waits for our agent, so nothing is missed meanwhile.
JOIN_S = 3.0


def record_black_box(
    agent: Agent,
    scene: Scene,
    path: Path,
    seed: int,
    play_s: float,
    wait_cycles: int = 0,
    after_s: float = 2.0,
) -> float:
    """Set ``scene`` up (from ``seed``) on a hosted league server, record the player with
    ``mimic record --server`` into ``path``, let the robot stand ``wait_cycles`` cycles, play
    ``agent`` for at most ``play_s`` [s] (until it is done), then stand ``after_s`` [s].

    Returns the time the agent played [s]. Exits with the recorder's own line if it failed.
    """
    world = LeagueWorld(T1)
    try:
        scene.setup(world, np.random.default_rng(seed))
        seconds = wait_cycles * CYCLE_S + play_s + after_s + 1.0
        recorder = subprocess.Popen(
            [MIMIC, "record", "--server", world.server.monitor_address, "--team",
             world.config.team, "--player", str(world.config.player), "--seconds",
             f"{seconds:.1f}", "-o", str(path), "--force"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        )  # fmt: skip
        time.sleep(JOIN_S)
        episode = Episode(world)
        if wait_cycles:
            episode.stand_still(max_s=wait_cycles * CYCLE_S)
        start_s = world.observe().time_s
        episode.run(agent, max_s=play_s, abort_on_fall=False)
        played_s = world.observe().time_s - start_s
        episode.stand_still(max_s=after_s)
        if recorder.wait(timeout=120) != 0:
            sys.exit(f"mimic record failed: {recorder.stdout.read().strip()}")
    finally:
        world.close()
    return played_s


def mimic(*args: str) -> list[str]:
    """Run ``mimic ARGS``; its output lines. Exits with its error line if it failed."""
    # Wide lines: rich wraps at 80 columns when it writes to a pipe.
    env = {**os.environ, "COLUMNS": "200"}
    done = subprocess.run([MIMIC, *args], capture_output=True, text=True, env=env)
    if done.returncode != 0:
        sys.exit(f"mimic {args[0]} failed: {done.stderr.strip() or done.stdout.strip()}")
    return done.stdout.splitlines() + done.stderr.splitlines()
