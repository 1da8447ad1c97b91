"""How fast the kick trial runs: simulated minutes per wall second, against bare MuJoCo
stepping measured in the same process (the baseline).

    python benchmarks/trial_speed.py --minutes 30
"""

from __future__ import annotations

import argparse
import time

from mimic.agents.registry import AgentSpec
from mimic.robot.actuators import JointCommand
from mimic.trials.api import kick_trial
from mimic.world.mujoco_world import MujocoWorld


def bare_stepping_real_time_factor(sim_s: float = 20.0) -> float:
    world = MujocoWorld()
    world.reset()
    world.place_robot(0.0, 0.0)
    start = time.perf_counter()
    for _ in range(int(sim_s / 0.02)):
        world.step(JointCommand.speeds(world.robot.zeros()))
    return sim_s / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--minutes", type=float, default=30.0)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    baseline = bare_stepping_real_time_factor()
    start = time.perf_counter()
    result = kick_trial([AgentSpec("motion", "kick_right")], minutes=args.minutes,
                        workers=args.workers)
    wall_s = time.perf_counter() - start
    simulated_s = float(result.summary["simulated_min"][0]) * 60
    factor = simulated_s / wall_s
    print(f"kick trial: {simulated_s / 60:.1f} simulated min in {wall_s:.1f} s wall "
          f"({factor:.0f}x real time; target: 30 min in <= 60 s, i.e. >= 30x)")
    print(f"bare MuJoCo stepping, one process: {baseline:.0f}x real time")
    print(f"trial / bare stepping ratio: {factor / baseline:.2f} "
          f"(above 1 means the workers' parallelism beats one bare process)")
    print(f"kicks: {result.summary['attempts'][0]}, episodes: {result.summary['episodes'][0]}")


if __name__ == "__main__":
    main()
