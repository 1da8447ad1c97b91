"""Success rates of our keyframe motions over seeded, perturbed runs in the simulator.

Run: python benchmarks/motion_rates.py [runs] [--robot t1] [--league]
Kick success: ball at least 3 m forward and the robot standing 2 s after the motion.
Get-up success: upright at the motion's end + 1 s. Start poses get small random perturbations
(see mimic.checks.motions.Perturbation); seeds 0..runs-1. ``--robot``: whose motions (default
our NAO, in our MuJoCo world; a league robot plays on the league's field and ball there).
``--league``: run them in the league's own server instead (``LeagueWorld``, hosted, one server
for every run).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from rich.console import Console
from rich.table import Table

from mimic.checks.motions import run_getup, run_kick
from mimic.motion.files import load_motion

KICK_MIN_DISTANCE_M = 3.0


def main(runs: int = 10, robot: str = "nao", league: bool = False) -> None:
    world = None
    if league:
        from mimic.world.league_server import LeagueWorld

        world = LeagueWorld(robot)
    where = "the league server" if league else "our MuJoCo world"
    table = Table(title=f"{robot} keyframe motions in {where}, {runs} seeded runs each")
    for column in (
        "motion",
        "success",
        "falls",
        "distance mean (m)",
        "distance std (m)",
        "direction error mean (deg)",
        "time to upright mean (s)",
        "wall (s)",
    ):
        table.add_column(column)
    try:
        for name in ("kick_right", "kick_left"):
            start = time.perf_counter()
            outs = [run_kick(load_motion(name, robot), seed, world=world) for seed in range(runs)]
            dist = np.array([o.distance_m for o in outs])
            err = np.degrees([o.direction_error_rad for o in outs])
            ok = sum(o.forward_m >= KICK_MIN_DISTANCE_M and o.standing_after for o in outs)
            table.add_row(
                name,
                f"{ok}/{runs}",
                str(sum(not o.standing_after for o in outs)),
                f"{dist.mean():.2f}",
                f"{dist.std():.2f}",
                f"{np.nanmean(err):+.1f}",
                "-",
                f"{time.perf_counter() - start:.1f}",
            )
        for side in ("front", "back"):
            start = time.perf_counter()
            movement = load_motion(f"getup_{side}", robot)
            outs = [run_getup(movement, side, seed, world=world) for seed in range(runs)]
            times = [o.time_to_upright_s for o in outs if o.upright]
            table.add_row(
                f"getup_{side}",
                f"{sum(o.upright for o in outs)}/{runs}",
                "-",
                "-",
                "-",
                "-",
                f"{np.mean(times):.2f}" if times else "-",
                f"{time.perf_counter() - start:.1f}",
            )
    finally:
        if world is not None:
            world.close()
    Console(width=140).print(table)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="?", type=int, default=10)
    parser.add_argument("--robot", default="nao")
    parser.add_argument("--league", action="store_true")
    args = parser.parse_args()
    main(args.runs, args.robot, args.league)
