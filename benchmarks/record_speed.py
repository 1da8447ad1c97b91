"""How fast the record path runs, against MuJoCo stepping alone, in the same process.

    python benchmarks/record_speed.py [MOTION]

Prints simulated seconds per wall-clock second and per CPU second of this process for (a) bare
MujocoWorld.step cycles with zero speed commands (the baseline) and (b) the whole `record` path
(agent, TF, encoding, compression, file), and their ratio. Both run single-threaded, so the CPU
figures hold on a shared machine where the wall-clock ones do not. Target: the record path
above 30x real time.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

from mimic.motion.files import list_motions
from mimic.recording.recorder import RecordConfig, record
from mimic.robot.actuators import JointCommand
from mimic.world.base import CYCLE_S
from mimic.world.mujoco_world import MujocoWorld


def baseline_rate(sim_s: float) -> tuple[float, float]:
    """Simulated seconds per wall second and per CPU second of MujocoWorld.step alone."""
    world = MujocoWorld()
    world.reset()
    cycles = int(sim_s / CYCLE_S)
    zero = JointCommand.speeds(world.robot.zeros())
    start, cpu = time.perf_counter(), time.process_time()
    for _ in range(cycles):
        world.observe()
        world.step(zero)
    simulated = cycles * CYCLE_S
    return simulated / (time.perf_counter() - start), simulated / (time.process_time() - cpu)


def record_rate(motion: str, sim_s: float, tf_every: int) -> tuple[float, float, int]:
    """Simulated seconds per wall second and per CPU second of `record` (incl. world build
    and settle), and the file's size [bytes]."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench.mcap"
        config = RecordConfig(tf_every=tf_every)
        start, cpu = time.perf_counter(), time.process_time()
        result = record(motion, path, duration_s=sim_s, config=config)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        simulated = result.duration_s + config.settle_s
        return simulated / wall, simulated / cpu, path.stat().st_size


def main() -> None:
    motion = (
        sys.argv[1]
        if len(sys.argv) > 1
        else ("kick_right" if "kick_right" in list_motions() else "stand")
    )
    sim_s = 10.0
    base, base_cpu = baseline_rate(sim_s)
    print(
        f"MuJoCo stepping alone:        {base:7.1f}x real time (wall), "
        f"{base_cpu:7.1f}x per CPU second"
    )
    for tf_every in (1, 2):
        rate, rate_cpu, size = record_rate(motion, sim_s, tf_every)
        print(
            f"record {motion} (tf every {tf_every}): {rate:7.1f}x real time (wall), "
            f"{rate_cpu:7.1f}x per CPU second; {rate / base:.2f} of the baseline (wall), "
            f"{rate_cpu / base_cpu:.2f} (CPU); {size / sim_s / 1000:.0f} kB per sim second"
        )


if __name__ == "__main__":
    main()
