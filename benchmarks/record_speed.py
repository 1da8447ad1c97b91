"""How fast the record path runs, against MuJoCo stepping alone, in the same process.

    python benchmarks/record_speed.py [MOTION]

Prints simulated seconds per wall-clock second for (a) bare World.step cycles with zero
commands (the baseline) and (b) the whole `record` path (agent, TF, encoding, compression,
file), and their ratio. Target: the record path above 30x real time.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from mimic.motion.files import list_motions
from mimic.recording.recorder import RecordConfig, record
from mimic.world.base import CYCLE_S
from mimic.world.mujoco_world import MujocoWorld


def baseline_rate(sim_s: float) -> float:
    """Simulated seconds per wall second of World.step alone."""
    world = MujocoWorld()
    world.reset()
    cycles = int(sim_s / CYCLE_S)
    zero = np.zeros(22)
    start = time.perf_counter()
    for _ in range(cycles):
        world.observe()
        world.step(zero)
    return cycles * CYCLE_S / (time.perf_counter() - start)


def record_rate(motion: str, sim_s: float, tf_every: int) -> tuple[float, int]:
    """Simulated seconds per wall second of `record` (incl. world build and settle)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench.mcap"
        config = RecordConfig(tf_every=tf_every)
        start = time.perf_counter()
        result = record(motion, path, duration_s=sim_s, config=config)
        wall = time.perf_counter() - start
        simulated = result.duration_s + config.settle_s
        return simulated / wall, path.stat().st_size


def main() -> None:
    motion = sys.argv[1] if len(sys.argv) > 1 else (
        "kick_right" if "kick_right" in list_motions() else "stand")
    sim_s = 10.0
    base = baseline_rate(sim_s)
    print(f"MuJoCo stepping alone:        {base:7.1f}x real time")
    for tf_every in (1, 2):
        rate, size = record_rate(motion, sim_s, tf_every)
        print(f"record {motion} (tf every {tf_every}): {rate:7.1f}x real time, "
              f"{rate / base:.2f} of the baseline, {size / sim_s / 1000:.0f} kB per sim second")


if __name__ == "__main__":
    main()
