"""Go-to-pose behind the ball: how often our walk lines up without touching the ball.

    python benchmarks/goto_ball.py [--near 12] [--around 6] [--seed 0]

Runs ``mimic.checks.ball_approach.walk_behind_ball`` (the kick trial's walk to the ball) from
``--near`` starts just ahead of the ball (facing away: the walk turns round and passes it) and
``--around`` starts 0.4 to 1.0 m from it in any direction. A run passes when the robot arrives
standing, the ball moved less than 3 cm and lies within 5 cm of the kick's ball offset in the
robot frame. Prints one line per start and the count that failed.
"""

from __future__ import annotations

import argparse

import numpy as np

from mimic.checks.ball_approach import approach_starts, walk_behind_ball
from mimic.world.mujoco_world import MujocoWorld


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--near", type=int, default=12)
    parser.add_argument("--around", type=int, default=6)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    world = MujocoWorld()
    starts = approach_starts(np.random.default_rng(args.seed), args.near, args.around)
    failed = 0
    print(f"{'start':>6} {'ball moved m':>12} {'offset error m':>14} {'time s':>7}  result")
    for i, (ball, start) in enumerate(starts):
        r = walk_behind_ball(world, ball, start)
        failed += not r.ok
        kind = "near" if i < args.near else "around"
        verdict = "ok" if r.ok else ("fell" if r.fell else "FAIL")
        print(
            f"{kind:>6} {r.ball_moved_m:12.3f} {r.offset_error_m:14.3f} {r.time_s:7.1f}  {verdict}"
        )
    print(f"failed {failed} of {len(starts)}")


if __name__ == "__main__":
    main()
