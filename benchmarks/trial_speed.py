"""How fast the kick trial runs: simulated minutes per wall second, against bare MuJoCo
stepping measured in the same process (the baseline).

    python benchmarks/trial_speed.py --minutes 30

Also per CPU second (this process and its worker processes, counted once they have exited):
on a shared machine the wall-clock figures depend on the other jobs, the CPU ones much less.
"""

from __future__ import annotations

import argparse
import resource
import time

from mimic.agents.registry import AgentSpec
from mimic.robot.actuators import JointCommand
from mimic.trials.api import kick_trial
from mimic.world.mujoco_world import MujocoWorld


def cpu_s() -> float:
    """CPU seconds of this process and of its children that have exited."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def bare_stepping_real_time_factor(sim_s: float = 20.0) -> tuple[float, float]:
    """Simulated seconds per wall second and per CPU second of bare stepping."""
    world = MujocoWorld()
    world.reset()
    world.place_robot(0.0, 0.0)
    start, cpu = time.perf_counter(), time.process_time()
    for _ in range(int(sim_s / 0.02)):
        world.step(JointCommand.speeds(world.robot.zeros()))
    return sim_s / (time.perf_counter() - start), sim_s / (time.process_time() - cpu)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--minutes", type=float, default=30.0)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    baseline, baseline_cpu = bare_stepping_real_time_factor()
    start, cpu = time.perf_counter(), cpu_s()
    result = kick_trial(
        [AgentSpec("motion", "kick_right")], minutes=args.minutes, workers=args.workers
    )
    wall_s, cpu_used_s = time.perf_counter() - start, cpu_s() - cpu
    simulated_s = float(result.summary["simulated_min"][0]) * 60
    factor, factor_cpu = simulated_s / wall_s, simulated_s / cpu_used_s
    print(
        f"kick trial: {simulated_s / 60:.1f} simulated min in {wall_s:.1f} s wall "
        f"({factor:.0f}x real time; target: 30 min in <= 60 s, i.e. >= 30x), "
        f"{cpu_used_s:.1f} CPU s ({factor_cpu:.0f}x per CPU second)"
    )
    print(
        f"bare MuJoCo stepping, one process: {baseline:.0f}x real time, "
        f"{baseline_cpu:.0f}x per CPU second"
    )
    print(
        f"trial / bare stepping ratio: {factor / baseline:.2f} wall "
        f"(above 1 means the workers' parallelism beats one bare process), "
        f"{factor_cpu / baseline_cpu:.2f} per CPU second (the trial's overhead)"
    )
    print(f"kicks: {result.summary['attempts'][0]}, episodes: {result.summary['episodes'][0]}")


if __name__ == "__main__":
    main()
