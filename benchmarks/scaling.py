"""Episodes per second for 1 and 2 local workers, the process pool against Ray, in one run;
and the short kick trial of issue 15 (2 simulated minutes) with 1, 2 and 16 workers.

    python benchmarks/scaling.py                 # both parts
    python benchmarks/scaling.py --no-ray        # without Ray (not installed)
    python benchmarks/scaling.py --no-trial      # the episode rates only

The same numbers, episode rates only: ``mimic bench scaling``.
"""

from __future__ import annotations

import argparse
import time

from mimic.agents.registry import AgentSpec
from mimic.trials.api import kick_trial
from mimic.trials.scaling import bench_scaling, format_scaling


def short_kick_trial(workers: int) -> tuple[float, float, int]:
    """(wall s, simulated min, kicks) of a 2-minute kick trial of kick_right, seed 7."""
    start = time.perf_counter()
    result = kick_trial([AgentSpec("motion", "kick_right")], minutes=2.0, seed=7, workers=workers)
    row = result.summary.row(0, named=True)
    return time.perf_counter() - start, row["simulated_min"], row["attempts"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--episodes", type=int, default=8)
    parser.add_argument("--ray", action=argparse.BooleanOptionalAction, default=True)
    parser.add_argument("--trial", action=argparse.BooleanOptionalAction, default=True)
    args = parser.parse_args()
    start = time.perf_counter()
    print(format_scaling(bench_scaling(episodes=args.episodes, ray=args.ray)))
    if args.trial:
        print("| 2-min kick trial | wall s | simulated min | kicks |\n|---|---|---|---|")
        for workers in (1, 2, 16):
            wall_s, sim_min, kicks = short_kick_trial(workers)
            print(f"| --workers {workers} | {wall_s:.1f} | {sim_min:.2f} | {kicks} |")
    print(f"\nbenchmark wall time: {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
