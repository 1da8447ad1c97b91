"""Record one player black-box, as a user would: an agent plays on a league server mimic hosts
while ``mimic record --server`` (a process of its own) records it from the monitor stream.

Shared by the benchmarks that learn a T1 motion from what the monitor shows
(``t1_copyable_kick.py --black-box``, ``league_copies.py``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from mimic.agents.base import Agent
from mimic.episode import Episode, Scene
from mimic.world.base import CYCLE_S
from mimic.world.league_server import LeagueWorld

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
    world = LeagueWorld("t1")
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
