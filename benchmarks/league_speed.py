"""How fast the league world runs beside our MuJoCo (NAO) world, in the same run.

1. The same episode work in each world (``mimic bench league``): the robot placed behind the
   ball, standing, kicking, standing while the ball rolls; the T1 in the league's simulation
   in this process and on a hosted server, the T1 and the NAO in our world; beside bare
   ``mj_step`` of the league's T1 model. Real-time factors and CPU per simulated s.
2. Kick trials of ``--minutes`` simulated minutes on ``--workers`` workers: the NAO in our
   world (walking to the ball) and the T1 in the league's, in process and on hosted servers
   (placed behind the ball; one server per episode, so K workers run K servers). Acceptance
   for the hosted league: 10 simulated minutes in at most 5 min of wall time on 2 cores
   (>= 2x real time).

    python benchmarks/league_speed.py                    # 2-minute trials
    python benchmarks/league_speed.py --minutes 10       # the acceptance run (~5 min)

The T1 kicks with its shipped ``kick_right`` when there is one, else with
``tests/league_standin_kick.txt`` (a stand-in that pushes the ball a metre or two and falls).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from mimic.agents.registry import agent_spec
from mimic.trials.api import kick_trial
from mimic.trials.world_speed import bench_worlds, default_kick, format_world_speeds

STANDIN_KICK = Path(__file__).resolve().parents[1] / "tests" / "league_standin_kick.txt"


def _trial(world: str, kick: str, robot: str, minutes: float, workers: int) -> str:
    start = time.perf_counter()
    result = kick_trial(
        [agent_spec(kick, robot=robot)], minutes=minutes, workers=workers, world=world
    )
    wall = time.perf_counter() - start
    row = result.summary.row(0, named=True)
    simulated = row["simulated_min"] * 60
    return (
        f"{world:13} {robot:4} {row['reach']:5} {row['episodes']:3} episodes "
        f"{row['attempts']:4} kicks {simulated / 60:5.2f} sim min in {wall:6.1f} s wall: "
        f"{simulated / wall:5.1f}x real time"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--seconds", type=float, default=20.0, help="simulated seconds of episode work per world"
    )
    parser.add_argument(
        "--minutes", type=float, default=2.0, help="simulated minutes per kick trial (0: no trials)"
    )
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    t1_kick = default_kick("t1") or str(STANDIN_KICK)
    print(f"T1 kick: {t1_kick}")
    print(format_world_speeds(bench_worlds(args.seconds, kicks={"t1": t1_kick})))
    if args.minutes > 0:
        print(f"kick trials, {args.minutes:g} simulated min, {args.workers} workers:")
        print(_trial("mujoco", "kick_right", "nao", args.minutes, args.workers))
        print(_trial("league", t1_kick, "t1", args.minutes, args.workers))
        print(_trial("league-server", t1_kick, "t1", args.minutes, args.workers))


if __name__ == "__main__":
    main()
